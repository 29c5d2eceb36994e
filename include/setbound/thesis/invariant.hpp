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
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/ellipsoid.hpp"
#include "setbound/sets/interval_matrix.hpp"
#include "setbound/sets/polytope.hpp"
#include "setbound/thesis/hinf_gain.hpp"

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
    if (N % 2 == 1) ++N;  // even: the polygon is symmetric about the origin
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

/// Def 1.5 / eq 1.40: the tightest axis-aligned box around {x : (x−c)ᵀP(x−c) ≤ ρ},
/// c ± sqrt(diag(ρP⁻¹)) (half-widths rounded outward by Ellipsoid::box_inflation). Each bound is
/// attained at x* = c ± √ρ·P⁻¹e_i/√((P⁻¹)_ii). The thesis's printed box of Ex 1.3/1.4 used diag(P)
/// and is wrong (spec §3.3).
inline Box ellipsoid_bounding_box(const Eigen::MatrixXd& P, const Eigen::VectorXd& c, double rho) {
  require_finite(rho, "rho");
  if (!(rho > 0)) throw InvalidArgumentError("rho: the level must be > 0, got " + std::to_string(rho));
  const Ellipsoid e(P, c, rho);
  const BoundingBox bb = e.bounding_box();
  return Box(bb.lo, bb.hi, "ellipsoid box");
}

/// β = the smallest β ≥ 0 with AᵀPA ≼ β²P, i.e. sqrt(λ_max of the pair (AᵀPA, P)) (eq 1.67–1.69).
/// Then ‖A x‖_P ≤ β‖x‖_P, so A^kΨ ⊆ β^kΨ for every P-level set Ψ. The value is rounded up by a
/// relative 1e-10 (it is computed from an eigenvalue problem). Throws when A is not square/finite
/// ("A: ..."), P not symmetric positive definite ("P: ...").
inline double contraction_rate(const Eigen::MatrixXd& A, const Eigen::MatrixXd& P) {
  require_square(A, "A");
  require_finite(A, "A");
  require_positive_definite(P, "P");
  if (P.rows() != A.rows())
    throw DimensionError("P: expected " + std::to_string(A.rows()) + "x" + std::to_string(A.rows()) +
                         " (the size of A), got " + std::to_string(P.rows()) + "x" + std::to_string(P.cols()));
  const Eigen::MatrixXd Ps = 0.5 * (P + P.transpose());
  const Eigen::LLT<Eigen::MatrixXd> llt(Ps);
  // P = UᵀU (Cholesky). With y = Ux: ‖Ax‖_P/‖x‖_P = ‖U A U⁻¹ y‖/‖y‖, so β = ‖U A U⁻¹‖₂.
  const Eigen::MatrixXd U = llt.matrixU();
  const Eigen::MatrixXd M =
      U * A * U.triangularView<Eigen::Upper>().solve(Eigen::MatrixXd::Identity(A.rows(), A.rows()));
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M);
  return svd.singularValues()(0) * (1.0 + 1e-10);
}

/// Stop rules of Algorithm 1 (ε is always a RADIUS: 𝔹(ε) = {x : ‖x‖₂ ≤ ε}).
enum class MrpiStopRule {
  /// [reconstructed, rigorous] β^k·sqrt(c_out/λ_min(P)) ≤ ε, which implies A^kΦ_0 ⊆ 𝔹(ε).
  Radius,
  /// Ex 1.5: the shrinking index ρ̄_k = β^k·sqrt(μ·λ_max(P)/λ_min(P)) ≤ ε (relative precision).
  ShrinkingIndex,
  /// [proposed] max over the vertices v of Φ_0 of ‖A^k v‖₂ ≤ ε: exact for A^kΦ_0 ⊆ 𝔹(ε).
  VertexNorm,
};

struct MrpiOptions {
  MrpiStopRule stop = MrpiStopRule::Radius;
  /// μ of the shrinking index ρ̄_k (reporting; and the ShrinkingIndex stop rule).
  double mu = 1.0;
  /// k* larger than this throws InfeasibleError.
  int max_iterations = 500;
};

