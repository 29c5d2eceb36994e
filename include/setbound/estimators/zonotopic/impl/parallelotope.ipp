// setbound — definitions of the functions declared in setbound/estimators/zonotopic/parallelotope.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include "setbound/estimators/zonotopic/parallelotope.hpp"
#include "setbound/core/config.hpp"
#include "setbound/estimators/zonotopic/strip_swap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace setbound {

namespace parallelotope_detail {

/// The Vicino–Zappa step as CORA's aux_Parallelotope computes it (normalised strip |pᵀx − c| ≤ 1
/// with p = C_iᵀ/σ, c = y/σ; no rounding control, no emptiness check). Returns whether stage 3
/// swapped a column.
SETBOUND_INLINE bool vz_cora(Eigen::VectorXd& theta, Eigen::MatrixXd& t, const Eigen::VectorXd& p, double c) {
  const Eigen::Index n = t.rows();
  const Eigen::VectorXd t0 = p / p.squaredNorm();
  // Stage 0: p'·t_j >= 0, P0 = Σ_j p'·t_j, the range [E0n, E0p] of pᵀx − c over the parallelotope.
  double P0 = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (p.dot(t.col(j)) < 0) t.col(j) = -t.col(j);
    P0 += p.dot(t.col(j));
  }
  const double d = p.dot(theta) - c;
  const double E0p = d + P0, E0n = d - P0;
  // Stage 1: the strip tightened to that range.
  const double rop = std::min(1.0, E0p), ron = std::min(1.0, -E0n);
  const Eigen::VectorXd p1 = p;
  const Eigen::VectorXd pn = 2.0 * p / (rop + ron);
  const double cn = (2.0 / (rop + ron)) * (c + 0.5 * (rop - ron));
  // Stage 2: each generator segment shrunk to what the strip allows.
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double K = p1.dot(t.col(j));
    double rp = 1.0, rn = 1.0;
    if (K != 0) {
      rp = std::min(1.0, (1.0 - E0n) / K - 1.0);
      rn = std::min(1.0, (1.0 + E0p) / K - 1.0);
    }
    shift += (rp - rn) * t.col(j);
    t.col(j) *= 0.5 * (rp + rn);
  }
  theta += 0.5 * shift;
  // Stage 3: candidate 0 is t0 (keep T); the first maximiser of p'ᵀt_j wins (MATLAB's max).
  Eigen::Index index = 0;
  double best = pn.dot(t0);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double v = pn.dot(t.col(j));
    if (v > best || (std::isnan(best) && !std::isnan(v))) {
      best = v;
      index = j + 1;
    }
  }
  if (index == 0) return false;
  const Eigen::VectorXd tj = t.col(index - 1);
  const double kappa = 1.0 / pn.dot(tj);
  theta += kappa * tj * (cn - pn.dot(theta));
  for (Eigen::Index j = 0; j < n; ++j) {
    if (j == index - 1) t.col(j) = kappa * tj;
    else t.col(j) -= kappa * pn.dot(t.col(j)) * tj;
  }
  return true;
}

