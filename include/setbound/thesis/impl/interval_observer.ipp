// setbound — definitions of the functions declared in setbound/thesis/interval_observer.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/thesis/interval_observer.hpp"
#include "setbound/core/config.hpp"

namespace setbound {
namespace thesis {
namespace iobs_detail {

SETBOUND_INLINE double gam(Eigen::Index k) {
  const double ku = static_cast<double>(k + 2) * (kEps / 2);
  return 2.0 * ku / (1.0 - ku);
}

SETBOUND_INLINE double up(double x) { return x * (1.0 + 4.0 * kEps) + std::numeric_limits<double>::denorm_min(); }

SETBOUND_INLINE std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

SETBOUND_INLINE double spectral_radius(const Eigen::MatrixXd& M) {
  if (M.size() == 0) return 0.0;
  Eigen::EigenSolver<Eigen::MatrixXd> es(M, false);
  return es.eigenvalues().cwiseAbs().maxCoeff();
}

SETBOUND_INLINE Contraction certify_contraction(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& theta,
                                       const std::string& name) {
  const Eigen::Index n = Ao.rows();
  const double rho = spectral_radius(Ao);
  if (!(rho < 1.0))
    throw InvalidArgumentError(name + ": A_o = A - L C is not Schur stable (spectral radius " + num(rho) +
                               " >= 1); the error enclosure needs a stabilising gain");
  // P = Σ (A_oᵀ)^i A_o^i by doubling: P_{j+1} = P_j + (A^{2^j})ᵀ P_j A^{2^j}.
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n), Ak = Ao;
  for (int it = 0; it < 64; ++it) {
    P += Ak.transpose() * P * Ak;
    Ak = Ak * Ak;
    if (!P.allFinite()) break;
    if (Ak.cwiseAbs().maxCoeff() < 1e-20) break;
  }
  symmetrize(P);
  if (!P.allFinite())
    throw NumericalError(name + ": A_o = A - L C is too close to instability (spectral radius " + num(rho) +
                         "): its Lyapunov matrix overflows");
  Contraction c;
  c.P = P;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ep(P, Eigen::EigenvaluesOnly);
  double lmin = ep.eigenvalues().minCoeff() * (1.0 - 1e-8);
  for (int t = 0; t < 10 && lmin > 0; ++t) {
    Eigen::MatrixXd S = P;
    S.diagonal().array() -= lmin;
    Eigen::LLT<Eigen::MatrixXd> llt(S);
    const double tr = S.diagonal().cwiseAbs().sum();
    S.diagonal().array() -= 8 * gam(n + 1) * tr;
    if (Eigen::LLT<Eigen::MatrixXd>(S).info() == Eigen::Success) break;
    lmin *= 0.5;
  }
  if (!(lmin > 0)) throw NumericalError(name + ": cannot certify the Lyapunov matrix of A - L C");
  const double lmax = up(P.cwiseAbs().rowwise().sum().maxCoeff() * (1.0 + gam(n)));
  c.sqrt_lmax = up(std::sqrt(lmax));
  c.inv_sqrt_lmin = up(1.0 / std::sqrt(lmin));
  c.sqrt_kappa = up(c.sqrt_lmax * c.inv_sqrt_lmin);
  // β_fl² ≥ λ_max(A_flᵀ P A_fl, P), certified by Cholesky of β²P − A_flᵀPA_fl with margin.
  const Eigen::MatrixXd G = Ao.transpose() * P * Ao;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ge(0.5 * (G + G.transpose()), P,
                                                              Eigen::EigenvaluesOnly);
  const double b0 = std::max(0.0, ge.eigenvalues().maxCoeff());
  double margin = std::max(1e-12, 1e-7 * (1.0 - b0));
  double b2 = -1;
  for (int t = 0; t < 12; ++t) {
    const double cand = b0 + margin;
    if (cand >= 1.0) break;
    Eigen::MatrixXd S = cand * P - G;
    symmetrize(S);
    // rounding of forming G and cand·P: relative to tr(|G|) + tr(cand P)
    const double tr = (G.diagonal().cwiseAbs().sum() + cand * P.diagonal().sum());
    S.diagonal().array() -= (8 * gam(n + 1) + 4 * gam(2 * n)) * tr;
    if (Eigen::LLT<Eigen::MatrixXd>(S).info() == Eigen::Success) {
      b2 = cand;
      break;
    }
    margin *= 4;
  }
  if (b2 < 0)
    throw NumericalError(name + ": cannot certify a contraction of A - L C (spectral radius " + num(rho) +
                         "); it is too close to instability");
  const double theta_P = c.sqrt_kappa * up(theta.norm());  // ‖Θ‖_P ≤ √κ ‖Θ‖_F
  c.beta = up(std::sqrt(b2) * (1.0 + 2 * kEps)) + theta_P;
  if (!(c.beta < 1.0))
    throw NumericalError(name + ": cannot certify a contraction of A - L C (bound " + num(c.beta) + " >= 1)");
  return c;
}

SETBOUND_INLINE Eigen::VectorXd column_P_norms(const Eigen::MatrixXd& M, const Contraction& c) {
  Eigen::VectorXd out(M.cols());
  for (Eigen::Index l = 0; l < M.cols(); ++l) {
    const Eigen::VectorXd x = M.col(l);
    // |xᵀPx − fl| ≤ γ |x|ᵀ|P||x|
    const double q = x.dot(c.P * x) + gam(2 * M.rows()) * x.cwiseAbs().dot(c.P.cwiseAbs() * x.cwiseAbs());
    out(l) = up(std::sqrt(up(std::max(q, 0.0))));
  }
  return out;
}

SETBOUND_INLINE void abs_mul_up(const Eigen::MatrixXd& M, const double* r, double* out) {
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    double s = 0;
    for (Eigen::Index j = 0; j < M.cols(); ++j) s = rounding::add_up(s, rounding::mul_up(std::fabs(M(i, j)), r[j]));
    out[i] = s;
  }
}

SETBOUND_INLINE ErrorPowers build_powers(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& theta, const Eigen::MatrixXd& E,
                                const Eigen::MatrixXd& e_err, int min_steps, const std::string& name) {
  ErrorPowers p;
  const Eigen::Index n = Ao.rows();
  p.Ao = Ao;
  p.E = E;
  p.theta = theta;
  p.e_err = e_err;
  p.ctr = certify_contraction(Ao, theta, name);
  p.Ao_abs_up = Ao.cwiseAbs() + theta;
  for (Eigen::Index i = 0; i < p.Ao_abs_up.size(); ++i) p.Ao_abs_up.data()[i] = up(p.Ao_abs_up.data()[i]);
  const Eigen::MatrixXd errA = theta + gam(n) * Ao.cwiseAbs();  // |A_ex M − fl(A_fl M)| ≤ errA |M|
  const double emax = E.size() ? E.cwiseAbs().maxCoeff() : 0.0;
  p.M.push_back(Eigen::MatrixXd::Identity(n, n));
  p.N.push_back(E);
  p.d.push_back(0.0);
  p.q.push_back(up(p.ctr.sqrt_lmax * up(e_err.norm())));
  const int cap = std::max(kMaxPowers, min_steps);
  for (int i = 0; i < cap; ++i) {
    const Eigen::MatrixXd& Mi = p.M.back();
    const Eigen::MatrixXd& Ni = p.N.back();
    const bool small_M = Mi.cwiseAbs().maxCoeff() <= kNegligible;
    const bool small_N = E.size() == 0 || Ni.cwiseAbs().maxCoeff() <= kNegligible * emax;
    if (i >= min_steps && small_M && small_N) break;
    const double eps_M = up((errA * Mi.cwiseAbs()).norm() * (1.0 + gam(n)));
    const double eps_N = E.size() ? up((errA * Ni.cwiseAbs()).norm() * (1.0 + gam(n))) : 0.0;
    p.d.push_back(up(p.ctr.beta * p.d.back() + p.ctr.sqrt_kappa * eps_M));
    p.q.push_back(up(p.ctr.beta * p.q.back() + p.ctr.sqrt_lmax * eps_N));
    p.M.push_back(Ao * Mi);
    p.N.push_back(Ao * Ni);
  }
  p.K = static_cast<int>(p.M.size()) - 1;
  return p;
}

SETBOUND_INLINE const Eigen::VectorXd& ErrorBoxTable::lo_at(long k) const { return lo[std::size_t(std::min<long>(k, long(lo.size()) - 1))]; }

SETBOUND_INLINE const Eigen::VectorXd& ErrorBoxTable::hi_at(long k) const { return hi[std::size_t(std::min<long>(k, long(hi.size()) - 1))]; }

SETBOUND_INLINE ErrorBoxTable error_box_table(const ErrorPowers& p, const Eigen::VectorXd& c0, const Eigen::VectorXd& r0,
                                     const Eigen::VectorXd& rw, ErrorRecursion variant) {
  using namespace rounding;
  const Eigen::Index n = p.Ao.rows(), m = p.E.cols();
  const Contraction& c = p.ctr;
  const Eigen::VectorXd a0 = c0.cwiseAbs() + r0;  // |e_0| ≤ a0
  const double a0n = up(a0.norm()), rwn = up(rw.norm());
  // wrapped: [g_0] = E_exact[±rw] ⊆ ±rg0
  Eigen::VectorXd rg0 = Eigen::VectorXd::Zero(n);
  if (variant == ErrorRecursion::Wrapped && m > 0) {
    const Eigen::MatrixXd Eabs = p.E.cwiseAbs() + p.e_err;
    abs_mul_up(Eabs, rw.data(), rg0.data());
  }
  const double rg0n = up(rg0.norm());
  ErrorBoxTable t;
  Eigen::VectorXd S = Eigen::VectorXd::Zero(n), tmp(n), rad(n);
  double Qsum = 0, Dsum = 0;  // Σ_{i<k} q_i, Σ_{i<k} d_i
  for (int k = 0; k <= p.K; ++k) {
    const Eigen::MatrixXd& Mk = p.M[std::size_t(k)];
    const Eigen::VectorXd ck = Mk * c0;
    abs_mul_up(Mk, r0.data(), rad.data());
    // rounding of ck: γ_n |M_k||c_0|
    Eigen::VectorXd cabs(n);
    const Eigen::VectorXd ac0 = c0.cwiseAbs();
    abs_mul_up(Mk, ac0.data(), cabs.data());
    double resid = up(p.d[std::size_t(k)] * c.sqrt_lmax * a0n);
    resid += variant == ErrorRecursion::Wrapped ? up(Dsum * c.sqrt_lmax * rg0n) : up(Qsum * rwn);
    const double rs = up(up(resid) * c.inv_sqrt_lmin);
    Eigen::VectorXd lo(n), hi(n);
    for (Eigen::Index j = 0; j < n; ++j) {
      const double cr = k == 0 ? 0.0 : up(gam(n) * cabs(j));  // M_0 = I: the centre is exact
      const double r = add_up(add_up(add_up(rad(j), S(j)), cr), rs);
      lo(j) = sub_down(ck(j), r);
      hi(j) = add_up(ck(j), r);
    }
    t.lo.push_back(lo);
    t.hi.push_back(hi);
    // accumulate the k-th disturbance term for step k+1
    if (variant == ErrorRecursion::Wrapped) {
      abs_mul_up(Mk, rg0.data(), tmp.data());
      Dsum = up(Dsum + p.d[std::size_t(k)]);
    } else if (m > 0) {
      abs_mul_up(p.N[std::size_t(k)], rw.data(), tmp.data());
      Qsum = up(Qsum + p.q[std::size_t(k)]);
    } else {
      tmp.setZero();
    }
    for (Eigen::Index j = 0; j < n; ++j) S(j) = add_up(S(j), tmp(j));
  }
  // k > K: S holds Σ_{i≤K}; bound A_o^k e_0 and Σ_{i>K} by the geometric P-norm tail.
  const Eigen::VectorXd mK = column_P_norms(p.M[std::size_t(p.K)], c);
  double tail0 = up(mK.dot(a0) * (1 + gam(n)) + p.d[std::size_t(p.K)] * c.sqrt_lmax * a0n);
  // terms i ≥ K+1: ‖A^i E w‖_P ≤ β^{i−K}(‖N_K w‖_P + q_K‖w‖)
  const double geo = up(c.beta / (1.0 - c.beta) * (1.0 + 4 * kEps));
  double tailw;
  if (variant == ErrorRecursion::Wrapped) {
    tailw = up(geo * up(mK.dot(rg0) * (1 + gam(n)) + p.d[std::size_t(p.K)] * c.sqrt_lmax * rg0n));
  } else if (m > 0) {
    const Eigen::VectorXd nK = column_P_norms(p.N[std::size_t(p.K)], c);
    tailw = up(geo * up(nK.dot(rw) * (1 + gam(m)) + p.q[std::size_t(p.K)] * rwn));
  } else {
    tailw = 0;
  }
  const double resid = variant == ErrorRecursion::Wrapped ? up(Dsum * c.sqrt_lmax * rg0n) : up(Qsum * rwn);
  const double rs = up(up(tail0 + tailw + resid) * c.inv_sqrt_lmin);
  Eigen::VectorXd lo(n), hi(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    hi(j) = add_up(S(j), rs);
    lo(j) = -hi(j);
  }
  t.lo.push_back(lo);
  t.hi.push_back(hi);
  return t;
}

SETBOUND_INLINE double center_step_perturbation_P(const ErrorPowers& p, const Eigen::VectorXd& c, const Eigen::VectorXd& Ecw,
                                         const Eigen::VectorXd& ecw_err, Eigen::VectorXd& work) {
  const Eigen::Index n = p.Ao.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    double s = 0, t = 0;
    for (Eigen::Index j = 0; j < n; ++j) {
      s += std::fabs(p.Ao(i, j)) * std::fabs(c(j));
      t += p.theta(i, j) * std::fabs(c(j));
    }
    work(i) = gam(n + 2) * (s + std::fabs(Ecw(i))) * 2 + t * (1 + gam(n)) + ecw_err(i);
  }
  return up(p.ctr.sqrt_lmax * up(work.norm()));
}

