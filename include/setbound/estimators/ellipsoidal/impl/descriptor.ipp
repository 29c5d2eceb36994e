// setbound — definitions of the functions declared in setbound/estimators/ellipsoidal/descriptor.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/ellipsoidal/descriptor.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE DescriptorSystem::DescriptorSystem(Eigen::MatrixXd E, Eigen::MatrixXd A, Eigen::MatrixXd C, Eigen::MatrixXd D, Eigen::MatrixXd F,
                   Eigen::MatrixXd B)
    : E_(std::move(E)), A_(std::move(A)), B_(std::move(B)), C_(std::move(C)), D_(std::move(D)), F_(std::move(F)) {
  if (A_.rows() == 0) throw DimensionError("A: the state dimension must be >= 1");
  require_square(A_, "A");
  require_finite(A_, "A");
  const Eigen::Index n = A_.rows();
  require_shape(E_, n, n, "E");
  require_finite(E_, "E");
  if (C_.cols() != n || C_.rows() == 0)
    throw DimensionError("C: expected shape (n_y, " + std::to_string(n) + ") with n_y >= 1, got " +
                         detail::shape_string(C_.rows(), C_.cols()));
  require_finite(C_, "C");
  const Eigen::Index ny = C_.rows();
  if (D_.rows() != n)
    throw DimensionError("D: expected " + std::to_string(n) + " rows (the state dimension), got " +
                         std::to_string(D_.rows()));
  require_finite(D_, "D");
  require_shape(F_, ny, D_.cols(), "F");
  require_finite(F_, "F");
  if (B_.size() == 0) B_ = Eigen::MatrixXd::Zero(n, 0);
  if (B_.rows() != n)
    throw DimensionError("B: expected " + std::to_string(n) + " rows (the state dimension), got " +
                         std::to_string(B_.rows()));
  require_finite(B_, "B");

  // Infinite observability and [T N] = pinv([E; C]).
  Eigen::MatrixXd M(n + ny, n);
  M << E_, C_;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double tol = 1e-10 * std::max(1.0, sv(0));
  Eigen::Index rank = 0;
  while (rank < sv.size() && sv(rank) > tol) ++rank;
  if (rank < n)
    throw NotDetectableError("E, C: the infinite observability condition rank [E; C] = n_x fails (rank " +
                             std::to_string(rank) + " < n_x = " + std::to_string(n) +
                             "): no T, N with T E + N C = I exist (setbound docs: Methods › Ellipsoidal estimation › Descriptor systems)");
  Eigen::MatrixXd pinv = svd.matrixV() * sv.cwiseInverse().asDiagonal() * svd.matrixU().transpose();
  // pinv(M) = (MᵀM)⁻¹Mᵀ: the column of a zero row of M is exactly zero (the SVD leaves
  // rounding noise there, which would keep a disturbance column that does not exist).
  for (Eigen::Index r = 0; r < n + ny; ++r)
    if (!(M.row(r).array() != 0.0).any()) pinv.col(r).setZero();
  T_ = pinv.leftCols(n);
  N_ = pinv.rightCols(ny);
  TA_ = T_ * A_;

  // Finite observability at the eigenvalues of T A (see above).
  Eigen::EigenSolver<Eigen::MatrixXd> eig(TA_, false);
  if (eig.info() != Eigen::Success) throw NumericalError("A: eigenvalues of T A did not converge");
  const double scale_EA = std::max({1.0, E_.norm(), A_.norm(), C_.norm()});
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::complex<double> lambda = eig.eigenvalues()(i);
    Eigen::MatrixXcd Ml(n + ny, n);
    Ml.topRows(n) = lambda * E_.cast<std::complex<double>>() - A_.cast<std::complex<double>>();
    Ml.bottomRows(ny) = C_.cast<std::complex<double>>();
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXcd>(Ml).singularValues();
    if (s(n - 1) <= 1e-9 * scale_EA * std::max(1.0, std::abs(lambda))) {
      std::ostringstream msg;
      msg << "E, A, C: the finite observability condition rank [lambda E - A; C] = n_x fails at lambda = "
          << lambda.real();
      if (lambda.imag() != 0) msg << (lambda.imag() > 0 ? " + " : " - ") << std::abs(lambda.imag()) << "i";
      msg << " (a finite mode that C does not see; setbound docs: Methods › Ellipsoidal estimation › Descriptor systems)";
      throw NotDetectableError(msg.str());
    }
  }
}

SETBOUND_INLINE LinearSystem DescriptorSystem::equivalent() const {
  const Eigen::Index n = nx(), ny_ = ny(), nw_ = nw();
  Eigen::MatrixXd Eeq(n, 2 * nw_), Feq(ny_, 2 * nw_);
  Eeq << T_ * D_, -(N_ * F_);
  Feq << F_, Eigen::MatrixXd::Zero(ny_, nw_);
  return LinearSystem(TA_, C_, Eeq, Feq, T_ * B_);
}

