// setbound — definitions of the functions declared in setbound/estimators/zonotopic/observer.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/observer.hpp"
#include "setbound/core/config.hpp"

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
  if (rule < 1 || rule > 7) throw InvalidArgumentError("rule: unknown zonotopic gain rule " + std::to_string(rule));
  const int conv = static_cast<int>(opt_.convention);
  if (conv < 0 || conv > 1) throw InvalidArgumentError("convention: must be Setbound or Cora");
  const int red = static_cast<int>(opt_.reduction);
  if (red < 1 || red > 3) throw InvalidArgumentError("reduction: must be Combastel, Girard or Pca");
  if (sys_.uncertain_A())
    throw InvalidArgumentError("system: this observer needs a known A (an interval [A] is not supported)");
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
  setup();
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
  gain_last_ = Mat::Zero(n_, ny);
  lo_ = hi_ = Vec::Zero(n_);
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
    lo_.setZero();
    hi_.setZero();
  } else {
    prior_ = Set{Vec::Zero(n_), Vec::Zero(n_), Mat::Zero(n_, 0)};
    cur_ = s;
    has_current_ = true;
    hull(cur_);
  }
}

SETBOUND_INLINE void ZonotopicObserver::reset() { load_initial(); }

SETBOUND_INLINE Zonotope ZonotopicObserver::current_set() const {
  if (!has_current_) throw InvalidArgumentError("observer: no step has been taken yet");
  const Eigen::Index m = cur_.G.cols();
  const Eigen::Index nb = static_cast<Eigen::Index>((cur_.r.array() > 0).count());
  Mat out(n_, m + nb);
  out.leftCols(m) = cur_.G;
  Eigen::Index j = m;
  for (Eigen::Index i = 0; i < n_; ++i)
    if (cur_.r(i) > 0) {
      out.col(j).setZero();
      out(i, j++) = cur_.r(i);
    }
  return Zonotope(cur_.p, std::move(out));
}

SETBOUND_INLINE void ZonotopicObserver::update(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (y.size() != sys_.ny())
    throw DimensionError("y: expected length " + std::to_string(sys_.ny()) + ", got " + std::to_string(y.size()));
  if (u.size() != sys_.nu())
    throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u.size()));
  require_no_infinity(y, "y");
  require_finite(u, "u");
  Mat gain = Mat::Zero(n_, sys_.ny());
  if (is_filter()) {
    Set X = prior_;
    correct(X, y, u, gain);
    // CORA's strip-based loop does not reduce the first corrected set (spec §1.3).
    finish_set(X, !(opt_.convention == Convention::Cora && k_ == 0));
    Set P = X;
    predict(P, u);
    if (!X.p.allFinite() || !X.G.allFinite() || !X.r.allFinite() || !P.p.allFinite() || !P.G.allFinite() ||
        !P.r.allFinite())
      throw NumericalError("observer: the set overflowed (non-finite values) at step " + std::to_string(k_));
    // Commit (nothing below throws but memory).
    cur_ = std::move(X);
    prior_ = std::move(P);
  } else {
    Set X = cur_;
    propagate(X, y, u, gain);
    finish_set(X, true);
    if (!X.p.allFinite() || !X.G.allFinite() || !X.r.allFinite())
      throw NumericalError("observer: the set overflowed (non-finite values) at step " + std::to_string(k_));
    cur_ = std::move(X);
  }
  gain_last_ = std::move(gain);
  has_current_ = true;
  hull(cur_);
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

