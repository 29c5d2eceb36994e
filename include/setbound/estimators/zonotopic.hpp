// setbound — the zonotopic estimator structure of papers.md §3.1 (Algorithm 1 of [Le2013]).
//
//   prediction (A known):  p⁺ = A p + B u,  H⁺ = [A H, E]
//   prediction ([A]):      p⁺ = mid[A] p + B u,  H⁺ = [mid[A] H, rs(rad[A]|H|), diag(rad[A]|p|), E]
//   correction, strip by strip (|c_iᵀx + D_i u − y_i| ≤ φ_i, φ_i = Σ_j |F_ij|):
//                          p̂ = p + λ_i (y_i − D_i u − c_iᵀ p),  Ĥ = [(I − λ_i c_iᵀ) H, φ_i λ_i]
//   reduction to at most s generators (options.reduction: Combastel, papers §0.1; Girard; or
//   CORA's PCA), when more than s non-zero generators are left after the correction.
//
// Guarantee: x_k ∈ X̂_k for ANY choice of λ_i ([Le2013] Property 6), because prediction,
// correction and reduction are all outer approximations. The gain rule only changes the size.
//
// Floating point. The products A p, A H, λ(y − cᵀp) and (I − λcᵀ)H are rounded. Their errors
// are bounded (Higham's γ_k) and collected in one pending box B_r, carried exactly through
// later corrections ((Z ⊕ B_r) ∩ S ⊆ family(Z) ⊕ κB_r ⊆ family(Z) ⊕ box(|κ|r), κ = I − λcᵀ) and
// predictions (A B_r ⊆ box(|A| r)). The reduction absorbs the box into its replacement
// generators, so the box never counts toward max_generators and never changes which generators
// are kept (CORA's choices are reproduced); between reductions a set is Z ⊕ B_r, reported with
// up to n_x extra axis-aligned generators. Should the box grow above 1e-6 of the set's largest
// radius before a reduction (a long run with no reduction), it is appended as generators. It
// is ~1e-15 of the radius on small systems, up to ~1e-11 of the largest radius on tank30.
//
// Speed. Segment minimisation and fixed gains need only the n×n Gram matrix S = H Hᵀ and the
// strip data, so the generator matrix is not touched strip by strip: the corrections and the
// next prediction accumulate into an n×n transform T (H_k = T H_{k−1} ⊕ new columns), applied
// once per step with one matrix product; S is updated alongside (rank-two updates, the
// reduction's removed and added columns). Other gain rules (volume minimisation, user rules)
// receive the set before each strip as a Zonotope. All buffers are allocated at construction.
//
// Time indexing (identical for every estimator of the library): measurements y_0 … y_{N−1},
// inputs u_0 … u_{N−1}; row k of a trajectory is a set for x_k. step(y_k, u_k) returns the set
// for x_k after using y_k (this family is a filter) and then predicts x_{k+1} with u_k.
// With use_first_measurement = false the first step returns X_0 unchanged, as [Le2013] does.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/state.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/strip.hpp"
#include "setbound/sets/zonotope.hpp"

namespace setbound {

/// One-strip correction: the output-i row (c, D_i u, φ) of the model and the gain λ.
struct StripMeasurement {
  Strip strip;   // |cᵀx − (y_i − D_i u)| ≤ φ
  Eigen::Index output;
};

/// λ rule: given the set before the strip and the strip, return λ (any λ is guaranteed).
using ZonotopeGainRule = std::function<Eigen::VectorXd(const Zonotope&, const StripMeasurement&)>;

/// [Alamo2005] segment minimisation (papers.md §5.1): λ* = H Hᵀ c / (cᵀ H Hᵀ c + φ²), the
/// minimiser of ‖(I − λcᵀ)H‖_F² + φ²‖λ‖². With nothing to gain (H Hᵀ c = 0) λ = 0.
inline Eigen::VectorXd segment_min_gain(const Zonotope& Z, const StripMeasurement& m) {
  const Eigen::VectorXd& c = m.strip.normal();
  const Eigen::VectorXd g = Z.generators() * (Z.generators().transpose() * c);
  const double phi = m.strip.half_width();
  const double denom = c.dot(g) + phi * phi;
  if (!(denom > 0)) return Eigen::VectorXd::Zero(Z.dimension());
  return g / denom;
}

/// The estimator's gain rule. Segment minimisation (segment_min_gain, also inside a
/// ZonotopeGainRule) and fixed gains (ZonotopeGain::fixed, pradius_gain) are recognised and
/// run on the estimator's fast path; any other callable gets the set before each strip.
class ZonotopeGain {
 public:
  enum class Kind { SegmentMin, Fixed, Custom };
  using Function = Eigen::VectorXd (*)(const Zonotope&, const StripMeasurement&);