SETBOUND_INLINE EllDesign design_descriptor_offline(const DescriptorSystem& sys, const EllDesignOptions& opt) {
  return detail::ell_design_impl(sys.equivalent(), opt, "design_descriptor_offline", "(C, TA)");
}

SETBOUND_INLINE DescriptorEstimator::DescriptorEstimator(EllDesign design, DescriptorSystem sys, const Ellipsoid& x0)
    : d_(std::move(design)), sys_(std::move(sys)), eq_(sys_.equivalent()), cur_(check(d_, sys_, x0)) {
  const Eigen::Index n = sys_.nx(), ny = sys_.ny();
  detail::ell_check_design_values(d_, ny);
  // The design must hold for *this* system's equivalent (whatever system it was made for).
  const detail::EllLmiData data(eq_);
  const std::vector<Eigen::VectorXd> omegas = detail::ell_box_vertices(data.m(), true);
  if (data.m() > 24 || omegas.size() > detail::kMaxEllVertexBlocks)
    throw InvalidArgumentError("sys: too many disturbance columns for the vertex LMIs");
  const detail::EllGainTerms terms(d_.P, d_.L, data, data.Et, data.Ft);
  if (!detail::ell_certify_design(d_.P, terms, data, omegas, d_.beta, d_.sigma))
    throw InvalidArgumentError("design: the descriptor LMI (setbound docs: Methods › Ellipsoidal estimation › Descriptor systems) does not hold (certified) at the design's "
                               "(P, L, beta, sigma) for this descriptor system");
  lmax_up_ = ell_rounding::lambda_max_upper(d_.P);
  lmin_low_ = detail::ell_lambda_min_lower(d_.P);
  if (!(lmin_low_ > 0)) throw NumericalError("design.P: its smallest eigenvalue could not be bounded away from 0");
  // Rounding of the stored T, N and of the products T A, T B, T D, N F (module comment).
  using ell_rounding::gamma;
  const Eigen::MatrixXd aT = sys_.T().cwiseAbs(), aN = sys_.N().cwiseAbs();
  dA_ = gamma(n + 1) * aT * sys_.A().cwiseAbs();
  dB_ = gamma(n + 1) * aT * sys_.B().cwiseAbs();
  dw_ = (gamma(n + 1) * aT * sys_.D().cwiseAbs()).rowwise().sum() +
        (gamma(ny + 1) * aN * sys_.F().cwiseAbs()).rowwise().sum();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd Rb = (sys_.T() * sys_.E() + sys_.N() * sys_.C() - I).cwiseAbs() +
                             2.0 * gamma(n + ny + 2) * (aT * sys_.E().cwiseAbs() + aN * sys_.C().cwiseAbs() + I);
  r_ = ell_rounding::round_up(Rb.norm() * (1.0 + 1e-10));
  den_ = 1.0 - r_ * std::sqrt(lmax_up_ / lmin_low_) * (1.0 + 1e-10);
  if (!(den_ > 0.5))
    throw NumericalError("sys: T E + N C = I holds too inaccurately for the conditioning of design.P");
}

