// setbound benchmarks — the order statistics every bench program reports (one definition).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace setbound_bench {

/// The q-quantile of v (nearest rank, q in [0, 1]); NaN for an empty v.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

/// The median (the upper one of an even count); NaN for an empty v.
inline double median(std::vector<double> v) { return percentile(std::move(v), 0.5); }

}  // namespace setbound_bench