/// Result of Algorithm 1. Index k runs over 0…k*.
struct MrpiShrinking {
  std::vector<Polytope> sets;            // Φ_k (empty in the box-only variant)
  std::vector<Box> boxes;                // [Φ_k] = box(A^kΦ_0) + Σ_{i<k} box(A^iEΔ), outward rounded
  std::vector<double> radius_bound;      // β^k·sqrt(c_out/λ_min(P)) ≥ max ‖A^kΦ_0‖
  std::vector<double> vertex_radius;     // max_v ‖A^k v‖ over the vertices of Φ_0 (exact radius)
  std::vector<double> shrinking_index;   // ρ̄_k = β^k·sqrt(μ·λ_max(P)/λ_min(P))
  int k_star = 0;
  double beta = 0;
};

namespace detail {

inline void check_mrpi_inputs(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Box& delta,
                              const Polytope& Phi0, const Eigen::MatrixXd& P, double c_out,
                              double eps, const MrpiOptions& opt) {
  require_square(A, "A");
  require_finite(A, "A");
  const Eigen::Index n = A.rows();
  if (n < 1) throw DimensionError("A: must be at least 1x1");
  if (E.rows() != n)
    throw DimensionError("E: expected " + std::to_string(n) + " rows (the size of A), got " +
                         std::to_string(E.rows()));
  require_finite(E, "E");
  if (delta.size() != E.cols())
    throw DimensionError("delta: expected " + std::to_string(E.cols()) +
                         " components (the columns of E), got " + std::to_string(delta.size()));
  if (delta.is_empty()) throw InvalidArgumentError("delta: the disturbance box is empty");
  if (!delta.lo().allFinite() || !delta.hi().allFinite())
    throw InvalidArgumentError("delta: the disturbance box must be bounded");
  if ((delta.lo().array() > 0).any() || (delta.hi().array() < 0).any())
    throw InvalidArgumentError("delta: the disturbance box must contain 0");
  if (Phi0.dimension() != n)
    throw DimensionError("Phi0: expected dimension " + std::to_string(n) + ", got " +
                         std::to_string(Phi0.dimension()));
  require_positive_definite(P, "P");
  if (P.rows() != n) throw DimensionError("P: expected " + std::to_string(n) + "x" + std::to_string(n));
  require_finite(c_out, "c_out");
  if (!(c_out > 0)) throw InvalidArgumentError("c_out: must be > 0");
  require_finite(eps, "eps");
  if (!(eps > 0)) throw InvalidArgumentError("eps: the stop radius must be > 0, got " + std::to_string(eps));
  require_finite(opt.mu, "mu");
  if (!(opt.mu >= 1)) throw InvalidArgumentError("mu: must be >= 1, got " + std::to_string(opt.mu));
  if (opt.max_iterations < 1) throw InvalidArgumentError("max_iterations: must be >= 1");
  const Eigen::MatrixXd& V = Phi0.vertices();
  for (Eigen::Index j = 0; j < V.cols(); ++j)
    if (!(V.col(j).dot(P * V.col(j)) <= c_out))
      throw InvalidArgumentError("Phi0: vertex " + std::to_string(j) +
                                 " lies outside {x'Px <= c_out}; Phi0 must be inside the outer ellipsoid");
}

/// The scalar sequences and k*; fills everything but sets/boxes.
inline MrpiShrinking mrpi_schedule(const Eigen::MatrixXd& A, const Polytope& Phi0, const Eigen::MatrixXd& P,
                                   double c_out, double eps, const MrpiOptions& opt) {
  MrpiShrinking r;
  r.beta = contraction_rate(A, P);
  if (!(r.beta < 1.0)) {
    std::ostringstream s;
    s << "A: not contractive in the P-norm (beta = " << r.beta
      << " >= 1): A must be Schur stable and P a Lyapunov matrix of A (the BRL P)";
    throw InvalidArgumentError(s.str());
  }
  const Eigen::VectorXd ev =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (P + P.transpose()), Eigen::EigenvaluesOnly).eigenvalues();
  const double lmin = ev.minCoeff(), lmax = ev.maxCoeff();
  const double r0 = std::sqrt(c_out / lmin);
  const double s0 = std::sqrt(opt.mu * lmax / lmin);
  Eigen::MatrixXd Vk = Phi0.vertices();
  double bk = 1.0;
  for (int k = 0;; ++k) {
    r.radius_bound.push_back(bk * r0);
    r.shrinking_index.push_back(bk * s0);
    r.vertex_radius.push_back(Vk.colwise().norm().maxCoeff());
    if (k >= 1) {
      const double crit = opt.stop == MrpiStopRule::Radius ? r.radius_bound.back()
                          : opt.stop == MrpiStopRule::ShrinkingIndex ? r.shrinking_index.back()
                                                                     : r.vertex_radius.back();
      if (crit <= eps) {
        r.k_star = k;
        break;
      }
    }
    if (k >= opt.max_iterations) {
      std::ostringstream s;
      s << "eps: the stop rule is not met within max_iterations = " << opt.max_iterations
        << " (beta = " << r.beta << "); increase eps or max_iterations";
      throw InfeasibleError(s.str());
    }
    bk *= r.beta;
    Vk = A * Vk;
  }
  return r;
}

