// setbound — definitions of the functions declared in setbound/estimators/zonotopic/gain_estimator.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "setbound/core/config.hpp"

namespace setbound {

SETBOUND_INLINE Eigen::VectorXd segment_min_gain(const Zonotope& Z, const StripMeasurement& m) {
  const Eigen::VectorXd& c = m.strip.normal();
  const Eigen::VectorXd g = Z.generators() * (Z.generators().transpose() * c);
  const double phi = m.strip.half_width();
  const double denom = c.dot(g) + phi * phi;
  if (!(denom > 0)) return Eigen::VectorXd::Zero(Z.dimension());
  return g / denom;
}

SETBOUND_INLINE ZonotopeGain::ZonotopeGain(Function f)
    : rule_(f) {  // NOLINT: implicit, as a function is a rule
  if (f == &segment_min_gain) kind_ = Kind::SegmentMin;
}

SETBOUND_INLINE ZonotopeGain::ZonotopeGain(ZonotopeGainRule rule)
    : rule_(std::move(rule)) {  // NOLINT
  if (const Function* f = rule_.target<Function>(); f && *f == &segment_min_gain) kind_ = Kind::SegmentMin;
  if (const ZonotopeGain* g = rule_.target<ZonotopeGain>()) *this = ZonotopeGain(*g);
}

SETBOUND_INLINE ZonotopeGain ZonotopeGain::fixed(Eigen::MatrixXd lambdas) {
  require_finite(lambdas, "lambdas");
  ZonotopeGain g;
  g.kind_ = Kind::Fixed;
  g.lambdas_ = std::move(lambdas);
  return g;
}

SETBOUND_INLINE ZonotopeGain::operator bool() const { return kind_ != Kind::Custom || static_cast<bool>(rule_); }

SETBOUND_INLINE Eigen::VectorXd ZonotopeGain::operator()(const Zonotope& Z, const StripMeasurement& m) const {
  switch (kind_) {
    case Kind::SegmentMin: return segment_min_gain(Z, m);
    case Kind::Fixed: return lambdas_.row(m.output).transpose();
    default: return rule_(Z, m);
  }
}

SETBOUND_INLINE ZonotopicEstimator::ZonotopicEstimator(LinearSystem system, const Zonotope& x0, ZonotopeGain gain, ZonotopicOptions options)
    : sys_(std::move(system)), gain_(std::move(gain)), opt_(std::move(options)), x0_(x0), reset_set_(x0) {
  const Eigen::Index n = sys_.nx(), ny = sys_.ny();
  if (x0.dimension() != n)
    throw DimensionError("x0: expected a zonotope of dimension " + std::to_string(n) + ", got " +
                         std::to_string(x0.dimension()));
  if (!gain_) throw InvalidArgumentError("rule: a gain rule is required");
  if (gain_.kind() == ZonotopeGain::Kind::Fixed &&
      (gain_.lambdas().rows() != ny || gain_.lambdas().cols() != n))
    throw DimensionError("lambdas: expected shape " + detail::shape_string(ny, n) + ", got " +
                         detail::shape_string(gain_.lambdas().rows(), gain_.lambdas().cols()));
  if (opt_.max_generators < n)
    throw InvalidArgumentError("max_generators: must be >= n_x = " + std::to_string(n) + ", got " +
                               std::to_string(opt_.max_generators));
  if (opt_.strip_order.empty()) {
    opt_.strip_order.resize(static_cast<std::size_t>(ny));
    std::iota(opt_.strip_order.begin(), opt_.strip_order.end(), Eigen::Index{0});
  } else {
    std::vector<bool> seen(static_cast<std::size_t>(ny), false);
    if (static_cast<Eigen::Index>(opt_.strip_order.size()) != ny)
      throw InvalidArgumentError("strip_order: must be a permutation of 0..n_y-1");
    for (Eigen::Index i : opt_.strip_order) {
      if (i < 0 || i >= ny || seen[static_cast<std::size_t>(i)])
        throw InvalidArgumentError("strip_order: must be a permutation of 0..n_y-1");
      seen[static_cast<std::size_t>(i)] = true;
    }
  }
  setup_model();
  allocate(x0.remove_zero_generators().num_generators());
  set_inconsistency_policy(opt_.on_inconsistency, x0);  // validates the policy; reset set = x0
  load_prior(x0);
  chk_.clear(ny);
  last_check_.clear(ny);
}

SETBOUND_INLINE void ZonotopicEstimator::set_inconsistency_policy(OnInconsistency policy) {
  set_inconsistency_policy(policy, x0_);
}

SETBOUND_INLINE void ZonotopicEstimator::set_inconsistency_policy(OnInconsistency policy, const Zonotope& reset_set) {
  if (static_cast<int>(policy) < 0 || static_cast<int>(policy) > 2)
    throw InvalidArgumentError("on_inconsistency: must be Flag, Raise or Reset");
  if (reset_set.dimension() != n_)
    throw DimensionError("reset_set: expected a zonotope of dimension " + std::to_string(n_) + ", got " +
                         std::to_string(reset_set.dimension()));
  Zonotope r = reset_set.remove_zero_generators();
  const Eigen::Index limit = cap_ - capN_ - n_;  // the generator capacity of the prior
  if (r.num_generators() > limit)
    throw InvalidArgumentError("reset_set: at most " + std::to_string(limit) +
                               " generators (max_generators or those of x0), got " +
                               std::to_string(r.num_generators()));
  opt_.on_inconsistency = policy;
  reset_set_ = std::move(r);
}

SETBOUND_INLINE void ZonotopicEstimator::reset() {
  load_prior(x0_);
  k_ = 0;
  has_current_ = false;
  reduced_ = false;
  m_ = 0;
  cur_p_.setZero();
  cur_r_.setZero();
  cur_w_.setZero();
  cur_lo_.setZero();
  cur_hi_.setZero();
  last_check_.clear(sys_.ny());
}

SETBOUND_INLINE Zonotope ZonotopicEstimator::prediction() const {
  Eigen::MatrixXd H(n_, mG() + mN_);
  Eigen::VectorXd r = rP_;
  materialize_prior(H, r);
  return with_box(p_, H, r);
}

SETBOUND_INLINE void ZonotopicEstimator::update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (y.size() != sys_.ny())
    throw DimensionError("y: expected length " + std::to_string(sys_.ny()) + ", got " + std::to_string(y.size()));
  if (u.size() != sys_.nu())
    throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u.size()));
  require_no_infinity(y, "y");
  require_finite(u, "u");
  const bool correct = !(k_ == 0 && !opt_.use_first_measurement);
  correct_and_reduce(y, u, correct);  // may throw (policy Raise, a gain rule); commits last
  if (correct && opt_.on_inconsistency == OnInconsistency::Reset && chk_.flagged()) {
    // Restart from the reset set and correct it with this step's outputs (those inconsistent
    // with it are skipped). The report keeps the test that triggered the reset.
    const MeasurementCheck trigger = chk_;
    const std::vector<double> before = save_state();
    try {
      load_prior(reset_set_);
      correct_and_reduce(y, u, true);
    } catch (...) {
      restore_state(before);
      throw;
    }
    last_check_ = trigger;
    last_check_.reset = true;
  }
  predict_prior(u);
  ++k_;
}

