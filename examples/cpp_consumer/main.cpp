// A downstream program using an installed setbound two ways: the header-heavy C++ API and
// the C ABI of libsetbound. Exits non-zero if anything disagrees (the test suite runs it).
// It includes only the headers it uses (the umbrella <setbound/setbound.hpp> works too, and the
// C++ tests compile it, but parsing every header costs a minute of compile time).
extern "C" {
#include <setbound/setbound.h>
}
#include <setbound/sets/ellipsoid.hpp>
#include <setbound/sets/zonotope.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>

int main() {
  std::printf("setbound %s (ABI %d)\n", sb_version(), sb_abi_version());

  // C++ API: one prediction step x+ = A x + w of a zonotope (papers.md §3.1), its hull.
  Eigen::Matrix2d A;
  A << 0.0, -0.5, 1.0, 1.0;
  Eigen::MatrixXd Fw(2, 1);
  Fw << -0.12, 0.02;
  const setbound::Zonotope X0(Eigen::Vector2d::Zero(), 3.0 * Eigen::Matrix2d::Identity());
  const setbound::Zonotope W(Eigen::Vector2d::Zero(), Fw);
  const setbound::Zonotope X1 = X0.linear_map(A) + W;
  const auto hull = X1.interval_hull();
  std::printf("x1 in [%.4f, %.4f] x [%.4f, %.4f]\n", hull.lo(0), hull.hi(0), hull.lo(1), hull.hi(1));

  // C ABI: the same volume through sb_zonotope_volume (generators in row-major order).
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMatrix H = X1.generators();
  double volume_c = 0.0;
  if (sb_zonotope_volume(2, static_cast<int>(H.cols()), X1.center().data(), H.data(), &volume_c) != SB_OK) {
    std::printf("sb_zonotope_volume failed: %s\n", sb_last_error());
    return 1;
  }
  const double volume_cpp = X1.volume();
  std::printf("volume: C++ %.6f, C ABI %.6f\n", volume_cpp, volume_c);
  if (std::abs(volume_c - volume_cpp) > 1e-12 * volume_cpp) return 1;

  // Errors: C++ throws a typed exception, the C ABI returns a status and a message.
  const double P_bad[4] = {1.0, 2.0, 2.0, 1.0};  // symmetric, indefinite
  const double c[2] = {0.0, 0.0};
  double lo[2], hi[2];
  const int rc = sb_ellipsoid_bounding_box(2, P_bad, c, 1.0, lo, hi);
  std::printf("indefinite P -> status %d (%s): %s\n", rc, sb_status_name(rc), sb_last_error());
  if (rc != SB_ERR_NOT_POSITIVE_DEFINITE || std::strstr(sb_last_error(), "P") == nullptr) return 1;
  try {
    setbound::Ellipsoid bad(Eigen::Map<const Eigen::Matrix2d>(P_bad), Eigen::Vector2d::Zero(), 1.0);
    return 1;
  } catch (const setbound::NotPositiveDefiniteError& e) {
    std::printf("C++: %s\n", e.what());
  }
  std::printf("consumer ok\n");
  return 0;
}