SETBOUND_INLINE Eigen::MatrixXd ao_error_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& L, const Eigen::MatrixXd& C) {
  Eigen::MatrixXd t = gam(C.rows() + 2) * (A.cwiseAbs() + L.cwiseAbs() * C.cwiseAbs()) * 2;
  return t;
}

SETBOUND_INLINE Eigen::MatrixXd lz_error_bound(const Eigen::MatrixXd& L, const Eigen::MatrixXd& Z) {
  if (Z.cols() == 0) return Eigen::MatrixXd::Zero(L.rows(), 0);
  return gam(Z.rows() + 2) * (L.cwiseAbs() * Z.cwiseAbs()) * 2;
}

SETBOUND_INLINE void require_box(const Box& b, Eigen::Index n, const std::string& name) {
  if (b.size() != n)
    throw DimensionError(name + ": expected a box with " + std::to_string(n) + " components, got " +
                         std::to_string(b.size()));
  if (b.is_empty()) throw InvalidArgumentError(name + ": the box is empty");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(b.lo()(i)) || !std::isfinite(b.hi()(i)))
      throw NotFiniteError(name + ": component " + std::to_string(i) + " is unbounded; a bounded box is required");
}

SETBOUND_INLINE void require_vec(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Index n, const char* name) {
  if (v.size() != n)
    throw DimensionError(std::string(name) + ": expected " + std::to_string(n) + " entries, got " +
                         std::to_string(v.size()));
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isfinite(v(i)))
      throw NotFiniteError(std::string(name) + ": entry " + std::to_string(i) + " is " + num(v(i)) +
                           "; all entries must be finite");
}

SETBOUND_INLINE void mid_rad(const Box& b, Eigen::VectorXd& c, Eigen::VectorXd& r) {
  c.resize(b.size());
  r.resize(b.size());
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    c(i) = b[i].mid();
    r(i) = b[i].rad();
  }
}

SETBOUND_INLINE Box stack_boxes(const Box& a, const Box& b) {
  Eigen::VectorXd lo(a.size() + b.size()), hi(a.size() + b.size());
  lo << a.lo(), b.lo();
  hi << a.hi(), b.hi();
  return Box(lo, hi, "w");
}