/// [Φ_k] for k = 0…K (rigorous, outward rounded): box(A^kΦ_0) + Σ_{i<k} box(A^iEΔ), with the
/// powers A^k kept as interval matrices.
inline std::vector<Box> mrpi_boxes(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Box& delta,
                                   const Polytope& Phi0, int K) {
  const Eigen::Index n = A.rows();
  std::vector<Box> out;
  IntervalMatrix Ak = IntervalMatrix::point(Eigen::MatrixXd::Identity(n, n));
  Box omega = Box::point(Eigen::VectorXd::Zero(n));  // Ω_k hull
  const Eigen::MatrixXd& V = Phi0.vertices();
  for (int k = 0; k <= K; ++k) {
    Box img = Box::empty(n);
    for (Eigen::Index j = 0; j < V.cols(); ++j) {
      const Box b = Ak * Eigen::VectorXd(V.col(j));
      img = img.hull(b);
    }
    out.push_back(img + omega);
    omega = omega + (Ak * E) * delta;   // add box(A^kEΔ)
    Ak = Ak * A;
  }
  return out;
}

/// Corners of the box Δ mapped by E (columns), deduplicated for zero-width components.
inline Eigen::MatrixXd mapped_corners(const Eigen::MatrixXd& E, const Box& delta) {
  std::vector<Eigen::Index> var;
  for (Eigen::Index i = 0; i < delta.size(); ++i)
    if (delta.hi()(i) > delta.lo()(i)) var.push_back(i);
  if (var.size() > 16) throw InvalidArgumentError("delta: more than 16 non-degenerate components");
  const Eigen::Index p = Eigen::Index(1) << var.size();
  Eigen::MatrixXd D(delta.size(), p);
  for (Eigen::Index k = 0; k < p; ++k) {
    D.col(k) = delta.lo();
    for (std::size_t t = 0; t < var.size(); ++t)
      if ((k >> t) & 1) D(var[t], k) = delta.hi()(var[t]);
  }
  return E * D;
}

}  // namespace detail

/// The box-only variant (for Ch. 4): same schedule and k*, boxes [Φ_k] only (no polytope hulls;
/// cost O(k*·(p + m)·n²) with p the vertex count of Φ_0).
inline MrpiShrinking mrpi_outer_shrinking_boxes(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                                const Box& delta, const Polytope& Phi0,
                                                const Eigen::MatrixXd& P, double c_out, double eps,
                                                const MrpiOptions& opt = {}) {
  detail::check_mrpi_inputs(A, E, delta, Phi0, P, c_out, eps, opt);
  MrpiShrinking r = detail::mrpi_schedule(A, Phi0, P, c_out, eps, opt);
  r.boxes = detail::mrpi_boxes(A, E, delta, Phi0, r.k_star);
  return r;
}

