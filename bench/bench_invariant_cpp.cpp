// Design/computation times of the thesis Chapter 1 invariant-set methods
// (include/setbound/thesis/invariant.hpp): BRL (1.48), Φ_v (§3.5), Algorithm 1 with polytopes and
// box-only, on Example 1.5 and a fixed 4-D system. Prints a markdown table (median of repeats).
//
//   cmake -DSETBOUND_BUILD_BENCH=ON ... && ./bench_invariant_cpp [repeats]
#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "bench_stats.hpp"
#include "setbound/thesis/invariant.hpp"

using namespace setbound;

namespace {

double median_seconds(const std::function<void()>& f, int repeats) {
  std::vector<double> t;
  for (int r = 0; r < repeats; ++r) {
    const auto a = std::chrono::steady_clock::now();
    f();
    const auto b = std::chrono::steady_clock::now();
    t.push_back(std::chrono::duration<double>(b - a).count());
  }
  return setbound_bench::median(std::move(t));
}

void row(const std::string& what, const std::string& detail, double s) {
  if (s < 1e-3)
    std::printf("| %s | %s | %.1f µs |\n", what.c_str(), detail.c_str(), s * 1e6);
  else
    std::printf("| %s | %s | %.2f ms |\n", what.c_str(), detail.c_str(), s * 1e3);
}

void bench_case(const std::string& name, const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                const Eigen::VectorXd& wbar, double mu, double eps, int repeats) {
  const thesis::BrlRpi brl = thesis::brl_ellipsoidal_rpi(A, E, wbar);
  const auto lv = thesis::expanded_ellipsoid_levels(brl.P, std::sqrt(brl.g), wbar.squaredNorm(), mu);
  const Polytope phi = thesis::polyhedral_rpi_between_ellipsoids(brl.P, lv.c_in, lv.c_out);
  const Box delta(-wbar, wbar);
  const auto full = thesis::mrpi_outer_shrinking(A, E, delta, phi, brl.P, lv.c_out, eps);
  char info[200];
  std::snprintf(info, sizeof info, "n = %d, m = %d, μ = %g, ε = %g: γ = %.6g, |Φ_v| = %d vertices, k* = %d, |Φ_k*| = %d vertices",
                int(A.rows()), int(E.cols()), mu, eps, brl.gamma, int(phi.num_vertices()), full.k_star,
                int(full.sets.back().num_vertices()));
  std::printf("\n%s (%s)\n\n| step | detail | median time |\n|---|---|---|\n", name.c_str(), info);
  row("BRL LMI (1.48)", "brl_ellipsoidal_rpi", median_seconds([&] { thesis::brl_ellipsoidal_rpi(A, E, wbar); }, repeats));
  row("Φ_v (§3.5)", "polyhedral_rpi_between_ellipsoids",
      median_seconds([&] { thesis::polyhedral_rpi_between_ellipsoids(brl.P, lv.c_in, lv.c_out); }, repeats));
  row("Algorithm 1, polytopes", "mrpi_outer_shrinking (given Φ_v, P)",
      median_seconds([&] { thesis::mrpi_outer_shrinking(A, E, delta, phi, brl.P, lv.c_out, eps); }, repeats));
  row("Algorithm 1, boxes only", "mrpi_outer_shrinking_boxes (given Φ_v, P)",
      median_seconds([&] { thesis::mrpi_outer_shrinking_boxes(A, E, delta, phi, brl.P, lv.c_out, eps); }, repeats));
  row("Algorithm 1, everything", "BRL + Φ_v + polytopes",
      median_seconds([&] { thesis::mrpi_outer_shrinking(A, E, wbar, mu, eps); }, repeats));
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 15;
  std::printf("# bench_invariant_cpp (median of %d runs)\n", repeats);
  Eigen::MatrixXd A(2, 2), E(2, 1);
  A << 0.2, 0.2, -0.2, 0.5;
  E << 0, 1;
  bench_case("Example 1.5", A, E, Eigen::VectorXd::Ones(1), 1.2, 1e-3, repeats);
  bench_case("Example 1.5", A, E, Eigen::VectorXd::Ones(1), 2.0, 1e-3, repeats);
  Eigen::MatrixXd A4(4, 4), E4(4, 2);
  A4 << 0.3, 0.2, -0.1, 0.0,
        -0.2, 0.4, 0.1, 0.1,
        0.0, -0.1, 0.2, 0.3,
        0.1, 0.0, -0.2, 0.1;
  E4 << 1, 0, 0, 0.5, 0.2, 0, 0, 1;
  bench_case("4-D system", A4, E4, Eigen::Vector2d(1.0, 0.5), 2.0, 0.05, repeats);
  // Φ_v alone for growing dimension (P = I, c_out/c_in = 1.5)
  std::printf("\nΦ_v alone, P = I, c_out/c_in = 1.5\n\n| n | vertices | facets | median time |\n|---|---|---|---|\n");
  for (int n = 2; n <= 5; ++n) {
    const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n);
    const Polytope p = thesis::polyhedral_rpi_between_ellipsoids(P, 1.0, 1.5);
    const double s = median_seconds([&] { thesis::polyhedral_rpi_between_ellipsoids(P, 1.0, 1.5); }, std::max(3, repeats / 3));
    std::printf("| %d | %d | %d | %.3f ms |\n", n, int(p.num_vertices()), int(p.num_facets()), s * 1e3);
  }
  // the size that Chapter 4's Ex 4.5.2 asks for: μ = 2 and λ_max(P) ≈ 22.6 give c_out/c_in ≈ 1.0226
  std::printf("\nΦ_v alone, n = 4, c_out/c_in = 1.0226 (Ex 4.5.2's levels with μ = 2)\n\n");
  {
    const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(4, 4);
    const auto a = std::chrono::steady_clock::now();
    try {
      const Polytope p = thesis::polyhedral_rpi_between_ellipsoids(P, 1.0, 1.0226);
      const auto b = std::chrono::steady_clock::now();
      std::printf("%d vertices, %d facets, %.1f ms (one run)\n", int(p.num_vertices()), int(p.num_facets()),
                  std::chrono::duration<double>(b - a).count() * 1e3);
    } catch (const std::exception& e) {
      std::printf("failed: %s\n", e.what());
    }
  }
  return 0;
}
