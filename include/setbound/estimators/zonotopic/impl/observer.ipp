// setbound — definitions of the functions declared in setbound/estimators/zonotopic/observer.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/observer.hpp"
#include "setbound/core/config.hpp"
#include "setbound/core/symmetric.hpp"
#include "setbound/estimators/zonotopic/strip_swap.hpp"
#include "setbound/estimators/zonotopic/volume_min.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <string>

namespace setbound {

SETBOUND_INLINE bool is_intersection_free(ZonotopicRule rule) {
  return rule == ZonotopicRule::Combastel || rule == ZonotopicRule::FixedGain;
}

SETBOUND_INLINE bool needs_gain(ZonotopicRule rule) {
  return rule == ZonotopicRule::FixedStrips || rule == ZonotopicRule::FixedLambda || rule == ZonotopicRule::FixedGain;
}

SETBOUND_INLINE ZonotopicObserver::ZonotopicObserver(LinearSystem system, const Zonotope& x0, ZonotopicObserverOptions options)
    : sys_(std::move(system)), opt_(std::move(options)), x0_(x0) {
  const int rule = static_cast<int>(opt_.rule);
  if (rule < 1 || rule > 8) throw InvalidArgumentError("rule: unknown zonotopic gain rule " + std::to_string(rule));
  const int conv = static_cast<int>(opt_.convention);
  if (conv < 0 || conv > 1) throw InvalidArgumentError("convention: must be Setbound or Cora");
  const int red = static_cast<int>(opt_.reduction);
  if (red < 1 || red > 3) throw InvalidArgumentError("reduction: must be Combastel, Girard or Pca");
  if (sys_.uncertain_A() && is_intersection_free(opt_.rule))
    throw InvalidArgumentError(
        "system: the intersection-free rules (Combastel, FixedGain) need a known A (an interval [A] is supported by "
        "the strip-based rules)");
  const Eigen::Index n = sys_.nx(), ny = sys_.ny();
  if (x0.dimension() != n)
    throw DimensionError("x0: expected a zonotope of dimension " + std::to_string(n) + ", got " +
                         std::to_string(x0.dimension()));
  if (needs_gain(opt_.rule)) {
    require_shape(opt_.gain, n, ny, "gain");
    require_finite(opt_.gain, "gain");
  } else if (opt_.gain.size() > 0) {
    throw InvalidArgumentError("gain: only the fixed-gain rules take a gain");
  }
  if (opt_.max_generators < n)
    throw InvalidArgumentError("max_generators: must be >= n_x = " + std::to_string(n) + ", got " +
                               std::to_string(opt_.max_generators));
  set_inconsistency_policy(opt_.on_inconsistency);
  setup();
  if (opt_.rule == ZonotopicRule::VolumeMin) {
    // The LP of a strip has a row per subset of n_x − 1 generators of the set before it: the
    // reduced set, E, [A]'s two boxes (a column per row of rad with a non-zero) and the earlier
    // strips' columns; x0's on the first step, and under the Cora convention (no reduction of the
    // first set) those with the first strips' columns and a box through the second step.
    // Refused here rather than at the step that would reach the limit.
    const Eigen::Index boxes = sys_.uncertain_A() ? 2 * (sys_.A_rad().rowwise().maxCoeff().array() > 0).count() : 0;
    const Eigen::Index first = x0.remove_zero_generators().num_generators();
    Eigen::Index steady = opt_.max_generators + Enz_.cols() + boxes;
    if (opt_.convention == Convention::Cora) steady = std::max(steady, first + ny + n + Enz_.cols() + boxes);
    const Eigen::Index widest = std::max(steady, first) + std::max<Eigen::Index>(ny - 1, 0);
    if (detail::binomial(widest, n - 1) > kVolumeMinMaxSubsets)
      throw InvalidArgumentError(
          std::string(first > steady ? "x0" : "max_generators") + ": the volume-minimising rule enumerates the subsets of " +
          std::to_string(n - 1) + " of up to " + std::to_string(widest) + " generators per strip, more than " +
          std::to_string(static_cast<long>(kVolumeMinMaxSubsets)) + "; " +
          (first > steady ? "give x0 fewer generators" : "lower max_generators") + " or use segment minimisation");
  }
  load_initial();
}

SETBOUND_INLINE void ZonotopicObserver::setup() {
  n_ = sys_.nx();
  const Eigen::Index ny = sys_.ny(), nw = sys_.nw();
  std::vector<Eigen::Index> nz;
  fcols_.clear();
  ecols_.clear();
  for (Eigen::Index j = 0; j < nw; ++j) {
    const bool e = sys_.E().col(j).cwiseAbs().maxCoeff() > 0;
    const bool f = ny > 0 && sys_.F().col(j).cwiseAbs().maxCoeff() > 0;
    if (e) nz.push_back(j);
    if (f) fcols_.push_back(j);
    else if (e) ecols_.push_back(j);
  }
  Enz_.resize(n_, static_cast<Eigen::Index>(nz.size()));
  for (std::size_t j = 0; j < nz.size(); ++j) Enz_.col(static_cast<Eigen::Index>(j)) = sys_.E().col(nz[j]);
  // σ_i = Σ_j |F_ij| (spec §1.2), rounded up.
  sigma_ = detail::abs_row_sums(sys_.F()) * (1.0 + static_cast<double>(nw + 2) * std::numeric_limits<double>::epsilon());
  if (nw == 0) sigma_ = Vec::Zero(ny);
  FFt_.noalias() = sys_.F() * sys_.F().transpose();
  EEt_.noalias() = sys_.E() * sys_.E().transpose();
  absA_ = sys_.A().cwiseAbs();
  absB_ = sys_.B().cwiseAbs();
  absC_ = sys_.C().cwiseAbs();
  rsE_ = Enz_.cols() > 0 ? Vec(Enz_.cwiseAbs().rowwise().sum()) : Vec(Vec::Zero(n_));
  // The gains of Wang, segment minimisation and Combastel need the Gram matrix; the screening
  // (Setbound) uses it for a cheap lower bound of the output set's radius (screen()).
  // Bravo's candidate scores need it too (kept, not recomputed from the columns each step).
  // An explicit prior is corrected like x0 in the first step: its gains and screening read its
  // columns, so no Gram matrix is kept.
  explicit_prior_ = !is_intersection_free(opt_.rule) && (opt_.rule == ZonotopicRule::VolumeMin || sys_.uncertain_A());
  needs_gram_ = !explicit_prior_ && (opt_.rule == ZonotopicRule::Wang || opt_.rule == ZonotopicRule::SegmentMin ||
                                     opt_.rule == ZonotopicRule::Combastel || opt_.rule == ZonotopicRule::Bravo ||
                                     opt_.convention == Convention::Setbound);
  chk_.clear(ny, OutputStatus::Unused);
  last_check_.clear(ny, OutputStatus::Unused);
  gain_last_ = Mat::Zero(n_, ny);
  gainw_ = Mat::Zero(n_, ny);
  lo_ = hi_ = Vec::Zero(n_);
  // The step's buffers at their steady-state size: the reduction limit, the columns one step
  // adds (E, one per output) and room for a rounding box turned into generators.
  const Eigen::Index cap = opt_.max_generators + Enz_.cols() + nw + ny + 2 * n_;
  W_.resize(n_, cap);
  N_.resize(n_, Enz_.cols() + nw + ny);
  detail::reserve_reduction_workspace(rws_, n_, cap);
}

SETBOUND_INLINE void ZonotopicObserver::load_initial() {
  const Zonotope z = x0_.remove_zero_generators();
  Set s{z.center(), Vec::Zero(n_), z.generators()};
  k_ = 0;
  gain_last_.setZero();
  if (is_filter()) {
    prior_ = s;
    cur_ = Set{Vec::Zero(n_), Vec::Zero(n_), Mat::Zero(n_, 0)};
    has_current_ = false;
    w_cur_ = Vec::Zero(n_);
    S_cur_ = Mat::Zero(n_, n_);
    lo_.setZero();
    hi_.setZero();
  } else {
    prior_ = Set{Vec::Zero(n_), Vec::Zero(n_), Mat::Zero(n_, 0)};
    cur_ = s;
    has_current_ = true;
    refresh_current(true, true);
  }
}

SETBOUND_INLINE void ZonotopicObserver::reset() { load_initial(); }

SETBOUND_INLINE Zonotope ZonotopicObserver::current_set() const {
  Mat out(n_, current_num_generators());  // throws before the first step
  const Eigen::Index m = cur_.G.cols();
  out.leftCols(m) = cur_.G;
  Eigen::Index j = m;
  for (Eigen::Index i = 0; i < n_; ++i)
    if (cur_.r(i) > 0) {
      out.col(j).setZero();
      out(i, j++) = cur_.r(i);
    }
  return Zonotope(cur_.p, std::move(out));
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::current_num_generators() const {
  if (!has_current_) throw InvalidArgumentError("observer: no step has been taken yet");
  return cur_.G.cols() + static_cast<Eigen::Index>((cur_.r.array() > 0).count());
}

SETBOUND_INLINE void ZonotopicObserver::update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (y.size() != sys_.ny())
    throw DimensionError("y: expected length " + std::to_string(sys_.ny()) + ", got " + std::to_string(y.size()));
  if (u.size() != sys_.nu())
    throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u.size()));
  require_no_infinity(y, "y");
  require_finite(u, "u");
  screen_readings(y, u);  // policy Raise throws here: nothing has changed yet
  if (opt_.on_inconsistency == OnInconsistency::Reset && chk_.flagged()) {
    // Restart from x0 and use this step's readings that are consistent with it; the report keeps
    // the test that triggered the restart. Built aside, so an error leaves this observer as it was.
    ZonotopicObserver next(*this);
    next.load_initial();
    next.screen_readings(y, u);
    next.advance(next.yscr_, u);
    next.k_ = k_ + 1;
    next.last_check_ = chk_;
    next.last_check_.reset = true;
    *this = std::move(next);
    return;
  }
  advance(yscr_, u);
  last_check_.status = chk_.status;  // same sizes: no allocation
  last_check_.margin = chk_.margin;
  last_check_.reset = false;
}