SETBOUND_INLINE double luenberger_update(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& C,
                                const Eigen::MatrixXd& L, const Eigen::VectorXd& x, const double* u, const double* y,
                                const double* a, double a_err, Eigen::VectorXd& xn, Eigen::VectorXd& innov,
                                Eigen::VectorXd& innov_mag, Eigen::VectorXd& work) {
  const Eigen::Index n = A.rows(), nu = B.cols(), ny = C.rows();
  for (Eigen::Index i = 0; i < ny; ++i) {
    double s = y[i], mag = std::fabs(y[i]);
    for (Eigen::Index j = 0; j < n; ++j) {
      s -= C(i, j) * x(j);
      mag += std::fabs(C(i, j) * x(j));
    }
    innov(i) = s;
    innov_mag(i) = mag;
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    double s = 0, mag = 0;
    for (Eigen::Index j = 0; j < n; ++j) {
      s += A(i, j) * x(j);
      mag += std::fabs(A(i, j) * x(j));
    }
    for (Eigen::Index j = 0; j < nu; ++j) {
      s += B(i, j) * u[j];
      mag += std::fabs(B(i, j) * u[j]);
    }
    for (Eigen::Index j = 0; j < ny; ++j) {
      s += L(i, j) * innov(j);
      mag += std::fabs(L(i, j)) * innov_mag(j);
    }
    if (a) {
      s += a[i];
      mag += std::fabs(a[i]);
    }
    xn(i) = s;
    work(i) = mag;
  }
  const double g = 2 * gam(n + nu + 2 * ny + 4);
  return up(up(g * work.norm()) + a_err);
}

}  // namespace iobs_detail
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

SETBOUND_INLINE std::vector<Box> interval_error_recursion(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E, const Box& e0,
                                                 const Box& w, int steps,
                                                 ErrorRecursion variant) {
  using namespace iobs_detail;
  require_square(Ao, "Ao");
  if (Ao.rows() == 0) throw DimensionError("Ao: the state dimension must be >= 1");
  require_finite(Ao, "Ao");
  const Eigen::Index n = Ao.rows();
  if (E.rows() != n)
    throw DimensionError("E: expected " + std::to_string(n) + " rows, got " + std::to_string(E.rows()));
  require_finite(E, "E");
  require_box(e0, n, "e0");
  require_box(w, E.cols(), "w");
  if (steps < 0) throw InvalidArgumentError("steps: must be >= 0, got " + std::to_string(steps));
  if (variant != ErrorRecursion::Tight && variant != ErrorRecursion::Wrapped && variant != ErrorRecursion::Naive)
    throw InvalidArgumentError("variant: unknown error recursion");
  const Eigen::MatrixXd zero_nn = Eigen::MatrixXd::Zero(n, n), zero_nm = Eigen::MatrixXd::Zero(n, E.cols());
  ErrorPowers p = build_powers(Ao, zero_nn, E, zero_nm, variant == ErrorRecursion::Naive ? 0 : 0, "Ao");
  Eigen::VectorXd c0, r0, cw, rw;
  mid_rad(e0, c0, r0);
  mid_rad(w, cw, rw);
  // centre part Σ A^i E c_w by recursion, with its P-norm rounding residue ξ
  const Eigen::VectorXd Ecw = E * cw;
  const Eigen::VectorXd ecw_err = (gam(E.cols()) * 2 * (E.cwiseAbs() * cw.cwiseAbs())).unaryExpr([](double x) {
    return up(x);
  });
  const bool has_cw = cw.cwiseAbs().maxCoeff() > 0;
  Eigen::VectorXd cc = Eigen::VectorXd::Zero(n), work(n);
  double xi = 0;
  std::vector<Box> out;
  out.reserve(std::size_t(steps) + 1);
  ErrorBoxTable table;
  Eigen::VectorXd naive_c = c0, naive_r = r0, rg0 = Eigen::VectorXd::Zero(n);
  if (variant == ErrorRecursion::Naive) {
    if (E.cols() > 0) abs_mul_up(E.cwiseAbs(), rw.data(), rg0.data());
  } else {
    table = error_box_table(p, c0, r0, rw, variant);
  }
  for (int k = 0; k <= steps; ++k) {
    Eigen::VectorXd lo(n), hi(n);
    const double xs = up(xi * p.ctr.inv_sqrt_lmin);
    if (variant == ErrorRecursion::Naive) {
      // the naive recursion carries its own centre: e ∈ naive_c ± naive_r, plus ξ for the centre rounding
      for (Eigen::Index j = 0; j < n; ++j) {
        lo(j) = rounding::sub_down(naive_c(j), rounding::add_up(naive_r(j), xs));
        hi(j) = rounding::add_up(naive_c(j), rounding::add_up(naive_r(j), xs));
      }
    } else {
      const Eigen::VectorXd& tlo = table.lo_at(k);
      const Eigen::VectorXd& thi = table.hi_at(k);
      for (Eigen::Index j = 0; j < n; ++j) {
        lo(j) = rounding::sub_down(rounding::add_down(cc(j), tlo(j)), xs);
        hi(j) = rounding::add_up(rounding::add_up(cc(j), thi(j)), xs);
      }
    }
    out.push_back(Box::from_intervals([&] {
      std::vector<Interval> v;
      for (Eigen::Index j = 0; j < n; ++j) v.push_back(Interval::unchecked(lo(j), hi(j)));
      return v;
    }()));
    if (k == steps) break;
    if (variant == ErrorRecursion::Naive) {
      // [e⁺] = A[e] + [g_0]: centre A c + E c_w (rounding into ξ), radius |A| r + |E| r_w (up)
      const double pert = center_step_perturbation_P(p, naive_c, Ecw, ecw_err, work);
      Eigen::VectorXd rn(n);
      abs_mul_up(p.Ao_abs_up, naive_r.data(), rn.data());
      for (Eigen::Index j = 0; j < n; ++j) rn(j) = rounding::add_up(rn(j), rg0(j));
      naive_c = Ao * naive_c + Ecw;
      naive_r = rn;
      xi = up(p.ctr.beta * xi + pert);
    } else if (has_cw) {
      const double pert = center_step_perturbation_P(p, cc, Ecw, ecw_err, work);
      cc = Ao * cc + Ecw;
      xi = up(p.ctr.beta * xi + pert);
    }
  }
  return out;
}