  ZonotopeGain(Function f) : rule_(f) {  // NOLINT: implicit, as a function is a rule
    if (f == &segment_min_gain) kind_ = Kind::SegmentMin;
  }
  ZonotopeGain(ZonotopeGainRule rule) : rule_(std::move(rule)) {  // NOLINT
    if (const Function* f = rule_.target<Function>(); f && *f == &segment_min_gain) kind_ = Kind::SegmentMin;
    if (const ZonotopeGain* g = rule_.target<ZonotopeGain>()) *this = ZonotopeGain(*g);
  }
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, Function> &&
                                              !std::is_same_v<std::decay_t<F>, ZonotopeGain> &&
                                              !std::is_same_v<std::decay_t<F>, ZonotopeGainRule> &&
                                              std::is_invocable_r_v<Eigen::VectorXd, F&, const Zonotope&,
                                                                    const StripMeasurement&>>>
  ZonotopeGain(F f) : ZonotopeGain(ZonotopeGainRule(std::move(f))) {}  // NOLINT

  /// Fixed gains: row i is λ_i of output i (e.g. an offline P-radius design).
  static ZonotopeGain fixed(Eigen::MatrixXd lambdas) {
    require_finite(lambdas, "lambdas");
    ZonotopeGain g;
    g.kind_ = Kind::Fixed;
    g.lambdas_ = std::move(lambdas);
    return g;
  }

  Kind kind() const { return kind_; }
  const Eigen::MatrixXd& lambdas() const { return lambdas_; }
  explicit operator bool() const { return kind_ != Kind::Custom || static_cast<bool>(rule_); }

  Eigen::VectorXd operator()(const Zonotope& Z, const StripMeasurement& m) const {
    switch (kind_) {
      case Kind::SegmentMin: return segment_min_gain(Z, m);
      case Kind::Fixed: return lambdas_.row(m.output).transpose();
      default: return rule_(Z, m);
    }
  }

 private:
  ZonotopeGain() = default;
  Kind kind_ = Kind::Custom;
  ZonotopeGainRule rule_;
  Eigen::MatrixXd lambdas_;
};

struct ZonotopicOptions {
  Eigen::Index max_generators = 20;   ///< reduction limit s (>= n_x), rounding box not counted
  bool use_first_measurement = true;  ///< intersect X_0 with the strips of y_0 (CORA's loop)
  std::vector<Eigen::Index> strip_order;  ///< order of the outputs; empty = 0, 1, …, n_y − 1
  /// Combastel (papers §0.1), Girard (CORA's default) or Pca (CORA's observer examples).
  ZonotopeReduction reduction = ZonotopeReduction::Combastel;
};

/// Sets of one run: row k of center/lower/upper and element k of the lists describe x_k.
struct ZonotopeTrajectory {
  Eigen::MatrixXd center, lower, upper;  ///< N × n_x
  std::vector<Zonotope> sets;
};

class ZonotopicEstimator {
 public:
  ZonotopicEstimator(LinearSystem system, const Zonotope& x0, ZonotopeGain gain, ZonotopicOptions options = {})
      : sys_(std::move(system)), gain_(std::move(gain)), opt_(std::move(options)) {
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
    load_prior(x0);
  }

  const LinearSystem& system() const { return sys_; }
  const ZonotopicOptions& options() const { return opt_; }
  /// Changes the reduction method from the next step on (every method is guaranteed).
  void set_reduction(ZonotopeReduction method) { opt_.reduction = method; }
  Eigen::Index steps_taken() const { return k_; }