SETBOUND_INLINE Eigen::Index ZonotopicEstimator::current_num_generators() const {
  return m_ + static_cast<Eigen::Index>((cur_r_.array() > 0).count());
}

SETBOUND_INLINE Zonotope ZonotopicEstimator::current_set() const {
  if (!has_current_) throw InvalidArgumentError("estimator: no step has been taken yet");
  return with_box(cur_p_, H_[cur_].leftCols(m_), cur_r_);
}

SETBOUND_INLINE ZonotopeTrajectory ZonotopicEstimator::run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U) {
  const Eigen::Index N = Y.rows();
  if (Y.cols() != sys_.ny())
    throw DimensionError("y: expected " + std::to_string(sys_.ny()) + " columns, got " + std::to_string(Y.cols()));
  if (sys_.nu() > 0) require_shape(U, N, sys_.nu(), "u");
  ZonotopeTrajectory t{Eigen::MatrixXd(N, n_), Eigen::MatrixXd(N, n_), Eigen::MatrixXd(N, n_), {}, {}};
  t.sets.reserve(static_cast<std::size_t>(N));
  t.checks.reserve(static_cast<std::size_t>(N));
  reset();
  const Eigen::VectorXd no_input(0);
  for (Eigen::Index k = 0; k < N; ++k) {
    if (sys_.nu() > 0) update(Y.row(k).transpose(), U.row(k).transpose());
    else update(Y.row(k).transpose(), no_input);
    t.center.row(k) = cur_p_.transpose();
    t.lower.row(k) = cur_lo_.transpose();
    t.upper.row(k) = cur_hi_.transpose();
    t.sets.push_back(current_set());
    t.checks.push_back(last_check_);
  }
  return t;
}