SETBOUND_INLINE void ZonotopicObserver::set_inconsistency_policy(OnInconsistency policy) {
  const int pol = static_cast<int>(policy);
  if (pol < 0 || pol > 2) throw InvalidArgumentError("on_inconsistency: must be Flag, Raise or Reset");
  if (opt_.convention == Convention::Cora && policy != OnInconsistency::Flag)
    throw InvalidArgumentError(
        "on_inconsistency: CORA's observers do not test their readings (convention Cora); only Flag is accepted");
  opt_.on_inconsistency = policy;
}

SETBOUND_INLINE void ZonotopicObserver::screen_readings(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u) {
  const Eigen::Index ny = sys_.ny();
  chk_.clear(ny, OutputStatus::Used);  // same sizes every step: no allocation
  for (Eigen::Index i = 0; i < ny; ++i)
    if (std::isnan(y(i))) chk_.status[static_cast<std::size_t>(i)] = OutputStatus::Missing;
  yscr_ = y;
  if (opt_.convention != Convention::Setbound) return;  // CORA tests nothing
  screen(y, u, chk_);
  for (Eigen::Index i = 0; i < ny; ++i)
    if (chk_.status[static_cast<std::size_t>(i)] == OutputStatus::Inconsistent) yscr_(i) = std::nan("");
}

SETBOUND_INLINE void ZonotopicObserver::screen(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                                               MeasurementCheck& chk) {
  shifted(y, u, screen_rows_, screen_ys_, screen_sig_);
  const Eigen::Index q = static_cast<Eigen::Index>(screen_rows_.size());
  if (q == 0) return;
  // The set this step corrects: a filter's prior (after the first step of a lazy filter the
  // implicit A·cur ⊕ E with its centre prior_.p and that centre's error prior_.r), a
  // predictor's current set (y_k and x_k; the output set adds F B, i.e. ±σ_i).
  const bool implicit = is_filter() && k_ > 0 && !explicit_prior_;
  const Set& X = is_filter() ? prior_ : cur_;
  const Mat& G = implicit ? cur_.G : X.G;
  const Vec& r = implicit ? cur_.r : X.r;
  const Eigen::Index m = G.cols(), ne = implicit ? Enz_.cols() : 0;
  const bool kept = implicit || !is_filter();  // row sums and Gram matrix of G are kept
  if (!kept) wp_ = m > 0 ? Vec(G.cwiseAbs().rowwise().sum()) : Vec(Vec::Zero(n_));
  const Vec& w = kept ? w_cur_ : wp_;
  const bool low_bound = kept && needs_gram_ && S_cur_.rows() == n_;
  const Eigen::Index terms = 2 * n_ + m + ne + sys_.nu() + 4;
  const Mat& C = sys_.C();
  for (Eigen::Index s = 0; s < q; ++s) {
    const Eigen::Index i = screen_rows_[static_cast<std::size_t>(s)];
    const auto c = C.row(i).transpose();
    const auto ac = absC_.row(i).transpose();
    // Support of the set in ±c: centre cᵀp, radius Σ_j |tᵀg_j| + |t|ᵀ r (+ E, + the centre's
    // error), t = Aᵀc for the implicit prior (c otherwise); `magnitude` bounds every term.
    double center = c.dot(X.p), fixed = 0.0, magnitude = ac.dot(X.p.cwiseAbs());
    if (implicit) {
      ta_.noalias() = sys_.A().transpose() * c;
      v_.noalias() = absA_.transpose() * ac;
      fixed = ac.dot(prior_.r) + ta_.cwiseAbs().dot(r);
      for (Eigen::Index k = 0; k < ne; ++k) fixed += std::abs(c.dot(Enz_.col(k)));
      magnitude += ac.dot(prior_.r) + v_.dot(w + r) + ac.dot(rsE_);
    } else {
      ta_ = c;
      fixed = ac.dot(r);
      magnitude += ac.dot(w + r);
    }
    const double sig = screen_sig_(s), ys = screen_ys_(s);
    if (low_bound) {
      // ‖Gᵀt‖₁ >= ‖Gᵀt‖₂ = (tᵀ S t)^½ with the kept Gram matrix S ≈ G Gᵀ (O(n²)): a reading
      // inside that smaller output set is consistent without the O(n m) pass.
      const double low =
          gram_radius_lower_bound(ta_.dot(S_cur_ * ta_), S_cur_.cwiseAbs().maxCoeff(), ta_.squaredNorm());
      const OutputTest t = test_output(ys, center, fixed + low, sig, magnitude, terms);
      if (t.margin <= 0) {
        chk.margin(i) = t.margin;  // an upper bound of the exact margin
        continue;
      }
    }
    const double radius = fixed + (m > 0 ? detail::abs_projection_sum(G, m, ta_) : 0.0);
    const OutputTest t = test_output(ys, center, radius, sig, magnitude, terms);
    chk.margin(i) = t.margin;
    if (!t.inconsistent) continue;
    if (opt_.on_inconsistency == OnInconsistency::Raise)
      throw_inconsistent(k_, i, y(i), center + (y(i) - ys), radius, sig, t.margin);
    chk.status[static_cast<std::size_t>(i)] = OutputStatus::Inconsistent;
  }
}