SETBOUND_INLINE Box interval_error_limit(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& E, const Box& w,
                                ErrorRecursion variant) {
  using namespace iobs_detail;
  require_square(Ao, "Ao");
  if (Ao.rows() == 0) throw DimensionError("Ao: the state dimension must be >= 1");
  require_finite(Ao, "Ao");
  const Eigen::Index n = Ao.rows();
  if (E.rows() != n)
    throw DimensionError("E: expected " + std::to_string(n) + " rows, got " + std::to_string(E.rows()));
  require_finite(E, "E");
  require_box(w, E.cols(), "w");
  if (variant == ErrorRecursion::Naive)
    throw InvalidArgumentError("variant: the naive recursion has no useful limit (it may diverge); use Tight or Wrapped");
  ErrorPowers p = build_powers(Ao, Eigen::MatrixXd::Zero(n, n), E, Eigen::MatrixXd::Zero(n, E.cols()), 0, "Ao");
  Eigen::VectorXd cw, rw;
  mid_rad(w, cw, rw);
  const ErrorBoxTable t = error_box_table(p, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), rw, variant);
  // centre c∞ = (I − A)^{-1} E c_w, with the residual bound ‖c − c∞‖_P ≤ ‖res‖_P/(1 − β)
  const Eigen::MatrixXd IA = Eigen::MatrixXd::Identity(n, n) - Ao;
  const Eigen::VectorXd Ecw = E * cw;
  const Eigen::VectorXd c = IA.partialPivLu().solve(Ecw);
  const Eigen::VectorXd res = IA * c - Ecw;
  const Eigen::VectorXd res_mag =
      res.cwiseAbs() + 2 * gam(n + E.cols() + 2) * (IA.cwiseAbs() * c.cwiseAbs() + E.cwiseAbs() * cw.cwiseAbs());
  const double cerr = up(up(p.ctr.sqrt_lmax * up(res_mag.norm())) / (1.0 - p.ctr.beta) * p.ctr.inv_sqrt_lmin);
  const Eigen::VectorXd& thi = t.hi.back();
  std::vector<Interval> v;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double r = rounding::add_up(thi(j), cerr);
    v.push_back(Interval::unchecked(rounding::sub_down(c(j), r), rounding::add_up(c(j), r)));
  }
  return Box::from_intervals(v);
}

}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {
namespace iobs_detail {

SETBOUND_INLINE void fingerprint_plant_table(StateFingerprint& f, const Plant& p, const Eigen::MatrixXd& L, const ErrorBoxTable& t) {
  f.add(p.A).add(p.B).add(p.C).add(p.F).add(p.Z).add(L);
  for (const auto& v : t.lo) f.add(v);
  for (const auto& v : t.hi) f.add(v);
}

}  // namespace iobs_detail
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

SETBOUND_INLINE IntervalLuenbergerObserver::IntervalLuenbergerObserver(const Plant& plant, const Eigen::MatrixXd& L, const Box& x0,
                             const Eigen::VectorXd& xhat0, const Box& d, const Box& v,
                             const IntervalObserverOptions& opt)
    : plant_(plant), L_(L) {
  using namespace iobs_detail;
  const Eigen::Index n = plant.nx();
  require_shape(L, n, plant.ny(), "L");
  require_finite(L, "L");
  require_box(x0, n, "x0");
  require_vec(xhat0, n, "xhat0");
  require_box(d, plant.nd(), "d");
  require_box(v, plant.nv(), "v");
  if (opt.variant != ErrorRecursion::Tight && opt.variant != ErrorRecursion::Wrapped)
    throw InvalidArgumentError("variant: the online observer supports Tight and Wrapped (Naive diverges)");
  if (!x0.contains(xhat0)) throw InvalidArgumentError("xhat0: must lie in the initial box x0 (thesis §6.2)");
  variant_ = opt.variant;
  Ao_ = plant.A - L * plant.C;
  E_ = plant.error_input(L);
  const Eigen::MatrixXd theta = ao_error_bound(plant.A, L, plant.C);
  Eigen::MatrixXd e_err = Eigen::MatrixXd::Zero(n, plant.m());
  e_err.rightCols(plant.nv()) = lz_error_bound(L, plant.Z);
  powers_ = build_powers(Ao_, theta, E_, e_err, 0, "L");
  const Box w = stack_boxes(d, v);
  Eigen::VectorXd c0, r0, cw, rw;
  // [e_0] = [x_0] − x̂_0, enclosed outward
  const Box e0 = x0 - Box::point(xhat0);
  mid_rad(e0, c0, r0);
  mid_rad(w, cw, rw);
  table_ = error_box_table(powers_, c0, r0, rw, variant_);
  rw_ = rw;
  dbox_ = d;
  vbox_ = v;
  screen_.init(plant.ny(), x0);
  rlo_ = x0.lo();
  rhi_ = x0.hi();
  Ecw_ = E_ * cw;
  ecw_err_ = (2 * gam(plant.m() + 2) * (E_.cwiseAbs() * cw.cwiseAbs()) + e_err * cw.cwiseAbs()).unaryExpr([](double x) {
    return up(x);
  });
  has_cw_ = cw.size() > 0 && cw.cwiseAbs().maxCoeff() > 0;
  xhat_ = xhat0;
  cc_ = Eigen::VectorXd::Zero(n);
  xn_.resize(n);
  cn_.resize(n);
  work_.resize(n);
  innov_.resize(plant.ny());
  innov_mag_.resize(plant.ny());
  lo_.resize(n);
  hi_.resize(n);
  update_bounds();
}

namespace iobs_detail {

SETBOUND_INLINE void require_reading(const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Index ny) {
  if (y.size() != ny)
    throw DimensionError("y: expected " + std::to_string(ny) + " entries, got " + std::to_string(y.size()));
  require_no_infinity(y, "y");
}

}  // namespace iobs_detail

SETBOUND_INLINE void IntervalLuenbergerObserver::restart(const Box& X, long k) {
  using namespace iobs_detail;
  Eigen::VectorXd xh = X.mid();
  const Box e0 = X - Box::point(xh);
  Eigen::VectorXd c0, r0;
  mid_rad(e0, c0, r0);
  ErrorBoxTable t = error_box_table(powers_, c0, r0, rw_, variant_);
  Eigen::VectorXd lo = X.lo(), hi = X.hi();
  // commit (swaps and moves)
  rtable_ = std::move(t);
  rlo_.swap(lo);
  rhi_.swap(hi);
  restarted_ = true;
  k0_ = k;
  k_ = k;
  xhat_.swap(xh);
  cc_.setZero();
  xi_ = 0;
  update_bounds();
}

SETBOUND_INLINE void IntervalLuenbergerObserver::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  using namespace iobs_detail;
  require_reading(y, plant_.ny());
  if (plant_.nu() > 0) require_vec(u, plant_.nu(), "u");
  if (!screen_detail::screen_box_step(screen_, plant_.C, plant_.Z, vbox_, lo_, hi_, y, k_)) {
    Eigen::VectorXd lo = lo_, hi = hi_;
    const MeasurementCheck use = screen_detail::apply_reset(screen_, plant_.C, plant_.Z, vbox_, y, lo, hi);
    restart(screen_detail::fallback_prediction(plant_.A, plant_.B, plant_.F, plant_.C, plant_.Z, lo, hi, y, u, dbox_,
                                               vbox_, use),
            k_ + 1);
    return;
  }
  const double dn = luenberger_update(plant_.A, plant_.B, plant_.C, L_, xhat_, u.data(), y.data(), nullptr, 0.0, xn_,
                                      innov_, innov_mag_, work_);
  if (!xn_.allFinite()) throw NumericalError("y: the observer state overflowed");
  double pert = up(powers_.ctr.sqrt_lmax * dn);
  if (has_cw_) {
    pert += center_step_perturbation_P(powers_, cc_, Ecw_, ecw_err_, work_);
    for (Eigen::Index i = 0; i < cc_.size(); ++i) {
      double s = Ecw_(i);
      for (Eigen::Index j = 0; j < cc_.size(); ++j) s += Ao_(i, j) * cc_(j);
      cn_(i) = s;
    }
    cc_.swap(cn_);
  }
  xhat_.swap(xn_);
  xi_ = up(powers_.ctr.beta * xi_ + pert);
  ++k_;
  update_bounds();
}

SETBOUND_INLINE std::vector<double> IntervalLuenbergerObserver::save_state() const {
  StateWriter w(StateKind::IntervalLuenbergerObserver, fingerprint());
  w.count(k_).vec(xhat_).vec(cc_).scalar(xi_).flag(restarted_).count(k0_).vec(rlo_).vec(rhi_);
  return w.finish();
}

SETBOUND_INLINE void IntervalLuenbergerObserver::restore_state(const std::vector<double>& state) {
  long long k = 0, k0 = 0;
  Eigen::VectorXd xh, cc, rlo, rhi;
  double xi = 0;
  bool restarted = false;
  iobs_detail::ErrorBoxTable rt;
  guard_state_memory(StateKind::IntervalLuenbergerObserver, [&] {
    const Eigen::Index n = plant_.nx();
    StateReader r(state, StateKind::IntervalLuenbergerObserver, fingerprint());
    k = r.count("steps");
    xh = r.vec(n, "xhat");
    cc = r.vec(n, "center offset");
    xi = r.scalar("rounding residue");
    restarted = r.flag("restarted");
    k0 = r.count("restart step");
    rlo = r.vec(n, "restart lower");
    rhi = r.vec(n, "restart upper");
    r.finish();
    if (!(xi >= 0)) r.fail("rounding residue must be >= 0");
    if (k0 > k || (!restarted && k0 != 0)) r.fail("restart step must be 0 or at most the step count");
    if ((rhi.array() < rlo.array()).any()) r.fail("restart box has lower > upper");
    if (restarted) {
      Eigen::VectorXd c0, r0;
      const Box X(rlo, rhi, "restart box");
      iobs_detail::mid_rad(X - Box::point(X.mid()), c0, r0);
      rt = iobs_detail::error_box_table(powers_, c0, r0, rw_, variant_);
    }
  });
  // Commit (swaps; update_bounds writes into sized buffers: nothing throws).
  k_ = static_cast<long>(k);
  k0_ = static_cast<long>(k0);
  restarted_ = restarted;
  rtable_ = std::move(rt);
  rlo_.swap(rlo);
  rhi_.swap(rhi);
  xhat_.swap(xh);
  cc_.swap(cc);
  xi_ = xi;
  update_bounds();
}

SETBOUND_INLINE StateFingerprint IntervalLuenbergerObserver::fingerprint() const {
  StateFingerprint f;
  f.add_int(static_cast<int>(variant_));
  iobs_detail::fingerprint_plant_table(f, plant_, L_, table_);
  f.add(Ecw_).add(ecw_err_);
  return f;
}