SETBOUND_INLINE void ZonotopicObserver::strip_update(Set& X, const Mat& Lam, const Mat& CS, const Vec& ys, const Vec& sig,
                                                     Eigen::Index replace) {
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
  if (m > 0) Gn.leftCols(m) = X.G - Lam * (CS * X.G);
  r += 2.0 * g * (w + absL * (absC * w));
  // New columns Λ diag(σ_S) (rounding u |Λ| σ).
  for (Eigen::Index j = 0; j < q; ++j) Gn.col(m + j) = Lam.col(j) * sig(j);
  r += g * (absL * sig);
  if (replace >= 0) {
    // Bravo: (I − λcᵀ)g_j is zero in exact arithmetic with λ = g_j / cᵀg_j; its computed value
    // (and the rounding bound above) stays in the box, the new column takes its place.
    r += Gn.col(replace).cwiseAbs();
    Gn.col(replace) = Gn.col(m);
    Gn.conservativeResize(n, m);
  }
  X.p.swap(pn);
  X.G.swap(Gn);
  X.r = r * (1.0 + g);
}

SETBOUND_INLINE void ZonotopicObserver::affine(Set& X, const Mat& M, const Mat& dM, const Vec& t, const Vec& dt, const Mat& N,
                                               const Vec& dN) {
  using rounding_bounds::gamma;
  const Eigen::Index n = X.p.size(), m = X.G.cols(), k = N.cols();
  const double g = gamma(n + 4);
  const Vec w = X.G.cwiseAbs().rowwise().sum();
  const Mat absM = M.cwiseAbs();
  const Vec absp = X.p.cwiseAbs();
  Vec pn = M * X.p + t;
  Vec r = (absM + dM) * X.r + dM * (w + absp) + g * (absM * (w + absp)) + g * pn.cwiseAbs() + dt + dN;
  Mat Gn(n, m + k);
  if (m > 0) Gn.leftCols(m).noalias() = M * X.G;
  if (k > 0) Gn.rightCols(k) = N;
  X.p.swap(pn);
  X.G.swap(Gn);
  X.r = r * (1.0 + g);
}