/// The strip update x' = x + λ(y − cᵀx − v) of X = (p, G, r) with column `replace` of G taken by
/// the new column λσ (Bravo's / Vicino–Zappa's swap), as observer.ipp's bravo_update for one
/// strip: every rounding error bounded and added to the box, the box carried by |I − λcᵀ|. The
/// centre's and the generators' terms are detail::strip_swap_terms, shared with bravo_update;
/// the box's term keeps the computed K here (strip_swap.hpp says why).
SETBOUND_INLINE void strip_swap(ParallelotopeEstimator::Set& X, const Eigen::VectorXd& lam,
                                const Eigen::Ref<const Eigen::VectorXd>& c, double y, double sig,
                                Eigen::Index replace) {
  using rounding_bounds::gamma;
  const Eigen::Index n = X.p.size();
  const double g = gamma(n + 5);
  const Eigen::VectorXd w = X.G.cwiseAbs().rowwise().sum();
  const Eigen::VectorXd absL = lam.cwiseAbs(), absc = c.cwiseAbs();
  // K = I − λcᵀ as computed, and a bound of its rounding: |K − K̃| <= g (I + |λ||c|ᵀ).
  Eigen::MatrixXd K = -(lam * c.transpose());
  K.diagonal().array() += 1.0;
  Eigen::MatrixXd dK = g * (absL * absc.transpose());
  dK.diagonal().array() += g;
  Eigen::VectorXd r = (K.cwiseAbs() + dK) * X.r;
  // The centre p + λ(y − cᵀp) and its rounding; (I − λcᵀ)G = G − λ(cᵀG), rounding
  // <= 2g (|G| + |λ||c|ᵀ|G|) per row sum.
  Eigen::VectorXd pn, absp;
  detail::strip_swap_terms(X.p, lam, absL, c, y, w, g, pn, absp, r);
  Eigen::MatrixXd Gn = X.G - lam * (c.transpose() * X.G);
  // (I − λcᵀ)g_replace is zero in exact arithmetic with λ = g_replace / cᵀg_replace; its computed
  // value (and the bound above) stays in the box; the new column λσ (rounding u|λ|σ) takes its place.
  r += Gn.col(replace).cwiseAbs();
  Gn.col(replace) = lam * sig;
  r += g * absL * sig;
  X.p.swap(pn);
  X.G.swap(Gn);
  X.r = r * (1.0 + g);
}