SETBOUND_INLINE void IntervalLuenbergerObserver::update_bounds() {
  using namespace rounding;
  const iobs_detail::ErrorBoxTable& t = restarted_ ? rtable_ : table_;
  const Eigen::VectorXd& tlo = t.lo_at(k_ - k0_);
  const Eigen::VectorXd& thi = t.hi_at(k_ - k0_);
  const double xs = iobs_detail::up(xi_ * powers_.ctr.inv_sqrt_lmin);
  for (Eigen::Index j = 0; j < xhat_.size(); ++j) {
    const double clo = add_down(xhat_(j), cc_(j)), chi = add_up(xhat_(j), cc_(j));
    lo_(j) = sub_down(add_down(clo, tlo(j)), xs);
    hi_(j) = add_up(add_up(chi, thi(j)), xs);
  }
}

SETBOUND_INLINE NonlinearIntervalObserver::NonlinearIntervalObserver(const Plant& plant, const Eigen::MatrixXd& L, const Box& x0, const Eigen::VectorXd& xhat0,
                            const Box& v, NonlinearityBox h, const NonlinearObserverOptions& opt)
    : plant_(plant), L_(L), h_(std::move(h)) {
  using namespace iobs_detail;
  const Eigen::Index n = plant.nx();
  if (plant.nd() != n || !plant.F.isApprox(Eigen::MatrixXd::Identity(n, n), 0.0))
    throw InvalidArgumentError("plant.F: the nonlinear observer needs F = I (h enters the state directly, "
                               "E = [I, -L Z]; setbound docs: Methods › Interval observers › Nonlinear interval observer)");
  require_shape(L, n, plant.ny(), "L");
  require_finite(L, "L");
  require_box(x0, n, "x0");
  require_vec(xhat0, n, "xhat0");
  require_box(v, plant.nv(), "v");
  if (!x0.contains(xhat0)) throw InvalidArgumentError("xhat0: must lie in the initial box x0 (thesis §6.6)");
  if (opt.window < 1) throw InvalidArgumentError("window: must be >= 1, got " + std::to_string(opt.window));
  Ao_ = plant.A - L * plant.C;
  const Eigen::MatrixXd LZ = -L * plant.Z;
  const Eigen::MatrixXd theta = ao_error_bound(plant.A, L, plant.C);
  const Eigen::MatrixXd lz_err = lz_error_bound(L, plant.Z);
  powers_ = build_powers(Ao_, theta, LZ, lz_err, 0, "L");
  Eigen::VectorXd c0, r0, cv, rv;
  const Box e0 = x0 - Box::point(xhat0);
  mid_rad(e0, c0, r0);
  mid_rad(v, cv, rv);
  table_ = error_box_table(powers_, c0, r0, rv, ErrorRecursion::Tight);
  rv_ = rv;
  vbox_ = v;
  screen_.init(plant.ny(), x0);
  rlo_ = x0.lo();
  rhi_ = x0.hi();
  Ecw_ = LZ * cv;
  ecw_err_ = (2 * gam(plant.nv() + 2) * (LZ.cwiseAbs() * cv.cwiseAbs()) + lz_err * cv.cwiseAbs()).unaryExpr(
      [](double x) { return up(x); });
  has_cw_ = cv.size() > 0 && cv.cwiseAbs().maxCoeff() > 0;
  W_ = std::min(powers_.K, opt.window);
  if (W_ < 1) W_ = 1;
  if (W_ > powers_.K) {  // need M_W: extend (K ≥ 1 always unless A_o is tiny)
    powers_ = build_powers(Ao_, theta, LZ, lz_err, W_, "L");
    table_ = error_box_table(powers_, c0, r0, rv, ErrorRecursion::Tight);
  }
  const Contraction& c = powers_.ctr;
  mW_ = column_P_norms(powers_.M[std::size_t(W_)], c);
  Dw_ = 0;
  for (int i = 0; i < W_; ++i) Dw_ = up(Dw_ + powers_.d[std::size_t(i)]);
  ring_ = Eigen::MatrixXd::Zero(n, W_);
  Rmax_ = Eigen::VectorXd::Zero(n);
  xhat_ = xhat0;
  cc_ = Eigen::VectorXd::Zero(n);
  xn_.resize(n);
  cn_.resize(n);
  work_.resize(n);
  hc_.resize(n);
  hr_.resize(n);
  conv_.resize(n);
  tmp_.resize(n);
  innov_.resize(plant.ny());
  innov_mag_.resize(plant.ny());
  lo_.resize(n);
  hi_.resize(n);
  update_bounds();
}

SETBOUND_INLINE void NonlinearIntervalObserver::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (!h_) throw InvalidArgumentError("h: no nonlinearity functor was given; pass the box of h to step()");
  const Box hb = h_(current(), k_);
  step(y, u, hb);
}

SETBOUND_INLINE void NonlinearIntervalObserver::restart(const Box& X, long k) {
  using namespace iobs_detail;
  Eigen::VectorXd xh = X.mid();
  Eigen::VectorXd c0, r0;
  mid_rad(X - Box::point(xh), c0, r0);
  ErrorBoxTable t = error_box_table(powers_, c0, r0, rv_, ErrorRecursion::Tight);
  Eigen::VectorXd lo = X.lo(), hi = X.hi();
  // commit (swaps and moves); the window starts empty: the h terms before k are inside X
  rtable_ = std::move(t);
  rlo_.swap(lo);
  rhi_.swap(hi);
  restarted_ = true;
  k0_ = k;
  k_ = k;
  xhat_.swap(xh);
  cc_.setZero();
  xi_ = 0;
  ring_.setZero();
  Rmax_.setZero();
  rmax_norm_ = 0;
  rmax_norm_out_ = 0;
  update_bounds();
}

SETBOUND_INLINE void NonlinearIntervalObserver::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u, const Box& hbox) {
  using namespace iobs_detail;
  const Eigen::Index n = plant_.nx();
  require_reading(y, plant_.ny());
  if (plant_.nu() > 0) require_vec(u, plant_.nu(), "u");
  if (hbox.size() != n)
    throw DimensionError("h: expected a box with " + std::to_string(n) + " components, got " +
                         std::to_string(hbox.size()));
  if (hbox.is_empty()) throw InvalidArgumentError("h: the box is empty");
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(hbox.lo()(i)) || !std::isfinite(hbox.hi()(i)))
      throw NotFiniteError("h: component " + std::to_string(i) + " is unbounded or NaN");
    hc_(i) = hbox[i].mid();
    hr_(i) = hbox[i].rad();
  }
  if (!screen_detail::screen_box_step(screen_, plant_.C, plant_.Z, vbox_, lo_, hi_, y, k_)) {
    // x⁺ = A x + h + B u: the plant's F is I, so [h]_k enters as the box of d
    Eigen::VectorXd lo = lo_, hi = hi_;
    const MeasurementCheck use = screen_detail::apply_reset(screen_, plant_.C, plant_.Z, vbox_, y, lo, hi);
    restart(screen_detail::fallback_prediction(plant_.A, plant_.B, plant_.F, plant_.C, plant_.Z, lo, hi, y, u, hbox,
                                               vbox_, use),
            k_ + 1);
    return;
  }
  // the constant added to x̂: ĥ + (−LZ) c_v (only ĥ when v is centred)
  const double dn = luenberger_update(plant_.A, plant_.B, plant_.C, L_, xhat_, u.data(), y.data(), hc_.data(), 0.0,
                                      xn_, innov_, innov_mag_, work_);
  if (!xn_.allFinite()) throw NumericalError("y: the observer state overflowed");
  double pert = up(powers_.ctr.sqrt_lmax * dn);
  if (has_cw_) {
    pert += center_step_perturbation_P(powers_, cc_, Ecw_, ecw_err_, work_);
    for (Eigen::Index i = 0; i < n; ++i) {
      double s = Ecw_(i);
      for (Eigen::Index j = 0; j < n; ++j) s += Ao_(i, j) * cc_(j);
      cn_(i) = s;
    }
    cc_.swap(cn_);
  }
  xhat_.swap(xn_);
  xi_ = up(powers_.ctr.beta * xi_ + pert);
  // ring buffer of the last W radii: slot (k mod W) receives r_h,k; the one it replaces leaves
  const long kr = k_ - k0_;  // steps since the (re)start
  const int slot = static_cast<int>(kr % W_);
  if (kr >= W_) {
    for (Eigen::Index i = 0; i < n; ++i) Rmax_(i) = std::max(Rmax_(i), ring_(i, slot));
    rmax_norm_out_ = std::max(rmax_norm_out_, up(ring_.col(slot).norm()));
  }
  ring_.col(slot) = hr_;
  rmax_norm_ = std::max(rmax_norm_, up(hr_.norm()));
  ++k_;
  update_bounds();
}