SETBOUND_INLINE Eigen::Index ZonotopicObserver::bravo_choice(const Set& X, const Eigen::Ref<const Vec>& c, double y, double sig,
                                                             Vec& lam) const {
  (void)y;
  lam = Vec::Zero(n_);
  const Eigen::Index m = X.G.cols();
  if (m == 0) return -1;
  const Mat& G = X.G;
  const Vec cg = G.transpose() * c;
  const Vec ac = c.cwiseAbs();
  // Candidate 0 is the set itself; candidate j (Bravo 2006, Property 1) replaces g_j by the strip
  // direction: g_i − (cᵀg_i / a) g_j for i ≠ j, (σ / a) g_j for i = j, a = cᵀg_j. Score: det(T Tᵀ)
  // (a volume proxy); the first minimiser wins (candidate 0 wins exact ties, spec §2.2).
  double best = (G * G.transpose()).determinant();
  Eigen::Index bestj = -1;
  const double base = 1e10 * std::numeric_limits<double>::epsilon();
  Mat T(n_, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const double a = cg(j);
    const double thr = opt_.convention == Convention::Cora ? base : base * ac.dot(G.col(j).cwiseAbs());
    if (!(std::abs(a) > thr)) continue;
    T.noalias() = G - G.col(j) * (cg.transpose() / a);
    T.col(j) = (sig / a) * G.col(j);
    const double d = (T * T.transpose()).determinant();
    if (d < best) {
      best = d;
      bestj = j;
    }
  }
  if (bestj >= 0) lam = G.col(bestj) / cg(bestj);
  return bestj;
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

SETBOUND_INLINE void ZonotopicObserver::correct(Set& X, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                                                Mat& gain) const {
  std::vector<Eigen::Index> rows;
  Vec ys, sig;
  shifted(y, u, rows, ys, sig);
  const Eigen::Index q = static_cast<Eigen::Index>(rows.size());
  if (q == 0) return;
  const Mat& C = sys_.C();
  switch (opt_.rule) {
    case ZonotopicRule::SegmentMin:
    case ZonotopicRule::Bravo:
    case ZonotopicRule::FixedStrips: {
      // S-I: one strip at a time, in the order of the outputs.
      for (Eigen::Index t = 0; t < q; ++t) {
        const Eigen::Index i = rows[static_cast<std::size_t>(t)];
        const Vec c = C.row(i).transpose();
        Vec lam;
        Eigen::Index replace = -1;
        if (opt_.rule == ZonotopicRule::SegmentMin) {
          // λ = G Gᵀc / (cᵀG Gᵀc + σ²) ([Alamo2005], spec §2.3).
          const Vec v = X.G * (X.G.transpose() * c);
          const double den = c.dot(v) + sig(t) * sig(t);
          lam = den > 0 ? Vec(v / den) : Vec(Vec::Zero(n_));
        } else if (opt_.rule == ZonotopicRule::Bravo) {
          replace = bravo_choice(X, c, ys(t), sig(t), lam);
          if (replace < 0) continue;  // the set itself is the best candidate
        } else {
          lam = opt_.gain.col(i);
        }
        if (!lam.allFinite())
          throw NumericalError("gain rule: non-finite weight for output " + std::to_string(i));
        if (lam.cwiseAbs().maxCoeff() == 0) continue;  // nothing changes (CORA's zero column is dropped)
        strip_update(X, lam, C.row(i), ys.segment(t, 1), sig.segment(t, 1), replace);
        gain.col(i) = lam;
      }
      return;
    }
    case ZonotopicRule::Wang:
    case ZonotopicRule::FixedLambda: {
      // S-II: all present strips at once with one n × q weight.
      Mat CS(q, n_);
      for (Eigen::Index t = 0; t < q; ++t) CS.row(t) = C.row(rows[static_cast<std::size_t>(t)]);
      Mat Lam(n_, q);
      if (opt_.rule == ZonotopicRule::Wang) {
        // Wang, Puig, Cembrano 2018 Thm. 2: Λ = R̄ C_Sᵀ (C_S R̄ C_Sᵀ + F Fᵀ)⁻¹ with R̄ the
        // predicted set's G Gᵀ; CORA (sic, spec §2.4) forms R̄ = A (G Gᵀ) Aᵀ + E Eᵀ from the
        // predicted set, i.e. applies A and W a second time.
        // R̄ is never formed: with H = Gᵀ C_Sᵀ (Gᵀ Aᵀ C_Sᵀ in CORA's convention; m × q),
        // R̄ C_Sᵀ = G H (A G H + E Eᵀ C_Sᵀ) and C_S R̄ C_Sᵀ = HᵀH (+ C_S E Eᵀ C_Sᵀ) cost O(n m q)
        // instead of the O(n² m) of G Gᵀ (tank30 at order 100: n = 30, m ≈ 3000).
        const bool cora = opt_.convention == Convention::Cora;
        const Mat ACt = cora ? Mat(sys_.A().transpose() * CS.transpose()) : Mat(CS.transpose());
        const Mat H = X.G.transpose() * ACt;
        Mat RC = X.G * H;
        Mat S = H.transpose() * H;
        if (cora) {
          RC = sys_.A() * RC + EEt_ * CS.transpose();
          S += CS * EEt_ * CS.transpose();
        }
        for (Eigen::Index a = 0; a < q; ++a)
          for (Eigen::Index b = 0; b < q; ++b)
            S(a, b) += FFt_(rows[static_cast<std::size_t>(a)], rows[static_cast<std::size_t>(b)]);
        Lam = solve_gain(RC, S);
      } else {
        for (Eigen::Index t = 0; t < q; ++t) Lam.col(t) = opt_.gain.col(rows[static_cast<std::size_t>(t)]);
      }
      strip_update(X, Lam, CS, ys, sig, -1);
      for (Eigen::Index t = 0; t < q; ++t) gain.col(rows[static_cast<std::size_t>(t)]) = Lam.col(t);
      return;
    }
    default: return;
  }
}

SETBOUND_INLINE void ZonotopicObserver::predict(Set& X, const Eigen::Ref<const Vec>& u) const {
  using rounding_bounds::gamma;
  Vec t = Vec::Zero(n_), dt = Vec::Zero(n_);
  if (sys_.nu() > 0) {
    t.noalias() = sys_.B() * u;
    dt = gamma(sys_.nu()) * (sys_.B().cwiseAbs() * u.cwiseAbs());
  }
  affine(X, sys_.A(), Mat::Zero(n_, n_), t, dt, Enz_, Vec::Zero(n_));
}

SETBOUND_INLINE void ZonotopicObserver::propagate(Set& X, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                                                  Mat& L) const {
  using rounding_bounds::gamma;
  std::vector<Eigen::Index> rows;
  Vec ys, sig;
  shifted(y, u, rows, ys, sig);
  const Eigen::Index q = static_cast<Eigen::Index>(rows.size());
  const Mat& A = sys_.A();
  const Mat& C = sys_.C();
  L.setZero(n_, sys_.ny());
  if (q > 0) {
    if (opt_.rule == ZonotopicRule::Combastel) {
      // Combastel 2015: L_k = A P Cᵀ (C P Cᵀ + F Fᵀ)⁻¹ with P = G Gᵀ of the current set (spec §2.5),
      // over the present outputs.
      Mat CS(q, n_);
      for (Eigen::Index t = 0; t < q; ++t) CS.row(t) = C.row(rows[static_cast<std::size_t>(t)]);
      // P is never formed: with H = GᵀC_Sᵀ, A P C_Sᵀ = A (G H) and C_S P C_Sᵀ = HᵀH, O(n m q).
      const Mat H = X.G.transpose() * CS.transpose();
      Mat S = H.transpose() * H;
      for (Eigen::Index a = 0; a < q; ++a)
        for (Eigen::Index b = 0; b < q; ++b)
          S(a, b) += FFt_(rows[static_cast<std::size_t>(a)], rows[static_cast<std::size_t>(b)]);
      const Mat Lq = solve_gain(A * (X.G * H), S);
      for (Eigen::Index t = 0; t < q; ++t) L.col(rows[static_cast<std::size_t>(t)]) = Lq.col(t);
    } else {
      for (Eigen::Index t = 0; t < q; ++t) {
        const Eigen::Index i = rows[static_cast<std::size_t>(t)];
        L.col(i) = opt_.gain.col(i);
      }
    }
  }
  if (!L.allFinite()) throw NumericalError("gain rule: non-finite observer gain");
  const double g = gamma(sys_.ny() + sys_.nu() + 4);
  const Mat absL = L.cwiseAbs();
  // M = A − L C and the bound of its rounding.
  const Mat M = A - L * C;
  const Mat dM = g * (A.cwiseAbs() + absL * C.cwiseAbs());
  // t = B u + L (y − D u) over the present outputs (L's other columns are zero).
  Vec t = Vec::Zero(n_), dt = Vec::Zero(n_);
  Vec yfull = Vec::Zero(sys_.ny()), yabs = Vec::Zero(sys_.ny());
  for (Eigen::Index s = 0; s < q; ++s) {
    const Eigen::Index i = rows[static_cast<std::size_t>(s)];
    yfull(i) = ys(s);
    yabs(i) = std::abs(y(i)) + (sys_.nu() > 0 ? sys_.D().row(i).cwiseAbs().dot(u.cwiseAbs()) : 0.0);
  }
  if (sys_.nu() > 0) {
    t.noalias() = sys_.B() * u;
    dt = g * (sys_.B().cwiseAbs() * u.cwiseAbs());
  }
  t.noalias() += L * yfull;
  dt += 2.0 * g * (absL * yabs) + g * t.cwiseAbs();
  // Disturbance columns: E_j − L F_j for the ω entering the outputs, then E_j (CORA's order
  // [−L G_V, G_W] on its model, spec §1.3).
  Mat N(n_, static_cast<Eigen::Index>(fcols_.size() + ecols_.size()));
  Eigen::Index k = 0;
  Vec dN = Vec::Zero(n_);
  for (Eigen::Index j : fcols_) {
    N.col(k++) = sys_.E().col(j) - L * sys_.F().col(j);
    dN += g * (sys_.E().col(j).cwiseAbs() + absL * sys_.F().col(j).cwiseAbs());
  }
  for (Eigen::Index j : ecols_) N.col(k++) = sys_.E().col(j);
  affine(X, M, dM, t, dt, N, dN);
}

SETBOUND_INLINE void ZonotopicObserver::finish_set(Set& X, bool reduce) {
  // Drop exactly-zero columns (CORA never counts them), keeping the order.
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < X.G.cols(); ++j) {
    if ((X.G.col(j).array() == 0.0).all()) continue;
    if (k != j) X.G.col(k) = X.G.col(j);
    ++k;
  }
  X.G.conservativeResize(n_, k);
  // A pending box that is no longer negligible becomes generators (counted).
  const double scale = k > 0 ? X.G.cwiseAbs().rowwise().sum().maxCoeff() : 0.0;
  if (X.r.maxCoeff() > kBoxToGenerators * scale) {
    const Eigen::Index nb = static_cast<Eigen::Index>((X.r.array() > 0).count());
    X.G.conservativeResize(n_, k + nb);
    for (Eigen::Index i = 0; i < n_; ++i)
      if (X.r(i) > 0) {
        X.G.col(k).setZero();
        X.G(i, k++) = X.r(i);
      }
    X.r.setZero();
  }
  if (reduce && k > opt_.max_generators) {
    k = detail::reduce_in_place(opt_.reduction, X.G, k, opt_.max_generators, &X.r, rws_);
    if (rws_.reduced_count > 0) X.r.setZero();
    X.G.conservativeResize(n_, k);
  }
}