SETBOUND_INLINE Zonotope ZonotopicEstimator::correct(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                   const Eigen::Ref<const Eigen::VectorXd>& u) const {
  detail::require_length(X.dimension(), n_, "X");
  detail::require_length(y.size(), sys_.ny(), "y");
  detail::require_length(u.size(), sys_.nu(), "u");
  require_no_infinity(y, "y");
  require_finite(u, "u");
  ZonotopicEstimator tmp(sys_, X, gain_, opt_);
  tmp.k_ = k_;
  tmp.correct_and_reduce(y, u, true);
  return tmp.current_set();
}

SETBOUND_INLINE Zonotope ZonotopicEstimator::predict(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& u) const {
  detail::require_length(X.dimension(), n_, "X");
  detail::require_length(u.size(), sys_.nu(), "u");
  require_finite(u, "u");
  ZonotopicEstimator tmp(sys_, X, gain_, opt_);
  tmp.correct_and_reduce(Eigen::VectorXd::Zero(sys_.ny()), u, false);
  tmp.predict_prior(u);
  return tmp.prediction();
}

SETBOUND_INLINE std::vector<double> ZonotopicEstimator::save_state() const {
  StateWriter w(StateKind::ZonotopicEstimator, fingerprint());
  const Eigen::Index mh = std::max(mG_, m_);
  w.count(k_).flag(has_current_).flag(reduced_).count(static_cast<int>(opt_.reduction));
  w.count(cap_).count(mG_).count(mN_).count(m_).flag(T_identity_);
  w.vec(p_).vec(rA_).vec(rP_).vec(wG_).mat(T_).mat(N_.leftCols(mN_)).mat(S_);
  w.mat(H_[cur_].leftCols(mh)).vec(cur_p_).vec(cur_r_).vec(cur_w_).vec(cur_lo_).vec(cur_hi_);
  return w.finish();
}

SETBOUND_INLINE void ZonotopicEstimator::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k, method, mG, mN, m;
    bool has_cur, red, Tid;
    Vec p, rA, rP, wG, cp, cr, cw, clo, chi;
    Mat T, N, S, H, H0, H1;
  };
  Parsed q = guard_state_memory(StateKind::ZonotopicEstimator, [&] {
    StateReader r(state, StateKind::ZonotopicEstimator, fingerprint());
    Parsed t;
    t.k = r.count("steps");
    t.has_cur = r.flag("has_current");
    t.red = r.flag("reduced_last_step");
    t.method = r.count("reduction", 1, 3);
    const long long s = opt_.max_generators, minimum_cap = s + capN_ + n_;
    const long long cap = r.count("capacity", minimum_cap);
    t.mG = r.count("prior generators", 0, cap - capN_ - n_);
    // A prior after a step holds E's non-zero columns and, for [A], up to 2n box columns; the
    // correction appends one column per output, so N's capacity capN_ is never exceeded.
    const long long nE = Enz_.cols(), nN = t.has_cur ? nE + (interval_ ? 2 * n_ : 0) : 0;
    t.mN = r.count("prior new generators", t.has_cur ? nE : 0, nN);
    t.m = r.count("current generators", 0, cap);
    t.Tid = r.flag("T_identity");
    t.p = r.vec(n_, "p");
    t.rA = r.vec(n_, "rA");
    t.rP = r.vec(n_, "rP");
    t.wG = r.vec(n_, "wG");
    t.T = r.mat(n_, n_, "T");
    t.N = r.mat(n_, t.mN, "N");
    t.S = r.mat(n_, n_, "S");
    t.H = r.mat(n_, std::max(t.mG, t.m), "generators");
    t.cp = r.vec(n_, "current center");
    t.cr = r.vec(n_, "current box");
    t.cw = r.vec(n_, "current row sums");
    t.clo = r.vec(n_, "current lower");
    t.chi = r.vec(n_, "current upper");
    r.finish();
    // The invariants the steps rely on (a violated one is a corrupted state, not a set).
    if (t.has_cur) {
      if (t.k == 0) r.fail("a current set needs steps >= 1");
      if (t.m != t.mG) r.fail("current generators must equal prior generators after a step");
    } else {
      // Before the first step the prior is x0 itself: T = I, no box, no new generators. (Its
      // capacity may exceed the one of x0: a restore keeps larger work arrays.)
      if (t.k != 0 || t.m != 0) r.fail("steps and current generators must be 0 before the first step");
      if (!t.Tid || !t.rA.isZero(0) || !t.rP.isZero(0))
        r.fail("before the first step the prior must be the initial set (T = I, no rounding box)");
    }
    if (t.Tid && !t.T.isIdentity(0)) r.fail("T is flagged as the identity but is not");
    if ((t.rA.array() < 0).any() || (t.rP.array() < 0).any() || (t.cr.array() < 0).any() ||
        (t.wG.array() < 0).any() || (t.cw.array() < 0).any())
      r.fail("a box radius or row sum is negative");
    if (t.has_cur && ((t.clo.array() > t.cp.array()).any() || (t.chi.array() < t.cp.array()).any()))
      r.fail("the current hull does not contain the current center");
    // Work arrays: a step writes at most mG + capN_ + n_ columns (prior, new columns, box).
    const Eigen::Index need = static_cast<Eigen::Index>(std::max(t.mG, s)) + capN_ + n_;
    if (need > cap_) {
      t.H0.resize(n_, need);
      t.H1.resize(n_, need);
    }
    return t;
  });
  // Commit: moves, swaps and copies into buffers already large enough (nothing throws).
  if (q.H0.cols() > cap_) {
    H_[0].swap(q.H0);
    H_[1].swap(q.H1);
    cap_ = H_[0].cols();
  }
  opt_.reduction = static_cast<ZonotopeReduction>(q.method);
  k_ = static_cast<Eigen::Index>(q.k);
  has_current_ = q.has_cur;
  reduced_ = q.red;
  mG_ = static_cast<Eigen::Index>(q.mG);
  mN_ = static_cast<Eigen::Index>(q.mN);
  m_ = static_cast<Eigen::Index>(q.m);
  T_identity_ = q.Tid;
  p_.swap(q.p);
  rA_.swap(q.rA);
  rP_.swap(q.rP);
  wG_.swap(q.wG);
  T_.swap(q.T);
  N_.leftCols(mN_) = q.N;
  S_.swap(q.S);
  cur_ = 0;
  H_[0].leftCols(q.H.cols()) = q.H;
  cur_p_.swap(q.cp);
  cur_r_.swap(q.cr);
  cur_w_.swap(q.cw);
  cur_lo_.swap(q.clo);
  cur_hi_.swap(q.chi);
}