SETBOUND_INLINE std::vector<double> NonlinearIntervalObserver::save_state() const {
  StateWriter w(StateKind::NonlinearIntervalObserver, fingerprint());
  w.count(k_).vec(xhat_).vec(cc_).scalar(xi_).mat(ring_).vec(Rmax_).scalar(rmax_norm_).scalar(rmax_norm_out_);
  w.flag(restarted_).count(k0_).vec(rlo_).vec(rhi_);
  return w.finish();
}

SETBOUND_INLINE void NonlinearIntervalObserver::restore_state(const std::vector<double>& state) {
  long long k = 0, k0 = 0;
  Eigen::VectorXd xh, cc, rmax, rlo, rhi;
  Eigen::MatrixXd ring;
  double xi = 0, rn = 0, rno = 0;
  bool restarted = false;
  iobs_detail::ErrorBoxTable rt;
  guard_state_memory(StateKind::NonlinearIntervalObserver, [&] {
    const Eigen::Index n = plant_.nx();
    StateReader r(state, StateKind::NonlinearIntervalObserver, fingerprint());
    k = r.count("steps");
    xh = r.vec(n, "xhat");
    cc = r.vec(n, "center offset");
    xi = r.scalar("rounding residue");
    ring = r.mat(n, W_, "window");  // the window length is the design's W, never the blob's
    rmax = r.vec(n, "window maxima");
    rn = r.scalar("window norm");
    rno = r.scalar("window norm out");
    restarted = r.flag("restarted");
    k0 = r.count("restart step");
    rlo = r.vec(n, "restart lower");
    rhi = r.vec(n, "restart upper");
    r.finish();
    if (!(xi >= 0) || !(rn >= 0) || !(rno >= 0) || (ring.array() < 0).any() || (rmax.array() < 0).any())
      r.fail("a radius or residue is negative");
    if (k0 > k || (!restarted && k0 != 0)) r.fail("restart step must be 0 or at most the step count");
    if ((rhi.array() < rlo.array()).any()) r.fail("restart box has lower > upper");
    if (restarted) {
      Eigen::VectorXd c0, r0;
      const Box X(rlo, rhi, "restart box");
      iobs_detail::mid_rad(X - Box::point(X.mid()), c0, r0);
      rt = iobs_detail::error_box_table(powers_, c0, r0, rv_, ErrorRecursion::Tight);
    }
  });
  // Commit (swaps; update_bounds writes into sized buffers: nothing throws).
  k_ = static_cast<long>(k);
  k0_ = static_cast<long>(k0);
  restarted_ = restarted;
  rtable_ = std::move(rt);
  rlo_.swap(rlo);
  rhi_.swap(rhi);
  xhat_.swap(xh);
  cc_.swap(cc);
  xi_ = xi;
  ring_.swap(ring);
  Rmax_.swap(rmax);
  rmax_norm_ = rn;
  rmax_norm_out_ = rno;
  update_bounds();
}

SETBOUND_INLINE StateFingerprint NonlinearIntervalObserver::fingerprint() const {
  StateFingerprint f;
  f.add_int(W_);
  iobs_detail::fingerprint_plant_table(f, plant_, L_, table_);
  f.add(Ecw_).add(ecw_err_);
  return f;
}

SETBOUND_INLINE void NonlinearIntervalObserver::update_bounds() {
  using namespace rounding;
  using iobs_detail::up;
  const Eigen::Index n = plant_.nx();
  // h part: Σ_{i < min(k, W)} |M_i| r_h,k−1−i (exact radii), rounded up
  conv_.setZero();
  const long kr = k_ - k0_;  // steps since the (re)start
  const long terms = std::min<long>(kr, W_);
  for (long i = 0; i < terms; ++i) {
    const long j = kr - 1 - i;
    const int slot = static_cast<int>(j % W_);
    iobs_detail::abs_mul_up(powers_.M[std::size_t(i)], ring_.col(slot).data(), tmp_.data());
    for (Eigen::Index r = 0; r < n; ++r) conv_(r) = add_up(conv_(r), tmp_(r));
  }
  const iobs_detail::ErrorBoxTable& t = restarted_ ? rtable_ : table_;
  const Eigen::VectorXd& tlo = t.lo_at(kr);
  const Eigen::VectorXd& thi = t.hi_at(kr);
  const iobs_detail::Contraction& c = powers_.ctr;
  double resid = up(xi_ + up(Dw_ * c.sqrt_lmax * rmax_norm_));
  if (kr > W_) {
    const double geo = up(1.0 / (1.0 - c.beta) * (1.0 + 4 * iobs_detail::kEps));
    resid = up(resid + up(geo * up(mW_.dot(Rmax_) * (1 + iobs_detail::gam(n)) +
                                   powers_.d[std::size_t(W_)] * c.sqrt_lmax * rmax_norm_out_)));
  }
  const double xs = up(resid * c.inv_sqrt_lmin);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double clo = add_down(xhat_(j), cc_(j)), chi = add_up(xhat_(j), cc_(j));
    const double r = add_up(conv_(j), xs);
    lo_(j) = sub_down(add_down(clo, tlo(j)), r);
    hi_(j) = add_up(add_up(chi, thi(j)), r);
  }
}

SETBOUND_INLINE IntervalLuenbergerObserver design_interval_luenberger(const Plant& plant, const Box& x0,
                                                             const Eigen::VectorXd& xhat0, const Box& d, const Box& v,
                                                             const IntervalObserverOptions& opt,
                                                             const HinfOptions& hopt, HinfGain* gain_out) {
  HinfGain g = hinf_observer_gain(plant, Eigen::MatrixXd(), hopt);
  IntervalLuenbergerObserver obs(plant, g.L, x0, xhat0, d, v, opt);
  if (gain_out) *gain_out = std::move(g);
  return obs;
}

SETBOUND_INLINE NonlinearIntervalObserver design_nonlinear_interval_observer(const Plant& plant, const Box& x0,
                                                                    const Eigen::VectorXd& xhat0, const Box& v,
                                                                    NonlinearityBox h,
                                                                    const NonlinearObserverOptions& opt,
                                                                    const HinfOptions& hopt,
                                                                    HinfGain* gain_out) {
  const Eigen::Index n = plant.nx();
  if (plant.nd() != n || !plant.F.isApprox(Eigen::MatrixXd::Identity(n, n), 0.0))
    throw InvalidArgumentError("plant.F: the nonlinear observer needs F = I (h enters the state directly, "
                               "E = [I, -L Z]; setbound docs: Methods › Interval observers › Nonlinear interval observer)");
  HinfGain g = hinf_observer_gain(plant, Eigen::MatrixXd(), hopt);
  NonlinearIntervalObserver obs(plant, g.L, x0, xhat0, v, std::move(h), opt);
  if (gain_out) *gain_out = std::move(g);
  return obs;
}

SETBOUND_INLINE const Box& InvariantObserverDesign::box_at(long k) const { return sequence[std::size_t(std::min<long>(k, k_star))]; }

}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {
namespace iobs_detail {

SETBOUND_INLINE double certified_rate(const Eigen::MatrixXd& Ao, const Eigen::MatrixXd& P, const std::string& name) {
  const Eigen::Index n = Ao.rows();
  const Eigen::MatrixXd G = Ao.transpose() * P * Ao;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ge(0.5 * (G + G.transpose()), 0.5 * (P + P.transpose()),
                                                              Eigen::EigenvaluesOnly);
  const double b0 = std::max(0.0, ge.eigenvalues().maxCoeff());
  double margin = 1e-12 + 1e-10 * b0;
  for (int t = 0; t < 20; ++t) {
    const double cand = b0 + margin;
    Eigen::MatrixXd S = cand * P - G;
    const double tr = G.diagonal().cwiseAbs().sum() + cand * P.diagonal().cwiseAbs().sum();
    symmetrize(S);
    S.diagonal().array() -= (8 * gam(n + 1) + 4 * gam(2 * n)) * tr;
    if (Eigen::LLT<Eigen::MatrixXd>(S).info() == Eigen::Success) return up(std::sqrt(cand));
    margin *= 4;
  }
  throw NumericalError(name + ": cannot certify the contraction rate beta of A - L C in the P norm");
}

}  // namespace iobs_detail
}  // namespace thesis
}  // namespace setbound