SETBOUND_INLINE void ZonotopicObserver::hull(const Set& X) {
  const double eps = std::numeric_limits<double>::epsilon();
  const Eigen::Index m = X.G.cols();
  Vec e = m > 0 ? Vec(X.G.cwiseAbs().rowwise().sum()) : Vec(Vec::Zero(n_));
  e = (e + X.r + eps * X.p.cwiseAbs()) * (1.0 + static_cast<double>(m + n_ + 4) * eps);
  lo_ = X.p - e;
  hi_ = X.p + e;
}

SETBOUND_INLINE std::vector<double> ZonotopicObserver::save_state() const {
  StateWriter w(StateKind::ZonotopicObserver, fingerprint());
  w.count(k_).flag(has_current_);
  w.vec(prior_.p).vec(prior_.r).mat(prior_.G);
  w.vec(cur_.p).vec(cur_.r).mat(cur_.G);
  w.mat(gain_last_);
  return w.finish();
}

SETBOUND_INLINE void ZonotopicObserver::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k;
    bool has;
    Set prior, cur;
    Mat gain;
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
    r.finish();
    if ((t.prior.r.array() < 0).any() || (t.cur.r.array() < 0).any()) r.fail("a box radius is negative");
    if (is_filter() && t.has != (t.k > 0)) r.fail("a filter has a current set exactly after its first step");
    if (!is_filter() && !t.has) r.fail("a predictor always has a current set");
    return t;
  });
  k_ = static_cast<Eigen::Index>(q.k);
  has_current_ = q.has;
  prior_ = std::move(q.prior);
  cur_ = std::move(q.cur);
  gain_last_ = std::move(q.gain);
  if (has_current_) {
    hull(cur_);
  } else {
    lo_.setZero();
    hi_.setZero();
  }
}

SETBOUND_INLINE StateFingerprint ZonotopicObserver::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F());
  f.add_int(static_cast<int>(opt_.rule)).add(opt_.gain).add_int(opt_.max_generators);
  f.add_int(static_cast<int>(opt_.reduction)).add_int(static_cast<int>(opt_.convention));
  return f;
}

}  // namespace setbound