/// Algorithm 1 (eqs 1.59–1.72) from a given Φ_0 (usually polyhedral_rpi_between_ellipsoids):
///   Φ_{k+1} = AΦ_k ⊕ EΔ (V-rep: all sums A v_i + E d_j over the corners d_j of Δ, then a Qhull
///   hull), until the stop rule holds (k* ≥ 1). P is the BRL matrix of A (§3.4), c_out the level
///   of the outer ellipsoid Ψ̄ ⊇ Φ_0 (checked), eps a RADIUS (see MrpiStopRule).
/// Guarantees (exact arithmetic; the boxes are also rigorous under rounding): Φ_{k+1} ⊆ Φ_k when
/// Φ_0 is RPI; each Φ_k is RPI; Ω_k ⊆ Φ_k; A^{k*}Φ_0 ⊆ 𝔹(eps) for the Radius and VertexNorm rules.
/// Throws: shapes/NaN ("A", "E", "delta", "Phi0", "P"), delta empty/unbounded/not containing 0,
/// eps ≤ 0, β ≥ 1 (A not Schur or P not a Lyapunov matrix), k* > max_iterations.
inline MrpiShrinking mrpi_outer_shrinking(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                          const Box& delta, const Polytope& Phi0,
                                          const Eigen::MatrixXd& P, double c_out, double eps,
                                          const MrpiOptions& opt = {}) {
  MrpiShrinking r = mrpi_outer_shrinking_boxes(A, E, delta, Phi0, P, c_out, eps, opt);
  const Eigen::MatrixXd W = detail::mapped_corners(E, delta);
  r.sets.reserve(static_cast<std::size_t>(r.k_star) + 1);
  r.sets.push_back(Phi0);
  for (int k = 1; k <= r.k_star; ++k) {
    const Eigen::MatrixXd AV = A * r.sets.back().vertices();
    Eigen::MatrixXd S(AV.rows(), AV.cols() * W.cols());
    for (Eigen::Index j = 0; j < W.cols(); ++j) S.middleCols(j * AV.cols(), AV.cols()) = AV.colwise() + W.col(j);
    r.sets.push_back(Polytope::from_vertices(S, "Phi_" + std::to_string(k)));
  }
  return r;
}

/// Everything Algorithm 1 computes from the data.
struct MrpiDesign {
  BrlRpi brl;              // step 1: P and the minimum γ of LMI (1.48)
  EllipsoidLevels levels;  // c_in, c_out of Ψ̄⁺(μ), Ψ̄(μ) (1.57–1.58)
  double mu = 0;
  Polytope phi_v;          // step 2: Ψ̄⁺ ⊆ Φ_v ⊆ Ψ̄
  MrpiShrinking shrinking; // steps 3–5 (shrinking.sets.back() = Φ_{k*})
};

/// Algorithm 1 from the data: x⁺ = A x + E w with |w_i| ≤ wbar_i (Δ = [−w̄, w̄]); BRL (1.48),
/// Φ_v between Ψ̄⁺(μ) and Ψ̄(μ) (μ > 1), then the shrinking iteration with stop radius eps.
/// opt.mu is overwritten by mu (the shrinking index uses the μ of the construction). With
/// boxes_only = true the polytopes Φ_k (k ≥ 1) are not built.
inline MrpiDesign mrpi_outer_shrinking(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                       const Eigen::VectorXd& wbar, double mu, double eps,
                                       MrpiOptions opt = {}, bool boxes_only = false,
                                       const PolyhedralRpiOptions& popt = {},
                                       const HinfOptions& hopt = {}) {
  require_finite(mu, "mu");
  if (!(mu > 1)) throw InvalidArgumentError("mu: must be > 1 (for mu = 1 the two ellipsoids coincide), got " + std::to_string(mu));
  require_finite(eps, "eps");
  if (!(eps > 0)) throw InvalidArgumentError("eps: the stop radius must be > 0, got " + std::to_string(eps));
  MrpiDesign d;
  d.brl = brl_ellipsoidal_rpi(A, E, wbar, hopt);
  if (!(d.brl.g > 0)) throw InvalidArgumentError("wbar: gamma is 0 (E w is identically zero)");
  d.mu = mu;
  d.levels = expanded_ellipsoid_levels(d.brl.P, std::sqrt(d.brl.g), wbar.squaredNorm(), mu);
  d.phi_v = polyhedral_rpi_between_ellipsoids(d.brl.P, d.levels.c_in, d.levels.c_out, popt);
  opt.mu = mu;
  const Box delta(-wbar, wbar, "wbar");
  d.shrinking = boxes_only ? mrpi_outer_shrinking_boxes(A, E, delta, d.phi_v, d.brl.P, d.levels.c_out, eps, opt)
                           : mrpi_outer_shrinking(A, E, delta, d.phi_v, d.brl.P, d.levels.c_out, eps, opt);
  return d;
}

}  // namespace setbound::thesis