namespace setbound {
namespace thesis {

namespace iobs_detail {

SETBOUND_INLINE Eigen::MatrixXd sequence_e_err(const InvariantObserverDesign& D) {
  Eigen::MatrixXd e_err = Eigen::MatrixXd::Zero(D.plant.nx(), D.plant.m());
  e_err.rightCols(D.plant.nv()) = lz_error_bound(D.L, D.plant.Z);
  return e_err;
}

SETBOUND_INLINE void fill_error_sequence(InvariantObserverDesign& D, const Box& x0, const Eigen::VectorXd& xhat0,
                                         double inflation_opt) {
  const Plant& plant = D.plant;
  const Eigen::Index n = plant.nx();
  const Eigen::MatrixXd Ao = plant.A - D.L * plant.C;
  D.x0 = x0;
  D.xhat0 = xhat0;
  D.shrinking_index.clear();
  D.sequence.clear();
  // inflation: smallest λ ≥ 1 with every corner of [e_0] in λΦ_0 (Φ_0 = {Hx ≤ b}, b > 0)
  const Box e0 = x0 - Box::point(xhat0);
  double lam = 1.0;
  const Eigen::MatrixXd& H = D.phi0.H();
  const Eigen::VectorXd& b = D.phi0.b();
  const long corners = 1L << n;
  for (long c = 0; c < corners; ++c) {
    Eigen::VectorXd x(n);
    for (Eigen::Index j = 0; j < n; ++j) x(j) = (c >> j) & 1 ? e0.hi()(j) : e0.lo()(j);
    for (Eigen::Index i = 0; i < H.rows(); ++i) {
      const double t = H.row(i).dot(x);
      const double terr = gam(n) * H.row(i).cwiseAbs().dot(x.cwiseAbs());
      lam = std::max(lam, up((t + terr) / b(i) * (1 + 4 * kEps)));
    }
  }
  D.inflation_min = lam;
  if (inflation_opt == 0) {
    D.inflation = lam;
  } else {
    if (inflation_opt < lam)
      throw InvalidArgumentError("inflation: " + num(inflation_opt) + " is too small, [e_0] is not inside " +
                                 "inflation*Phi_0 (the smallest admissible value is " + num(lam) + ")");
    D.inflation = inflation_opt;
  }

  // k*: first k with λ β^k √(c_out/λ_min(P)) ≤ ε (rigorous version of (4.33))
  const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(D.P, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
  const double lmax = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(D.P, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  const double R = D.inflation * std::sqrt(D.c_out / lmin);
  int kstar = 0;
  double bk = R;
  while (bk > D.epsilon) {
    bk *= D.beta;
    ++kstar;
    if (kstar > 1000000) throw NumericalError("epsilon: k* exceeds 10^6 (beta too close to 1 or epsilon too small)");
  }
  D.k_star = kstar;
  for (int k = 0; k <= kstar; ++k) D.shrinking_index.push_back(std::pow(D.beta, k) * std::sqrt(D.mu * lmax / lmin));

  // interval part [s_k], k < k*, for the centred error e⁺ = A_o e + E Δw
  const Eigen::MatrixXd theta = ao_error_bound(plant.A, D.L, plant.C);
  const Eigen::MatrixXd e_err = sequence_e_err(D);
  const ErrorPowers pw = build_powers(Ao, theta, D.E, e_err, kstar, "L");
  Eigen::VectorXd c0, r0;
  mid_rad(e0, c0, r0);
  const ErrorBoxTable tab = error_box_table(pw, c0, r0, D.w_radius, D.variant);
  const ErrorBoxTable omega =
      error_box_table(pw, Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n), D.w_radius, ErrorRecursion::Tight);
  auto to_box = [&](const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
    std::vector<Interval> iv;
    for (Eigen::Index j = 0; j < n; ++j) iv.push_back(Interval::unchecked(lo(j), hi(j)));
    return Box::from_intervals(iv);
  };
  for (int k = 0; k < kstar; ++k) D.sequence.push_back(to_box(tab.lo_at(k), tab.hi_at(k)));
  // tail [Φ_k*] = box(A_o^k* λΦ_0) + Σ_{i<k*} |A_o^iE| rad(Δw)
  {
    const Eigen::MatrixXd& Mk = pw.M[std::size_t(kstar)];
    const Eigen::MatrixXd V = D.inflation * D.phi0.vertices();
    const Eigen::MatrixXd Y = Mk * V;
    double vmax = 0;
    for (Eigen::Index j = 0; j < V.cols(); ++j) vmax = std::max(vmax, V.col(j).norm());
    const double resid = up(up(pw.d[std::size_t(kstar)] * pw.ctr.sqrt_lmax * up(vmax)) * pw.ctr.inv_sqrt_lmin);
    const Eigen::MatrixXd Yerr = gam(n) * 2 * (Mk.cwiseAbs() * V.cwiseAbs());
    Eigen::VectorXd lo(n), hi(n);
    for (Eigen::Index j = 0; j < n; ++j) {
      double mx = -rounding::kInf, mn = rounding::kInf;
      for (Eigen::Index c = 0; c < Y.cols(); ++c) {
        mx = std::max(mx, rounding::add_up(Y(j, c), up(Yerr(j, c))));
        mn = std::min(mn, rounding::sub_down(Y(j, c), up(Yerr(j, c))));
      }
      const Eigen::VectorXd& ohi = omega.hi_at(kstar);
      const Eigen::VectorXd& olo = omega.lo_at(kstar);
      hi(j) = rounding::add_up(rounding::add_up(mx, ohi(j)), resid);
      lo(j) = rounding::sub_down(rounding::add_down(mn, olo(j)), resid);
    }
    D.sequence.push_back(to_box(lo, hi));
  }
  D.rounding_beta = pw.ctr.beta;
  D.rounding_sqrt_lmax = pw.ctr.sqrt_lmax;
  D.rounding_inv_sqrt_lmin = pw.ctr.inv_sqrt_lmin;
}

}  // namespace iobs_detail

SETBOUND_INLINE InvariantObserverDesign offline_error_sequence(const Plant& plant, const HinfGain& gain, const Box& x0,
                                                      const Eigen::VectorXd& xhat0, const Box& d, const Box& v,
                                                      const InvariantObserverOptions& opt) {
  using namespace iobs_detail;
  const Eigen::Index n = plant.nx();
  require_shape(gain.L, n, plant.ny(), "L");
  require_finite(gain.L, "L");
  require_shape(gain.P, n, n, "P");
  require_positive_definite(gain.P, "P");
  require_positive(gain.gamma, "gamma");
  require_box(x0, n, "x0");
  require_vec(xhat0, n, "xhat0");
  require_box(d, plant.nd(), "d");
  require_box(v, plant.nv(), "v");
  if (!x0.contains(xhat0)) throw InvalidArgumentError("xhat0: must lie in the initial box x0 (thesis §6.3)");
  require_finite(opt.mu, "mu");
  if (!(opt.mu > 1)) throw InvalidArgumentError("mu: must be > 1, got " + num(opt.mu));
  require_finite(opt.epsilon, "epsilon");
  if (!(opt.epsilon > 0)) throw InvalidArgumentError("epsilon: must be > 0 (a radius), got " + num(opt.epsilon));
  require_finite(opt.inflation, "inflation");
  if (opt.inflation != 0 && !(opt.inflation >= 1))
    throw InvalidArgumentError("inflation: must be >= 1 (or 0 for the smallest admissible value), got " +
                               num(opt.inflation));
  if (opt.variant != ErrorRecursion::Tight && opt.variant != ErrorRecursion::Wrapped)
    throw InvalidArgumentError("variant: the offline sequence supports Tight and Wrapped");

  InvariantObserverDesign D{plant};
  D.L = gain.L;
  D.P = 0.5 * (gain.P + gain.P.transpose());
  D.gamma = gain.gamma;
  D.mu = opt.mu;
  D.epsilon = opt.epsilon;
  D.variant = opt.variant;
  D.x0 = x0;
  D.xhat0 = xhat0;
  const Eigen::MatrixXd Ao = plant.A - gain.L * plant.C;
  D.E = plant.error_input(gain.L);
  // the dissipation inequality (4.13) must hold for the values used (Q = I)
  const double g = std::max(gain.g, gain.gamma * gain.gamma);
  if (!hinf_detail::certify_dissipation(D.P, Eigen::MatrixXd::Identity(n, n), Ao, D.E, g, HinfOptions{}.certificate_slack))
    throw InvalidArgumentError("P: (L, P, gamma) do not satisfy the dissipation LMI (4.13); use hinf_observer_gain");
  D.beta = certified_rate(Ao, D.P, "L");
  if (!(D.beta < 1)) throw InvalidArgumentError("L: A - L C is not contractive in the P norm (beta >= 1)");

  const Box w = stack_boxes(d, v);
  mid_rad(w, D.w_center, D.w_radius);
  D.wbar_sq = up(D.w_radius.squaredNorm() * (1 + gam(D.w_radius.size())));
  if (!(D.wbar_sq > 0)) throw InvalidArgumentError("d, v: the disturbance boxes are all degenerate (w̄ = 0)");
  const EllipsoidLevels lv = expanded_ellipsoid_levels(D.P, gain.gamma, D.wbar_sq, opt.mu);
  D.c_in = lv.c_in;
  D.c_out = lv.c_out;
  D.phi0 = polyhedral_rpi_between_ellipsoids(D.P, D.c_in, D.c_out, opt.polytope);

  fill_error_sequence(D, x0, xhat0, opt.inflation);
  const Eigen::MatrixXd e_err = sequence_e_err(D);
  D.Ecw = D.E * D.w_center;
  const Eigen::VectorXd ecw_err = 2 * gam(plant.m() + 2) * (D.E.cwiseAbs() * D.w_center.cwiseAbs()) +
                                  e_err * D.w_center.cwiseAbs();
  D.Ecw_err = up(ecw_err.norm() * (1 + 4 * kEps));
  return D;
}

SETBOUND_INLINE InvariantObserverDesign offline_error_sequence(const Plant& plant, const Box& x0, const Eigen::VectorXd& xhat0,
                                                      const Box& d, const Box& v,
                                                      const InvariantObserverOptions& opt,
                                                      const HinfOptions& hopt) {
  return offline_error_sequence(plant, hinf_observer_gain(plant, Eigen::MatrixXd(), hopt), x0, xhat0, d, v, opt);
}

SETBOUND_INLINE IntervalInvariantObserver::IntervalInvariantObserver(InvariantObserverDesign design)
    : D_(std::move(design)) {
  const Eigen::Index n = D_.plant.nx();
  xhat_ = D_.xhat0;
  xn_.resize(n);
  work_.resize(n);
  innov_.resize(D_.plant.ny());
  innov_mag_.resize(D_.plant.ny());
  lo_.resize(n);
  hi_.resize(n);
  // the boxes of d and v, outward from the design's centred form w = w_c ± rad(Δw)
  const Eigen::Index nd = D_.plant.nd(), nv = D_.plant.nv();
  Eigen::VectorXd wlo(nd + nv), whi(nd + nv);
  for (Eigen::Index i = 0; i < nd + nv; ++i) {
    wlo(i) = rounding::sub_down(D_.w_center(i), D_.w_radius(i));
    whi(i) = rounding::add_up(D_.w_center(i), D_.w_radius(i));
  }
  dbox_ = Box(wlo.head(nd), whi.head(nd), "d");
  vbox_ = Box(wlo.tail(nv), whi.tail(nv), "v");
  screen_.init(D_.plant.ny(), D_.x0);
  rlo_ = D_.x0.lo();
  rhi_ = D_.x0.hi();
  update_bounds();
}

SETBOUND_INLINE const Box& IntervalInvariantObserver::active_box() const {
  if (!restarted_) return D_.box_at(k_);
  return rseq_[std::size_t(std::min<long>(k_ - k0_, long(rseq_.size()) - 1))];
}

SETBOUND_INLINE void IntervalInvariantObserver::restart(const Box& X, long k) {
  Eigen::VectorXd xh = X.mid();
  InvariantObserverDesign D2 = D_;
  iobs_detail::fill_error_sequence(D2, X, xh, 0.0);
  Eigen::VectorXd lo = X.lo(), hi = X.hi();
  // commit (swaps)
  rseq_.swap(D2.sequence);
  rlo_.swap(lo);
  rhi_.swap(hi);
  restarted_ = true;
  k0_ = k;
  k_ = k;
  xhat_.swap(xh);
  xi_ = 0;
  update_bounds();
}

SETBOUND_INLINE void IntervalInvariantObserver::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  using namespace iobs_detail;
  require_reading(y, D_.plant.ny());
  if (D_.plant.nu() > 0) require_vec(u, D_.plant.nu(), "u");
  const Plant& p = D_.plant;
  if (!screen_detail::screen_box_step(screen_, p.C, p.Z, vbox_, lo_, hi_, y, k_)) {
    Eigen::VectorXd lo = lo_, hi = hi_;
    const MeasurementCheck use = screen_detail::apply_reset(screen_, p.C, p.Z, vbox_, y, lo, hi);
    restart(screen_detail::fallback_prediction(p.A, p.B, p.F, p.C, p.Z, lo, hi, y, u, dbox_, vbox_, use), k_ + 1);
    return;
  }
  const double dn = luenberger_update(D_.plant.A, D_.plant.B, D_.plant.C, D_.L, xhat_, u.data(), y.data(),
                                      D_.Ecw.data(), D_.Ecw_err, xn_, innov_, innov_mag_, work_);
  if (!xn_.allFinite()) throw NumericalError("y: the observer state overflowed");
  xhat_.swap(xn_);
  xi_ = up(D_.rounding_beta * xi_ + up(D_.rounding_sqrt_lmax * dn));
  ++k_;
  update_bounds();
}

SETBOUND_INLINE std::vector<double> IntervalInvariantObserver::save_state() const {
  StateWriter w(StateKind::IntervalInvariantObserver, fingerprint());
  w.count(k_).vec(xhat_).scalar(xi_).flag(restarted_).count(k0_).vec(rlo_).vec(rhi_);
  return w.finish();
}

SETBOUND_INLINE void IntervalInvariantObserver::restore_state(const std::vector<double>& state) {
  long long k = 0, k0 = 0;
  Eigen::VectorXd xh, rlo, rhi;
  double xi = 0;
  bool restarted = false;
  std::vector<Box> rseq;
  guard_state_memory(StateKind::IntervalInvariantObserver, [&] {
    const Eigen::Index n = D_.plant.nx();
    StateReader r(state, StateKind::IntervalInvariantObserver, fingerprint());
    k = r.count("steps");
    xh = r.vec(n, "xhat");
    xi = r.scalar("rounding residue");
    restarted = r.flag("restarted");
    k0 = r.count("restart step");
    rlo = r.vec(n, "restart lower");
    rhi = r.vec(n, "restart upper");
    r.finish();
    if (!(xi >= 0)) r.fail("rounding residue must be >= 0");
    if (k0 > k || (!restarted && k0 != 0)) r.fail("restart step must be 0 or at most the step count");
    if ((rhi.array() < rlo.array()).any()) r.fail("restart box has lower > upper");
    if (restarted) {
      const Box X(rlo, rhi, "restart box");
      InvariantObserverDesign D2 = D_;
      iobs_detail::fill_error_sequence(D2, X, X.mid(), 0.0);
      rseq.swap(D2.sequence);
    }
  });
  // Commit (swaps; update_bounds writes into sized buffers: nothing throws).
  k_ = static_cast<long>(k);
  k0_ = static_cast<long>(k0);
  restarted_ = restarted;
  rseq_.swap(rseq);
  rlo_.swap(rlo);
  rhi_.swap(rhi);
  xhat_.swap(xh);
  xi_ = xi;
  update_bounds();
}

SETBOUND_INLINE StateFingerprint IntervalInvariantObserver::fingerprint() const {
  StateFingerprint f;
  const Plant& p = D_.plant;
  f.add(p.A).add(p.B).add(p.C).add(p.F).add(p.Z).add(D_.L).add(D_.Ecw).add(D_.Ecw_err).add(D_.rounding_beta);
  for (const Box& b : D_.sequence) f.add(b.lo()).add(b.hi());
  return f;
}

SETBOUND_INLINE void IntervalInvariantObserver::update_bounds() {
  using namespace rounding;
  const Box& s = active_box();
  const double xs = iobs_detail::up(xi_ * D_.rounding_inv_sqrt_lmin);
  for (Eigen::Index j = 0; j < xhat_.size(); ++j) {
    lo_(j) = sub_down(add_down(xhat_(j), s.lo()(j)), xs);
    hi_(j) = add_up(add_up(xhat_(j), s.hi()(j)), xs);
  }
}

}  // namespace thesis
}  // namespace setbound