/// The guaranteed Vicino–Zappa step of X = θ ⊕ T B^n ⊕ box(r) with |cᵀx − y| ≤ sig (see the
/// header). Returns whether stage 3 swapped a column.
SETBOUND_INLINE bool vz_guaranteed(ParallelotopeEstimator::Set& X, const Eigen::Ref<const Eigen::VectorXd>& c, double y,
                                   double sig) {
  using rounding_bounds::gamma;
  const double u = rounding_bounds::kUnitRoundoff;
  const Eigen::Index n = X.p.size();
  Eigen::MatrixXd& T = X.G;
  const double g = gamma(2 * n + 8);
  const Eigen::VectorXd absc = c.cwiseAbs();
  // K_j = cᵀt_j >= 0 after flipping t_j (exact), and the bound eK_j of its rounding.
  Eigen::VectorXd K(n), eK(n);
  double S = 0.0, magT = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    double k = c.dot(T.col(j));
    if (k < 0) {
      T.col(j) = -T.col(j);
      k = -k;
    }
    K(j) = k;
    const double a = absc.dot(T.col(j).cwiseAbs());
    eK(j) = g * a;
    magT += a;
    S += k + eK(j);
  }
  S *= 1.0 + g;  // >= Σ_j (K_j + eK_j) >= Σ_j |cᵀt_j| (exact)
  const double d = c.dot(X.p);
  const double e_d = g * absc.dot(X.p.cwiseAbs());
  const double cr = absc.dot(X.r) * (1.0 + g);
  const double sig_w = (sig + cr) * (1.0 + g);  // the strip widened by the box
  // Magnitude of every term of the sums below: their own rounding is within g·M.
  const double M = std::abs(y) + sig_w + std::abs(d) + e_d + S + magT;
  const double slack = g * M;

  // Stage 1: the strip tightened to the range of cᵀx over Θ ⊕ B_r (outward on both sides).
  double ys = y, ss = sig;
  {
    const double lo = std::max(y - sig - slack, d - S - cr - e_d - slack);
    const double hi = std::min(y + sig + slack, d + S + cr + e_d + slack);
    if (lo <= hi) {
      ys = 0.5 * (lo + hi);
      ss = (0.5 * (hi - lo) + u * (std::abs(lo) + std::abs(hi))) * (1.0 + g);
      if (ss > sig) {  // no tightening: keep the reading's own strip
        ys = y;
        ss = sig;
      }
    }
    // lo > hi: empty within the rounding (the screening let it through): the strip itself still
    // contains the intersection.
  }

  // Stage 2: ξ_j in [lower, upper] ∩ [−1, 1], from
  //   ξ_j K_j <= y + σ_w − cᵀθ + Σ_{i≠j} |K_i|,   ξ_j K_j >= y − σ_w − cᵀθ − Σ_{i≠j} |K_i|.
  Eigen::VectorXd a = Eigen::VectorXd::Zero(n), b = Eigen::VectorXd::Ones(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double klo = K(j) - eK(j), khi = K(j) + eK(j);
    if (!(klo > 0)) continue;  // K_j = 0 or not certified positive: keep [−1, 1]
    const double others = S - K(j) - eK(j);
    const double U = y + sig_w - d + e_d + others + slack;
    const double L = y - sig_w - d - e_d - others - slack;
    double up = U >= 0 ? U / klo : U / khi;
    up = up >= 0 ? up * (1.0 + g) : up * (1.0 - g);
    double low = L <= 0 ? L / klo : L / khi;
    low = low <= 0 ? low * (1.0 + g) : low * (1.0 - g);
    up = std::min(1.0, up);
    low = std::max(-1.0, low);
    if (!(low <= up) || (up == 1.0 && low == -1.0)) continue;  // empty within rounding, or no change
    a(j) = 0.5 * (up + low);
    b(j) = (0.5 * (up - low) + u * (std::abs(up) + std::abs(low))) * (1.0 + 2.0 * u);
  }
  {
    // θ' = θ + Σ a_j t_j, t_j' = b_j t_j; their rounding into the box.
    Eigen::VectorXd rr = X.p.cwiseAbs();
    Eigen::VectorXd pn = X.p;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (a(j) != 0) {
        pn += a(j) * T.col(j);
        rr += std::abs(a(j)) * T.col(j).cwiseAbs();
      }
      if (b(j) != 1.0) {
        rr += b(j) * T.col(j).cwiseAbs();
        T.col(j) *= b(j);
      }
    }
    rr += pn.cwiseAbs();
    X.r = (X.r + g * rr) * (1.0 + g);
    X.p.swap(pn);
  }

  // Stage 3: the least-volume candidate: swap column j* (the largest cᵀt_j, not rounding noise)
  // when cᵀt_j* > σ (the reading's half-width, CORA's test; see the header: the same choice as
  // cᵀt_j* > σ' in exact arithmetic).
  const double base = 1e10 * std::numeric_limits<double>::epsilon();
  Eigen::Index best = -1;
  double score = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double v = c.dot(T.col(j));
    if (v > score && v > base * absc.dot(T.col(j).cwiseAbs())) {
      score = v;
      best = j;
    }
  }
  if (best < 0 || !(score > sig)) return false;
  const Eigen::VectorXd lam = T.col(best) / score;
  if (!lam.allFinite()) return false;
  strip_swap(X, lam, c, ys, ss, best);
  return true;
}

}  // namespace parallelotope_detail

SETBOUND_INLINE bool ParallelotopeEstimator::vicino_zappa(Set& X, const Eigen::Ref<const Eigen::VectorXd>& c, double y,
                                                          double sigma, Convention convention) {
  const Eigen::Index n = X.p.size();
  if (c.size() != n || X.G.rows() != n || X.G.cols() != n || X.r.size() != n)
    throw DimensionError("vicino_zappa: expected a parallelotope (n x n generators) and c of length n");
  if (convention == Convention::Cora) {
    if (!(sigma > 0)) throw InvalidArgumentError("sigma: CORA's normalised strip needs a positive half-width");
    const Eigen::VectorXd p = c / sigma;
    return parallelotope_detail::vz_cora(X.p, X.G, p, y / sigma);
  }
  return parallelotope_detail::vz_guaranteed(X, c, y, sigma);
}