SETBOUND_INLINE StateFingerprint ZonotopicEstimator::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.A_rad()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F());
  f.add_int(static_cast<int>(gain_.kind())).add(gain_.lambdas());
  f.add_int(opt_.max_generators).add_int(opt_.use_first_measurement ? 1 : 0);
  for (Eigen::Index i : opt_.strip_order) f.add_int(i);
  return f;
}

SETBOUND_INLINE Zonotope ZonotopicEstimator::with_box(const Vec& p, const Eigen::Ref<const Mat>& H, const Vec& r) {
  const Eigen::Index n = p.size(), m = H.cols();
  const Eigen::Index nb = static_cast<Eigen::Index>((r.array() > 0).count());
  Mat out(n, m + nb);
  out.leftCols(m) = H;
  Eigen::Index j = m;
  for (Eigen::Index i = 0; i < n; ++i)
    if (r(i) > 0) {
      out.col(j).setZero();
      out(i, j++) = r(i);
    }
  return Zonotope(p, std::move(out));
}

SETBOUND_INLINE void ZonotopicEstimator::setup_model() {
  n_ = sys_.nx();
  const Eigen::Index ny = sys_.ny();
  lazy_ = gain_.kind() != ZonotopeGain::Kind::Custom;
  want_S_ = gain_.kind() == ZonotopeGain::Kind::SegmentMin;
  interval_ = sys_.uncertain_A();
  absMid_ = sys_.A().cwiseAbs();
  absA_ = absMid_ + sys_.A_rad();
  std::vector<Eigen::Index> cols;
  for (Eigen::Index j = 0; j < sys_.nw(); ++j)
    if (sys_.E().col(j).cwiseAbs().maxCoeff() > 0) cols.push_back(j);
  Enz_.resize(n_, static_cast<Eigen::Index>(cols.size()));
  for (std::size_t j = 0; j < cols.size(); ++j) Enz_.col(static_cast<Eigen::Index>(j)) = sys_.E().col(cols[j]);
  EEt_.noalias() = Enz_ * Enz_.transpose();
  Ct_ = sys_.C().transpose();
  absCt_ = Ct_.cwiseAbs();
  phi_.resize(ny);
  D_used_.assign(static_cast<std::size_t>(ny), false);
  c_zero_.assign(static_cast<std::size_t>(ny), false);
  for (Eigen::Index i = 0; i < ny; ++i) {
    // A zero row of C (a sensor that measures only noise, or only D u) says nothing about x:
    // its strip is the whole space and is skipped by every gain rule (the Strip of a custom
    // rule could not even be formed), so the result equals the one without that output.
    c_zero_[static_cast<std::size_t>(i)] = sys_.C().row(i).cwiseAbs().maxCoeff() == 0.0;
    // φ_i = Σ_j |F_ij|, rounded up when more than one term is summed.
    const Eigen::Index terms = (sys_.F().row(i).array() != 0).count();
    phi_(i) = sys_.output_noise_bound(i) *
              (terms > 1 ? 1.0 + static_cast<double>(terms + 2) * std::numeric_limits<double>::epsilon() : 1.0);
    D_used_[static_cast<std::size_t>(i)] = sys_.nu() > 0 && sys_.D().row(i).cwiseAbs().maxCoeff() > 0;
  }
  absB_ = sys_.B().cwiseAbs();
  absD_ = sys_.D().cwiseAbs();
}

