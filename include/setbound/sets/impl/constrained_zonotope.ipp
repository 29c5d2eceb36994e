// setbound — definitions of the functions declared in setbound/sets/constrained_zonotope.hpp.
// Included by that header (header-only use) or compiled once into libsetbound
// (SETBOUND_SEPARATE_COMPILATION); see setbound/core/config.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <limits>
#include <string>
#include <vector>
#include <utility>

#include "setbound/core/config.hpp"
#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box_lp.hpp"
#include "setbound/sets/constrained_zonotope.hpp"
#include "setbound/sets/interval.hpp"
#include "setbound/sets/zonotope_reduction.hpp"  // rounding_bounds::gamma

namespace setbound {

namespace czono_detail {

/// v·(1 + 2γ_k), elementwise: an upper bound of the exact value of a computed sum of k
/// non-negative terms (γ_k >= 2(k+2)u already covers the sum; the factor 2 covers this product).
SETBOUND_INLINE Eigen::VectorXd inflate(const Eigen::VectorXd& v, Eigen::Index k) {
  return v * (1.0 + 2.0 * rounding_bounds::gamma(k));
}

/// Upper bound of |c| + |G|·1 (the magnitude of the points c + Gξ, ‖ξ‖∞ <= 1, per row).
SETBOUND_INLINE Eigen::VectorXd magnitude(const Eigen::VectorXd& c, const Eigen::MatrixXd& G) {
  Eigen::VectorXd s = c.cwiseAbs();
  if (G.cols() > 0) s += G.cwiseAbs().rowwise().sum();
  return inflate(s, G.cols() + 1);
}

SETBOUND_INLINE void require_vector(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Index n, const std::string& name) {
  if (v.size() != n)
    throw DimensionError(name + ": expected length " + std::to_string(n) + ", got " + std::to_string(v.size()));
  require_finite(v, name);
}

/// For each column, its only row when it is a row's own slack (exactly one non-zero entry in A,
/// zero in G), else −1.
SETBOUND_INLINE std::vector<Eigen::Index> slack_rows(const Eigen::MatrixXd& G, const Eigen::MatrixXd& A) {
  const Eigen::Index q = A.rows(), m = A.cols();
  std::vector<Eigen::Index> only_row(static_cast<size_t>(m), -1);
  for (Eigen::Index j = 0; j < m; ++j) {
    // G first (n entries): most columns are not zero there, while a slack column's A part must be
    // scanned whole (this runs on every substitution and rescaling).
    if (box_lp_detail::max_abs(G.col(j)) > 0.0) continue;
    Eigen::Index row = -1, count = 0;
    for (Eigen::Index k = 0; k < q && count < 2; ++k)
      if (A(k, j) != 0.0) row = k, ++count;
    if (count == 1) only_row[static_cast<size_t>(j)] = row;
  }
  return only_row;
}

/// Widens every row k of A ξ = b by s_k >= 0 (it then allows |A_k ξ − b_k| <= s_k): through a
/// column private to the row (zero in G and in every other row: {a ζ + s t} = {(|a| + s) ζ'}
/// in one dimension) when there is one, else through a new column s_k e_k (zero in G).
SETBOUND_INLINE void absorb_row_slack(Eigen::MatrixXd& G, Eigen::MatrixXd& A, const Eigen::VectorXd& s) {
  const Eigen::Index q = A.rows(), m = A.cols();
  const std::vector<Eigen::Index> only_row = slack_rows(G, A);  // one pass instead of a search per row
  std::vector<Eigen::Index> private_col(static_cast<size_t>(q), -1);  // the first such column per row
  for (Eigen::Index j = m - 1; j >= 0; --j)
    if (only_row[static_cast<size_t>(j)] >= 0) private_col[static_cast<size_t>(only_row[static_cast<size_t>(j)])] = j;
  std::vector<Eigen::Index> extra;
  for (Eigen::Index k = 0; k < q; ++k) {
    if (!(s(k) > 0.0)) continue;
    const Eigen::Index pc = private_col[static_cast<size_t>(k)];
    if (pc >= 0) {
      const double a = A(k, pc);
      A(k, pc) = std::copysign(rounding::add_up(std::abs(a), s(k)), a);
    } else {
      extra.push_back(k);
    }
  }
  if (extra.empty()) return;
  const Eigen::Index me = static_cast<Eigen::Index>(extra.size());
  G.conservativeResize(Eigen::NoChange, m + me);
  G.rightCols(me).setZero();
  A.conservativeResize(Eigen::NoChange, m + me);
  A.rightCols(me).setZero();
  for (Eigen::Index e = 0; e < me; ++e) A(extra[static_cast<size_t>(e)], m + e) = s(extra[static_cast<size_t>(e)]);
}

/// Removes row i of M (column-major: each column's tail moves up one place).
SETBOUND_INLINE void drop_row(Eigen::MatrixXd& M, Eigen::Index i) {
  const Eigen::Index rows = M.rows(), tail = rows - i - 1;
  if (tail > 0)
    for (Eigen::Index j = 0; j < M.cols(); ++j)
      std::memmove(M.col(j).data() + i, M.col(j).data() + i + 1, static_cast<size_t>(tail) * sizeof(double));
  M.conservativeResize(rows - 1, Eigen::NoChange);
}

/// Removes column j of M (column-major: the later columns are one contiguous block).
SETBOUND_INLINE void drop_col(Eigen::MatrixXd& M, Eigen::Index j) {
  const Eigen::Index cols = M.cols(), tail = cols - j - 1;
  if (tail > 0 && M.rows() > 0)
    std::memmove(M.col(j).data(), M.col(j + 1).data(), static_cast<size_t>(tail * M.rows()) * sizeof(double));
  M.conservativeResize(Eigen::NoChange, cols - 1);
}

/// Removes entry i of v.
SETBOUND_INLINE void drop_entry(Eigen::VectorXd& v, Eigen::Index i) {
  const Eigen::Index tail = v.size() - i - 1;
  if (tail > 0) std::memmove(v.data() + i, v.data() + i + 1, static_cast<size_t>(tail) * sizeof(double));
  v.conservativeResize(v.size() - 1);
}


/// What reduce_limits' next steps will leave, for box_cheapest and absorb_cheapest: rows that are
/// not 0 = 0 are eliminated down to max_constraints, each taking one column with it; columns zero
/// in G and A are dropped. `excess` = columns left + `added` (what the method itself adds) − the
/// limit. Columns that are a row's own slack (zero in G, one non-zero in A) are not candidates:
/// boxing one only turns it into the same slack; each row's count of them (own_slack) decides
/// whether the rows' part of a boxed column needs a new slack column. Columns flagged in
/// `excluded` (a basis) are no candidates either.
struct CheapestPlan {
  Eigen::Index excess = 0;
  std::vector<Eigen::Index> own_slack, candidates;
};

SETBOUND_INLINE CheapestPlan cheapest_plan(const Eigen::MatrixXd& G, const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                           Eigen::Index max_generators, Eigen::Index max_constraints,
                                           Eigen::Index added, const std::vector<char>& excluded) {
  const Eigen::Index q = A.rows(), m = G.cols();
  Eigen::Index rows = 0, cols = 0;
  for (Eigen::Index i = 0; i < q; ++i)
    if (b(i) != 0.0 || box_lp_detail::max_abs(A.row(i)) > 0.0) ++rows;
  const Eigen::Index eliminated = std::max<Eigen::Index>(0, rows - max_constraints);
  const std::vector<Eigen::Index> slack_row = slack_rows(G, A);
  CheapestPlan plan;
  plan.own_slack.assign(static_cast<size_t>(q), 0);
  for (Eigen::Index j = 0; j < m; ++j) {
    if (box_lp_detail::max_abs(G.col(j)) == 0.0 && (q == 0 || box_lp_detail::max_abs(A.col(j)) == 0.0))
      continue;  // dropped anyway
    ++cols;
    const Eigen::Index row = slack_row[static_cast<size_t>(j)];
    if (row >= 0) ++plan.own_slack[static_cast<size_t>(row)];
    else if (excluded.empty() || !excluded[static_cast<size_t>(j)]) plan.candidates.push_back(j);
  }
  plan.excess = cols + added - eliminated - max_generators;
  return plan;
}

/// The candidates of least `cost` until the plan's excess is paid (each taken column pays one, a
/// row that gets slack without having a column of its own costs one more), plus every candidate
/// flagged in `forced` whatever the excess.
SETBOUND_INLINE std::vector<Eigen::Index> take_cheapest(CheapestPlan plan, const Eigen::MatrixXd& A,
                                                        const Eigen::VectorXd& cost, const std::vector<char>& forced) {
  const Eigen::Index q = A.rows();
  const auto is_forced = [&](Eigen::Index j) { return !forced.empty() && forced[static_cast<size_t>(j)]; };
  // Forced columns first (in the columns' order), then by cost (stable: ties keep that order too).
  std::stable_sort(plan.candidates.begin(), plan.candidates.end(), [&](Eigen::Index a, Eigen::Index b) {
    if (is_forced(a) || is_forced(b)) return is_forced(a) && !is_forced(b);
    return cost(a) < cost(b);
  });
  std::vector<Eigen::Index> which;
  std::vector<char> new_slack(static_cast<size_t>(q), 0);
  for (const Eigen::Index j : plan.candidates) {
    if (plan.excess <= 0 && !is_forced(j)) break;
    which.push_back(j);
    --plan.excess;
    for (Eigen::Index i = 0; i < q; ++i)
      if (A(i, j) != 0.0 && plan.own_slack[static_cast<size_t>(i)] == 0 && !new_slack[static_cast<size_t>(i)]) {
        new_slack[static_cast<size_t>(i)] = 1;  // this row's slack needs a column of its own
        ++plan.excess;
      }
  }
  return which;
}

}  // namespace czono_detail

SETBOUND_INLINE ConstrainedZonotope::ConstrainedZonotope(Eigen::VectorXd c, Eigen::MatrixXd G, Eigen::MatrixXd A,
                                                        Eigen::VectorXd b)
    : c_(std::move(c)), G_(std::move(G)), A_(std::move(A)), b_(std::move(b)) {
  if (c_.size() == 0) throw DimensionError("c: the centre must have at least one entry");
  require_finite(c_, "c");
  if (G_.rows() != c_.size())
    throw DimensionError("G: expected " + std::to_string(c_.size()) + " rows (the length of c), got shape " +
                         detail::shape_string(G_.rows(), G_.cols()));
  require_finite(G_, "G");
  if (A_.cols() != G_.cols())
    throw DimensionError("A: expected " + std::to_string(G_.cols()) + " columns (one per generator), got shape " +
                         detail::shape_string(A_.rows(), A_.cols()));
  require_finite(A_, "A");
  if (b_.size() != A_.rows())
    throw DimensionError("b: expected length " + std::to_string(A_.rows()) + " (the rows of A), got " +
                         std::to_string(b_.size()));
  require_finite(b_, "b");
  r_ = Eigen::VectorXd::Zero(c_.size());
}

SETBOUND_INLINE ConstrainedZonotope::ConstrainedZonotope(Eigen::VectorXd c, Eigen::MatrixXd G, Eigen::MatrixXd A,
                                                        Eigen::VectorXd b, Eigen::VectorXd r, bool)
    : c_(std::move(c)), G_(std::move(G)), A_(std::move(A)), b_(std::move(b)), r_(std::move(r)) {
  require_no_overflow();  // results of operations on validated sets
}

SETBOUND_INLINE void ConstrainedZonotope::require_no_overflow() const {
  // Σ 0·x is 0 when every x is finite and NaN otherwise (0·±inf = NaN), and cannot overflow: one
  // vectorised pass, where allFinite() took ~5 instructions per entry (every operation runs this).
  const auto finite = [](const auto& M) { return M.size() == 0 || (M.array() * 0.0).sum() == 0.0; };
  if (!finite(c_) || !finite(G_) || !finite(A_) || !finite(b_) || !finite(r_))
    throw NumericalError("constrained zonotope: an operation overflowed (entries beyond 1.8e308)");
}

SETBOUND_INLINE ConstrainedZonotope::ConstrainedZonotope(const Zonotope& z)
    : ConstrainedZonotope(z.center(), z.generators(), Eigen::MatrixXd(0, z.num_generators()), Eigen::VectorXd(0)) {}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::from_parts(Eigen::VectorXd c, Eigen::MatrixXd G,
                                                                   Eigen::MatrixXd A, Eigen::VectorXd b,
                                                                   Eigen::VectorXd r) {
  ConstrainedZonotope Z(std::move(c), std::move(G), std::move(A), std::move(b));
  if (r.size() != Z.dimension())
    throw DimensionError("r: expected length " + std::to_string(Z.dimension()) + " (the length of c), got " +
                         std::to_string(r.size()));
  require_finite(r, "r");
  for (Eigen::Index i = 0; i < r.size(); ++i)
    if (r(i) < 0.0)
      throw InvalidArgumentError("r: the rounding radii must be >= 0, entry " + std::to_string(i) + " is " +
                                 std::to_string(r(i)));
  Z.r_ = std::move(r);
  return Z;
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::from_bounds(const Eigen::Ref<const Eigen::VectorXd>& lo,
                                                                    const Eigen::Ref<const Eigen::VectorXd>& hi) {
  if (lo.size() == 0) throw DimensionError("lo: the box must have at least one dimension");
  czono_detail::require_vector(lo, lo.size(), "lo");
  czono_detail::require_vector(hi, lo.size(), "hi");
  const Eigen::Index n = lo.size();
  Eigen::VectorXd c(n), rad(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (lo(i) > hi(i))
      throw InvalidArgumentError("lo: entry " + std::to_string(i) + " is above hi (" + std::to_string(lo(i)) + " > " +
                                 std::to_string(hi(i)) + ")");
    c(i) = 0.5 * lo(i) + 0.5 * hi(i);
    rad(i) = std::max(rounding::sub_up(hi(i), c(i)), rounding::sub_up(c(i), lo(i)));  // covers [lo, hi]
  }
  return ConstrainedZonotope(c, rad.asDiagonal().toDenseMatrix(), Eigen::MatrixXd(0, n), Eigen::VectorXd(0));
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::linear_map(const Eigen::Ref<const Eigen::MatrixXd>& K) const {
  if (K.cols() != dimension() || K.rows() == 0)
    throw DimensionError("K: expected shape (k, " + std::to_string(dimension()) + ") with k >= 1, got " +
                         detail::shape_string(K.rows(), K.cols()));
  require_finite(K, "K");
  using czono_detail::inflate;
  const Eigen::Index n = dimension();
  const Eigen::VectorXd mag = czono_detail::magnitude(c_, G_);
  // K(c + Gξ + diag(r)η) = fl(Kc) + fl(KG)ξ + e, |e| <= γ_n |K|(|c| + |G|1) + |K| r.
  // (|K| r boxes K·box(r): see absorb_rounding for why a long run must turn r into columns.)
  Eigen::VectorXd per_row = r_ + rounding_bounds::gamma(n) * mag;
  per_row = inflate(per_row, 2);
  const Eigen::VectorXd r = inflate(K.cwiseAbs() * per_row, n);
  return ConstrainedZonotope(K * c_, K * G_, A_, b_, r, true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::translate(const Eigen::Ref<const Eigen::VectorXd>& v) const {
  czono_detail::require_vector(v, dimension(), "v");
  const Eigen::VectorXd c = c_ + v;
  const Eigen::VectorXd r = czono_detail::inflate(r_ + rounding_bounds::gamma(1) * c.cwiseAbs(), 2);
  return ConstrainedZonotope(c, G_, A_, b_, r, true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::minkowski_sum(const Zonotope& W) const {
  return minkowski_sum(ConstrainedZonotope(W));
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::minkowski_sum(const ConstrainedZonotope& Y) const {
  if (Y.dimension() != dimension())
    throw DimensionError("Y: expected a set in R^" + std::to_string(dimension()) + ", got R^" +
                         std::to_string(Y.dimension()));
  const Eigen::Index m1 = num_generators(), m2 = Y.num_generators();
  const Eigen::Index q1 = num_constraints(), q2 = Y.num_constraints();
  Eigen::MatrixXd G(dimension(), m1 + m2);
  G << G_, Y.G_;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(q1 + q2, m1 + m2);
  A.topLeftCorner(q1, m1) = A_;
  A.bottomRightCorner(q2, m2) = Y.A_;
  Eigen::VectorXd b(q1 + q2);
  b << b_, Y.b_;
  const Eigen::VectorXd c = c_ + Y.c_;
  const Eigen::VectorXd r = czono_detail::inflate(r_ + Y.r_ + rounding_bounds::gamma(1) * c.cwiseAbs(), 3);
  return ConstrainedZonotope(c, std::move(G), std::move(A), std::move(b), r, true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::intersect(const ConstrainedZonotope& Y,
                                                                  const Eigen::Ref<const Eigen::MatrixXd>& R) const {
  const Eigen::Index n = dimension(), k = Y.dimension();
  if (R.rows() != k || R.cols() != n)
    throw DimensionError("R: expected shape " + detail::shape_string(k, n) + " (Y's dimension × this set's), got " +
                         detail::shape_string(R.rows(), R.cols()));
  require_finite(R, "R");
  const Eigen::Index m1 = num_generators(), m2 = Y.num_generators();
  const Eigen::Index q1 = num_constraints(), q2 = Y.num_constraints();
  // R x ∈ Y with x = c + Gξ + diag(r)η and Y = c_Y + G_Y ζ + diag(r_Y)η_Y:
  //   fl(RG) ξ − G_Y ζ = fl(c_Y − fl(R c)) + s ∘ t,  ‖t‖∞ <= 1,
  // where s bounds everything left out: |R| r + r_Y and the rounding of RG (on the box) and of
  // the right-hand side. s is absorbed by a generator of Y used only in that row, else by a new
  // column (czono_detail::absorb_row_slack).
  const Eigen::MatrixXd RG = R * G_;
  const Eigen::VectorXd rhs = Y.c_ - R * c_;
  const Eigen::VectorXd magnitude = czono_detail::magnitude(c_, G_);
  Eigen::VectorXd s = R.cwiseAbs() * czono_detail::inflate(r_ + rounding_bounds::gamma(n + 1) * magnitude, 2) + Y.r_ +
                      rounding_bounds::gamma(1) * Y.c_.cwiseAbs();
  s = czono_detail::inflate(s, n + 3);
  const Eigen::Index m = m1 + m2;
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, m);
  G.leftCols(m1) = G_;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(q1 + q2 + k, m);
  A.topLeftCorner(q1, m1) = A_;
  A.block(q1, m1, q2, m2) = Y.A_;
  A.block(q1 + q2, 0, k, m1) = RG;
  A.block(q1 + q2, m1, k, m2) = -Y.G_;
  Eigen::VectorXd slack = Eigen::VectorXd::Zero(q1 + q2 + k);
  slack.tail(k) = s;
  czono_detail::absorb_row_slack(G, A, slack);
  Eigen::VectorXd b(q1 + q2 + k);
  b << b_, Y.b_, rhs;
  return ConstrainedZonotope(c_, std::move(G), std::move(A), std::move(b), r_, true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::intersect(const ConstrainedZonotope& Y) const {
  if (Y.dimension() != dimension())
    throw DimensionError("Y: expected a set in R^" + std::to_string(dimension()) + ", got R^" +
                         std::to_string(Y.dimension()));
  return intersect(Y, Eigen::MatrixXd::Identity(dimension(), dimension()));
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::intersect_strip(const Strip& s) const {
  if (s.dimension() != dimension())
    throw DimensionError("strip: expected a strip in R^" + std::to_string(dimension()) + ", got R^" +
                         std::to_string(s.dimension()));
  const ConstrainedZonotope Y(Eigen::VectorXd::Constant(1, s.measurement()),
                              Eigen::MatrixXd::Constant(1, 1, s.half_width()), Eigen::MatrixXd(0, 1), Eigen::VectorXd(0));
  return intersect(Y, s.normal().transpose());
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::intersect_halfspace(const HalfSpace& h) const {
  czono_detail::require_vector(h.a, dimension(), "a");
  require_finite(h.b, "b");
  if (support(h.a) <= h.b) return *this;  // the half-space keeps all of Z (certified)
  // L <= aᵀx on c + Gξ + diag(r)η for every ξ in the box: −(−aᵀc + ‖Gᵀa‖₁ + |a|ᵀr), certified.
  const double upper_neg = rounding::add_up(
      box_lp_detail::upper_bound_q_plus_l1(G_, c_, -h.a),
      (h.a.cwiseAbs().dot(r_)) * (1.0 + 2.0 * rounding_bounds::gamma(dimension())));
  const double L = -upper_neg;
  if (h.b < L) {  // not even the unconstrained zonotope meets the half-space: the empty set
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(num_constraints() + 1, num_generators());
    A.topRows(num_constraints()) = A_;
    Eigen::VectorXd b(num_constraints() + 1);
    b << b_, 1.0;  // 0 = 1: BoxLP certifies the emptiness with y = e_last
    return ConstrainedZonotope(c_, G_, std::move(A), std::move(b), r_, true);
  }
  // aᵀx ∈ [L, f] as a strip centred at (L + f)/2, half-width rounded to cover both ends.
  const double mid = 0.5 * L + 0.5 * h.b;
  const double half = std::max(rounding::sub_up(h.b, mid), rounding::sub_up(mid, L));
  const ConstrainedZonotope Y(Eigen::VectorXd::Constant(1, mid), Eigen::MatrixXd::Constant(1, 1, half),
                              Eigen::MatrixXd(0, 1), Eigen::VectorXd(0));
  return intersect(Y, h.a.transpose());
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::intersect_output(const Eigen::Ref<const Eigen::MatrixXd>& C,
                                                                         const Eigen::Ref<const Eigen::VectorXd>& y,
                                                                         const Zonotope& V) const {
  if (C.cols() != dimension() || C.rows() == 0)
    throw DimensionError("C: expected shape (p, " + std::to_string(dimension()) + ") with p >= 1, got " +
                         detail::shape_string(C.rows(), C.cols()));
  czono_detail::require_vector(y, C.rows(), "y");
  if (V.dimension() != C.rows())
    throw DimensionError("V: expected a set in R^" + std::to_string(C.rows()) + " (one entry per output), got R^" +
                         std::to_string(V.dimension()));
  // C x ∈ y − V = (y − c_V) ⊕ G_V B (V symmetric about its centre): exact, V used as a set.
  const Eigen::VectorXd centre = y - V.center();
  const Eigen::VectorXd r = czono_detail::inflate(rounding_bounds::gamma(1) * centre.cwiseAbs(), 1);
  const ConstrainedZonotope Y(centre, V.generators(), Eigen::MatrixXd(0, V.num_generators()), Eigen::VectorXd(0), r,
                              true);
  return intersect(Y, C);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::substitute_rows(const Eigen::Ref<const Eigen::MatrixXd>& Lambda,
                                                                        Eigen::Index first_row) const {
  if (first_row < 0 || first_row > num_constraints())
    throw InvalidArgumentError("first_row: expected 0.." + std::to_string(num_constraints()) + ", got " +
                               std::to_string(first_row));
  const Eigen::Index p = num_constraints() - first_row;
  if (Lambda.rows() != dimension() || Lambda.cols() != p)
    throw DimensionError("Lambda: expected shape " + detail::shape_string(dimension(), p) + ", got " +
                         detail::shape_string(Lambda.rows(), Lambda.cols()));
  require_finite(Lambda, "Lambda");
  if (p == 0) return *this;
  const auto AL = A_.bottomRows(p);
  const auto bL = b_.tail(p);
  const Eigen::VectorXd c = c_ + Lambda * bL;
  const Eigen::MatrixXd G = G_ - Lambda * AL;
  // |error| <= γ_{p+1} (|c| + |Λ||b_L| + (|G| + |Λ||A_L|) 1), per row.
  Eigen::VectorXd mag = c_.cwiseAbs() + Lambda.cwiseAbs() * bL.cwiseAbs();
  if (num_generators() > 0)
    mag += G_.cwiseAbs().rowwise().sum() + Lambda.cwiseAbs() * AL.cwiseAbs().rowwise().sum();
  const Eigen::VectorXd r =
      czono_detail::inflate(r_ + rounding_bounds::gamma(p + 1) * czono_detail::inflate(mag, num_generators() + p + 2), 2);
  return ConstrainedZonotope(c, G, A_, b_, r, true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::remove_zero_constraints() const {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < num_constraints(); ++i)
    if (b_(i) != 0.0 || box_lp_detail::max_abs(A_.row(i)) > 0.0) keep.push_back(i);
  Eigen::MatrixXd A(static_cast<Eigen::Index>(keep.size()), num_generators());
  Eigen::VectorXd b(static_cast<Eigen::Index>(keep.size()));
  for (size_t k = 0; k < keep.size(); ++k) {
    A.row(static_cast<Eigen::Index>(k)) = A_.row(keep[k]);
    b(static_cast<Eigen::Index>(k)) = b_(keep[k]);
  }
  return ConstrainedZonotope(c_, G_, std::move(A), std::move(b), r_, true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::rescale() const {
  ConstrainedZonotope Z = *this;
  Z.rescale_in_place();
  Z.require_no_overflow();
  return Z;
}

SETBOUND_INLINE void ConstrainedZonotope::rescale_in_place() {
  const Eigen::Index q = num_constraints(), m = num_generators();
  if (q == 0 || m == 0) return;
  Eigen::ArrayXd lo = Eigen::ArrayXd::Constant(m, -1.0), hi = Eigen::ArrayXd::Constant(m, 1.0);
  // Row i keeps a_j ξ_j in b_i − Σ_{k≠j} a_k ξ_k. The row's terms' ends are summed in plain floating
  // point and the whole row's rounding is covered by one a-priori margin E (Higham §3.1: every
  // sum, product, the subtraction of term j and the final b_i − … err by at most γ_{m+4} times the
  // sum S of the terms' magnitudes and |b_i|; 4γ leaves a factor 2 for the computed S and γ), so
  // the propagation is a few vector operations per row instead of two directed roundings per term.
  // The quotient by a_j is then moved outward by 4u of itself (its own rounding and that of the
  // move) and a subnormal (underflow).
  const double u = std::ldexp(1.0, -53), tiny = std::numeric_limits<double>::denorm_min();
  const double margin_factor = 4.0 * rounding_bounds::gamma(m + 4);
  // Two passes over each row (its sums, then its variables' bounds), on a transposed copy so a
  // row is contiguous: an elimination rescales before every row it removes, and this loop was a
  // fifth of a CZN-A step as a dozen whole-row array expressions (callgrind, pedestrian4).
  const Eigen::MatrixXd At = A_.transpose();
  double* lo_ = lo.data();
  double* hi_ = hi.data();
  for (int sweep = 0; sweep < 4; ++sweep) {
    bool changed = false;
    for (Eigen::Index i = 0; i < q; ++i) {
      const double* a = At.col(i).data();
      const double bi = b_(i);
      // The terms' ends: a_j ξ_j in [tl_j, tu_j] (0 where a_j = 0); their sums and magnitudes.
      // Both loops are written without branches on the data (selects instead): A's signs and
      // zeros are as good as random, and the mispredicted branches made this loop a quarter of a
      // tank30 step. The values are the same as with branches: for a_j > 0 (lo <= hi) the ends
      // are a_j lo and a_j hi, for a_j < 0 the other way round, for a_j = 0 both 0.
      double L = 0.0, U = 0.0, S = 0.0, W = 0.0;
      for (Eigen::Index j = 0; j < m; ++j) {
        const double p = a[j] * lo_[j], r = a[j] * hi_[j];
        const bool pos = a[j] > 0.0;
        const double tl = pos ? p : r, tu = pos ? r : p;
        L += tl;
        U += tu;
        S += std::abs(tl) + std::abs(tu);
        W = std::max(W, tu - tl);
      }
      S += std::abs(bi);
      const double E = margin_factor * S + static_cast<double>(m + 4) * tiny;
      // The row can tighten term j only if the term's own width tu_j − tl_j exceeds
      // min(U − b_i, b_i − L) + E (else the interval below contains [tl_j, tu_j]). Most rows tighten
      // nothing (pedestrian4, vehicle6: ~9 of 10), and the pass below, two divisions per entry, was
      // most of this function. The skip keeps half of E in reserve, far above the rounding of the
      // few operations involved (a few u·S), so a skipped row is one whose pass would have changed
      // no bound: the results are the same bit for bit.
      if (W <= std::min(U - bi, bi - L) + 0.5 * E) continue;
      // a_j ξ_j ∈ [b_i − (U − tu_j) − E, b_i − (L − tl_j) + E], with lo/hi as they were for the sums
      // (entry j is only changed after its own bounds are computed). Entries with a_j = 0 divide
      // by 1 instead, and the final selects discard what they computed.
      bool empty = false;
      for (Eigen::Index j = 0; j < m; ++j) {
        const double aj = a[j], l = lo_[j], h = hi_[j];
        const bool pos = aj > 0.0, used = aj != 0.0;
        const double p = aj * l, r = aj * h;
        const double tl = pos ? p : r, tu = pos ? r : p;
        const double rl = (bi - (U - tu)) - E, ru = (bi - (L - tl)) + E;
        const double den = used ? aj : 1.0;
        const double ql = rl / den, qu = ru / den;
        double xl = pos ? ql : qu;
        double xu = pos ? qu : ql;
        xl -= 4.0 * u * std::abs(xl) + tiny;
        xu += 4.0 * u * std::abs(xu) + tiny;
        empty |= used & (!(xl <= xu) | (xl > h) | (xu < l));
        changed |= used & ((xl > l + 1e-12) | (xu < h - 1e-12));
        lo_[j] = used ? std::max(l, xl) : l;
        hi_[j] = used ? std::min(h, xu) : h;
      }
      if (empty) return;  // empty: BoxLP certifies that
    }
    if (!changed) break;
  }
  if ((lo.array() == -1.0).all() && (hi.array() == 1.0).all()) return;
  // ξ = mid + diag(ρ) ξ' with [mid − ρ, mid + ρ] ⊇ [lo, hi].
  Eigen::VectorXd mid(m), rho(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    mid(j) = 0.5 * lo(j) + 0.5 * hi(j);
    rho(j) = std::max(rounding::sub_up(hi(j), mid(j)), rounding::sub_up(mid(j), lo(j)));
  }
  // Rounding: the products and sums below, over ξ' in its box (from the data before the change).
  const Eigen::VectorXd rx = rounding_bounds::gamma(m + 1) *
      czono_detail::inflate(c_.cwiseAbs() + G_.cwiseAbs() * (mid.cwiseAbs() + rho), m + 2);
  const Eigen::VectorXd s = rounding_bounds::gamma(m + 1) *
      czono_detail::inflate(b_.cwiseAbs() + A_.cwiseAbs() * (mid.cwiseAbs() + rho), m + 2);
  const Eigen::VectorXd Gmid = G_ * mid, Amid = A_ * mid;  // each product first, then the sum
  c_ += Gmid;
  b_ -= Amid;
  G_ = G_ * rho.asDiagonal();  // coefficient-wise: no aliasing
  A_ = A_ * rho.asDiagonal();
  czono_detail::absorb_row_slack(G_, A_, czono_detail::inflate(s, 2));
  r_ = czono_detail::inflate(r_ + rx, 2);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::eliminate_constraints(Eigen::Index max_constraints) const {
  return eliminate_impl(max_constraints, nullptr);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::eliminate_constraints(Eigen::Index max_constraints,
                                                                              const Eigen::VectorXd& row_weight) const {
  if (row_weight.size() != num_constraints())
    throw DimensionError("row_weight: expected length " + std::to_string(num_constraints()) + " (one per row), got " +
                         std::to_string(row_weight.size()));
  require_finite(row_weight, "row_weight");
  return eliminate_impl(max_constraints, &row_weight);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::eliminate_impl(Eigen::Index max_constraints,
                                                                       const Eigen::VectorXd* row_weight) const {
  if (max_constraints < 0)
    throw InvalidArgumentError("max_constraints: must be >= 0, got " + std::to_string(max_constraints));
  std::vector<double> weight;
  if (row_weight) {
    for (Eigen::Index i = 0; i < num_constraints(); ++i)
      if (b_(i) != 0.0 || box_lp_detail::max_abs(A_.row(i)) > 0.0) weight.push_back((*row_weight)(i));
  }
  ConstrainedZonotope Z = remove_zero_constraints();
  while (Z.num_constraints() > max_constraints) {
    Z.rescale_in_place();
    const Eigen::Index q = Z.num_constraints(), m = Z.num_generators();
    // Choose (i, j): the smallest ‖(g_j; a_j)‖ · excess_ij, larger |A_ij| among equals.
    Eigen::Index bi = -1, bj = -1;
    double best = rounding::kInf, best_pivot = 0.0, best_reach = 0.0;
    Eigen::VectorXd colnorm(m);
    for (Eigen::Index j = 0; j < m; ++j) colnorm(j) = std::sqrt(Z.G_.col(j).squaredNorm() + Z.A_.col(j).squaredNorm());
    // With weights: only the lightest row (that has a non-zero entry) is a candidate.
    Eigen::Index only = -1;
    if (row_weight) {
      double wbest = rounding::kInf;
      for (Eigen::Index i = 0; i < q; ++i)
        if (weight[static_cast<size_t>(i)] < wbest && box_lp_detail::max_abs(Z.A_.row(i)) > 0.0)
          wbest = weight[static_cast<size_t>(i)], only = i;
    }
    for (Eigen::Index i = 0; i < q; ++i) {
      if (only >= 0 && i != only) continue;
      const double rowsum = Z.A_.row(i).cwiseAbs().sum();
      const double rowmax = box_lp_detail::max_abs(Z.A_.row(i));
      for (Eigen::Index j = 0; j < m; ++j) {
        const double a = Z.A_(i, j);
        if (std::abs(a) <= 1e-9 * rowmax) continue;  // a tiny pivot would blow up the rest
        // ξ_j = (b_i − Σ_{k≠j} A_ik ξ_k)/A_ij, |ξ_k| <= 1: |ξ_j| <= (|b_i| + rest)/|A_ij|.
        const double rest = std::max(0.0, rowsum - std::abs(a));
        const double reach = (std::abs(Z.b_(i)) + rest) / std::abs(a);
        const double score = colnorm(j) * std::max(0.0, reach - 1.0);
        if (score < best || (score == best && std::abs(a) > best_pivot)) {
          best = score, bi = i, bj = j, best_pivot = std::abs(a), best_reach = reach;
        }
      }
    }
    if (bi < 0) {  // every remaining row is (numerically) zero: drop them only if exactly 0 = 0
      break;
    }
    if (row_weight) weight.erase(weight.begin() + bi);
    Z.eliminate_in_place(bi, bj, best_reach);
  }
  Z.require_no_overflow();
  return Z;
}

SETBOUND_INLINE void ConstrainedZonotope::eliminate_in_place(Eigen::Index bi, Eigen::Index bj, double best_reach) {
  const Eigen::Index n = dimension(), m = num_generators();
  const double u = std::ldexp(1.0, -53);
  const double piv = A_(bi, bj);
  const Eigen::VectorXd rhoG = G_.col(bj) / piv;  // any ρ keeps the identity; only products round
  const Eigen::VectorXd rhoA = A_.col(bj) / piv;
  const Eigen::RowVectorXd Ai = A_.row(bi);
  const double bi_val = b_(bi);
  // After the substitution ξ_j is free but |ξ_j| <= reach (row i, the others in their box); its
  // column is exactly G_j − ρ A_ij (a few ulps, not 0) and is dropped with that bound.
  const double reach = rounding::mul_up(best_reach, 1.0 + 8.0 * u);
  const double sumAi = Ai.cwiseAbs().sum();
  // The rounding of the substitution, from the data before it. x side: |fl(c + ρ b_i) − exact|
  // + |fl(G − ρ A_i) − exact|·1 + the dropped column, per row.
  Eigen::VectorXd rx = c_.cwiseAbs() + rhoG.cwiseAbs() * std::abs(bi_val) +
                       (m > 0 ? Eigen::VectorXd(G_.cwiseAbs().rowwise().sum()) : Eigen::VectorXd::Zero(n)) +
                       rhoG.cwiseAbs() * sumAi;
  rx = rounding_bounds::gamma(2) * czono_detail::inflate(rx, m + 2) + (2.0 * u * reach) * G_.col(bj).cwiseAbs();
  // Constraint side, every row but i: the same for A − ρ A_i and b − ρ b_i.
  Eigen::VectorXd sk = b_.cwiseAbs() + rhoA.cwiseAbs() * std::abs(bi_val) +
                       Eigen::VectorXd(A_.cwiseAbs().rowwise().sum()) + rhoA.cwiseAbs() * sumAi;
  sk = rounding_bounds::gamma(2) * czono_detail::inflate(sk, m + 2) + (2.0 * u * reach) * A_.col(bj).cwiseAbs();
  const Eigen::VectorXd shift = rhoG * bi_val;
  c_ += shift;
  G_.noalias() -= rhoG * Ai;  // entry by entry: G_kl − fl(ρ_k A_il)
  A_.noalias() -= rhoA * Ai;
  b_ -= rhoA * bi_val;
  czono_detail::drop_row(A_, bi);
  czono_detail::drop_col(A_, bj);
  czono_detail::drop_col(G_, bj);
  czono_detail::drop_entry(b_, bi);
  czono_detail::drop_entry(sk, bi);
  czono_detail::absorb_row_slack(G_, A_, czono_detail::inflate(sk, 2));
  r_ = czono_detail::inflate(r_ + czono_detail::inflate(rx, 2), 2);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::reduce_limits(Eigen::Index max_generators,
                                                                      Eigen::Index max_constraints,
                                                                      ZonotopeReduction technique) const {
  return reduce_limits_impl(max_generators, max_constraints, technique, nullptr);
}
SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::reduce_limits(Eigen::Index max_generators,
                                                                      Eigen::Index max_constraints,
                                                                      ZonotopeReduction technique,
                                                                      const HullSensitivity& sens) const {
  if (sens.row_weight.size() != num_constraints())
    throw DimensionError("row_weight: expected length " + std::to_string(num_constraints()) + " (one per row), got " +
                         std::to_string(sens.row_weight.size()));
  require_finite(sens.row_weight, "row_weight");
  if (sens.box_cost.size() != num_generators())
    throw DimensionError("box_cost: expected length " + std::to_string(num_generators()) +
                         " (one per generator), got " + std::to_string(sens.box_cost.size()));
  if (sens.box_cost.hasNaN()) throw NotFiniteError("box_cost: contains NaN");  // +inf: a cost never worth paying
  if (sens.duals.rows() != num_constraints() || sens.duals.cols() != 2 * dimension())
    throw DimensionError("duals: expected shape " + detail::shape_string(num_constraints(), 2 * dimension()) +
                         " (rows × 2n), got " + detail::shape_string(sens.duals.rows(), sens.duals.cols()));
  require_finite(sens.duals, "duals");
  if (sens.width.size() != dimension())
    throw DimensionError("width: expected length " + std::to_string(dimension()) + ", got " +
                         std::to_string(sens.width.size()));
  if (!sens.width.allFinite() || (sens.width.array() < 0.0).any())
    throw InvalidArgumentError("width: every entry must be finite and >= 0");
  return reduce_limits_impl(max_generators, max_constraints, technique, &sens);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::box_generators(const std::vector<Eigen::Index>& which) const {
  const Eigen::Index n = dimension(), q = num_constraints(), m = num_generators();
  std::vector<char> boxed(static_cast<size_t>(m), 0);
  for (const Eigen::Index j : which) {
    if (j < 0 || j >= m)
      throw InvalidArgumentError("which: generator index " + std::to_string(j) + " out of range [0, " + std::to_string(m) + ")");
    if (boxed[static_cast<size_t>(j)])
      throw InvalidArgumentError("which: generator index " + std::to_string(j) + " given twice");
    boxed[static_cast<size_t>(j)] = 1;
  }
  if (which.empty()) return *this;
  const Eigen::Index k = static_cast<Eigen::Index>(which.size());
  Eigen::VectorXd gx = Eigen::VectorXd::Zero(n), sa = Eigen::VectorXd::Zero(q);
  for (const Eigen::Index j : which) {
    gx += G_.col(j).cwiseAbs();
    if (q) sa += A_.col(j).cwiseAbs();
  }
  // Sums of k exact non-negative terms, rounded up.
  gx = czono_detail::inflate(gx, k + 1);
  sa = czono_detail::inflate(sa, k + 1);
  std::vector<Eigen::Index> coords;
  for (Eigen::Index i = 0; i < n; ++i)
    if (gx(i) > 0.0) coords.push_back(i);
  const Eigen::Index e = static_cast<Eigen::Index>(coords.size());
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, m - k + e), A = Eigen::MatrixXd::Zero(q, m - k + e);
  Eigen::Index out = 0;
  for (Eigen::Index j = 0; j < m; ++j) {
    if (boxed[static_cast<size_t>(j)]) continue;
    G.col(out) = G_.col(j);
    A.col(out) = A_.col(j);
    ++out;
  }
  for (Eigen::Index t = 0; t < e; ++t) G(coords[static_cast<size_t>(t)], out + t) = gx(coords[static_cast<size_t>(t)]);
  czono_detail::absorb_row_slack(G, A, sa);
  return ConstrainedZonotope(c_, std::move(G), std::move(A), b_, r_, true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::reduce_limits_impl(Eigen::Index max_generators,
                                                                      Eigen::Index max_constraints,
                                                                      ZonotopeReduction technique,
                                                                      const HullSensitivity* sens) const {
  if (max_constraints < 0)
    throw InvalidArgumentError("max_constraints: must be >= 0, got " + std::to_string(max_constraints));
  if (max_generators < dimension() + max_constraints)
    throw InvalidArgumentError("max_generators: must be >= n + max_constraints = " +
                               std::to_string(dimension() + max_constraints) + ", got " + std::to_string(max_generators));
  const Eigen::Index n = dimension();
  const std::vector<Eigen::Index> basis = sens ? absorbing_basis() : std::vector<Eigen::Index>{};
  const ConstrainedZonotope start = !sens ? *this
                                    : basis.empty() ? box_cheapest(max_generators, max_constraints, sens->box_cost)
                                                    : absorb_cheapest(max_generators, max_constraints, *sens, basis);
  ConstrainedZonotope Z =
      start.eliminate_impl(max_constraints, sens ? &sens->row_weight : nullptr).remove_zero_constraints();
  // Columns zero in G and A say nothing; dropping them makes the limit a limit on every column.
  std::vector<Eigen::Index> keep;
  for (Eigen::Index j = 0; j < Z.num_generators(); ++j)
    if (box_lp_detail::max_abs(Z.G_.col(j)) > 0.0 || box_lp_detail::max_abs(Z.A_.col(j)) > 0.0) keep.push_back(j);
  if (!basis.empty()) {
    // The absorbing path: the rounding box goes into a basis of the remaining columns as well (no
    // new column, so the limit is met without boxing more; r keeps only the residual's ulps).
    ConstrainedZonotope K(Z.c_, Z.G_(Eigen::all, keep), Z.A_(Eigen::all, keep), Z.b_, Z.r_, true);
    const std::vector<Eigen::Index> after = K.absorbing_basis();
    if (!after.empty()) {
      if (K.r_.maxCoeff() > 0.0) K.absorb_in_place(after, {}, true);
      K.require_no_overflow();
      return K.reduce_lift(technique, max_generators);
    }
  }
  // The rounding box joins the generators (the same set, exactly): into a column that is already
  // an axis-aligned segment of its coordinate (zero in A and in the other coordinates; the box
  // columns of box_generators are such), since box(s) ⊕ box(r) = box(s + r), else as a new column.
  // Kept apart, it would be mapped by |K| at every linear map — the wrapping effect: with
  // ρ(|A|) > 1 (vehicle6: a rotation-like block) it grew ~10 % per step, to a useless hull after a
  // few hundred steps and an overflow after 7 000 — whereas as generators it is mapped exactly and
  // the lift reduction bounds it like any other column.
  std::vector<Eigen::Index> axis(static_cast<size_t>(n), -1);  // an axis-aligned kept column per coordinate
  for (Eigen::Index k = 0; k < static_cast<Eigen::Index>(keep.size()); ++k) {
    const Eigen::Index j = keep[static_cast<size_t>(k)];
    if (Z.num_constraints() && box_lp_detail::max_abs(Z.A_.col(j)) > 0.0) continue;
    Eigen::Index nz = 0, row = -1;
    for (Eigen::Index i = 0; i < n && nz < 2; ++i)
      if (Z.G_(i, j) != 0.0) ++nz, row = i;
    if (nz == 1 && axis[static_cast<size_t>(row)] < 0) axis[static_cast<size_t>(row)] = k;
  }
  std::vector<Eigen::Index> box;
  for (Eigen::Index i = 0; i < n; ++i)
    if (Z.r_(i) > 0.0 && axis[static_cast<size_t>(i)] < 0) box.push_back(i);
  const Eigen::Index mk = static_cast<Eigen::Index>(keep.size()), mb = static_cast<Eigen::Index>(box.size());
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, mk + mb), A = Eigen::MatrixXd::Zero(Z.num_constraints(), mk + mb);
  G.leftCols(mk) = Z.G_(Eigen::all, keep);
  A.leftCols(mk) = Z.A_(Eigen::all, keep);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index k = axis[static_cast<size_t>(i)];
    if (k >= 0 && Z.r_(i) > 0.0) G(i, k) = std::copysign(rounding::add_up(std::abs(G(i, k)), Z.r_(i)), G(i, k));
  }
  for (Eigen::Index k = 0; k < mb; ++k) G(box[static_cast<size_t>(k)], mk + k) = Z.r_(box[static_cast<size_t>(k)]);
  return ConstrainedZonotope(Z.c_, std::move(G), std::move(A), Z.b_, Eigen::VectorXd::Zero(n), true)
      .reduce_lift(technique, max_generators);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::box_cheapest(Eigen::Index max_generators,
                                                                     Eigen::Index max_constraints,
                                                                     const Eigen::VectorXd& box_cost) const {
  // The n box columns are counted whatever they turn out to be (the rounding box joins them).
  const czono_detail::CheapestPlan plan =
      czono_detail::cheapest_plan(G_, A_, b_, max_generators, max_constraints, dimension(), {});
  if (plan.excess <= 0) return *this;
  return box_generators(czono_detail::take_cheapest(plan, A_, box_cost, {}));
}

SETBOUND_INLINE std::vector<Eigen::Index> ConstrainedZonotope::absorbing_basis() const {
  const Eigen::Index n = dimension(), m = num_generators();
  if (m < n) return {};
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G_);
  if (qr.rank() < n) return {};
  std::vector<Eigen::Index> basis(static_cast<size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) basis[static_cast<size_t>(k)] = qr.colsPermutation().indices()(k);
  // A nearly singular T would make α = T⁻¹ g (and the scaled columns) huge: the axes are better.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(G_(Eigen::all, basis));
  const Eigen::VectorXd& sv = svd.singularValues();
  if (!(sv(n - 1) > 1e-6 * sv(0))) return {};
  return basis;
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::absorb_generators(const std::vector<Eigen::Index>& basis,
                                                                          const std::vector<Eigen::Index>& which) const {
  const Eigen::Index n = dimension(), m = num_generators();
  std::vector<char> role(static_cast<size_t>(m), 0);  // 1: basis, 2: absorbed
  if (static_cast<Eigen::Index>(basis.size()) != n)
    throw InvalidArgumentError("basis: expected " + std::to_string(n) + " column indices, got " + std::to_string(basis.size()));
  for (const Eigen::Index j : basis) {
    if (j < 0 || j >= m || role[static_cast<size_t>(j)])
      throw InvalidArgumentError("basis: index " + std::to_string(j) + " out of range [0, " + std::to_string(m) +
                                 ") or given twice");
    role[static_cast<size_t>(j)] = 1;
  }
  for (const Eigen::Index j : which) {
    if (j < 0 || j >= m || role[static_cast<size_t>(j)])
      throw InvalidArgumentError("which: index " + std::to_string(j) + " out of range [0, " + std::to_string(m) +
                                 "), given twice or in the basis");
    role[static_cast<size_t>(j)] = 2;
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(G_(Eigen::all, basis));
  if (!lu.isInvertible()) throw InvalidArgumentError("basis: the columns are linearly dependent");
  ConstrainedZonotope Z = *this;
  Z.absorb_in_place(basis, which, false);
  Z.require_no_overflow();
  return Z;
}

SETBOUND_INLINE void ConstrainedZonotope::absorb_in_place(const std::vector<Eigen::Index>& basis,
                                                         const std::vector<Eigen::Index>& which, bool rounding) {
  const Eigen::Index n = dimension(), q = num_constraints(), m = num_generators();
  const Eigen::Index k = static_cast<Eigen::Index>(which.size()), kk = k + (rounding ? n : 0);
  const Eigen::MatrixXd T = G_(Eigen::all, basis), AT = A_(Eigen::all, basis);
  Eigen::MatrixXd GJ(n, kk), AJ = Eigen::MatrixXd::Zero(q, kk);
  GJ.leftCols(k) = G_(Eigen::all, which);
  AJ.leftCols(k) = A_(Eigen::all, which);
  if (rounding) GJ.rightCols(n) = r_.asDiagonal();  // box(r) = diag(r) B: n more columns to absorb
  // α: any approximation of T⁻¹ g_j; the identity g_j = T α_j + ρ_j, a_j = A_T α_j + β_j is exact
  // with the exact residuals, bounded by the computed ones plus γ_{n+1}(|g| + |T||α|) (a dot
  // product of n + 1 terms).
  // (No solve for nothing to absorb: Eigen's triangular solve on a 0-column right-hand side binds
  // a reference to its null data, undefined behaviour that UBSan reports.)
  const Eigen::MatrixXd alpha = kk > 0 ? Eigen::MatrixXd(T.partialPivLu().solve(GJ)) : Eigen::MatrixXd(n, 0);
  const Eigen::MatrixXd absAlpha = alpha.cwiseAbs();
  const double g = rounding_bounds::gamma(n + 2);
  Eigen::VectorXd rx = ((GJ - T * alpha).cwiseAbs() + g * (GJ.cwiseAbs() + T.cwiseAbs() * absAlpha)).rowwise().sum();
  Eigen::VectorXd sa = Eigen::VectorXd::Zero(q);
  if (q) sa = ((AJ - AT * alpha).cwiseAbs() + g * (AJ.cwiseAbs() + AT.cwiseAbs() * absAlpha)).rowwise().sum();
  // |ξ_T,k + Σ_j α_jk ξ_j| <= s_k: the basis column k scaled by s_k (rounded up) covers them all;
  // the product's own rounding, u|fl(s_k t_k)| per entry, goes to r (and to the rows' slack).
  const Eigen::VectorXd s =
      czono_detail::inflate(Eigen::VectorXd(Eigen::VectorXd::Ones(n) + absAlpha.rowwise().sum()), kk + 2);
  const double u = std::ldexp(1.0, -52);
  for (Eigen::Index t = 0; t < n; ++t) {
    const Eigen::Index j = basis[static_cast<size_t>(t)];
    G_.col(j) *= s(t);
    rx += u * G_.col(j).cwiseAbs();
    if (q) {
      A_.col(j) *= s(t);
      sa += u * A_.col(j).cwiseAbs();
    }
  }
  rx = czono_detail::inflate(rx, kk + n + 2);
  sa = czono_detail::inflate(sa, kk + n + 2);
  if (k > 0) {
    std::vector<char> gone(static_cast<size_t>(m), 0);
    for (const Eigen::Index j : which) gone[static_cast<size_t>(j)] = 1;
    std::vector<Eigen::Index> rest;
    for (Eigen::Index j = 0; j < m; ++j)
      if (!gone[static_cast<size_t>(j)]) rest.push_back(j);
    G_ = Eigen::MatrixXd(G_(Eigen::all, rest));
    A_ = Eigen::MatrixXd(A_(Eigen::all, rest));
  }
  if (q) czono_detail::absorb_row_slack(G_, A_, sa);
  r_ = rounding ? rx : czono_detail::inflate(Eigen::VectorXd(r_ + rx), 2);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::absorb_cheapest(Eigen::Index max_generators,
                                                                        Eigen::Index max_constraints,
                                                                        const HullSensitivity& sens,
                                                                        const std::vector<Eigen::Index>& basis) const {
  const Eigen::Index n = dimension(), q = num_constraints(), m = num_generators();
  std::vector<char> in_basis(static_cast<size_t>(m), 0);
  for (const Eigen::Index j : basis) in_basis[static_cast<size_t>(j)] = 1;
  // As box_cheapest's plan, without the n box columns (absorbing adds none).
  const czono_detail::CheapestPlan plan = czono_detail::cheapest_plan(G_, A_, b_, max_generators, max_constraints, 0, in_basis);
  // Negligible columns (round-off left by substitutions and gains) are absorbed whatever the
  // limit: they cost nothing, and kept they put entries of 1e-20 into the LPs' bases, where a
  // warm-started simplex once ended on a basis whose certified bound was 0.1 too loose (a random
  // 3-state system, test_prediction_is_the_set_the_next_step_corrects).
  Eigen::VectorXd lift_norm(m);
  for (Eigen::Index j = 0; j < m; ++j) lift_norm(j) = std::sqrt(G_.col(j).squaredNorm() + A_.col(j).squaredNorm());
  const double negligible = 1e-9 * (m ? lift_norm.maxCoeff() : 0.0);
  std::vector<char> forced(static_cast<size_t>(m), 0);
  bool any_forced = false;
  for (const Eigen::Index j : plan.candidates)
    if (lift_norm(j) <= negligible) forced[static_cast<size_t>(j)] = 1, any_forced = true;
  if (plan.excess <= 0 && !any_forced) return *this;
  // The price of absorbing column j, per hull LP (objective ±G_i, multipliers μ): its dual term
  // |±G_ij − μᵀa_j| goes; the basis columns' terms τ_k = |±G_i t_k − μᵀa_{t_k}| grow by |α_jk|
  // each, and the rows' slack adds |μ|ᵀ|β_j|. Summed over the 2n LPs, each relative to its width.
  const Eigen::MatrixXd T = G_(Eigen::all, basis), AT = A_(Eigen::all, basis);
  const Eigen::MatrixXd alpha = T.partialPivLu().solve(G_);
  const Eigen::MatrixXd absAlpha = alpha.cwiseAbs();
  const Eigen::MatrixXd absBeta = q ? Eigen::MatrixXd((A_ - AT * alpha).cwiseAbs()) : Eigen::MatrixXd(0, m);
  Eigen::VectorXd cost = Eigen::VectorXd::Zero(m);
  Eigen::RowVectorXd now(m);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int side = 0; side < 2; ++side) {
      const auto mu = sens.duals.col(2 * i + side);
      now = side ? Eigen::RowVectorXd(-G_.row(i)) : Eigen::RowVectorXd(G_.row(i));
      if (q) now.noalias() -= mu.transpose() * A_;
      now = now.cwiseAbs();
      Eigen::RowVectorXd after = now(basis) * absAlpha;
      if (q) after.noalias() += mu.cwiseAbs().transpose() * absBeta;
      cost += ((after - now).transpose() / std::max(sens.width(i), 1e-300)).cwiseMax(0.0);
    }
  ConstrainedZonotope Z = *this;
  Z.absorb_in_place(basis, czono_detail::take_cheapest(plan, A_, cost, forced), false);
  return Z;
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::reduce_cora(ZonotopeReduction technique, double order) const {
  require_finite(order, "order");
  if (!(order >= 1.0)) throw InvalidArgumentError("order: must be >= 1, got " + std::to_string(order));
  const ConstrainedZonotope Z = remove_zero_constraints();
  const double limit = std::floor(order * static_cast<double>(Z.dimension())) + static_cast<double>(Z.num_constraints());
  return Z.reduce_lift(technique, static_cast<Eigen::Index>(std::min(limit, 1e15)));
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::absorb_rounding(double relative) const {
  const Eigen::Index n = dimension();
  const double rmax = r_.maxCoeff();
  if (!(rmax > 0.0) || rmax <= relative * czono_detail::magnitude(c_, G_).maxCoeff()) return *this;
  std::vector<Eigen::Index> nz;
  for (Eigen::Index i = 0; i < n; ++i)
    if (r_(i) > 0.0) nz.push_back(i);
  const Eigen::Index m = num_generators(), e = static_cast<Eigen::Index>(nz.size());
  Eigen::MatrixXd G(n, m + e);
  G << G_, Eigen::MatrixXd::Zero(n, e);
  for (Eigen::Index j = 0; j < e; ++j) G(nz[static_cast<size_t>(j)], m + j) = r_(nz[static_cast<size_t>(j)]);
  Eigen::MatrixXd A(num_constraints(), m + e);
  A << A_, Eigen::MatrixXd::Zero(num_constraints(), e);
  // box(r) = diag(r) B exactly: no rounding, the new rounding box is zero.
  return ConstrainedZonotope(c_, std::move(G), std::move(A), b_, Eigen::VectorXd::Zero(n), true);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::reduce_lift(ZonotopeReduction technique, Eigen::Index limit) const {
  const Eigen::Index n = dimension(), q = num_constraints(), m = num_generators();
  Eigen::Index nonzero = 0;
  for (Eigen::Index j = 0; j < m; ++j)
    if (box_lp_detail::max_abs(G_.col(j)) > 0.0 || box_lp_detail::max_abs(A_.col(j)) > 0.0) ++nonzero;
  if (nonzero <= limit) return *this;
  Eigen::VectorXd centre(n + q);
  centre << c_, -b_;
  // The rounding box enters the lift as columns [diag(r); 0] (exact), so the reduction boxes it
  // with the other small generators and the result starts again with r = 0 (it is counted in the
  // reduction's input, not in the trigger above: CORA's rule stays CORA's).
  std::vector<Eigen::Index> nz;
  for (Eigen::Index i = 0; i < n; ++i)
    if (r_(i) > 0.0) nz.push_back(i);
  const Eigen::Index e = static_cast<Eigen::Index>(nz.size());
  Eigen::MatrixXd gens = Eigen::MatrixXd::Zero(n + q, m + e);
  gens.topLeftCorner(n, m) = G_;
  gens.bottomLeftCorner(q, m) = A_;
  for (Eigen::Index j = 0; j < e; ++j) gens(nz[static_cast<size_t>(j)], m + j) = r_(nz[static_cast<size_t>(j)]);
  const Zonotope lift(centre, gens);
  const Eigen::Index target = std::max(limit, n + q);
  const Zonotope reduced = technique == ZonotopeReduction::Pca      ? lift.reduce_pca(target)
                           : technique == ZonotopeReduction::Girard ? lift.reduce_girard_to(target)
                                                                    : lift.reduce_combastel(target);
  const Eigen::MatrixXd& H = reduced.generators();
  // The centre is unchanged by these reductions; the split keeps c and b exactly.
  return ConstrainedZonotope(c_, H.topRows(n), H.bottomRows(q), b_, Eigen::VectorXd::Zero(n), true);
}

SETBOUND_INLINE void ConstrainedZonotope::require_lp(const BoxLP& lp) const {
  if (lp.A().rows() != A_.rows() || lp.A().cols() != A_.cols() || lp.A() != A_ || lp.b() != b_)
    throw InvalidArgumentError("lp: built on other rows than this set's (expected A of shape " +
                               detail::shape_string(A_.rows(), A_.cols()) + ", got " +
                               detail::shape_string(lp.A().rows(), lp.A().cols()) + " or other entries)");
}

SETBOUND_INLINE BoundingBox ConstrainedZonotope::interval_hull() const {
  BoxLP lp(A_, b_);
  return interval_hull(lp);
}

SETBOUND_INLINE BoundingBox ConstrainedZonotope::interval_hull(BoxLP& lp, HullSensitivity& sens) const {
  return hull_impl(lp, &sens);
}

SETBOUND_INLINE BoundingBox ConstrainedZonotope::hull_impl(BoxLP& lp, HullSensitivity* sens,
                                                          Eigen::MatrixXd* maximisers) const {
  require_lp(lp);
  // ±G_i is exact, so BoxLP's certified bound of max ±G_i ξ is the hull's radius part.
  const Eigen::Index n = dimension(), q = num_constraints(), m = num_generators();
  if (sens) {
    sens->row_weight = Eigen::VectorXd::Zero(q);
    sens->box_cost = Eigen::VectorXd::Zero(m);
    sens->duals = Eigen::MatrixXd::Zero(q, 2 * n);
    sens->width = Eigen::VectorXd::Zero(n);
  }
  if (maximisers) maximisers->resize(n, 0);
  if (lp.feasibility() == BoxLP::Feasibility::empty)
    return {Eigen::VectorXd::Constant(n, rounding::kInf), Eigen::VectorXd::Constant(n, -rounding::kInf)};
  BoundingBox box{Eigen::VectorXd(n), Eigen::VectorXd(n)};
  if (maximisers) maximisers->setConstant(n, 2 * n, std::numeric_limits<double>::quiet_NaN());
  Eigen::VectorXd rmax, loss;
  Eigen::MatrixXd absA;
  if (sens && q) {
    rmax.resize(q);
    for (Eigen::Index i = 0; i < q; ++i) rmax(i) = box_lp_detail::max_abs(A_.row(i));
    absA = A_.cwiseAbs();
  }
  // All maxima first, then all minima: each LP starts from the previous one's basis, and max x_i
  // after max x_{i-1} (or min after min) is nearer than min x_i after max x_i, whose start has
  // every non-basic variable flipped (about 10 % fewer pivots on vehicle6 and pedestrian4's sets).
  std::vector<BoxLP::Bound> ups, downs;
  ups.reserve(static_cast<size_t>(n));
  downs.reserve(static_cast<size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) ups.push_back(lp.maximize(G_.row(i).transpose()));
  for (Eigen::Index i = 0; i < n; ++i) downs.push_back(lp.maximize(-G_.row(i).transpose()));
  for (Eigen::Index i = 0; i < n; ++i) {
    const BoxLP::Bound& up = ups[static_cast<size_t>(i)];
    const BoxLP::Bound& down = downs[static_cast<size_t>(i)];
    box.hi(i) = rounding::add_up(c_(i), rounding::add_up(up.value, r_(i)));
    box.lo(i) = rounding::sub_down(c_(i), rounding::add_up(down.value, r_(i)));
    if (maximisers) {
      if (up.optimal && up.point.size() == m) maximisers->col(2 * i).noalias() = c_ + G_ * up.point;
      if (down.optimal && down.point.size() == m) maximisers->col(2 * i + 1).noalias() = c_ + G_ * down.point;
    }
    if (!sens) continue;
    const double width = std::max(box.hi(i) - box.lo(i), 1e-300);
    sens->width(i) = width;
    // Without rows boxing a generator costs nothing beyond its own |G_ij| (loss 0): nothing to add.
    if (q == 0) continue;
    if (up.dual.size() == q) sens->duals.col(2 * i) = up.dual;
    if (down.dual.size() == q) sens->duals.col(2 * i + 1) = down.dual;
    sens->row_weight += (up.dual.cwiseAbs() + down.dual.cwiseAbs()).cwiseProduct(rmax) / width;
    // Column j's term in the dual bound of max ±G_i ξ is |±G_ij − μᵀa_j|; boxed, it becomes
    // |G_ij| + |μ|ᵀ|a_j| (the box in x plus the rows' slack priced by μ). Non-negative by the
    // triangle inequality; rounding can make it a hair negative.
    const auto g = G_.row(i).transpose();
    loss = 2.0 * g.cwiseAbs() + absA.transpose() * (up.dual.cwiseAbs() + down.dual.cwiseAbs());
    loss -= (g - A_.transpose() * up.dual).cwiseAbs() + (-g - A_.transpose() * down.dual).cwiseAbs();
    sens->box_cost += loss.cwiseMax(0.0) / width;
  }
  return box;
}

SETBOUND_INLINE BoundingBox ConstrainedZonotope::interval_hull(BoxLP& lp) const {
  return hull_impl(lp, nullptr);
}

SETBOUND_INLINE BoundingBox ConstrainedZonotope::interval_hull(BoxLP& lp, HullSensitivity* sensitivity,
                                                              Eigen::MatrixXd& maximisers) const {
  return hull_impl(lp, sensitivity, &maximisers);
}

SETBOUND_INLINE double ConstrainedZonotope::support(const Eigen::Ref<const Eigen::VectorXd>& d) const {
  czono_detail::require_vector(d, dimension(), "d");
  BoxLP lp(A_, b_);
  if (lp.feasibility() == BoxLP::Feasibility::empty) return -rounding::kInf;
  return support_with(lp, d);
}

SETBOUND_INLINE BoundingBox ConstrainedZonotope::image_bounds(const Eigen::Ref<const Eigen::MatrixXd>& K) const {
  if (K.cols() != dimension())
    throw DimensionError("K: expected " + std::to_string(dimension()) + " columns, got shape " +
                         detail::shape_string(K.rows(), K.cols()));
  require_finite(K, "K");
  BoxLP lp(A_, b_);
  return image_bounds(K, lp);
}

SETBOUND_INLINE BoundingBox ConstrainedZonotope::image_bounds(const Eigen::Ref<const Eigen::MatrixXd>& K, BoxLP& lp) const {
  if (K.cols() != dimension())
    throw DimensionError("K: expected " + std::to_string(dimension()) + " columns, got shape " +
                         detail::shape_string(K.rows(), K.cols()));
  require_finite(K, "K");
  require_lp(lp);
  const Eigen::Index k = K.rows();
  if (lp.feasibility() == BoxLP::Feasibility::empty)
    return {Eigen::VectorXd::Constant(k, rounding::kInf), Eigen::VectorXd::Constant(k, -rounding::kInf)};
  BoundingBox box{Eigen::VectorXd(k), Eigen::VectorXd(k)};
  for (Eigen::Index i = 0; i < k; ++i) {
    box.hi(i) = support_with(lp, K.row(i).transpose());
    box.lo(i) = -support_with(lp, -K.row(i).transpose());
  }
  return box;
}

SETBOUND_INLINE double ConstrainedZonotope::support_with(BoxLP& lp, const Eigen::Ref<const Eigen::VectorXd>& d) const {
  const Eigen::VectorXd g = G_.transpose() * d;  // rounded: only used to find μ
  const Eigen::VectorXd mu = lp.maximize(g).dual;
  // dᵀc + μᵀb + ‖Gᵀd − Aᵀμ‖₁ = qᵀw + ‖Mᵀw‖₁ with M = [G; A], q = [c; −b], w = [d; −μ], from
  // its parts (no stacked copy of G and A per query).
  const Eigen::Index n = dimension(), q = num_constraints();
  const Eigen::VectorXd res = g - A_.transpose() * mu;  // fl(Gᵀd) − Aᵀμ: Gᵀd's error is in `a`
  Eigen::VectorXd a = G_.cwiseAbs().transpose() * d.cwiseAbs();
  if (q > 0) a += A_.cwiseAbs().transpose() * mu.cwiseAbs();
  const double t = c_.dot(d) + (q > 0 ? b_.dot(mu) : 0.0);
  const double tb = c_.cwiseAbs().dot(d.cwiseAbs()) + (q > 0 ? b_.cwiseAbs().dot(mu.cwiseAbs()) : 0.0);
  const double core = box_lp_detail::certified_total(t, tb, res.cwiseAbs().sum(), a.sum(), n + q, num_generators());
  const double box = d.cwiseAbs().dot(r_) * (1.0 + 2.0 * rounding_bounds::gamma(n));
  return rounding::add_up(core, box);
}

SETBOUND_INLINE ConstrainedZonotope::Emptiness ConstrainedZonotope::emptiness() const {
  BoxLP lp(A_, b_);
  return emptiness(lp);
}

SETBOUND_INLINE ConstrainedZonotope::Emptiness ConstrainedZonotope::emptiness(BoxLP& lp) const {
  require_lp(lp);
  const BoxLP::Feasibility f = lp.feasibility();
  Emptiness e{f == BoxLP::Feasibility::empty, f != BoxLP::Feasibility::inconclusive, Eigen::VectorXd(), 0.0};
  if (e.empty) {
    e.certificate = lp.infeasibility_certificate();
    e.margin = lp.certificate_margin();
  }
  return e;
}

SETBOUND_INLINE bool ConstrainedZonotope::contains(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  czono_detail::require_vector(x, dimension(), "x");
  const Eigen::Index n = dimension(), m = num_generators(), q = num_constraints();
  // Variables ξ and the η of the non-zero rounding radii; rows: G ξ + diag(r) η = x − c, A ξ = b.
  std::vector<Eigen::Index> nz;
  for (Eigen::Index i = 0; i < n; ++i)
    if (r_(i) > 0.0) nz.push_back(i);
  const Eigen::Index me = static_cast<Eigen::Index>(nz.size());
  Eigen::MatrixXd Gx = Eigen::MatrixXd::Zero(n, m + me), Ax = Eigen::MatrixXd::Zero(q, m + me);
  Gx.leftCols(m) = G_;
  for (Eigen::Index e = 0; e < me; ++e) Gx(nz[static_cast<size_t>(e)], m + e) = r_(nz[static_cast<size_t>(e)]);
  Ax.leftCols(m) = A_;
  if (m + me == 0) return box_lp_detail::max_abs(x - c_) == 0.0 && !emptiness().empty;
  Eigen::MatrixXd rows(n + q, m + me);
  rows << Gx, Ax;
  Eigen::VectorXd rhs(n + q);
  rhs << x - c_, b_;  // rounded: the certificate is re-checked against the exact x and c below
  BoxLP lp(rows, rhs);
  if (lp.feasibility() != BoxLP::Feasibility::empty) return true;
  const Eigen::VectorXd y = lp.infeasibility_certificate();
  // Margin y₁ᵀ(x − c) + y₂ᵀb − ‖Gxᵀy₁ + Axᵀy₂‖₁ = −(qᵀw + ‖Mᵀw‖₁) with
  // M = [Gx; 0; Ax], q = [−x; c; −b], w = [y₁; y₁; y₂].
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * n + q, m + me);
  M.topRows(n) = Gx;
  M.bottomRows(q) = Ax;
  Eigen::VectorXd qv(2 * n + q), w(2 * n + q);
  qv << -x, c_, -b_;
  w << y.head(n), y.head(n), y.tail(q);
  return !(-box_lp_detail::upper_bound_q_plus_l1(M, qv, w) > 0.0);
}

SETBOUND_INLINE ConstrainedZonotope ConstrainedZonotope::remove_redundant_constraints(BoxLP& lp) const {
  require_lp(lp);
  const Eigen::Index q = num_constraints(), m = num_generators();
  if (q == 0 || lp.feasibility() != BoxLP::Feasibility::feasible) return *this;
  std::vector<char> drop(static_cast<size_t>(q), 0);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(m);
  bool any = false;
  for (Eigen::Index j = 0; j < m; ++j) {
    if (box_lp_detail::max_abs(G_.col(j)) > 0.0) continue;
    Eigen::Index row = -1, count = 0;
    for (Eigen::Index i = 0; i < q; ++i)
      if (A_(i, j) != 0.0) row = i, ++count;
    if (count != 1 || drop[static_cast<size_t>(row)]) continue;
    // Certified bounds of ξ_j over the set (BoxLP's duality bounds: hi >= max ξ_j, lo <= min ξ_j).
    e(j) = 1.0;
    const double hi = lp.maximize(e).value;
    e(j) = -1.0;
    const double lo = -lp.maximize(e).value;
    e(j) = 0.0;
    if (hi < 1.0 && lo > -1.0) drop[static_cast<size_t>(row)] = 1, any = true;
  }
  if (!any) return *this;
  std::vector<Eigen::Index> rows, cols;
  for (Eigen::Index i = 0; i < q; ++i)
    if (!drop[static_cast<size_t>(i)]) rows.push_back(i);
  for (Eigen::Index j = 0; j < m; ++j) {
    bool used = box_lp_detail::max_abs(G_.col(j)) > 0.0;
    for (size_t k = 0; k < rows.size() && !used; ++k) used = A_(rows[k], j) != 0.0;
    if (used) cols.push_back(j);
  }
  const Eigen::Index qk = static_cast<Eigen::Index>(rows.size()), mk = static_cast<Eigen::Index>(cols.size());
  Eigen::MatrixXd G(dimension(), mk), A(qk, mk);
  Eigen::VectorXd b(qk);
  for (Eigen::Index k = 0; k < mk; ++k) {
    G.col(k) = G_.col(cols[static_cast<size_t>(k)]);
    for (Eigen::Index i = 0; i < qk; ++i) A(i, k) = A_(rows[static_cast<size_t>(i)], cols[static_cast<size_t>(k)]);
  }
  for (Eigen::Index i = 0; i < qk; ++i) b(i) = b_(rows[static_cast<size_t>(i)]);
  return ConstrainedZonotope(c_, std::move(G), std::move(A), std::move(b), r_, true);
}

}  // namespace setbound