SETBOUND_INLINE Ellipsoid DescriptorEstimator::step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  using ell_rounding::gamma;
  using ell_rounding::round_up;
  detail::require_length(y.size(), sys_.ny(), "y");
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (std::isnan(y(i)))
      throw NotFiniteError("y: entry " + std::to_string(i) +
                           " is NaN (a missing reading): the descriptor estimator needs every output, the state "
                           "of a descriptor system is fixed through N y_k (setbound docs: Methods › Ellipsoidal estimation › Descriptor systems); use an explicit model");
  require_finite(y, "y");
  if (!(u.size() == sys_.nu() || (u.size() == 0 && sys_.nu() == 0)))
    detail::require_length(u.size(), sys_.nu(), "u");
  require_finite(u, "u");
  if (!started_) {
    y_prev_ = y;
    u_prev_ = u;
    started_ = true;
    return cur_;
  }
  const Eigen::MatrixXd& TA = eq_.A();
  const Eigen::MatrixXd& TB = eq_.B();
  const Eigen::MatrixXd& N = sys_.N();
  const Eigen::MatrixXd& C = sys_.C();
  const Eigen::VectorXd& c = cur_.center();
  const Eigen::VectorXd yv = y;
  const Eigen::VectorXd cn = TA * c + TB * u_prev_ + N * yv + d_.L * (y_prev_ - C * c);
  // Centre rounding, with the N y_{k+1} term.
  Eigen::VectorXd mag = TA.cwiseAbs() * c.cwiseAbs() + N.cwiseAbs() * yv.cwiseAbs() +
                        d_.L.cwiseAbs() * (y_prev_.cwiseAbs() + C.cwiseAbs() * c.cwiseAbs());
  if (TB.cols() > 0) mag += TB.cwiseAbs() * u_prev_.cwiseAbs();
  const Eigen::Index k = TA.cols() + TB.cols() + N.cols() + d_.L.cols() + 6;
  const Eigen::VectorXd dc = round_up(2.0 * gamma(k)) * mag;
  // ‖w‖_P ≤ √(βρ + σ) for the nominal error; model error e as in the module comment:
  // ‖z⁺‖_P ≤ [√ρ_nom + √λmax (a + r ‖x̄⁺‖)] / (1 − r √(λmax/λmin)).
  const double rho_nom = round_up(round_up(d_.beta * cur_.level()) + d_.sigma);
  const BoundingBox box = cur_.bounding_box();
  const Eigen::VectorXd xabs = box.lo.cwiseAbs().cwiseMax(box.hi.cwiseAbs());
  Eigen::VectorXd ev = dA_ * xabs + dw_;
  if (dB_.cols() > 0) ev += dB_ * u_prev_.cwiseAbs();
  const double a = round_up(ev.norm() * (1.0 + 1e-10));
  const double xn = round_up(cn.norm() + round_up(dc.norm()));
  const double sl = std::sqrt(lmax_up_) * (1.0 + 1e-15);
  const double num = round_up(std::sqrt(rho_nom) * (1.0 + 1e-15) + sl * round_up(a + r_ * xn));
  const double root = round_up(num / den_);
  const double rho_mid = round_up(root * root);
  const double rn = level_with_center_error(rho_mid, lmax_up_, dc);
  Ellipsoid next(d_.P, cn, rn);
  cur_ = next;
  y_prev_ = yv;
  u_prev_ = u;
  ++k_;
  return next;
}

SETBOUND_INLINE std::vector<double> DescriptorEstimator::save_state() const {
  StateWriter w(StateKind::DescriptorEstimator, fingerprint());
  w.count(k_).flag(started_).mat(cur_.shape()).vec(cur_.center()).scalar(cur_.level());
  w.vec(started_ ? y_prev_ : Eigen::VectorXd()).vec(started_ ? u_prev_ : Eigen::VectorXd());
  return w.finish();
}

SETBOUND_INLINE void DescriptorEstimator::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k;
    bool started;
    std::unique_ptr<Ellipsoid> cur;
    Eigen::VectorXd yp, up;
  };
  Parsed q = guard_state_memory(StateKind::DescriptorEstimator, [&] {
    const Eigen::Index n = sys_.nx();
    StateReader r(state, StateKind::DescriptorEstimator, fingerprint());
    Parsed t;
    t.k = r.count("steps");
    t.started = r.flag("started");
    Eigen::MatrixXd P = r.mat(n, n, "shape");
    Eigen::VectorXd c = r.vec(n, "center");
    const double rho = r.scalar("level");
    // The lengths are known (n_y, n_u or 0): a wrong one is refused before anything is read.
    t.yp = r.vec(t.started ? sys_.ny() : 0, "y_prev");
    t.up = r.vec(t.started ? sys_.nu() : 0, "u_prev");
    r.finish();
    if (!t.started && t.k != 0) r.fail("steps must be 0 before the first measurement");
    try {
      t.cur = std::make_unique<Ellipsoid>(std::move(P), std::move(c), rho);
    } catch (const Error& e) {
      r.fail(std::string("the saved set is invalid (") + e.what() + ")");
    }
    return t;
  });
  // Commit (moves and swaps: nothing throws).
  cur_ = std::move(*q.cur);
  k_ = static_cast<Eigen::Index>(q.k);
  started_ = q.started;
  y_prev_.swap(q.yp);
  u_prev_.swap(q.up);
}

SETBOUND_INLINE StateFingerprint DescriptorEstimator::fingerprint() const {
  StateFingerprint f;
  f.add(d_.P).add(d_.L).add(d_.beta).add(d_.sigma);
  f.add(sys_.E()).add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.F());
  return f;
}

SETBOUND_INLINE Ellipsoid DescriptorEstimator::check(const EllDesign& d, const DescriptorSystem& sys, const Ellipsoid& x0) {
  const Eigen::Index n = sys.nx();
  require_shape(d.P, n, n, "design.P");
  require_positive_definite(d.P, "design.P");
  if (x0.dimension() != n)
    throw DimensionError("x0: expected an ellipsoid of dimension " + std::to_string(n) + ", got " +
                         std::to_string(x0.dimension()));
  return x0.with_shape(0.5 * (d.P + d.P.transpose()));
}

}  // namespace setbound