SETBOUND_INLINE void ZonotopicEstimator::allocate(Eigen::Index m0) {
  capN_ = Enz_.cols() + (interval_ ? 2 * n_ : 0) + sys_.ny();
  cap_ = std::max(m0, opt_.max_generators) + capN_ + n_;
  for (Mat& H : H_) H.resize(n_, cap_);
  N_.resize(n_, capN_);
  Nc_.resize(n_, capN_);
  T_.resize(n_, n_);
  Tc_.resize(n_, n_);
  S_ = Mat::Zero(n_, n_);
  Sc_ = Mat::Zero(n_, n_);
  p_ = rA_ = rP_ = wG_ = Vec::Zero(n_);
  pc_ = rc_ = wH_ = wGA_ = Vec::Zero(n_);
  cur_p_ = cur_r_ = cur_lo_ = cur_hi_ = cur_w_ = Vec::Zero(n_);
  lam_ = sc_ = v_ = t_ = e_ = Vec::Zero(n_);
  uabs_ = Vec::Zero(sys_.nu());
  absT_ = Mat::Zero(n_, n_);
  cN_ = Vec::Zero(capN_);
  detail::reserve_reduction_workspace(rws_, n_, cap_);
}

SETBOUND_INLINE void ZonotopicEstimator::load_prior(const Zonotope& X) {
  const Zonotope Xn = X.remove_zero_generators();
  p_ = Xn.center();
  mG_ = Xn.num_generators();
  H_[cur_].leftCols(mG_) = Xn.generators();
  wG_ = detail::abs_row_sums(Xn.generators());
  if (mG_ == 0) wG_.setZero();
  T_.setIdentity();
  T_identity_ = true;
  mN_ = 0;
  rA_.setZero();
  rP_.setZero();
  if (want_S_) S_.noalias() = Xn.generators() * Xn.generators().transpose();
}