SETBOUND_INLINE ParallelotopeEstimator::ParallelotopeEstimator(LinearSystem system, const Zonotope& x0,
                                                               ParallelotopeOptions options)
    : sys_(std::move(system)), opt_(options), x0_(x0) {
  const int conv = static_cast<int>(opt_.convention);
  if (conv < 0 || conv > 1) throw InvalidArgumentError("convention: must be Setbound or Cora");
  const int red = static_cast<int>(opt_.reduction);
  if (red == static_cast<int>(ZonotopeReduction::Combastel))
    throw InvalidArgumentError(
        "reduction: ROPO reduces to a parallelotope with Girard (the interval hull, CORA's default) or Pca; "
        "Combastel's rule is Girard's box at order 1");
  if (red < 1 || red > 3) throw InvalidArgumentError("reduction: must be Girard or Pca");
  const int pol = static_cast<int>(opt_.on_inconsistency);
  if (pol < 0 || pol > 2) throw InvalidArgumentError("on_inconsistency: must be Flag, Raise or Reset");
  if (opt_.convention == Convention::Cora && opt_.on_inconsistency != OnInconsistency::Flag)
    throw InvalidArgumentError(
        "on_inconsistency: CORA's ROPO does not test its readings (convention Cora); only Flag is accepted");
  if (sys_.uncertain_A())
    throw InvalidArgumentError("system: ROPO needs a known A (an interval [A] is not supported)");
  n_ = sys_.nx();
  if (x0.dimension() != n_)
    throw DimensionError("x0: expected a zonotope of dimension " + std::to_string(n_) + ", got " +
                         std::to_string(x0.dimension()));
  const Eigen::Index ny = sys_.ny(), nw = sys_.nw();
  std::vector<Eigen::Index> nz;
  for (Eigen::Index j = 0; j < nw; ++j)
    if (sys_.E().col(j).cwiseAbs().maxCoeff() > 0) nz.push_back(j);
  Enz_.resize(n_, static_cast<Eigen::Index>(nz.size()));
  for (std::size_t j = 0; j < nz.size(); ++j) Enz_.col(static_cast<Eigen::Index>(j)) = sys_.E().col(nz[j]);
  // σ_i = Σ_j |F_ij| (spec §1.2), rounded up.
  sigma_ = nw > 0 ? Vec(detail::abs_row_sums(sys_.F()) *
                        (1.0 + static_cast<double>(nw + 2) * std::numeric_limits<double>::epsilon()))
                  : Vec(Vec::Zero(ny));
  if (opt_.convention == Convention::Cora)
    for (Eigen::Index i = 0; i < ny; ++i)
      if (!(sigma_(i) > 0) && sys_.C().row(i).cwiseAbs().maxCoeff() > 0)
        throw InvalidArgumentError("F: output " + std::to_string(i) +
                                   " has no noise (row of F is zero); CORA's ROPO normalises each strip by its "
                                   "half-width (convention Cora); use convention Setbound");
  lo_ = hi_ = Vec::Zero(n_);
  load_initial();
}

SETBOUND_INLINE void ParallelotopeEstimator::load_initial() {
  const Zonotope z = x0_.remove_zero_generators();
  prior_ = Set{z.center(), Vec::Zero(n_), z.generators()};
  cur_ = Set{Vec::Zero(n_), Vec::Zero(n_), Mat::Zero(n_, 0)};
  has_current_ = false;
  k_ = 0;
  lo_.setZero();
  hi_.setZero();
  last_check_.clear(sys_.ny());
}

SETBOUND_INLINE void ParallelotopeEstimator::reset() { load_initial(); }