SETBOUND_INLINE void ZonotopicObserver::advance(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u) {
  gainw_.setZero();
  // The new set is built in pw_ ⊕ W_.leftCols(m) B ⊕ box(rw_); the observer's state is only
  // written at the end (nothing after the commit throws).
  Eigen::Index m = 0;
  bool fresh_gram = false;
  const bool bravo = opt_.rule == ZonotopicRule::Bravo;
  if (is_filter() && k_ > 0 && !explicit_prior_) {
    m = bravo ? bravo_from_current(y, u, gainw_) : correct_from_current(y, u, gainw_);
  } else if (is_filter()) {
    fresh_gram = true;
    Set X = prior_;  // explicit: x0 before the first step, or an explicit prior
    correct(X, y, u, gainw_);
    m = X.G.cols();
    ensure_columns(W_, m + n_);
    W_.leftCols(m) = X.G;
    pw_.swap(X.p);
    rw_.swap(X.r);
  } else {
    m = propagate(y, u, gainw_);
  }
  // CORA's strip-based loop does not reduce the first corrected set (spec §1.3).
  const bool reduce = !(is_filter() && opt_.convention == Convention::Cora && k_ == 0);
  // The Gram matrix of the new set without touching its columns: T S Tᵀ + N Nᵀ, then
  // finish_set's box columns and reduction as rank updates.
  // (Bravo's bravo_S_ has followed its prior and strips already.)
  if (needs_gram_ && !fresh_gram && bravo) {
    Snew_ = bravo_S_;
  } else if (needs_gram_ && !fresh_gram && gram_from_strips_) {
    Snew_.swap(R_);  // segment minimisation's strips kept it (R_ is scratch)
  } else if (needs_gram_ && !fresh_gram) {
    const Eigen::Index nN = m - cur_.G.cols();
    K_.noalias() = T_ * S_cur_;
    Snew_.noalias() = K_ * T_.transpose();
    detail::add_gram(N_, 0, nN, Snew_);
  }
  m = finish_set(W_, m, rw_, ww_, reduce, needs_gram_ && !fresh_gram ? &Snew_ : nullptr);
  if (needs_gram_ && fresh_gram) detail::gram(W_, m, Snew_);
  if (needs_gram_) symmetrize(Snew_);
  // ww_ = rs|W| is finite exactly when every generator is.
  if (!pw_.allFinite() || !rw_.allFinite() || !ww_.allFinite())
    throw NumericalError("observer: the set overflowed (non-finite values) at step " + std::to_string(k_));
  // Commit (nothing below throws but memory; same sizes as the last step: no allocation).
  cur_.p.swap(pw_);
  cur_.r.swap(rw_);
  cur_.G = W_.leftCols(m);
  w_cur_.swap(ww_);
  if (needs_gram_) S_cur_.swap(Snew_);
  if (is_filter() && explicit_prior_) {
    predict_explicit(u);
  } else if (is_filter()) {
    // The implicit prior A·X̂ ⊕ B u_k ⊕ E: its centre and the bound of that centre's error
    // (the generators are cur_'s through A, composed with the next step's strips).
    if (k_ == 0) prior_.G.resize(n_, 0);
    const double g = rounding_bounds::gamma(n_ + sys_.nu() + sys_.ny() + 4);
    prior_.p.noalias() = sys_.A() * cur_.p;
    prior_.r.noalias() = absA_ * cur_.p.cwiseAbs();
    if (sys_.nu() > 0) {
      prior_.p.noalias() += sys_.B() * u;
      prior_.r.noalias() += absB_ * u.cwiseAbs();
    }
    prior_.r = g * (prior_.r + prior_.p.cwiseAbs());
  }
  gain_last_ = gainw_;
  has_current_ = true;
  refresh_current(false, false);
  ++k_;
}

SETBOUND_INLINE ZonotopicObserverTrajectory ZonotopicObserver::run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U) {
  const Eigen::Index N = Y.rows();
  if (Y.cols() != sys_.ny())
    throw DimensionError("y: expected " + std::to_string(sys_.ny()) + " columns, got " + std::to_string(Y.cols()));
  if (sys_.nu() > 0) require_shape(U, N, sys_.nu(), "u");
  ZonotopicObserverTrajectory t{Mat(N, n_), Mat(N, n_), Mat(N, n_), {}};
  t.sets.reserve(static_cast<std::size_t>(N));
  reset();
  const Vec no_input(0);
  for (Eigen::Index k = 0; k < N; ++k) {
    auto record = [&] {
      t.center.row(k) = cur_.p.transpose();
      t.lower.row(k) = lo_.transpose();
      t.upper.row(k) = hi_.transpose();
      t.sets.push_back(current_set());
    };
    if (!is_filter()) record();  // a predictor: row k is the set for x_k before y_k
    if (sys_.nu() > 0) update(Y.row(k).transpose(), U.row(k).transpose());
    else update(Y.row(k).transpose(), no_input);
    if (is_filter()) record();
  }
  return t;
}

SETBOUND_INLINE void ZonotopicObserver::shifted(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                                                std::vector<Eigen::Index>& rows, Vec& ys, Vec& sig) const {
  rows.clear();
  for (Eigen::Index i = 0; i < sys_.ny(); ++i)
    if (!std::isnan(y(i))) rows.push_back(i);
  const Eigen::Index q = static_cast<Eigen::Index>(rows.size());
  ys.resize(q);
  sig.resize(q);
  const double g = rounding_bounds::gamma(sys_.nu());
  for (Eigen::Index t = 0; t < q; ++t) {
    const Eigen::Index i = rows[static_cast<std::size_t>(t)];
    ys(t) = y(i);
    sig(t) = sigma_(i);
    if (sys_.nu() > 0 && sys_.D().row(i).cwiseAbs().maxCoeff() > 0) {
      ys(t) = y(i) - sys_.D().row(i).dot(u);
      sig(t) += g * (std::abs(y(i)) + sys_.D().row(i).cwiseAbs().dot(u.cwiseAbs()));
    }
  }
}