SETBOUND_INLINE void ZonotopicEstimator::correct_and_reduce(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, bool correct) {
  using rounding_bounds::gamma;
  const int work = 1 - cur_;
  Mat& W = H_[work];
  pc_ = p_;
  rc_ = rP_;
  Eigen::Index mW = 0;
  chk_.clear(sys_.ny(), correct ? OutputStatus::Used : OutputStatus::Unused);
  for (Eigen::Index i = 0; i < sys_.ny(); ++i)
    if (std::isnan(y(i))) chk_.status[static_cast<std::size_t>(i)] = OutputStatus::Missing;
  const double g = gamma(n_ + 2), g1 = 1.0 + g;
  // The columns the transform T acts on: G and the carried box diag(rA); rs|[G, diag(rA)]|.
  wGA_ = wG_ + rA_;
  if (lazy_ && correct) {
    Tc_ = T_;
    bool Tc_identity = T_identity_;
    Nc_.leftCols(mN_) = N_.leftCols(mN_);
    Eigen::Index mN = mN_;
    if (want_S_) Sc_ = S_;
    for (Eigen::Index i : opt_.strip_order) {
      if (std::isnan(y(i))) continue;  // missing (chk_ says so)
      const auto c = Ct_.col(i);
      const auto ac = absCt_.col(i);
      double phi = 0.0;
      const double yi = shifted_measurement(i, y, u, phi);
      {
        // Support of the set before this strip in direction c: |(Tᵀc)ᵀG|₁ + |Tᵀc|ᵀrA + |Nᵀc|₁
        // + |c|ᵀrc; its magnitude bounds the rounding of that computation.
        double radius = ac.dot(rc_), magnitude = ac.dot(pc_.cwiseAbs()) + radius;
        if (Tc_identity) {
          t_ = c;
          magnitude += ac.dot(wGA_);
        } else {
          // t_ = Tᵀc, absT_ = |T| and (below) cN_ = Nᵀc stay valid for this strip's update.
          t_.noalias() = Tc_.transpose() * c;
          absT_ = Tc_.cwiseAbs();  // preallocated: no temporary in the steady state
          v_.noalias() = absT_.transpose() * ac;
          magnitude += v_.dot(wGA_);
        }
        radius += t_.cwiseAbs().dot(rA_);
        double cN2 = 0.0;  // ‖Nᵀc‖₂²
        if (mN > 0) {
          cN_.head(mN).noalias() = Nc_.leftCols(mN).transpose() * c;
          radius += cN_.head(mN).cwiseAbs().sum();
          cN2 = cN_.head(mN).squaredNorm();
          for (Eigen::Index j = 0; j < mN; ++j) magnitude += ac.dot(Nc_.col(j).cwiseAbs());
        }
        const double center = c.dot(pc_);
        const Eigen::Index terms = n_ + mG_ + mN + 4;
        if (want_S_ && mG_ > 0) {
          // ‖Gᵀt‖₁ >= ‖Gᵀt‖₂ = (cᵀ S c − ‖Nᵀc‖²)^½ with the kept Gram matrix S of T G ⊕ N (O(n²)):
          // a reading inside that smaller output set is consistent without the O(n m) pass
          // (as the observers' screening, observer.ipp).
          sc_.noalias() = Sc_ * c;
          const double low = gram_radius_lower_bound(c.dot(sc_) - cN2, Sc_.cwiseAbs().maxCoeff(), c.squaredNorm());
          const OutputTest t = test_output(yi, center, radius + low, phi, magnitude, terms);
          if (t.margin <= 0) chk_.margin(i) = t.margin;  // an upper bound of the exact margin
          else if (!screen_output(i, yi, phi, center, radius + detail::abs_projection_sum(G(), mG_, t_), magnitude, terms, y))
            continue;
        } else {
          if (mG_ > 0) radius += detail::abs_projection_sum(G(), mG_, t_);
          if (!screen_output(i, yi, phi, center, radius, magnitude, terms, y)) continue;
        }
      }
      if (c_zero_[static_cast<std::size_t>(i)]) continue;  // tested, carries no information on x
      if (want_S_) {
        sc_.noalias() = Sc_ * c;
        const double den = c.dot(sc_) + phi * phi;
        if (den > 0) lam_ = sc_ / den;
        else lam_.setZero();
      } else {
        lam_ = gain_.lambdas().row(i).transpose();
      }
      if (!lam_.allFinite())
        throw NumericalError("gain rule: returned a non-finite lambda for output " + std::to_string(i));
      // Rounding of p̂ = p + λ(y − cᵀp), of T̂ = T − λ(cᵀT) applied to [G, diag(rA)] (|T| rs
      // bounds |T G| 1), of N̂ = N − λ(cᵀN) and of the new column φλ.
      const double innov = std::abs(yi) + ac.dot(pc_.cwiseAbs());
      e_ = pc_.cwiseAbs() + lam_.cwiseAbs() * innov;
      if (Tc_identity) {
        v_ = wGA_;
      } else {
        v_.noalias() = absT_ * wGA_;  // absT_ = |T| from the screening
      }
      e_ += v_ + lam_.cwiseAbs() * ac.dot(v_);
      if (mN > 0) {
        v_ = Nc_.leftCols(mN).cwiseAbs().rowwise().sum();
        e_ += v_ + lam_.cwiseAbs() * ac.dot(v_);
      }
      e_ += phi * lam_.cwiseAbs();
      // The box of this step's roundings through κ: |κ| rc, then the new errors.
      abs_kappa_times(c, rc_, v_);
      rc_ = g1 * (v_ + g * e_);
      // The updates (t_ = Tᵀc and cN_ = Nᵀc from the screening).
      pc_ += lam_ * (yi - c.dot(pc_));
      Tc_.noalias() -= lam_ * t_.transpose();
      Tc_identity = false;
      if (mN > 0) Nc_.leftCols(mN).noalias() -= lam_ * cN_.head(mN).transpose();
      if (phi > 0 && lam_.cwiseAbs().maxCoeff() > 0) Nc_.col(mN++) = phi * lam_;
      if (want_S_) {
        // S ← κ S κᵀ + φ² λλᵀ with κ = I − λcᵀ and S c = sc.
        const double csc = c.dot(sc_);
        Sc_.noalias() -= lam_ * sc_.transpose();
        Sc_.noalias() -= sc_ * lam_.transpose();
        Sc_.noalias() += (csc + phi * phi) * (lam_ * lam_.transpose());
      }
    }
    // One product for all the strips and the previous prediction: W = [T G, N]; the carried
    // box through the whole T at once (|T| rA), and the product's rounding.
    if (Tc_identity) {
      if (mG_ > 0) W.leftCols(mG_) = G().leftCols(mG_);
      rc_ += rA_;
    } else {
      if (mG_ > 0) detail::transform_generators(Tc_, G(), W, mG_);
      absT_ = Tc_.cwiseAbs();
      v_.noalias() = absT_ * rA_;
      t_.noalias() = absT_ * wGA_;
      rc_ = g1 * (rc_ + v_ + gamma(n_) * t_);
    }
    W.middleCols(mG_, mN) = Nc_.leftCols(mN);
    mW = mG_ + mN;
  } else {
    mW = materialize_prior(W, rc_);
    if (correct) mW = explicit_strips(W, mW, y, u);
    if (want_S_) Sc_.noalias() = W.leftCols(mW) * W.leftCols(mW).transpose();
  }
  // Drop zero columns, turn a large pending box into generators, reduce after a correction.
  mW = detail::finish_generators(opt_.reduction, W, mW, opt_.max_generators, correct, kBoxToGenerators, rc_, wH_, rws_,
                                 want_S_ ? &Sc_ : nullptr);
  const bool reduced = rws_.reduced_count > 0;
  // Commit the current set (nothing below throws).
  cur_ = work;
  m_ = mW;
  mG_ = mW;
  cur_p_ = pc_;
  cur_r_ = rc_;
  cur_w_ = wH_;
  reduced_ = reduced;
  last_check_.status = chk_.status;  // same sizes: no allocation
  last_check_.margin = chk_.margin;
  last_check_.reset = false;
  has_current_ = true;
  const double infl = 1.0 + static_cast<double>(mW + n_ + 4) * std::numeric_limits<double>::epsilon();
  e_ = (wH_ + rc_) * infl;
  cur_lo_ = cur_p_ - e_;
  cur_hi_ = cur_p_ + e_;
  if (want_S_) S_ = Sc_;
}