SETBOUND_INLINE Zonotope ParallelotopeEstimator::current_set() const {
  if (!has_current_) throw InvalidArgumentError("estimator: no step has been taken yet");
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

SETBOUND_INLINE double ParallelotopeEstimator::shifted(Eigen::Index i, const Eigen::Ref<const Vec>& y,
                                                       const Eigen::Ref<const Vec>& u, double& sig) const {
  sig = sigma_(i);
  if (sys_.nu() == 0 || sys_.D().row(i).cwiseAbs().maxCoeff() == 0) return y(i);
  const double ys = y(i) - sys_.D().row(i).dot(u);
  if (opt_.convention == Convention::Setbound)
    sig += rounding_bounds::gamma(sys_.nu()) * (std::abs(y(i)) + sys_.D().row(i).cwiseAbs().dot(u.cwiseAbs()));
  return ys;
}

SETBOUND_INLINE void ParallelotopeEstimator::to_parallelotope(Set& X) {
  // Drop exactly-zero columns, keeping the order (CORA never counts them).
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < X.G.cols(); ++j) {
    if ((X.G.col(j).array() == 0.0).all()) continue;
    if (k != j) X.G.col(k) = X.G.col(j);
    ++k;
  }
  const bool guaranteed = opt_.convention == Convention::Setbound;
  if (guaranteed) {
    // A pending box that is no longer negligible becomes generators (then reduced with the rest).
    const double scale = k > 0 ? X.G.leftCols(k).cwiseAbs().rowwise().sum().maxCoeff() : 0.0;
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
  }
  if (k > n_) {
    // CORA's reduce(Z, technique, 1): every column reduced into n box columns (the zero ones are
    // not kept); the rounding box is absorbed.
    k = detail::reduce_in_place(opt_.reduction, X.G, k, n_, guaranteed ? &X.r : nullptr, rws_);
    if (rws_.reduced_count > 0) X.r.setZero();
  }
  // Fewer than n columns (no reduction, or box rows that are zero): pad with zero columns, so that
  // T is always n × n (CORA would index out of range here; see the header).
  X.G.conservativeResize(n_, n_);
  for (Eigen::Index j = k; j < n_; ++j) X.G.col(j).setZero();
}

SETBOUND_INLINE void ParallelotopeEstimator::correct(Set& X, const Eigen::Ref<const Vec>& y, const Eigen::Ref<const Vec>& u,
                                                     MeasurementCheck& chk) const {
  const Mat& C = sys_.C();
  const bool guaranteed = opt_.convention == Convention::Setbound;
  for (Eigen::Index i = 0; i < sys_.ny(); ++i) {
    if (std::isnan(y(i))) continue;
    double sig = 0.0;
    const double ys = shifted(i, y, u, sig);
    const Vec c = C.row(i).transpose();
    if (guaranteed) {
      // Screening against the set before this strip (measurement_check.hpp): support of
      // θ ⊕ T B ⊕ box(r) in the direction ±c.
      const Vec ac = c.cwiseAbs();
      double radius = ac.dot(X.r), magnitude = ac.dot(X.p.cwiseAbs()) + radius;
      for (Eigen::Index j = 0; j < X.G.cols(); ++j) {
        radius += std::abs(c.dot(X.G.col(j)));
        magnitude += ac.dot(X.G.col(j).cwiseAbs());
      }
      const double center = c.dot(X.p);
      const OutputTest t = test_output(ys, center, radius, sig, magnitude, 2 * n_ + 4);
      chk.margin(i) = t.margin;
      if (t.inconsistent) {
        if (opt_.on_inconsistency == OnInconsistency::Raise)
          throw_inconsistent(k_, i, y(i), center + (y(i) - ys), radius, sig, t.margin);
        chk.status[static_cast<std::size_t>(i)] = OutputStatus::Inconsistent;
        continue;
      }
    }
    chk.status[static_cast<std::size_t>(i)] = OutputStatus::Used;
    if (c.cwiseAbs().maxCoeff() == 0) continue;  // tested; carries no information on x
    vicino_zappa(X, c, ys, sig, opt_.convention);
  }
}