SETBOUND_INLINE void ZonotopicObserver::strip_update(Set& X, const Mat& Lam, const Mat& CS, const Vec& ys, const Vec& sig) {
  using rounding_bounds::gamma;
  const Eigen::Index n = X.p.size(), m = X.G.cols(), q = Lam.cols();
  const double g = gamma(n + q + 4);
  const Vec w = X.G.cwiseAbs().rowwise().sum();
  const Mat absL = Lam.cwiseAbs(), absC = CS.cwiseAbs();
  // K = I − ΛC_S as computed, and a bound of its rounding: |K − K̃| <= g (I + |Λ||C_S|).
  Mat K = -(Lam * CS);
  K.diagonal().array() += 1.0;
  Mat dK = g * (absL * absC);
  dK.diagonal().array() += g;
  // Centre p + Λ(y_S − C_S p) and the bound of its rounding.
  const Vec innov = ys - CS * X.p;
  Vec pn = X.p + Lam * innov;
  const Vec absp = X.p.cwiseAbs();
  Vec r = (K.cwiseAbs() + dK) * X.r;
  r += 2.0 * g * (absp + absL * (ys.cwiseAbs() + absC * absp) + pn.cwiseAbs());
  // Generators (I − ΛC_S)G = G − Λ(C_S G), rounding <= 2g (|G| + |Λ||C_S||G|) per row sum.
  Mat Gn(n, m + q);
  if (m > 0 && q == 1) {
    // One strip (S-I): a row GEMV and an outer product (the general product would pack G).
    const Eigen::RowVectorXd cG = CS.row(0) * X.G;
    Gn.leftCols(m).noalias() = X.G - Lam.col(0) * cG;
  } else if (m > 0) {
    Gn.leftCols(m) = X.G - Lam * (CS * X.G);
  }
  r += 2.0 * g * (w + absL * (absC * w));
  // New columns Λ diag(σ_S) (rounding u |Λ| σ).
  for (Eigen::Index j = 0; j < q; ++j) Gn.col(m + j) = Lam.col(j) * sig(j);
  r += g * (absL * sig);
  X.p.swap(pn);
  X.G.swap(Gn);
  X.r = r * (1.0 + g);
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::bravo_choice(const Mat& G, Eigen::Index m, const Eigen::Ref<const Vec>& c,
                                                             double sig, Vec& lam) {
  lam.setZero(n_);
  if (m == 0) return -1;
  // Candidate 0 is the set itself; candidate j (Bravo 2006, Property 1) replaces g_j by the strip
  // direction: T_j = [g_i − (cᵀg_i / a) g_j for i ≠ j, (σ / a) g_j for i = j], a = cᵀg_j. Score:
  // det(T Tᵀ) (a volume proxy); the first minimiser wins (candidate 0 wins exact ties, spec §2.2).
  //
  // With P = I − g_j cᵀ/a (a projection with P g_j = 0), T_j = P G + (σ/a) g_j e_jᵀ and the cross
  // terms vanish: T_j T_jᵀ = P S Pᵀ + (σ/a)² g_j g_jᵀ, S = G Gᵀ. In a basis [ker cᵀ, g_j] this is
  // block-triangular, and the Schur complement gives
  //     det(T_j T_jᵀ) = (σ/a)² · det(S) · g_jᵀ S⁻¹ g_j,
  // so candidate j beats the set itself exactly when (σ/a)² ‖L⁻¹ g_j‖² < 1 (S = L Lᵀ): one
  // Cholesky factor and one pass over the columns per strip, O(n² m), instead of m determinants
  // of n × m products, O(n² m²) (vehicle6 at CORA's order 100: 600 columns). Only the choice uses
  // the score; every candidate is an outer bound, so its rounding cannot break the guarantee.
  // S = bravo_S_ comes from the kept Gram matrix (A S Aᵀ + E Eᵀ) and follows the strips by rank
  // updates (bravo_update).
  // The scores h_j = g_jᵀS⁻¹g_j too: after candidate j, with z = S⁻¹g_j,
  //     S'⁻¹ = S⁻¹ − z zᵀ/h_j + c cᵀ/σ²,  h'_i = h_i − (zᵀg_i)²/h_j (i ≠ j),  h'_j = 1
  // (cᵀg'_i = 0 for the updated columns), O(n) per column instead of the O(n²) of L⁻¹g_i; a score
  // that lost more than 8 digits to the subtraction is recomputed from L⁻¹ below.
  // The scoring runs inside the passes over the columns: the first strip's (strip_candidates)
  // or the last update's (bravo_advance, when bravo_ready_), which factored this S already.
  // A strip that chose the set itself leaves S, its factor and the scores h as they were: the next
  // strip's pass computes cᵀg_j only (strip_scores; tank30: most strips).
  const bool ready = bravo_ready_;
  bravo_ready_ = false;  // the next strip needs a pass unless bravo_update says otherwise
  if (bravo_state_ == BravoState::Flat) return -1;
  // Cauchy–Schwarz in the metric of S: a_j² = (cᵀg_j)² <= (cᵀSc)(g_jᵀS⁻¹g_j) = (cᵀSc) h_j, so
  // every score (σ/a_j)² h_j is at least σ²/(cᵀSc). A strip at least as wide as ‖cᵀG‖₂ keeps
  // the set itself without a pass over the columns (n² instead of n m; tank30: 18 of 21 strips
  // per step once the set has settled). The margins keep the choice the pass would make: a
  // relative one for the scores' rounding, an absolute one for S's (carried by rank updates,
  // accurate relative to its trace, not to a thin direction's cᵀSc).
  if (!ready && sig > 0.0) {
    sc_.noalias() = bravo_S_ * c;
    const double csc = c.dot(sc_);
    if (sig * sig >= (1.0 + 1e-6) * csc + 1e-10 * c.squaredNorm() * bravo_S_.trace()) return -1;
  }
  const bool scored = bravo_state_ == BravoState::Scored;
  if (!ready && !scored && !bravo_factor()) {
    bravo_state_ = BravoState::Flat;
    return -1;
  }
  // CORA's threshold on |cᵀg_j| is absolute; setbound's is relative to |c|ᵀ|g_j| (spec §2.2).
  // The first minimiser is sought over cᵀg_j ≠ 0 (CORA: above its threshold), and only the winner
  // is held to the relative threshold: if it passes, no admissible candidate before it scores
  // as low, so it is the first minimiser over the admissible ones too. A winner that fails (a
  // column numerically orthogonal to c) sends the choice through the thresholded scan. A score
  // left NaN by the update's cancellation is recomputed from L⁻¹ when its candidate is scored.
  const bool cora = opt_.convention == Convention::Cora;
  const auto admissible = [&](Eigen::Index j) {
    return std::abs(bravo_a_(j)) > kBravoThreshold * c.cwiseAbs().dot(G.col(j).cwiseAbs());
  };
  Eigen::Index bestj = bravo_next_;
  if (!ready && scored) {
    bestj = detail::strip_scores(G, m, c, bravo_a_.data(), bravo_h_.data(), bravo_scoring(sig));
  } else if (!ready) {
    for (Vec* v : {&bravo_a_, &bravo_h_})
      if (v->size() < m) v->resize(std::max<Eigen::Index>(m, 2 * v->size()));
    bestj = detail::strip_candidates(G, m, c, bravo_Linv_, bravo_a_.data(), bravo_h_.data(), bravo_scoring(sig));
    bravo_state_ = BravoState::Scored;
  }
  if (bestj >= 0 && !cora && !admissible(bestj)) {
    const detail::StripScoring sc = bravo_scoring(sig);
    detail::StripWinner winner(sig);
    for (Eigen::Index j = 0; j < m; ++j)
      if (admissible(j))
        detail::score_candidate<Eigen::Dynamic>(sc, j, bravo_a_(j), bravo_h_.data(), G.col(j).data(), winner);
    bestj = winner.index;
  }
  if (bestj >= 0) {
    lam = G.col(bestj) / bravo_a_(bestj);
    bravo_z_ = bravo_llt_.solve(G.col(bestj));  // S⁻¹g_j for the scores' update
  }
  return bestj;
}

SETBOUND_INLINE bool ZonotopicObserver::bravo_factor() {
  bravo_llt_.compute(bravo_S_);
  const bool ok = bravo_llt_.info() == Eigen::Success;
  const auto piv = bravo_llt_.matrixLLT().diagonal();
  // cond(S) below ~1e12. A flat set (S singular; numerically, cond(S) above ~1e12) has
  // det(T_j T_jᵀ) = (σ/a)² g_jᵀ adj(S) g_j = 0 for every candidate (g_j lies in the range of S,
  // adj(S) maps onto its kernel): all tie and candidate 0, the set itself, wins. (Scoring
  // noise-level determinants instead would pick a column by rounding.)
  if (!ok || !piv.allFinite() || !(piv.minCoeff() > 1e-6 * piv.maxCoeff())) return false;
  bravo_Linv_ = bravo_llt_.matrixL().solve(Mat::Identity(n_, n_));
  return true;
}

SETBOUND_INLINE detail::StripScoring ZonotopicObserver::bravo_scoring(double sig) const {
  detail::StripScoring sc;
  sc.sig = sig;
  sc.floor = opt_.convention == Convention::Cora ? kBravoThreshold : 0.0;
  sc.L = &bravo_Linv_;
  // λ_max(S) <= min(trace S, ‖S‖∞) (S positive semidefinite), widened for S's rounding.
  if (n_ > 8) {
    const double tr = bravo_S_.trace(), rowmax = bravo_S_.cwiseAbs().rowwise().sum().maxCoeff();
    sc.lmax = std::min(tr, rowmax) * (1.0 + 1e-6);
  }
  return sc;
}

SETBOUND_INLINE void ZonotopicObserver::bravo_update(Mat& G, Eigen::Index m, Vec& p, Vec& r, const Vec& lam,
                                                     const Eigen::Ref<const Vec>& c, double y, double sig, Eigen::Index j,
                                                     const Vec* cn, double sig_next) {
  using rounding_bounds::gamma;
  const double g = gamma(n_ + 1 + 4);
  const Vec& w = bravo_w_;  // >= rs|G| (bravo_correct's caller, then the recursion below)
  // The bounds of strip_update for one strip: K = I − λcᵀ and its rounding g (I + |λ||c|ᵀ), the
  // centre's, the generators' 2g (|G| + |λ||c|ᵀ|G|) by rows and the new column's g |λ| σ; the
  // centre's and the generators' are detail::strip_swap_terms, shared with ROPO's swap.
  al_ = lam.cwiseAbs();
  const auto ac = c.cwiseAbs();  // an expression: no vector allocated per strip
  v_ = (1.0 + g) * (r + al_ * ac.dot(r));  // (|K| + dK) r, |K| <= I + |λ||c|ᵀ
  detail::strip_swap_terms(p, lam, al_, c, y, w, g, pn_, t_, v_);  // and the new centre pn_
  v_ += (g * sig) * al_;
  // S ← K S Kᵀ + σ² λλᵀ with S c = sc (before the pass: the next strip's scores need its factor).
  sc_.noalias() = bravo_S_ * c;
  const double csc = c.dot(sc_);
  bravo_S_.noalias() -= lam * sc_.transpose();
  bravo_S_.noalias() -= sc_ * lam.transpose();
  bravo_S_.noalias() += (csc + sig * sig) * (lam * lam.transpose());
  // The next strip's factor (its scores come out of the pass below); without a next strip the
  // scores are left unfactored (the next step starts from its prior's S).
  bravo_state_ = BravoState::Unknown;
  if (cn) bravo_state_ = bravo_factor() ? BravoState::Scored : BravoState::Flat;
  if (bravo_state_ == BravoState::Flat) cn = nullptr;  // the next choice is the set itself
  // G ← G − λ (cᵀG) in place (cᵀg_i from the candidate pass), and the next strip's values and
  // winner. (I − λcᵀ) g_j is zero in exact arithmetic with λ = g_j / cᵀg_j; its computed value
  // (and the rounding bound above) stays in the box, the new column σλ takes its place.
  bravo_next_ = detail::bravo_advance(G, m, lam, sig, j, bravo_z_, bravo_a_.data(), bravo_h_.data(), bravo_res_, cn,
                                      bravo_scoring(sig_next));
  bravo_ready_ = cn != nullptr;
  v_ += bravo_res_;
  p.swap(pn_);
  r = v_ * (1.0 + g);
  // rs|G'| without a pass: |fl(g_i − λ a_i)| <= (|g_i| + |λ||a_i|)(1 + g), Σ|a_i| <= (1 + g)|c|ᵀw,
  // and the new column σλ; one more (1 + g) for this expression's own rounding.
  t_ = w + al_ * ((1.0 + g) * ac.dot(w) + sig);
  bravo_w_ = t_ * ((1.0 + g) * (1.0 + g));
}

SETBOUND_INLINE void ZonotopicObserver::bravo_correct(Mat& G, Eigen::Index m, Vec& p, Vec& r,
                                                      const std::vector<Eigen::Index>& rows, const Vec& ys,
                                                      const Vec& sig, Mat& gain) {
  // S-I: one strip at a time, in the order of the outputs, each on the set the last one left.
  const Mat& C = sys_.C();
  const std::size_t q = rows.size();
  bravo_ready_ = false;
  bravo_state_ = BravoState::Unknown;  // a new S (the prior's): not factored yet
  // Each row of C is copied once (a row of the column-major C is strided; the passes want a
  // contiguous normal): into bravo_cn_ while its predecessor is the current strip, where the
  // update's pass scores it, then swapped into bravo_c_ for its own strip.
  if (q > 0) bravo_c_ = C.row(rows[0]).transpose();
  for (std::size_t t = 0; t < q; ++t) {
    const Eigen::Index i = rows[t], ti = static_cast<Eigen::Index>(t);
    const bool next = t + 1 < q;
    if (next) bravo_cn_ = C.row(rows[t + 1]).transpose();
    const Eigen::Index j = bravo_choice(G, m, bravo_c_, sig(ti), lam_);
    if (j >= 0) {  // otherwise the set itself is the best candidate
      if (!lam_.allFinite()) throw NumericalError("gain rule: non-finite weight for output " + std::to_string(i));
      // In place; the same pass gives the next strip's scores.
      bravo_update(G, m, p, r, lam_, bravo_c_, ys(ti), sig(ti), j, next ? &bravo_cn_ : nullptr,
                   next ? sig(ti + 1) : 0.0);
      gain.col(i) = lam_;
    }
    if (next) bravo_c_.swap(bravo_cn_);  // no allocation: the two buffers trade storage
  }
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::bravo_from_current(const Eigen::Ref<const Vec>& y,
                                                                   const Eigen::Ref<const Vec>& u, Mat& gain) {
  using rounding_bounds::gamma;
  const double g = gamma(n_ + sys_.nu() + sys_.ny() + 4);
  // The prior A·X̂ ⊕ B u ⊕ E as explicit columns, once: its centre and that centre's error from
  // the end of the last step, the map A and the columns E exact (dT = 0, dN = 0).
  pc_ = prior_.p;
  ec_ = prior_.r;
  const Eigen::Index ne = Enz_.cols();
  if (ne > 0) N_.leftCols(ne) = Enz_;
  dT_.setZero(n_, n_);
  dN_.setZero(n_);
  const Eigen::Index m = map_current(sys_.A(), dT_, ne, g);
  prior_gram(bravo_S_);
  // rs|[fl(A G), E]| <= (1 + g)|A| w + rs|E| (w >= rs|G|), and this expression's rounding.
  bravo_w_ = (1.0 + g) * (absA_ * w_cur_) + (1.0 + gamma(ne + 2)) * rsE_;
  bravo_w_ *= 1.0 + g;
  shifted(y, u, rows_, ys_, sig_);
  if (!rows_.empty()) bravo_correct(W_, m, pw_, rw_, rows_, ys_, sig_, gain);
  return m;
}

SETBOUND_INLINE void ZonotopicObserver::gather_rows(const Mat& C, const std::vector<Eigen::Index>& rows, Mat& CS) {
  CS.resize(static_cast<Eigen::Index>(rows.size()), C.cols());
  for (std::size_t s = 0; s < rows.size(); ++s) CS.row(static_cast<Eigen::Index>(s)) = C.row(rows[s]);
}

SETBOUND_INLINE void ZonotopicObserver::add_noise_block(const std::vector<Eigen::Index>& rows, Mat& S) const {
  const Eigen::Index q = static_cast<Eigen::Index>(rows.size());
  for (Eigen::Index a = 0; a < q; ++a)
    for (Eigen::Index b = 0; b < q; ++b) S(a, b) += FFt_(rows[static_cast<std::size_t>(a)], rows[static_cast<std::size_t>(b)]);
}

SETBOUND_INLINE ZonotopicObserver::Mat ZonotopicObserver::solve_gain(const Mat& num, const Mat& S) {
  // Λ = num S⁻¹ with S symmetric positive semidefinite; a singular S gets the minimum-norm
  // solution (any weight is guaranteed), a non-finite one the zero weight.
  Mat out;
  Eigen::FullPivLU<Mat> lu(S);
  if (lu.isInvertible()) {
    out = lu.solve(num.transpose()).transpose();
  } else {
    Eigen::CompleteOrthogonalDecomposition<Mat> cod(S);
    out = cod.solve(num.transpose()).transpose();
  }
  if (!out.allFinite()) out.setZero(num.rows(), num.cols());
  return out;
}

SETBOUND_INLINE void ZonotopicObserver::wang_gain(Mat& R, const Mat& CS, const std::vector<Eigen::Index>& rows,
                                                  Mat& Lam) {
  // Λ = R̄ C_Sᵀ (C_S R̄ C_Sᵀ + F Fᵀ)⁻¹, R̄ = the predicted set's G Gᵀ (Wang 2018 Thm. 2); CORA
  // (sic, spec §2.4) forms R̄ from the predicted set as A (G Gᵀ) Aᵀ + E Eᵀ, i.e. applies A and
  // W a second time.
  if (opt_.convention == Convention::Cora) {
    K_.noalias() = sys_.A() * R;
    R.noalias() = K_ * sys_.A().transpose();
    R += EEt_;
    symmetrize(R);
  }
  RC_.noalias() = R * CS.transpose();
  Sq_.noalias() = CS * RC_;
  add_noise_block(rows, Sq_);
  Lam = solve_gain(RC_, Sq_);
}

SETBOUND_INLINE void ZonotopicObserver::correct(Set& X, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                                                Mat& gain) {
  std::vector<Eigen::Index> rows;
  Vec ys, sig;
  shifted(y, u, rows, ys, sig);
  const Eigen::Index q = static_cast<Eigen::Index>(rows.size());
  if (q == 0) return;
  const Mat& C = sys_.C();
  switch (opt_.rule) {
    case ZonotopicRule::Bravo:
      detail::gram(X.G, X.G.cols(), bravo_S_);
      detail::compact_and_sum(X.G, X.G.cols(), bravo_w_, false);  // rs|G| rounded up
      bravo_correct(X.G, X.G.cols(), X.p, X.r, rows, ys, sig, gain);
      return;
    case ZonotopicRule::SegmentMin:
    case ZonotopicRule::VolumeMin:
    case ZonotopicRule::FixedStrips: {
      // S-I: one strip at a time, in the order of the outputs.
      for (Eigen::Index t = 0; t < q; ++t) {
        const Eigen::Index i = rows[static_cast<std::size_t>(t)];
        const Vec c = C.row(i).transpose();
        Vec lam;
        if (opt_.rule == ZonotopicRule::SegmentMin) {
          // λ = G Gᵀc / (cᵀG Gᵀc + σ²) ([Alamo2005], spec §2.3).
          const Vec v = X.G * (X.G.transpose() * c);
          const double den = c.dot(v) + sig(t) * sig(t);
          lam = den > 0 ? Vec(v / den) : Vec(Vec::Zero(n_));
        } else if (opt_.rule == ZonotopicRule::VolumeMin) {
          // The λ of the smallest volume of the corrected set ([Alamo2005], papers.md §5.2);
          // the pending box is not part of the volume (any λ is guaranteed).
          lam = volume_min_gain(Zonotope(X.p, X.G), StripMeasurement{Strip(c, ys(t), sig(t)), i});
        } else {
          lam = opt_.gain.col(i);
        }
        if (!lam.allFinite())
          throw NumericalError("gain rule: non-finite weight for output " + std::to_string(i));
        if (lam.cwiseAbs().maxCoeff() == 0) continue;  // nothing changes (CORA's zero column is dropped)
        strip_update(X, lam, C.row(i), ys.segment(t, 1), sig.segment(t, 1));
        gain.col(i) = lam;
      }
      return;
    }
    case ZonotopicRule::Wang:
    case ZonotopicRule::FixedLambda: {
      // S-II: all present strips at once with one n × q weight.
      Mat CS;
      gather_rows(C, rows, CS);
      Mat Lam(n_, q);
      if (opt_.rule == ZonotopicRule::Wang) {
        // The first step's explicit set: its Gram matrix once (O(n² m)), then the formula of
        // every later step.
        detail::gram(X.G, X.G.cols(), R_);
        wang_gain(R_, CS, rows, Lam);
      } else {
        for (Eigen::Index t = 0; t < q; ++t) Lam.col(t) = opt_.gain.col(rows[static_cast<std::size_t>(t)]);
      }
      strip_update(X, Lam, CS, ys, sig);
      for (Eigen::Index t = 0; t < q; ++t) gain.col(rows[static_cast<std::size_t>(t)]) = Lam.col(t);
      return;
    }
    default: return;
  }
}

SETBOUND_INLINE void ZonotopicObserver::ensure_columns(Mat& M, Eigen::Index cols) const {
  if (M.cols() < cols) M.resize(n_, cols);
}

SETBOUND_INLINE void ZonotopicObserver::prior_gram(Mat& R) {
  K_.noalias() = sys_.A() * S_cur_;  // K_: scratch here (T_ may hold the step's map)
  R.noalias() = K_ * sys_.A().transpose();
  R += EEt_;
  symmetrize(R);
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::map_current(const Mat& T, const Mat& dT, Eigen::Index nN, double g) {
  // x = p + G ξ + ρ (|ξ| <= 1, |ρ| <= r) maps to T_exact x + …; the error of the computed T
  // (dT), of the product T G (γ|T||G|, row sums <= g |T| w) and of N_ (dN_) go to the box,
  // with the box itself through |T_exact| <= |T| + dT.
  const Eigen::Index m = cur_.G.cols();
  ensure_columns(W_, m + nN + n_);
  if (m > 0) detail::transform_generators(T, cur_.G, W_, m);
  if (nN > 0) W_.middleCols(m, nN) = N_.leftCols(nN);
  absT_ = T.cwiseAbs();
  v_ = w_cur_ + cur_.r;
  t_ = g * w_cur_ + cur_.r;
  rw_ = ec_ + dN_;
  rw_.noalias() += dT * v_;
  rw_.noalias() += absT_ * t_;
  rw_ *= 1.0 + g;
  pw_ = pc_;
  return m + nN;
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::correct_from_current(const Eigen::Ref<const Vec>& y,
                                                                     const Eigen::Ref<const Vec>& u, Mat& gain) {
  using rounding_bounds::gamma;
  const Mat& A = sys_.A();
  const Mat& C = sys_.C();
  const Eigen::Index nu = sys_.nu(), ne = Enz_.cols();
  const double g = gamma(n_ + nu + sys_.ny() + 4);
  // The prior's centre A p + B u_{k−1} and the bound of its error (prior_, end of the last step).
  pc_ = prior_.p;
  ec_ = prior_.r;
  // The map from the current set, starting with the prediction: T = A, N = E (both exact).
  T_ = A;
  dT_.setZero(n_, n_);
  if (ne > 0) N_.leftCols(ne) = Enz_;
  Eigen::Index nN = ne;
  dN_.setZero(n_);
  shifted(y, u, rows_, ys_, sig_);
  const Eigen::Index q = static_cast<Eigen::Index>(rows_.size());
  gram_from_strips_ = false;
  if (q == 0) return map_current(T_, dT_, nN, g);
  if (opt_.rule == ZonotopicRule::SegmentMin || opt_.rule == ZonotopicRule::FixedStrips) {
    // S-I: strip after strip, each the exact map K_i = I − λ_i c_iᵀ on the set so far, composed
    // into T and N; dT and dN carry the rounding of every update through the later K_i.
    const bool segment = opt_.rule == ZonotopicRule::SegmentMin;
    if (segment) prior_gram(R_);  // R = Gram of the set so far ([Alamo2005] λ = R c / (cᵀR c + σ²))
    for (Eigen::Index s = 0; s < q; ++s) {
      const Eigen::Index i = rows_[static_cast<std::size_t>(s)];
      const auto c = C.row(i).transpose();
      const auto ac = absC_.row(i).transpose();
      const double sig = sig_(s);
      if (segment) {
        sc_.noalias() = R_ * c;
        const double den = c.dot(sc_) + sig * sig;
        if (den > 0) lam_ = sc_ / den;
        else lam_.setZero(n_);
      } else {
        lam_ = opt_.gain.col(i);
      }
      if (!lam_.allFinite()) throw NumericalError("gain rule: non-finite weight for output " + std::to_string(i));
      if (lam_.cwiseAbs().maxCoeff() == 0) continue;  // nothing changes (CORA's zero column is dropped)
      al_ = lam_.cwiseAbs();
      // T ← T − λ (cᵀT): |K| dT <= dT + |λ| (|c|ᵀ dT), and the new rounding g (|T| + |λ| |c|ᵀ|T|).
      t_.noalias() = T_.transpose() * c;
      absT_ = T_.cwiseAbs();
      v_.noalias() = absT_.transpose() * ac;
      v_ *= g;
      v_.noalias() += dT_.transpose() * ac;
      dT_ += g * absT_;
      dT_.noalias() += al_ * v_.transpose();
      T_.noalias() -= lam_ * t_.transpose();
      // N ← N − λ (cᵀN), then the strip's own column σλ.
      if (nN > 0) {
        v_ = N_.leftCols(nN).cwiseAbs().rowwise().sum();
        const double spread = ac.dot(dN_) + g * ac.dot(v_);
        dN_ += g * v_ + spread * al_;
        cN_.noalias() = N_.leftCols(nN).transpose() * c;
        N_.leftCols(nN).noalias() -= lam_ * cN_.transpose();
      }
      if (sig > 0) {
        N_.col(nN++) = sig * lam_;
        dN_ += (g * sig) * al_;
      }
      // Centre p + λ (y − cᵀp); its error through K and the new rounding.
      const double innov = ys_(s) - c.dot(pc_);
      pn_ = pc_ + lam_ * innov;
      t_ = pc_.cwiseAbs();
      const double mag = std::abs(ys_(s)) + ac.dot(t_);
      ec_ += ac.dot(ec_) * al_ + 2.0 * g * (t_ + mag * al_ + pn_.cwiseAbs());
      pc_.swap(pn_);
      if (segment) {
        // R ← K R Kᵀ + σ² λλᵀ with R c = sc.
        const double csc = c.dot(sc_);
        R_.noalias() -= lam_ * sc_.transpose();
        R_.noalias() -= sc_ * lam_.transpose();
        R_.noalias() += (csc + sig * sig) * (lam_ * lam_.transpose());
      }
      gain.col(i) = lam_;
    }
    // Segment minimisation's R is now the Gram matrix of the corrected set [T G, N] (= T S Tᵀ +
    // N Nᵀ): advance() takes it instead of forming that product again (2 n³ per step).
    gram_from_strips_ = segment;
    return map_current(T_, dT_, nN, g);
  }
  // S-II: all present strips at once with one n × q weight Λ, K = I − Λ C_S.
  Lam_.resize(n_, q);
  gather_rows(C, rows_, CS_);
  if (opt_.rule == ZonotopicRule::Wang) {
    // The predicted set's G Gᵀ = A S Aᵀ + E Eᵀ from the current Gram S: never the n × m columns.
    prior_gram(R_);
    wang_gain(R_, CS_, rows_, Lam_);
  } else {
    for (Eigen::Index s = 0; s < q; ++s) Lam_.col(s) = opt_.gain.col(rows_[static_cast<std::size_t>(s)]);
  }
  absL_ = Lam_.cwiseAbs();
  absCS_ = CS_.cwiseAbs();
  // K = I − Λ C_S as computed and its rounding (for the centre's error).
  K_.noalias() = -(Lam_ * CS_);
  K_.diagonal().array() += 1.0;
  dK_.noalias() = g * (absL_ * absCS_);
  dK_.diagonal().array() += g;
  // T = K A computed as A − Λ (C_S A): |T − K A| <= g (|A| + |Λ| (|C_S| |A|)).
  CSA_.noalias() = CS_ * A;
  T_.noalias() -= Lam_ * CSA_;
  absT_.noalias() = absCS_ * absA_;
  dT_ = g * absA_;
  dT_.noalias() += g * (absL_ * absT_);
  // N = [K E, Λ diag σ].
  if (ne > 0) {
    CSE_.noalias() = CS_ * Enz_;
    N_.leftCols(ne).noalias() -= Lam_ * CSE_;
    v_.noalias() = absCS_ * rsE_;
    dN_ = g * rsE_;
    dN_.noalias() += g * (absL_ * v_);
  }
  for (Eigen::Index s = 0; s < q; ++s)
    if (sig_(s) > 0) {
      N_.col(nN++) = sig_(s) * Lam_.col(s);
      dN_ += (g * sig_(s)) * absL_.col(s);
    }
  // Centre p + Λ (y_S − C_S p); its error through K and the new rounding.
  innov_ = ys_;
  innov_.noalias() -= CS_ * pc_;
  pn_ = pc_;
  pn_.noalias() += Lam_ * innov_;
  t_ = pc_.cwiseAbs();
  v_ = ys_.cwiseAbs();
  v_.noalias() += absCS_ * t_;
  tmp_ = ec_;
  ec_ = dK_ * tmp_;
  ec_.noalias() += K_.cwiseAbs() * tmp_;
  ec_ += 2.0 * g * (t_ + pn_.cwiseAbs());
  ec_.noalias() += (2.0 * g) * (absL_ * v_);
  pc_.swap(pn_);
  for (Eigen::Index s = 0; s < q; ++s) gain.col(rows_[static_cast<std::size_t>(s)]) = Lam_.col(s);
  return map_current(T_, dT_, nN, g);
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::propagate(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                                                          Mat& L) {
  using rounding_bounds::gamma;
  shifted(y, u, rows_, ys_, sig_);
  const Eigen::Index q = static_cast<Eigen::Index>(rows_.size());
  const Mat& A = sys_.A();
  const Mat& C = sys_.C();
  const Eigen::Index nu = sys_.nu(), ny = sys_.ny();
  L.setZero(n_, ny);
  if (q > 0) {
    if (opt_.rule == ZonotopicRule::Combastel) {
      // Combastel 2015: L_k = A P C_Sᵀ (C_S P C_Sᵀ + F Fᵀ)⁻¹ with P = G Gᵀ of the current set
      // (spec §2.5), over the present outputs; P is the Gram matrix kept with the set.
      gather_rows(C, rows_, CS_);
      RC_.noalias() = S_cur_ * CS_.transpose();
      Sq_.noalias() = CS_ * RC_;
      add_noise_block(rows_, Sq_);
      ARC_.noalias() = A * RC_;  // A P C_Sᵀ
      Lam_ = solve_gain(ARC_, Sq_);
      for (Eigen::Index s = 0; s < q; ++s) L.col(rows_[static_cast<std::size_t>(s)]) = Lam_.col(s);
    } else {
      for (Eigen::Index s = 0; s < q; ++s) {
        const Eigen::Index i = rows_[static_cast<std::size_t>(s)];
        L.col(i) = opt_.gain.col(i);
      }
    }
  }
  if (!L.allFinite()) throw NumericalError("gain rule: non-finite observer gain");
  const double g = gamma(n_ + ny + nu + 4);
  absL_ = L.cwiseAbs();
  // T = A − L C and the bound of its rounding.
  T_ = A;
  T_.noalias() -= L * C;
  dT_ = g * absA_;
  dT_.noalias() += g * (absL_ * absC_);
  // Centre T p + B u + L (y − D u) over the present outputs (L's other columns are zero), and
  // the bound of its error: T's (dT |p|), the products' and the sums'.
  yfull_.setZero(ny);
  yabs_.setZero(ny);
  for (Eigen::Index s = 0; s < q; ++s) {
    const Eigen::Index i = rows_[static_cast<std::size_t>(s)];
    yfull_(i) = ys_(s);
    yabs_(i) = std::abs(y(i)) + (nu > 0 ? sys_.D().row(i).cwiseAbs().dot(u.cwiseAbs()) : 0.0);
  }
  pc_.noalias() = T_ * cur_.p;
  t_ = cur_.p.cwiseAbs();
  ec_.noalias() = dT_ * t_;
  absT_ = T_.cwiseAbs();
  ec_.noalias() += g * (absT_ * t_);
  if (nu > 0) {
    pc_.noalias() += sys_.B() * u;
    ec_.noalias() += g * (absB_ * u.cwiseAbs());
  }
  pc_.noalias() += L * yfull_;
  ec_.noalias() += (2.0 * g) * (absL_ * yabs_);
  ec_ += (2.0 * g) * pc_.cwiseAbs();
  // Disturbance columns: E_j − L F_j for the ω entering the outputs, then E_j (CORA's order
  // [−L G_V, G_W] on its model, spec §1.3).
  Eigen::Index nN = 0;
  dN_.setZero(n_);
  for (Eigen::Index j : fcols_) {
    N_.col(nN) = sys_.E().col(j);
    N_.col(nN++).noalias() -= L * sys_.F().col(j);
    dN_ += g * sys_.E().col(j).cwiseAbs();
    dN_.noalias() += g * (absL_ * sys_.F().col(j).cwiseAbs());
  }
  for (Eigen::Index j : ecols_) N_.col(nN++) = sys_.E().col(j);
  return map_current(T_, dT_, nN, g);
}

SETBOUND_INLINE void ZonotopicObserver::predict_explicit(const Eigen::Ref<const Vec>& u) {
  using rounding_bounds::gamma;
  // x⁺ = A x + B u + E ω with A = mid + Δ, |Δ| <= rad, x = p + G ξ + ρ (|ξ| <= 1, |ρ| <= r):
  //   mid p + B u          the centre, computed (error <= g (|mid||p| + |B||u| + |p⁺|))
  //   mid G ξ              columns fl(mid G) (row sums of the error <= g |mid| w, w >= rs|G|)
  //   Δ (p + G ξ)          the boxes rad·w and rad·|p| ([Le2013] §3.4), rounded up
  //   A ρ                  the box (|mid| + rad) r
  //   E ω                  the columns of E, exact.
  const Mat& A = sys_.A();
  const Eigen::Index m = cur_.G.cols(), ne = Enz_.cols();
  const double g = gamma(n_ + sys_.nu() + sys_.ny() + 4);
  const bool interval = sys_.uncertain_A();
  Eigen::Index nb = 0;
  if (interval) {
    const double up = 1.0 + static_cast<double>(n_ + 2) * std::numeric_limits<double>::epsilon();
    v_.noalias() = sys_.A_rad() * w_cur_;
    t_.noalias() = sys_.A_rad() * cur_.p.cwiseAbs();
    v_ *= up;
    t_ *= up;
    nb = static_cast<Eigen::Index>((v_.array() > 0).count() + (t_.array() > 0).count());
  }
  prior_.G.resize(n_, m + ne + nb);
  if (m > 0) prior_.G.leftCols(m).noalias() = A * cur_.G;
  if (ne > 0) prior_.G.middleCols(m, ne) = Enz_;
  Eigen::Index j = m + ne;
  if (interval)
    for (const Vec* box : {&v_, &t_})
      for (Eigen::Index i = 0; i < n_; ++i)
        if ((*box)(i) > 0) {
          prior_.G.col(j).setZero();
          prior_.G(i, j++) = (*box)(i);
        }
  prior_.p.noalias() = A * cur_.p;
  Vec e = absA_ * cur_.p.cwiseAbs();
  if (sys_.nu() > 0) {
    prior_.p.noalias() += sys_.B() * u;
    e.noalias() += absB_ * u.cwiseAbs();
  }
  e += prior_.p.cwiseAbs();
  e *= g;
  e.noalias() += absA_ * (cur_.r + g * w_cur_);
  if (interval) e.noalias() += sys_.A_rad() * cur_.r;
  prior_.r = e * (1.0 + g);
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::finish_set(Mat& W, Eigen::Index m, Vec& r, Vec& w, bool reduce, Mat* S) {
  // Setbound's convention moves the columns that no row can see into the box (CORA counts them).
  const double negligible = opt_.convention == Convention::Cora ? 0.0 : kNegligibleGenerator;
  return detail::finish_generators(opt_.reduction, W, m, opt_.max_generators, reduce, kBoxToGenerators, r, w, rws_, S,
                                   negligible);
}

SETBOUND_INLINE void ZonotopicObserver::refresh_current(bool row_sums, bool gram) {
  const Eigen::Index m = cur_.G.cols();
  if (row_sums) detail::compact_and_sum(cur_.G, m, w_cur_, false);
  if (gram) detail::gram(cur_.G, m, S_cur_);
  const double eps = std::numeric_limits<double>::epsilon();
  t_ = (w_cur_ + cur_.r + eps * cur_.p.cwiseAbs()) * (1.0 + static_cast<double>(m + n_ + 4) * eps);
  lo_ = cur_.p - t_;
  hi_ = cur_.p + t_;
}

SETBOUND_INLINE std::vector<double> ZonotopicObserver::save_state() const {
  StateWriter w(StateKind::ZonotopicObserver, fingerprint());
  w.count(k_).flag(has_current_);
  w.vec(prior_.p).vec(prior_.r).mat(prior_.G);
  w.vec(cur_.p).vec(cur_.r).mat(cur_.G);
  w.mat(gain_last_).mat(S_cur_);
  return w.finish();
}

SETBOUND_INLINE void ZonotopicObserver::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k;
    bool has;
    Set prior, cur;
    Mat gain, S;
  };
  Parsed q = guard_state_memory(StateKind::ZonotopicObserver, [&] {
    StateReader r(state, StateKind::ZonotopicObserver, fingerprint());
    Parsed t;
    t.k = r.count("steps");
    t.has = r.flag("has_current");
    t.prior.p = r.vec(n_, "prior center");
    t.prior.r = r.vec(n_, "prior box");
    t.prior.G = r.mat(n_, -1, "prior generators");
    t.cur.p = r.vec(n_, "current center");
    t.cur.r = r.vec(n_, "current box");
    t.cur.G = r.mat(n_, -1, "current generators");
    t.gain = r.mat(n_, sys_.ny(), "gain");
    t.S = r.mat(n_, n_, "Gram matrix");
    r.finish();
    if ((t.prior.r.array() < 0).any() || (t.cur.r.array() < 0).any()) r.fail("a box radius is negative");
    if (is_filter() && t.has != (t.k > 0)) r.fail("a filter has a current set exactly after its first step");
    if (!is_filter() && !t.has) r.fail("a predictor always has a current set");
    if (is_filter() && !explicit_prior_ && t.k > 0 && t.prior.G.cols() > 0)
      r.fail("this filter's prior after the first step has no generators of its own (they are the current set's)");
    return t;
  });
  k_ = static_cast<Eigen::Index>(q.k);
  has_current_ = q.has;
  prior_ = std::move(q.prior);
  cur_ = std::move(q.cur);
  gain_last_ = std::move(q.gain);
  S_cur_ = std::move(q.S);
  if (has_current_) {
    refresh_current(true, false);
  } else {
    w_cur_ = Vec::Zero(n_);
    S_cur_ = Mat::Zero(n_, n_);
    lo_.setZero();
    hi_.setZero();
  }
}

SETBOUND_INLINE StateFingerprint ZonotopicObserver::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F());
  f.add_int(static_cast<int>(opt_.rule)).add(opt_.gain).add_int(opt_.max_generators);
  f.add_int(static_cast<int>(opt_.reduction)).add_int(static_cast<int>(opt_.convention));
  // Layout 2: a filter's prior after its first step is implied by the current set (A·X̂ ⊕ E):
  // saved as its centre and the bound of that centre's error, no generators; the Gram matrix
  // the gains use is saved (it is updated, not recomputed). A state of layout 1 (the explicit
  // prior, no Gram matrix) is refused by this value. Layout 3: Bravo's prior became implicit too
  // (its states of layout 2 held the explicit prior; other rules are unchanged).
  // Layout 4: an explicit prior (VolumeMin, an interval [A]) is saved with its columns.
  f.add_int(explicit_prior_ ? 4 : opt_.rule == ZonotopicRule::Bravo ? 3 : 2);
  if (sys_.uncertain_A()) f.add(sys_.A_rad());
  return f;
}

}  // namespace setbound
