// setbound — thesis Chapter 1 invariant sets (Loukkas 2018, §1.3.3; spec thesis.md §3.3–3.6):
//   ellipsoid_bounding_box               (Def 1.5, eq 1.40)
//   expanded_ellipsoid_levels            (eqs 1.57–1.58: c_out and c_in of Ψ̄(μ) and Ψ̄⁺(μ))
//   polyhedral_rpi_between_ellipsoids    (§3.5 [reconstructed]: Ψ̄⁺ ⊆ Φ_v ⊆ Ψ̄)
//   contraction_rate                     (β: smallest β with AᵀPA ≼ β²P)
//   mrpi_outer_shrinking / mrpi_outer_shrinking_boxes   (Algorithm 1, eqs 1.59–1.72)
// See docs/thesis_invariant.md for the guarantees, assumptions and costs.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/polytope.hpp"

namespace setbound::thesis {

/// Options of polyhedral_rpi_between_ellipsoids.
struct PolyhedralRpiOptions {
  /// Upper bound on the number of vertices of Φ_v; exceeding it throws InfeasibleError
  /// (c_in/c_out too close to 1 for this dimension: choose a larger μ).
  int max_vertices = 10000;
};

namespace detail {

inline void require_levels(double c_in, double c_out) {
  require_finite(c_in, "c_in");
  require_finite(c_out, "c_out");
  if (!(c_in > 0)) {
    std::ostringstream s;
    s << "c_in: the inner level must be > 0, got " << c_in;
    throw InvalidArgumentError(s.str());
  }
  if (!(c_out > c_in)) {
    std::ostringstream s;
    s << "c_out: the outer level must be > c_in (" << c_in << "), got " << c_out;
    throw InvalidArgumentError(s.str());
  }
}

/// Symmetric square root T = P^{1/2} and its inverse (P symmetric positive definite).
inline void sqrt_and_inverse(const Eigen::MatrixXd& P, Eigen::MatrixXd& T, Eigen::MatrixXd& Tinv) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(P);
  const Eigen::VectorXd s = es.eigenvalues().cwiseSqrt();
  T = es.eigenvectors() * s.asDiagonal() * es.eigenvectors().transpose();
  Tinv = es.eigenvectors() * s.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace detail

/// Levels of the expanded ellipsoid Ψ̄(μ) and of its one-step image Ψ̄⁺(μ) (eqs 1.57–1.58):
///   c_out = μ·λ_max(P)·γ²·w̄ᵀw̄,   c_in = (μ·λ_max(P) − μ + 1)·γ²·w̄ᵀw̄,   μ > 1.
/// P is the BRL matrix (§3.4), gamma the BRL γ, wbar_sq = w̄ᵀw̄ = Σ w̄_i².
struct EllipsoidLevels {
  double c_in = 0;
  double c_out = 0;
};
inline EllipsoidLevels expanded_ellipsoid_levels(const Eigen::MatrixXd& P, double gamma,
                                                 double wbar_sq, double mu) {
  require_positive_definite(P, "P");
  require_finite(gamma, "gamma");
  require_finite(wbar_sq, "wbar_sq");
  require_finite(mu, "mu");
  if (!(gamma > 0)) throw InvalidArgumentError("gamma: must be > 0, got " + std::to_string(gamma));
  if (!(wbar_sq > 0))
    throw InvalidArgumentError("wbar_sq: must be > 0, got " + std::to_string(wbar_sq));
  if (!(mu > 1))
    throw InvalidArgumentError("mu: must be > 1 (for mu = 1 the two ellipsoids coincide), got " +
                               std::to_string(mu));
  const double lmax = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P, Eigen::EigenvaluesOnly)
                          .eigenvalues()
                          .maxCoeff();
  EllipsoidLevels L;
  L.c_out = mu * lmax * gamma * gamma * wbar_sq;
  L.c_in = (mu * lmax - mu + 1.0) * gamma * gamma * wbar_sq;
  return L;
}

/// §3.5 [reconstructed]: a polytope Φ_v with {xᵀPx ≤ c_in} ⊆ Φ_v ⊆ {xᵀPx ≤ c_out}, c_in < c_out.
///   Whitening z = P^{1/2}x turns both ellipsoids into balls of radii r_in = √c_in, r_out = √c_out.
///   n = 1: the interval; n = 2: a regular N-gon with vertices on the outer circle; n ≥ 3: the
///   polar (V-rep) form of the spec's cutting-plane loop: start from the cross-polytope ±R·e_i,
///   and while a facet of the hull is closer to the origin than r_in add the outer-sphere points
///   ±R·u at its unit normal u; repeat. A margin of min(1e-6, 1 % of the relative gap) is kept on both sides so that the
///   result is certified in floating point: the function checks vᵀPv ≤ c_out for every vertex
///   and √(c_in·hᵀP⁻¹h) ≤ b for every facet of the returned H-rep, and throws NumericalError if
///   either fails (P too ill-conditioned). The polytope is symmetric about the origin.
/// Throws on: P not symmetric positive definite ("P: ..."), c_in ≤ 0 or c_out ≤ c_in, more
/// more vertices than opt.max_vertices (InfeasibleError).
inline Polytope polyhedral_rpi_between_ellipsoids(const Eigen::MatrixXd& P, double c_in,
                                                  double c_out,
                                                  const PolyhedralRpiOptions& opt = {}) {
  if (P.rows() < 1) throw DimensionError("P: must be at least 1x1");
  require_positive_definite(P, "P");
  detail::require_levels(c_in, c_out);
  const Eigen::Index n = P.rows();
  const Eigen::MatrixXd Ps = 0.5 * (P + P.transpose());
  Eigen::MatrixXd T, Tinv;
  detail::sqrt_and_inverse(Ps, T, Tinv);
  const double r_in = std::sqrt(c_in), r_out = std::sqrt(c_out);
  const double margin = std::min(1e-6, 0.01 * (1.0 - r_in / r_out));
  const double rho = r_in * (1.0 + margin);    // cut offset (> r_in)
  const double R = r_out * (1.0 - margin);     // vertex radius bound (< r_out)

  Eigen::MatrixXd Vz;  // vertices in z coordinates
  if (n == 1) {
    Vz.resize(1, 2);
    Vz << -rho, rho;
  } else if (n == 2) {
    const double pi = 3.14159265358979323846;
    int N = std::max(3, static_cast<int>(std::ceil(pi / std::acos(rho / R))));
    while (R * std::cos(pi / N) < rho) ++N;
    if (N > opt.max_vertices)
      throw InfeasibleError("c_out: c_in/c_out is too close to 1 (a " + std::to_string(N) +
                            "-gon would be needed, more than max_vertices); choose a larger mu");
    Vz.resize(2, N);
    for (int k = 0; k < N; ++k) {
      const double a = 2.0 * pi * k / N;
      Vz(0, k) = R * std::cos(a);
      Vz(1, k) = R * std::sin(a);
    }
  } else {
    // Dual (V-rep) form of the cutting-plane construction: vertices on the sphere of radius R
    // (so Φ ⊆ outer ball by convexity); while a facet is closer to the origin than ρ, add the
    // point R·u at its outward normal u, which lies beyond that facet. On exit every facet is at
    // distance ≥ ρ > r_in (inner ball ⊆ Φ). Only forward hulls of points are needed (robust in
    // Qhull up to n = 6, unlike vertex enumeration of many near-tangent cuts).
    std::vector<Eigen::VectorXd> pts;
    for (Eigen::Index i = 0; i < n; ++i) {
      pts.push_back(R * Eigen::VectorXd::Unit(n, i));
      pts.push_back(-R * Eigen::VectorXd::Unit(n, i));
    }
    for (;;) {
      if (static_cast<int>(pts.size()) > opt.max_vertices)
        throw InfeasibleError("c_out: c_in/c_out is too close to 1 for dimension " + std::to_string(n) +
                              " (more than max_vertices = " + std::to_string(opt.max_vertices) +
                              " vertices needed); choose a larger mu");
      Eigen::MatrixXd Vc(n, static_cast<Eigen::Index>(pts.size()));
      for (std::size_t i = 0; i < pts.size(); ++i) Vc.col(static_cast<Eigen::Index>(i)) = pts[i];
      Polytope Pz;
      try {
        Pz = Polytope::from_vertices(Vc, "polyhedral RPI points");
      } catch (const std::bad_alloc&) {
        throw InfeasibleError("c_out: c_in/c_out is too close to 1 for dimension " + std::to_string(n) +
                              " (the hull ran out of memory); choose a larger mu");
      }
      std::vector<std::pair<double, Eigen::Index>> close;
      for (Eigen::Index f = 0; f < Pz.num_facets(); ++f)
        if (Pz.b()(f) < rho) close.emplace_back(Pz.b()(f), f);
      if (close.empty()) {
        Vz = Pz.vertices();
        break;
      }
      std::sort(close.begin(), close.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      std::vector<Eigen::VectorXd> added;
      for (const auto& c : close) {
        const Eigen::VectorXd u = Pz.H().row(c.second).transpose();
        bool destroyed = false;  // a point added this round already lies beyond this facet
        for (const auto& a : added)
          if (u.dot(a) > c.first) { destroyed = true; break; }
        if (destroyed) continue;
        added.push_back(R * u);
        added.push_back(-R * u);
      }
      pts.insert(pts.end(), added.begin(), added.end());
    }
  }
  Polytope Phi = Polytope::from_vertices(Tinv * Vz, "polyhedral RPI");
  // Certification in x coordinates.
  const Eigen::MatrixXd& V = Phi.vertices();
  for (Eigen::Index j = 0; j < V.cols(); ++j) {
    const double q = V.col(j).dot(Ps * V.col(j));
    if (!(q <= c_out))
      throw NumericalError("P: a vertex of the polytope lies outside {x'Px <= c_out} after rounding "
                           "(P is too ill-conditioned)");
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(Ps);
  const Eigen::MatrixXd Pinv = llt.solve(Eigen::MatrixXd::Identity(n, n));
  for (Eigen::Index i = 0; i < Phi.num_facets(); ++i) {
    const Eigen::VectorXd h = Phi.H().row(i).transpose();
    const double supp = std::sqrt(c_in * h.dot(Pinv * h));
    if (!(supp <= Phi.b()(i)))
      throw NumericalError("P: a facet of the polytope cuts {x'Px <= c_in} after rounding "
                           "(P is too ill-conditioned)");
  }
  return Phi;
}

}  // namespace setbound::thesis