SETBOUND_INLINE void ParallelotopeEstimator::predict(Set& X, const Eigen::Ref<const Vec>& u) const {
  using rounding_bounds::gamma;
  const Mat& A = sys_.A();
  const Eigen::Index m = X.G.cols(), k = Enz_.cols();
  Vec pn = A * X.p;
  if (sys_.nu() > 0) pn.noalias() += sys_.B() * u;
  Mat Gn(n_, m + k);
  if (m > 0) Gn.leftCols(m).noalias() = A * X.G;
  if (k > 0) Gn.rightCols(k) = Enz_;
  if (opt_.convention == Convention::Setbound) {
    // x' = A x + B u: the rounding of A p + B u and of A G, and the box carried by |A|.
    const double g = gamma(n_ + sys_.nu() + 4);
    const Mat absA = A.cwiseAbs();
    const Vec w = m > 0 ? Vec(X.G.cwiseAbs().rowwise().sum()) : Vec(Vec::Zero(n_));
    Vec r = absA * X.r + g * (absA * (w + X.p.cwiseAbs())) + g * pn.cwiseAbs();
    if (sys_.nu() > 0) r += g * (sys_.B().cwiseAbs() * u.cwiseAbs());
    X.r = r * (1.0 + g);
  }
  X.p.swap(pn);
  X.G.swap(Gn);
}

SETBOUND_INLINE void ParallelotopeEstimator::hull(const Set& X) {
  const double eps = std::numeric_limits<double>::epsilon();
  const Eigen::Index m = X.G.cols();
  Vec e = m > 0 ? Vec(X.G.cwiseAbs().rowwise().sum()) : Vec(Vec::Zero(n_));
  e = (e + X.r + eps * X.p.cwiseAbs()) * (1.0 + static_cast<double>(m + n_ + 4) * eps);
  lo_ = X.p - e;
  hi_ = X.p + e;
}

SETBOUND_INLINE void ParallelotopeEstimator::update(const Eigen::Ref<const Eigen::VectorXd>& y,
                                                    const Eigen::Ref<const Eigen::VectorXd>& u) {
  if (y.size() != sys_.ny())
    throw DimensionError("y: expected length " + std::to_string(sys_.ny()) + ", got " + std::to_string(y.size()));
  if (u.size() != sys_.nu())
    throw DimensionError("u: expected length " + std::to_string(sys_.nu()) + ", got " + std::to_string(u.size()));
  require_no_infinity(y, "y");
  require_finite(u, "u");
  const Eigen::Index ny = sys_.ny();
  MeasurementCheck chk;
  chk.clear(ny, OutputStatus::Unused);
  for (Eigen::Index i = 0; i < ny; ++i)
    if (std::isnan(y(i))) chk.status[static_cast<std::size_t>(i)] = OutputStatus::Missing;
  Set X = prior_;
  if (opt_.convention == Convention::Cora && k_ == 0) {
    // CORA's S' skeleton: R{1} = R0, y_1 unused, not reduced.
  } else {
    to_parallelotope(X);
    const MeasurementCheck blank = chk;
    correct(X, y, u, chk);  // may throw (policy Raise): nothing is committed yet
    if (opt_.on_inconsistency == OnInconsistency::Reset && chk.flagged()) {
      // Restart from x0 and correct it with this step's outputs (those inconsistent with it are
      // skipped); the report keeps the test that triggered the reset.
      const MeasurementCheck trigger = chk;
      const Zonotope z = x0_.remove_zero_generators();
      X = Set{z.center(), Vec::Zero(n_), z.generators()};
      to_parallelotope(X);
      MeasurementCheck again = blank;
      correct(X, y, u, again);
      chk = trigger;
      chk.reset = true;
    }
  }
  Set P = X;
  predict(P, u);
  if (!X.p.allFinite() || !X.G.allFinite() || !X.r.allFinite() || !P.p.allFinite() || !P.G.allFinite() ||
      !P.r.allFinite())
    throw NumericalError("ROPO: the set overflowed (non-finite values) at step " + std::to_string(k_) +
                         (opt_.convention == Convention::Cora ? " (CORA's recursion has no emptiness check)" : ""));
  // Commit (nothing below throws but memory).
  cur_ = std::move(X);
  prior_ = std::move(P);
  last_check_ = std::move(chk);
  has_current_ = true;
  hull(cur_);
  ++k_;
}