  /// Set for the next state x_{k+1} (before its measurement is used), the pending rounding
  /// box included as generators.
  Zonotope prediction() const {
    Eigen::MatrixXd H(n_, mG() + mN_);
    Eigen::VectorXd r = rP_;
    materialize_prior(H, r);
    return with_box(p_, H, r);
  }

  /// Uses y_k (and u_k for D u_k), then predicts x_{k+1} with u_k; the set for x_k is then
  /// available from the current_*() accessors. On any error the estimator is unchanged.
  void update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    if (y.size() != sys_.ny())
      throw DimensionError("y: expected length " + std::to_string(sys_.ny()) + ", got " + std::to_string(y.size()));
    if (u.size() != sys_.nu())
      throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u.size()));
    require_finite(y, "y");
    require_finite(u, "u");
    correct_and_reduce(y, u, !(k_ == 0 && !opt_.use_first_measurement));  // may throw; commits last
    predict_prior(u);
    ++k_;
  }

  /// update(), returning the set for x_k.
  Zonotope step(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
    update(y, u);
    return current_set();
  }

  // ---- the set for x_k of the last update: centre ⊕ generators B ⊕ box(current_box) ----
  bool has_current() const { return has_current_; }
  const Eigen::VectorXd& current_center() const { return cur_p_; }
  /// n × m generators of the last set (the rounding box excluded, see current_box()).
  Eigen::Block<const Eigen::MatrixXd, Eigen::Dynamic, Eigen::Dynamic, true> current_generators() const {
    return H_[cur_].leftCols(m_);
  }
  /// Radius of the pending rounding box (zero after a step that reduced).
  const Eigen::VectorXd& current_box() const { return cur_r_; }
  const Eigen::VectorXd& current_lower() const { return cur_lo_; }
  const Eigen::VectorXd& current_upper() const { return cur_hi_; }
  /// Whether the last update ran the order reduction.
  bool reduced_last_step() const { return reduced_; }
  /// Generator count of current_set(): the generators plus the non-zero box entries.
  Eigen::Index current_num_generators() const {
    return m_ + static_cast<Eigen::Index>((cur_r_.array() > 0).count());
  }
  /// The last set as one zonotope (the rounding box as axis-aligned generators).
  Zonotope current_set() const {
    if (!has_current_) throw InvalidArgumentError("estimator: no step has been taken yet");
    return with_box(cur_p_, H_[cur_].leftCols(m_), cur_r_);
  }

  /// Runs over rows of Y (N × n_y) and U (N × n_u, or empty when n_u = 0).
  ZonotopeTrajectory run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U = Eigen::MatrixXd()) {
    const Eigen::Index N = Y.rows();
    if (Y.cols() != sys_.ny())
      throw DimensionError("y: expected " + std::to_string(sys_.ny()) + " columns, got " + std::to_string(Y.cols()));
    if (sys_.nu() > 0) require_shape(U, N, sys_.nu(), "u");
    ZonotopeTrajectory t{Eigen::MatrixXd(N, n_), Eigen::MatrixXd(N, n_), Eigen::MatrixXd(N, n_), {}};
    t.sets.reserve(static_cast<std::size_t>(N));
    const Eigen::VectorXd no_input(0);
    for (Eigen::Index k = 0; k < N; ++k) {
      if (sys_.nu() > 0) update(Y.row(k).transpose(), U.row(k).transpose());
      else update(Y.row(k).transpose(), no_input);
      t.center.row(k) = cur_p_.transpose();
      t.lower.row(k) = cur_lo_.transpose();
      t.upper.row(k) = cur_hi_.transpose();
      t.sets.push_back(current_set());
    }
    return t;
  }

  /// Strip-by-strip correction (papers §3.1) of X, followed by the reduction.
  Zonotope correct(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& y,
                   const Eigen::Ref<const Eigen::VectorXd>& u) const {
    detail::require_length(X.dimension(), n_, "X");
    detail::require_length(y.size(), sys_.ny(), "y");
    detail::require_length(u.size(), sys_.nu(), "u");
    require_finite(y, "y");
    require_finite(u, "u");
    ZonotopicEstimator tmp(sys_, X, gain_, opt_);
    tmp.correct_and_reduce(y, u, true);
    return tmp.current_set();
  }

  /// Prediction of x_{k+1} from a set for x_k (exact for known A, [Le2013] inclusion for [A]).
  Zonotope predict(const Zonotope& X, const Eigen::Ref<const Eigen::VectorXd>& u) const {
    detail::require_length(X.dimension(), n_, "X");
    detail::require_length(u.size(), sys_.nu(), "u");
    require_finite(u, "u");
    ZonotopicEstimator tmp(sys_, X, gain_, opt_);
    tmp.correct_and_reduce(Eigen::VectorXd::Zero(sys_.ny()), u, false);
    tmp.predict_prior(u);
    return tmp.prediction();
  }

  /// Full mutable state (core/state.hpp): the prior for x_{k+1} (centre, the lazy transform T,
  /// its generators and pending boxes, the Gram matrix of segment minimisation), the set of the
  /// last step and its hull, the step counter and the reduction method (set_reduction).
  std::vector<double> save_state() const {
    StateWriter w(StateKind::ZonotopicEstimator, fingerprint());
    const Eigen::Index mh = std::max(mG_, m_);
    w.count(k_).flag(has_current_).flag(reduced_).count(static_cast<int>(opt_.reduction));
    w.count(cap_).count(mG_).count(mN_).count(m_).flag(T_identity_);
    w.vec(p_).vec(rA_).vec(rP_).vec(wG_).mat(T_).mat(N_.leftCols(mN_)).mat(S_);
    w.mat(H_[cur_].leftCols(mh)).vec(cur_p_).vec(cur_r_).vec(cur_w_).vec(cur_lo_).vec(cur_hi_);
    return w.finish();
  }
  /// Restores a state from save_state() into an estimator made with the same system, gain rule
  /// and options (the initial set may differ); throws InvalidArgumentError ("state: ...")
  /// otherwise. Unchanged on error, also on memory exhaustion.
  ///
  /// The saved capacity is the saving estimator's work-array size, max(generators of its x0, s)
  /// + the columns one step adds + n; x0 is not part of the design, so after the first step no
  /// design bound exists for it and it never sizes an allocation here: the work arrays are sized
  /// by the generators the blob actually carries (as if x0 had had that many), and kept when the
  /// current ones are large enough. save_state() then reports this estimator's own capacity;
  /// the steps do not depend on it.
  void restore_state(const std::vector<double>& state) {
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
  /// Hash of what a state depends on: the system, the gain rule's kind and fixed gains, and
  /// the options fixed at construction (a custom callable rule is not hashed).
  StateFingerprint fingerprint() const {
    StateFingerprint f;
    f.add(sys_.A()).add(sys_.A_rad()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F());
    f.add_int(static_cast<int>(gain_.kind())).add(gain_.lambdas());
    f.add_int(opt_.max_generators).add_int(opt_.use_first_measurement ? 1 : 0);
    for (Eigen::Index i : opt_.strip_order) f.add_int(i);
    return f;
  }

 private:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  /// Pending box above this fraction of the largest radius: appended as generators.
  static constexpr double kBoxToGenerators = 1e-6;

  static Zonotope with_box(const Vec& p, const Eigen::Ref<const Mat>& H, const Vec& r) {
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

  // ---- model data, fixed at construction ---------------------------------------------------
  void setup_model() {
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

  void allocate(Eigen::Index m0) {
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
  }

  /// The prior set p ⊕ H B, exactly (T = I, no pending box).
  void load_prior(const Zonotope& X) {
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

  Eigen::Index mG() const { return mG_; }
  const Mat& G() const { return H_[cur_]; }

  // ---- correction and reduction: writes the current set, the prior stays untouched until
  // the very end (nothing is committed if a gain rule throws) ------------------------------
  void correct_and_reduce(const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u, bool correct) {
    using rounding_bounds::gamma;
    const int work = 1 - cur_;
    Mat& W = H_[work];
    pc_ = p_;
    rc_ = rP_;
    Eigen::Index mW = 0;
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
        if (c_zero_[static_cast<std::size_t>(i)]) continue;
        const auto c = Ct_.col(i);
        const auto ac = absCt_.col(i);
        double phi = 0.0;
        const double yi = shifted_measurement(i, y, u, phi);
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
          absT_ = Tc_.cwiseAbs();
          v_.noalias() = absT_ * wGA_;
        }
        e_ += v_ + lam_.cwiseAbs() * ac.dot(v_);
        if (mN > 0) {
          v_ = Nc_.leftCols(mN).cwiseAbs().rowwise().sum();
          e_ += v_ + lam_.cwiseAbs() * ac.dot(v_);
        }
        e_ += phi * lam_.cwiseAbs();
        // The box of this step's roundings through κ: |κ| rc, then the new errors.
        abs_kappa_times(c, rc_, t_);
        rc_ = g1 * (t_ + g * e_);
        // The updates.
        pc_ += lam_ * (yi - c.dot(pc_));
        t_.noalias() = Tc_.transpose() * c;
        Tc_.noalias() -= lam_ * t_.transpose();
        Tc_identity = false;
        if (mN > 0) {
          cN_.head(mN).noalias() = Nc_.leftCols(mN).transpose() * c;
          Nc_.leftCols(mN).noalias() -= lam_ * cN_.head(mN).transpose();
        }
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
        if (mG_ > 0) product(Tc_, G(), W, mG_);
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
    // Drop zero columns (CORA never counts them) and take the row sums of |W|.
    mW = compact_and_sum(W, mW, wH_);
    // A pending box that is no longer negligible becomes generators (counted). On CORA's data
    // it stays below 2e-10 of the largest radius; the threshold only stops a long growth
    // without reductions.
    const double scale = mW > 0 ? wH_.maxCoeff() : 0.0;
    if (rc_.maxCoeff() > kBoxToGenerators * scale) {
      for (Eigen::Index i = 0; i < n_; ++i)
        if (rc_(i) > 0) {
          W.col(mW).setZero();
          W(i, mW++) = rc_(i);
          wH_(i) += rc_(i);
          if (want_S_) Sc_(i, i) += rc_(i) * rc_(i);
        }
      rc_.setZero();
    }
    bool reduced = false;
    if (correct && mW > opt_.max_generators) {
      const Eigen::Index m_before = mW;
      mW = detail::reduce_in_place(opt_.reduction, W, mW, opt_.max_generators, &rc_, rws_, want_S_);
      reduced = rws_.reduced_count > 0;
      if (reduced) {
        rc_.setZero();
        if (want_S_) {
          const Eigen::Index boxed = mW - (m_before - rws_.reduced_count);
          Sc_ -= rws_.gram;
          Sc_.noalias() += W.middleCols(mW - boxed, boxed) * W.middleCols(mW - boxed, boxed).transpose();
        }
        mW = compact_and_sum(W, mW, wH_, false);  // no zero columns left; the new row sums
      }
    }
    // Commit the current set (nothing below throws).
    cur_ = work;
    m_ = mW;
    mG_ = mW;
    cur_p_ = pc_;
    cur_r_ = rc_;
    cur_w_ = wH_;
    reduced_ = reduced;
    has_current_ = true;
    const double infl = 1.0 + static_cast<double>(mW + n_ + 4) * std::numeric_limits<double>::epsilon();
    e_ = (wH_ + rc_) * infl;
    cur_lo_ = cur_p_ - e_;
    cur_hi_ = cur_p_ + e_;
    if (want_S_) S_ = Sc_;
  }

  /// y_i − D_i u and the strip half-width, widened by the rounding of D_i u when D_i ≠ 0.
  double shifted_measurement(Eigen::Index i, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                             double& phi) const {
    phi = phi_(i);
    if (!D_used_[static_cast<std::size_t>(i)]) return y(i);
    const double yi = y(i) - sys_.D().row(i).dot(u);
    phi += rounding_bounds::gamma(sys_.nu()) * (std::abs(y(i)) + absD_.row(i).dot(u.cwiseAbs()));
    return yi;
  }

  /// W = [T G, N] explicitly; the carried box |T| rA and the product's rounding are added to
  /// r. Returns the column count.
  Eigen::Index materialize_prior(Mat& W, Vec& r) const {
    using rounding_bounds::gamma;
    if (T_identity_) {
      if (mG_ > 0) W.leftCols(mG_) = G().leftCols(mG_);
      r += rA_;
    } else {
      if (mG_ > 0) product(T_, G(), W, mG_);
      const Mat absT = T_.cwiseAbs();
      r = (1.0 + gamma(n_)) * (r + absT * rA_ + gamma(n_) * (absT * (wG_ + rA_)));
    }
    W.middleCols(mG_, mN_) = N_.leftCols(mN_);
    return mG_ + mN_;
  }

  /// t = |I − λcᵀ| r (the exact |κ|, with λ = lam_), rounded to nearest (the caller inflates).
  void abs_kappa_times(const Eigen::Ref<const Vec>& c, const Vec& r, Vec& t) const {
    for (Eigen::Index i = 0; i < n_; ++i) {
      double acc = 0.0;
      const double li = lam_(i);
      for (Eigen::Index j = 0; j < n_; ++j) acc += std::abs((i == j ? 1.0 : 0.0) - li * c(j)) * r(j);
      t(i) = acc;
    }
  }

  /// Strip by strip on the explicit generator matrix, for gain rules that need the set.
  Eigen::Index explicit_strips(Mat& W, Eigen::Index m, const Eigen::Ref<const Vec>& y,
                               const Eigen::Ref<const Vec>& u) {
    using rounding_bounds::gamma;
    const double g = gamma(n_ + 2), g1 = 1.0 + g;
    for (Eigen::Index i : opt_.strip_order) {
      if (c_zero_[static_cast<std::size_t>(i)]) continue;
      const auto c = Ct_.col(i);
      const auto ac = absCt_.col(i);
      double phi = 0.0;
      const double yi = shifted_measurement(i, y, u, phi);
      const StripMeasurement meas{Strip(Vec(c), yi, phi), i};
      const Vec lambda = gain_(Zonotope(pc_, W.leftCols(m)), meas);
      if (lambda.size() != n_ || !lambda.allFinite())
        throw NumericalError("gain rule: returned a non-finite or wrongly sized lambda for output " +
                             std::to_string(i));
      const double innov = std::abs(yi) + ac.dot(pc_.cwiseAbs());
      e_ = pc_.cwiseAbs() + lambda.cwiseAbs() * innov + phi * lambda.cwiseAbs();
      if (m > 0) {
        v_ = W.leftCols(m).cwiseAbs().rowwise().sum();
        e_ += v_ + lambda.cwiseAbs() * ac.dot(v_);
      }
      lam_ = lambda;
      abs_kappa_times(c, rc_, t_);
      rc_ = g1 * (t_ + g * e_);
      pc_ += lambda * (yi - c.dot(pc_));
      if (m > 0) {
        cN_.resize(std::max(cN_.size(), m));
        cN_.head(m).noalias() = W.leftCols(m).transpose() * c;
        W.leftCols(m).noalias() -= lambda * cN_.head(m).transpose();
      }
      if (phi > 0 && lambda.cwiseAbs().maxCoeff() > 0) W.col(m++) = phi * lambda;
    }
    return m;
  }

  /// Removes exactly-zero columns of W (keeping the order) when `drop_zeros`, and sets
  /// w = rs|W|, rounded up. Fixed-size column kernels for n <= 8.
  Eigen::Index compact_and_sum(Mat& W, Eigen::Index m, Vec& w, bool drop_zeros = true) const {
    switch (n_) {
      case 1: return compact_and_sum_impl<1>(W, m, w, drop_zeros);
      case 2: return compact_and_sum_impl<2>(W, m, w, drop_zeros);
      case 3: return compact_and_sum_impl<3>(W, m, w, drop_zeros);
      case 4: return compact_and_sum_impl<4>(W, m, w, drop_zeros);
      case 5: return compact_and_sum_impl<5>(W, m, w, drop_zeros);
      case 6: return compact_and_sum_impl<6>(W, m, w, drop_zeros);
      case 7: return compact_and_sum_impl<7>(W, m, w, drop_zeros);
      case 8: return compact_and_sum_impl<8>(W, m, w, drop_zeros);
      default: return compact_and_sum_impl<Eigen::Dynamic>(W, m, w, drop_zeros);
    }
  }
  template <int N>
  Eigen::Index compact_and_sum_impl(Mat& W, Eigen::Index m, Vec& w, bool drop_zeros) const {
    using Col = Eigen::Matrix<double, N, 1>;
    const Eigen::Index n = n_;
    // A fixed-size accumulator lives in registers; a dynamic one is w itself (no allocation).
    Col acc_fixed;
    if constexpr (N != Eigen::Dynamic) acc_fixed.setZero();
    else w.setZero();
    auto& acc = [&]() -> auto& {
      if constexpr (N != Eigen::Dynamic) return acc_fixed;
      else return w;
    }();
    double* const base = W.data();
    Eigen::Index k = 0;
    for (Eigen::Index j = 0; j < m; ++j) {
      const Eigen::Map<const Col> col(base + j * n, n);
      acc += col.cwiseAbs();
      if (drop_zeros && (col.array() == 0.0).all()) continue;
      if (k != j) Eigen::Map<Col>(base + k * n, n) = col;  // k < j: no overlap
      ++k;
    }
    const double infl = 1.0 + static_cast<double>(k + 2) * std::numeric_limits<double>::epsilon();
    if constexpr (N != Eigen::Dynamic) w = acc_fixed * infl;
    else w *= infl;
    return k;
  }

  /// W.leftCols(m) = T G.leftCols(m); fixed-size kernels for n <= 8 (Eigen's blocked product
  /// packs its operands, which costs more than the product for a few rows).
  static void product(const Mat& T, const Mat& G, Mat& W, Eigen::Index m) {
    switch (T.rows()) {
      case 1: W.leftCols(m).noalias() = T(0, 0) * G.leftCols(m); return;
      case 2: return small_product<2>(T, G, W, m);
      case 3: return small_product<3>(T, G, W, m);
      case 4: return small_product<4>(T, G, W, m);
      case 5: return small_product<5>(T, G, W, m);
      case 6: return small_product<6>(T, G, W, m);
      case 7: return small_product<7>(T, G, W, m);
      case 8: return small_product<8>(T, G, W, m);
      default: W.leftCols(m).noalias() = T * G.leftCols(m);
    }
  }
  template <int N>
  static void small_product(const Mat& T, const Mat& G, Mat& W, Eigen::Index m) {
    const Eigen::Matrix<double, N, N> Tf = T;
    Eigen::Map<const Eigen::Matrix<double, N, Eigen::Dynamic>> Gm(G.data(), N, m);
    Eigen::Map<Eigen::Matrix<double, N, Eigen::Dynamic>> Wm(W.data(), N, m);
    Wm.noalias() = Tf.lazyProduct(Gm);
  }

  // ---- prediction of the next prior from the current set ----------------------------------
  void predict_prior(const Eigen::Ref<const Vec>& u) {
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

  LinearSystem sys_;
  ZonotopeGain gain_;
  ZonotopicOptions opt_;
  Eigen::Index n_ = 0, cap_ = 0, capN_ = 0;
  bool lazy_ = false, want_S_ = false, interval_ = false;
  Mat absMid_, absA_, Enz_, EEt_, Ct_, absCt_, absB_, absD_;
  Vec phi_;
  std::vector<bool> D_used_, c_zero_;

  // The prior (the set for x_{k+1}): p_ ⊕ [T_ G, N_] B ⊕ T_ box(rA_) ⊕ box(rP_), with
  // G = H_[cur_].leftCols(mG_); S_ ≈ its Gram matrix (segment minimisation), wG_ = rs|G|
  // rounded up.
  Vec p_, rA_, rP_, wG_;
  Mat T_, N_, S_;
  bool T_identity_ = true;
  Eigen::Index mG_ = 0, mN_ = 0;

  // The current set (x_k): cur_p_ ⊕ H_[cur_].leftCols(m_) B ⊕ box(cur_r_), and its hull.
  Mat H_[2];
  int cur_ = 0;
  Eigen::Index m_ = 0;
  Vec cur_p_, cur_r_, cur_w_, cur_lo_, cur_hi_;
  bool has_current_ = false, reduced_ = false;
  Eigen::Index k_ = 0;

  // Scratch.
  Vec pc_, rc_, wH_, wGA_, lam_, sc_, v_, t_, e_, cN_, uabs_;
  Mat Tc_, Nc_, Sc_, absT_;
  detail::ReductionWorkspace rws_;
};

}  // namespace setbound
