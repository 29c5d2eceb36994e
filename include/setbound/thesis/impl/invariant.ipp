// setbound — definitions of the functions declared in setbound/thesis/invariant.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/invariant.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace thesis {
namespace detail {

SETBOUND_INLINE void require_levels(double c_in, double c_out) {
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

SETBOUND_INLINE void sqrt_and_inverse(const Eigen::MatrixXd& P, Eigen::MatrixXd& T, Eigen::MatrixXd& Tinv) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(P);
  const Eigen::VectorXd s = es.eigenvalues().cwiseSqrt();
  T = es.eigenvectors() * s.asDiagonal() * es.eigenvectors().transpose();
  Tinv = es.eigenvectors() * s.cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace detail
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

SETBOUND_INLINE EllipsoidLevels expanded_ellipsoid_levels(const Eigen::MatrixXd& P, double gamma,
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

SETBOUND_INLINE Polytope polyhedral_rpi_between_ellipsoids(const Eigen::MatrixXd& P, double c_in,
                                                  double c_out,
                                                  const PolyhedralRpiOptions& opt) {
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

SETBOUND_INLINE Box ellipsoid_bounding_box(const Eigen::MatrixXd& P, const Eigen::VectorXd& c, double rho) {
  require_finite(rho, "rho");
  if (!(rho > 0)) throw InvalidArgumentError("rho: the level must be > 0, got " + std::to_string(rho));
  const Ellipsoid e(P, c, rho);
  const BoundingBox bb = e.bounding_box();
  return Box(bb.lo, bb.hi, "ellipsoid box");
}

SETBOUND_INLINE double contraction_rate(const Eigen::MatrixXd& A, const Eigen::MatrixXd& P) {
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

}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {
namespace detail {

SETBOUND_INLINE void check_mrpi_inputs(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Box& delta,
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

SETBOUND_INLINE MrpiShrinking mrpi_schedule(const Eigen::MatrixXd& A, const Polytope& Phi0, const Eigen::MatrixXd& P,
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

SETBOUND_INLINE std::vector<Box> mrpi_boxes(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Box& delta,
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

SETBOUND_INLINE Eigen::MatrixXd mapped_corners(const Eigen::MatrixXd& E, const Box& delta) {
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
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

SETBOUND_INLINE MrpiShrinking mrpi_outer_shrinking_boxes(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                                const Box& delta, const Polytope& Phi0,
                                                const Eigen::MatrixXd& P, double c_out, double eps,
                                                const MrpiOptions& opt) {
  detail::check_mrpi_inputs(A, E, delta, Phi0, P, c_out, eps, opt);
  MrpiShrinking r = detail::mrpi_schedule(A, Phi0, P, c_out, eps, opt);
  r.boxes = detail::mrpi_boxes(A, E, delta, Phi0, r.k_star);
  return r;
}

SETBOUND_INLINE MrpiShrinking mrpi_outer_shrinking(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                          const Box& delta, const Polytope& Phi0,
                                          const Eigen::MatrixXd& P, double c_out, double eps,
                                          const MrpiOptions& opt) {
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

SETBOUND_INLINE MrpiDesign mrpi_outer_shrinking(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                       const Eigen::VectorXd& wbar, double mu, double eps,
                                       MrpiOptions opt, bool boxes_only,
                                       const PolyhedralRpiOptions& popt,
                                       const HinfOptions& hopt) {
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

}  // namespace thesis
}  // namespace setbound