SETBOUND_INLINE ParallelotopeTrajectory ParallelotopeEstimator::run(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& U) {
  const Eigen::Index N = Y.rows();
  if (Y.cols() != sys_.ny())
    throw DimensionError("y: expected " + std::to_string(sys_.ny()) + " columns, got " + std::to_string(Y.cols()));
  if (sys_.nu() > 0) require_shape(U, N, sys_.nu(), "u");
  ParallelotopeTrajectory t{Mat(N, n_), Mat(N, n_), Mat(N, n_), {}, {}};
  t.sets.reserve(static_cast<std::size_t>(N));
  t.checks.reserve(static_cast<std::size_t>(N));
  reset();
  const Vec no_input(0);
  for (Eigen::Index k = 0; k < N; ++k) {
    if (sys_.nu() > 0) update(Y.row(k).transpose(), U.row(k).transpose());
    else update(Y.row(k).transpose(), no_input);
    t.center.row(k) = cur_.p.transpose();
    t.lower.row(k) = lo_.transpose();
    t.upper.row(k) = hi_.transpose();
    t.sets.push_back(current_set());
    t.checks.push_back(last_check_);
  }
  return t;
}

SETBOUND_INLINE std::vector<double> ParallelotopeEstimator::save_state() const {
  StateWriter w(StateKind::ParallelotopeEstimator, fingerprint());
  w.count(k_).flag(has_current_);
  w.vec(prior_.p).vec(prior_.r).mat(prior_.G);
  w.vec(cur_.p).vec(cur_.r).mat(cur_.G);
  return w.finish();
}

SETBOUND_INLINE void ParallelotopeEstimator::restore_state(const std::vector<double>& state) {
  struct Parsed {
    long long k;
    bool has;
    Set prior, cur;
  };
  Parsed q = guard_state_memory(StateKind::ParallelotopeEstimator, [&] {
    StateReader r(state, StateKind::ParallelotopeEstimator, fingerprint());
    Parsed t;
    t.k = r.count("steps");
    t.has = r.flag("has_current");
    t.prior.p = r.vec(n_, "prior center");
    t.prior.r = r.vec(n_, "prior box");
    t.prior.G = r.mat(n_, -1, "prior generators");
    t.cur.p = r.vec(n_, "current center");
    t.cur.r = r.vec(n_, "current box");
    t.cur.G = r.mat(n_, -1, "current generators");
    r.finish();
    if ((t.prior.r.array() < 0).any() || (t.cur.r.array() < 0).any()) r.fail("a box radius is negative");
    if (t.has != (t.k > 0)) r.fail("the estimator has a current set exactly after its first step");
    if (opt_.convention == Convention::Cora && ((t.prior.r.array() != 0).any() || (t.cur.r.array() != 0).any()))
      r.fail("the Cora convention carries no rounding box");
    // After a correction the current set is an n × n parallelotope (Cora's step 0 keeps R0).
    if (t.has && t.cur.G.cols() != n_ && !(opt_.convention == Convention::Cora && t.k == 1))
      r.fail("the current set must have " + std::to_string(n_) + " generator columns (a parallelotope)");
    return t;
  });
  k_ = static_cast<Eigen::Index>(q.k);
  has_current_ = q.has;
  prior_ = std::move(q.prior);
  cur_ = std::move(q.cur);
  last_check_.clear(sys_.ny());
  if (has_current_) {
    hull(cur_);
  } else {
    lo_.setZero();
    hi_.setZero();
  }
}

SETBOUND_INLINE StateFingerprint ParallelotopeEstimator::fingerprint() const {
  StateFingerprint f;
  f.add(sys_.A()).add(sys_.B()).add(sys_.C()).add(sys_.D()).add(sys_.E()).add(sys_.F());
  f.add_int(static_cast<int>(opt_.reduction)).add_int(static_cast<int>(opt_.convention));
  f.add_int(static_cast<int>(opt_.on_inconsistency));
  return f;
}

}  // namespace setbound