SETBOUND_INLINE bool ZonotopicEstimator::screen_output(Eigen::Index i, double yi, double phi, double center, double radius,
                                                       double magnitude, Eigen::Index terms,
                                                       const Eigen::Ref<const Vec>& y) {
  const OutputTest t = test_output(yi, center, radius, phi, magnitude, terms);
  chk_.margin(i) = t.margin;
  if (!t.inconsistent) return true;
  if (opt_.on_inconsistency == OnInconsistency::Raise)
    throw_inconsistent(k_, i, y(i), center + (y(i) - yi), radius, phi, t.margin);
  chk_.status[static_cast<std::size_t>(i)] = OutputStatus::Inconsistent;
  return false;
}

SETBOUND_INLINE double ZonotopicEstimator::shifted_measurement(Eigen::Index i, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                             double& phi) const {
  phi = phi_(i);
  if (!D_used_[static_cast<std::size_t>(i)]) return y(i);
  const double yi = y(i) - sys_.D().row(i).dot(u);
  phi += rounding_bounds::gamma(sys_.nu()) * (std::abs(y(i)) + absD_.row(i).dot(u.cwiseAbs()));
  return yi;
}

SETBOUND_INLINE Eigen::Index ZonotopicEstimator::materialize_prior(Mat& W, Vec& r) const {
  using rounding_bounds::gamma;
  if (T_identity_) {
    if (mG_ > 0) W.leftCols(mG_) = G().leftCols(mG_);
    r += rA_;
  } else {
    if (mG_ > 0) detail::transform_generators(T_, G(), W, mG_);
    const Mat absT = T_.cwiseAbs();
    r = (1.0 + gamma(n_)) * (r + absT * rA_ + gamma(n_) * (absT * (wG_ + rA_)));
  }
  W.middleCols(mG_, mN_) = N_.leftCols(mN_);
  return mG_ + mN_;
}

SETBOUND_INLINE void ZonotopicEstimator::abs_kappa_times(const Eigen::Ref<const Vec>& c, const Vec& r, Vec& t) const {
  for (Eigen::Index i = 0; i < n_; ++i) {
    double acc = 0.0;
    const double li = lam_(i);
    for (Eigen::Index j = 0; j < n_; ++j) acc += std::abs((i == j ? 1.0 : 0.0) - li * c(j)) * r(j);
    t(i) = acc;
  }
}

