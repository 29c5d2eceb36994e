// setbound — per-step time of the zonotopic estimators in C++ on CORA's linearSysDT observer
// data (shared/benchmarks/cora_linearSysDT_observe), with CORA's settings (zonotope order ×
// n_x generators, CORA's reduction technique). Built only with -DSETBOUND_BUILD_BENCH=ON.
//
//   bench_zonotopic_cpp [DATA_DIR] [--min-steps N] [--only NAME] [--update-doc docs/benchmarks.md]
//
// For every data set and method it runs the whole horizon repeatedly (at least N timed steps
// in all, default 400), times every step with a steady clock and prints the median, the
// 90th percentile and the median over the steps where the generator limit is reached
// ("full"), plus the final interval hull's largest difference to CORA's saved one. With
// --update-doc the table replaces the block between the bench markers in that file.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bench_stats.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/zonotopic/pradius.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "cora_data.hpp"

using namespace setbound;
using namespace setbound_bench;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

struct Row {
  std::string data, method, reduction;
  Index n, limit;
  std::size_t steps;
  double median_us, p90_us, full_us, diff, box = 0;
  std::string golden_key;
};

ZonotopeReduction reduction_of(const std::string& cora) {
  if (cora.rfind("pca", 0) == 0) return ZonotopeReduction::Pca;
  if (cora.rfind("girard", 0) == 0) return ZonotopeReduction::Girard;
  return ZonotopeReduction::Combastel;
}

const char* reduction_name(ZonotopeReduction r) {
  switch (r) {
    case ZonotopeReduction::Pca: return "pca";
    case ZonotopeReduction::Girard: return "girard";
    default: return "combastel";
  }
}

Row run(const Benchmark& b, const std::string& method, const ZonotopeGain& gain, ZonotopeReduction red,
        std::size_t min_steps, const std::string& golden_key, Index horizon = -1,
        const std::vector<Index>& strip_order = {}) {
  const Index n = b.system->nx();
  ZonotopicOptions opt;
  opt.strip_order = strip_order;
  opt.max_generators = std::max<Index>(static_cast<Index>(b.order * static_cast<double>(n) + 1e-9), n);
  opt.reduction = red;
  const Index N = horizon > 0 ? std::min<Index>(horizon, b.Y.rows()) : b.Y.rows();
  std::vector<double> times, full;
  VectorXd lo, hi;
  double box = 0;
  const auto total_start = std::chrono::steady_clock::now();
  do {
    ZonotopicEstimator est(*b.system, Zonotope(b.p0, b.H0), gain, opt);
    for (Index k = 0; k < N; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      est.update(b.Y.row(k).transpose(), b.U.row(k).transpose());
      const auto t1 = std::chrono::steady_clock::now();
      const double us = std::chrono::duration<double, std::micro>(t1 - t0).count();
      times.push_back(us);
      if (est.reduced_last_step()) full.push_back(us);
      box = std::max(box, est.current_box().maxCoeff() / (est.current_upper() - est.current_lower()).maxCoeff() * 2);
    }
    lo = est.current_lower();
    hi = est.current_upper();
  } while (times.size() < min_steps &&
           std::chrono::steady_clock::now() - total_start < std::chrono::seconds(60));
  Row r{b.name, method, reduction_name(red), n, opt.max_generators, times.size(),
        percentile(times, 0.5), percentile(times, 0.9), percentile(full, 0.5), NAN, 0.0, golden_key};
  auto it = b.golden.find(golden_key);
  r.box = box;
  if (it != b.golden.end())
    r.diff = std::max((lo - it->second.first).cwiseAbs().maxCoeff(), (hi - it->second.second).cwiseAbs().maxCoeff());
  return r;
}