SETBOUND_INLINE Eigen::Index ZonotopicEstimator::explicit_strips(Mat& W, Eigen::Index m, const Eigen::Ref<const Vec>& y,
                               const Eigen::Ref<const Vec>& u) {
  using rounding_bounds::gamma;
  const double g = gamma(n_ + 2), g1 = 1.0 + g;
  for (Eigen::Index i : opt_.strip_order) {
    if (std::isnan(y(i))) continue;  // missing (chk_ says so)
    const auto c = Ct_.col(i);
    const auto ac = absCt_.col(i);
    double phi = 0.0;
    const double yi = shifted_measurement(i, y, u, phi);
    {
      double radius = ac.dot(rc_), magnitude = ac.dot(pc_.cwiseAbs()) + radius;
      if (m > 0) {
        // cN_ = Wᵀc and v_ = rs|W| stay valid for this strip's update.
        cN_.resize(std::max(cN_.size(), m));
        cN_.head(m).noalias() = W.leftCols(m).transpose() * c;
        radius += cN_.head(m).cwiseAbs().sum();
        v_ = W.leftCols(m).cwiseAbs().rowwise().sum();
        magnitude += ac.dot(v_);
      }
      if (!screen_output(i, yi, phi, c.dot(pc_), radius, magnitude, n_ + m + 4, y)) continue;
    }
    if (c_zero_[static_cast<std::size_t>(i)]) continue;  // tested, carries no information on x
    const StripMeasurement meas{Strip(Vec(c), yi, phi), i};
    const Vec lambda = gain_(Zonotope(pc_, W.leftCols(m)), meas);
    if (lambda.size() != n_ || !lambda.allFinite())
      throw NumericalError("gain rule: returned a non-finite or wrongly sized lambda for output " +
                           std::to_string(i));
    const double innov = std::abs(yi) + ac.dot(pc_.cwiseAbs());
    e_ = pc_.cwiseAbs() + lambda.cwiseAbs() * innov + phi * lambda.cwiseAbs();
    if (m > 0) e_ += v_ + lambda.cwiseAbs() * ac.dot(v_);
    lam_ = lambda;
    abs_kappa_times(c, rc_, t_);
    rc_ = g1 * (t_ + g * e_);
    pc_ += lambda * (yi - c.dot(pc_));
    if (m > 0) W.leftCols(m).noalias() -= lambda * cN_.head(m).transpose();
    if (phi > 0 && lambda.cwiseAbs().maxCoeff() > 0) W.col(m++) = phi * lambda;
  }
  return m;
}

SETBOUND_INLINE void ZonotopicEstimator::predict_prior(const Eigen::Ref<const Vec>& u) {
  using rounding_bounds::gamma;
  const Mat& A = sys_.A();
  // p⁺ = A p + B u and its rounding.
  p_.noalias() = A * cur_p_;
  v_ = cur_p_.cwiseAbs();
  e_.noalias() = absMid_ * v_;
  e_ *= gamma(n_);
  if (sys_.nu() > 0) {
    t_.noalias() = sys_.B() * u;
    uabs_ = u.cwiseAbs();
    v_.noalias() = absB_ * uabs_;
    e_ += gamma(sys_.nu()) * v_;
    e_ += gamma(1) * (p_.cwiseAbs() + t_.cwiseAbs());
    p_ += t_;
  }
  // The current set's box is carried to the next materialisation and mapped there by the
  // whole transform T = κ_q ⋯ κ_1 A at once (much tighter than |κ_q| ⋯ |κ_1| |A| r). For [A]
  // the part (A − mid) box(r) ⊆ box(rad r) is added to the prediction's own rounding.
  rA_ = cur_r_;
  rP_ = e_;
  if (interval_) {
    v_.noalias() = sys_.A_rad() * cur_r_;
    rP_ += (1.0 + gamma(n_)) * v_;
  }
  // Generators: A G lazily (T = A), then E and, for [A], the two boxes of [Le2013].
  T_ = A;
  T_identity_ = false;
  wG_ = cur_w_;
  mN_ = 0;
  N_.leftCols(Enz_.cols()) = Enz_;
  mN_ = Enz_.cols();
  if (interval_) {
    const double infl = 1.0 + static_cast<double>(n_ + 2) * std::numeric_limits<double>::epsilon();
    v_.noalias() = sys_.A_rad() * cur_w_;
    e_ = cur_p_.cwiseAbs();  // (free again: the prediction's rounding is in rP_)
    t_.noalias() = sys_.A_rad() * e_;
    for (const Vec* box : {&v_, &t_})
      for (Eigen::Index i = 0; i < n_; ++i)
        if ((*box)(i) > 0) {
          N_.col(mN_).setZero();
          N_(i, mN_++) = (*box)(i) * infl;
        }
  }
  if (want_S_) {
    Sc_.noalias() = A * S_;
    S_.noalias() = Sc_ * A.transpose();
    S_ += EEt_;
    for (Eigen::Index j = Enz_.cols(); j < mN_; ++j) S_.noalias() += N_.col(j) * N_.col(j).transpose();
  }
}

}  // namespace setbound