std::string fmt(double v, const char* f) {
  if (std::isnan(v)) return "—";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir;
  if (const char* env = std::getenv("SETBOUND_CORA_DATA")) dir = env;
#ifdef SETBOUND_CORA_DATA_DEFAULT
  if (dir.empty()) dir = SETBOUND_CORA_DATA_DEFAULT;
#endif
  std::size_t min_steps = 400;
  std::string doc, only;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--min-steps" && i + 1 < argc) min_steps = static_cast<std::size_t>(std::stoul(argv[++i]));
    else if (a == "--only" && i + 1 < argc) only = argv[++i];
    else if (a == "--update-doc" && i + 1 < argc) doc = argv[++i];
    else dir = a;
  }
  if (dir.empty()) {
    std::fprintf(stderr, "usage: bench_zonotopic_cpp DATA_DIR [--min-steps N] [--only NAME] [--update-doc FILE]\n");
    return 2;
  }
  std::vector<Row> rows;
  const ZonotopeGain seg(segment_min_gain);
  for (const char* name : {"alamo2005_2d_cora_unittest", "vehicle2_cora_unittest", "pedestrian4", "vehicle6", "tank30"}) {
    if (!only.empty() && only != name) continue;
    const Benchmark b = load(dir + "/" + name + ".json", name);
    const ZonotopeReduction cora_red = reduction_of(b.reduction);
    const std::string key = b.golden.count("FRad-A") ? "FRad-A" : (b.golden.count("FRad-A [else]") ? "FRad-A [else]" : "");
    rows.push_back(run(b, "segment min. (FRad-A)", seg, cora_red, min_steps, key));
    if (cora_red != ZonotopeReduction::Combastel)
      rows.push_back(run(b, "segment min. (FRad-A)", seg, ZonotopeReduction::Combastel, min_steps, key));
    if (std::string(name) == "tank30")
      rows.push_back(run(b, "segment min., 20 steps", seg, cora_red, min_steps, "FRad-A [tFinal==10]", 20));
    // The P-radius estimator ([Le2013], papers.md §3.2): offline gains, the fixed-gain path of the same step.
    if (std::string(name) == "alamo2005_2d_cora_unittest" || std::string(name) == "vehicle6") {
      try {
        const PRadiusDesign d = design_pradius(*b.system);
        rows.push_back(run(b, "P-radius (approach 1)", pradius_gain(d), cora_red, min_steps, "", -1, d.strip_order));
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: P-radius design failed: %s\n", name, e.what());
      }
    }
  }
  std::string loadavg = "unknown";
  if (std::ifstream la("/proc/loadavg"); la) {
    std::string a, b, c;
    la >> a >> b >> c;
    loadavg = a + " " + b + " " + c;
  }
#if defined(__AVX512F__)
  const char* simd = "AVX-512";
#elif defined(__AVX2__)
  const char* simd = "AVX2";
#elif defined(__AVX__)
  const char* simd = "AVX";
#else
  const char* simd = "SSE2";
#endif
  std::ostringstream out;
  char when[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(when, sizeof when, "%Y-%m-%d", std::localtime(&now));
  out << "Generated by `bench/bench_zonotopic_cpp` on " << when << ", " << std::thread::hardware_concurrency()
      << " hardware threads, load average " << loadavg << " at the start, vectorised for " << simd
      << "; one `update()` per step timed with a steady clock, median over at least "
      << min_steps << " steps (whole horizons repeated). \"full\": median over the steps that ran the "
      << "reduction (the generator limit reached). \"box\": largest pending rounding box over the run, "
      << "relative to the largest radius of the set.\n\n"
      << "| data | n_x | method | reduction | limit | steps timed | median µs/step | p90 µs | full µs | "
         "final hull vs CORA | box |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows)
    out << "| " << r.data << " | " << r.n << " | " << r.method << " | " << r.reduction << " | " << r.limit << " | "
        << r.steps << " | " << fmt(r.median_us, "%.2f") << " | " << fmt(r.p90_us, "%.2f") << " | "
        << fmt(r.full_us, "%.2f") << " | " << fmt(r.diff, "%.1e") << " | " << fmt(r.box, "%.0e") << " |\n";
  std::printf("%s", out.str().c_str());
  if (!doc.empty()) {
    std::ifstream in(doc);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const std::string begin = "<!-- bench_zonotopic_cpp:begin -->", end = "<!-- bench_zonotopic_cpp:end -->";
    const std::string block = begin + "\n" + out.str() + end;
    const auto a = text.find(begin), e = text.find(end);
    if (a != std::string::npos && e != std::string::npos) text.replace(a, e + end.size() - a, block);
    else text += "\n## C++ per-step times\n\n" + block + "\n";
    std::ofstream(doc) << text;
  }
  return 0;
}
