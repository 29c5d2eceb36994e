// setbound — constrained zonotopes Z = {c + Gξ : Aξ = b, ‖ξ‖∞ <= 1} (spec cora_observers.md §1.5,
// §2.17, §2.18; Scott, Raimondo, Marseglia, Braatz, Automatica 69 (2016) 126–136, "[Scott2016]").
//
// Why: a zonotope loses accuracy at every strip intersection (it can only outer-bound it); a
// constrained zonotope represents the intersection with a measurement exactly (one more row), so
// with generous limits it tracks the exact consistent set, and with bounded limits (reduction) it
// stays guaranteed and tighter than the zonotope methods.
//
// Rounding. Every operation contains its exact counterpart after floating-point rounding: the
// errors of the computed centre and generators (Higham's a-priori bounds) are collected in a
// *rounding box* r >= 0, so the set this class stands for is
//
//   Z = {c + Gξ + diag(r) η : Aξ = b, ‖ξ‖∞ <= 1, ‖η‖∞ <= 1},
//
// η free (it enters no constraint). r is zero for a set built from exact data and stays at the
// level of a few ulps of the set's size; keeping it apart (instead of appending n tiny generator
// columns per operation) keeps the LPs small. A new constraint row accounts for r and for its own
// rounding by widening the row's noise term ([Scott2016] eq. 13 written for Z ⊕ box(r)), which is
// an outer bound, never a cut. The queries (interval hull, support, membership, emptiness) are
// certified through BoxLP's duality bounds (box_lp.hpp): the hull contains the exact hull,
// "empty" and "not a member" are reported only with a verified certificate.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "setbound/sets/box_lp.hpp"
#include "setbound/sets/ellipsoid.hpp"  // BoundingBox
#include "setbound/sets/strip.hpp"      // Strip, HalfSpace
#include "setbound/sets/zonotope.hpp"

namespace setbound {

class ConstrainedZonotope {
 public:
  /// Validates: c non-empty and finite ("c"); G with n rows ("G"); A with G's column count
  /// ("A", any number of rows, also zero); b of length rows(A) ("b"); all finite. The rounding
  /// box starts at zero.
  ConstrainedZonotope(Eigen::VectorXd c, Eigen::MatrixXd G, Eigen::MatrixXd A, Eigen::VectorXd b);

  /// The zonotope as a constrained zonotope with no constraints (exact).
  explicit ConstrainedZonotope(const Zonotope& z);

  /// The box [lo, hi] (finite, lo <= hi): centre and radii rounded so that it contains the box.
  static ConstrainedZonotope from_bounds(const Eigen::Ref<const Eigen::VectorXd>& lo,
                                         const Eigen::Ref<const Eigen::VectorXd>& hi);

  /// The set {c + Gξ + diag(r)η : Aξ = b, ‖ξ‖∞ <= 1, ‖η‖∞ <= 1} from its parts (as the C ABI and
  /// saved states carry it): validated as the constructor, and r of length n, finite and >= 0 ("r").
  static ConstrainedZonotope from_parts(Eigen::VectorXd c, Eigen::MatrixXd G, Eigen::MatrixXd A, Eigen::VectorXd b,
                                        Eigen::VectorXd r);

  Eigen::Index dimension() const { return c_.size(); }
  Eigen::Index num_generators() const { return G_.cols(); }
  Eigen::Index num_constraints() const { return A_.rows(); }
  const Eigen::VectorXd& center() const { return c_; }
  const Eigen::MatrixXd& generators() const { return G_; }
  const Eigen::MatrixXd& constraint_matrix() const { return A_; }
  const Eigen::VectorXd& constraint_vector() const { return b_; }
  /// The rounding box r (see the file comment): zero unless operations rounded.
  const Eigen::VectorXd& rounding_radius() const { return r_; }

  // ---- Operations (each returns a set containing the exact result) ----------------------

  /// K Z (K: k×n, finite): K c ⊕ K G, constraints unchanged ([Scott2016] eq. 11).
  ConstrainedZonotope linear_map(const Eigen::Ref<const Eigen::MatrixXd>& K) const;
  /// Z + v.
  ConstrainedZonotope translate(const Eigen::Ref<const Eigen::VectorXd>& v) const;
  /// Z ⊕ W for a zonotope: W's generators appended, constraints unchanged (eq. 12).
  ConstrainedZonotope minkowski_sum(const Zonotope& W) const;
  /// Z ⊕ Y: generators side by side, constraints block-diagonal (eq. 12).
  ConstrainedZonotope minkowski_sum(const ConstrainedZonotope& Y) const;

  /// Generalized intersection {x ∈ Z : R x ∈ Y} (R: k×n, Y in R^k; eq. 13): Y's generators and
  /// constraints appended, plus the k rows R G ξ − G_Y ζ = c_Y − R c. The rows' rounding and Z's
  /// rounding box enter as a widening of a generator of Y private to the row when there is one,
  /// else as one extra column per row.
  ConstrainedZonotope intersect(const ConstrainedZonotope& Y, const Eigen::Ref<const Eigen::MatrixXd>& R) const;
  /// Z ∩ Y (R = I).
  ConstrainedZonotope intersect(const ConstrainedZonotope& Y) const;
  /// Z ∩ {x : |hᵀx − y| <= φ}: one row and one generator (exact up to rounding).
  ConstrainedZonotope intersect_strip(const Strip& s) const;
  /// Z ∩ {x : aᵀx <= f}: one row and one slack generator ([Scott2016] §3: the slack spans
  /// [L, f] for a lower bound L of aᵀx over Z, so the row cuts nothing the half-space keeps).
  /// Unchanged when the half-space contains Z (certified by the support function).
  ConstrainedZonotope intersect_halfspace(const HalfSpace& h) const;
  /// The states consistent with a measurement: {x ∈ Z : y − C x ∈ V} (CZN-A's correction,
  /// spec §2.17: V used as a set, not as strips). C: p×n, y: length p, V in R^p.
  ConstrainedZonotope intersect_output(const Eigen::Ref<const Eigen::MatrixXd>& C,
                                       const Eigen::Ref<const Eigen::VectorXd>& y, const Zonotope& V) const;

  /// The same set written differently (CZN-B's correction, spec §2.18): with the rows
  /// A_L ξ = b_L from `first_row` on and any Λ (n × their count), x = c + Gξ equals
  /// c + Λ b_L + (G − Λ A_L) ξ on every ξ satisfying them, so c' = c + Λ b_L, G' = G − Λ A_L
  /// (the rows stay). Rounding of c' and G' goes to the rounding box.
  ConstrainedZonotope substitute_rows(const Eigen::Ref<const Eigen::MatrixXd>& Lambda, Eigen::Index first_row) const;

  /// Drops constraint rows that are exactly zero with a zero right-hand side (they say 0 = 0).
  ConstrainedZonotope remove_zero_constraints() const;

  /// The same set with its variables' box tightened ([Scott2016] §4.2, rescaling): bounds
  /// [l_j, u_j] ⊆ [−1, 1] that every feasible ξ satisfies are found by interval constraint
  /// propagation over the rows (a few sweeps, outward rounded), and ξ = m + diag(ρ) ξ' maps them
  /// back to the unit box (c + G m, G diag ρ, A diag ρ, b − A m). Elimination after it loses less:
  /// a row that now keeps its variable in [−1, 1] is eliminated exactly.
  ConstrainedZonotope rescale() const;

  /// Constraint elimination ([Scott2016] §4.2): while more than `max_constraints` (>= 0) rows
  /// remain, one row i and one variable ξ_j (A_ij != 0) are removed by solving row i for ξ_j and
  /// substituting it everywhere, and ξ_j's bound |ξ_j| <= 1 is dropped — an outer bound, exact
  /// when row i alone already keeps ξ_j in [−1, 1]. The pair chosen is the one whose dropped bound
  /// can add the least: ‖(g_j; a_j)‖₂ times how far row i lets ξ_j leave [−1, 1] with the other
  /// variables in their box (zero when it cannot). Rounding of the substitution goes to the
  /// rounding box (x side) and to the rows' noise terms (constraint side); ξ_j stays bounded by
  /// row i, which bounds the tiny column left behind.
  ConstrainedZonotope eliminate_constraints(Eigen::Index max_constraints) const;
  /// eliminate_constraints with the rows taken in order of increasing `row_weight` (one finite
  /// entry per row, "row_weight"), each eliminated through the variable of the least score in it.
  /// With interval_hull(lp, row_weight)'s dual weights, the rows the hull leans on least go first
  /// (they say least about the set's projection onto x; the box-based score alone cannot see the
  /// projection). Same guarantee: an outer bound, rounding absorbed as above.
  ConstrainedZonotope eliminate_constraints(Eigen::Index max_constraints, const Eigen::VectorXd& row_weight) const;
  /// What the 2n interval-hull LPs say about the parts of the set (interval_hull(lp, sensitivity)):
  /// the estimators' default reduction is guided by it.
  struct HullSensitivity {
    /// Per row: Σ over the hull LPs of |μ_i| · max_j |A_ij| / (the width of that LP's coordinate).
    /// A row of weight 0 has a zero multiplier in every hull LP: dropping it leaves the certified
    /// hull unchanged.
    Eigen::VectorXd row_weight;
    /// Per generator: by how much the certified hull would grow, with the LPs' multipliers μ kept
    /// and each width counted relative to itself, if the generator were replaced by its interval
    /// hull in the lift (|g_j| as a box in x, |a_j| as slack of the rows):
    /// Σ_i (|G_ij| + |μ|ᵀ|a_j| − |±G_ij − μᵀa_j|) / width_i over both LPs of coordinate i. Exact
    /// to first order for a set of generators boxed together (the growth is additive in them).
    Eigen::VectorXd box_cost;
    /// The LPs' multipliers themselves (rows × 2n; column 2i: the LP of max x_i, 2i+1: min x_i;
    /// zeros where an LP fell back) and each coordinate's hull width (n): what reduce_limits
    /// needs to price absorbing a generator into a basis of other generators (absorb_generators).
    Eigen::MatrixXd duals;
    Eigen::VectorXd width;
  };

  /// reduce_limits guided by the hull LPs. The set's own generators give a basis (absorbing_basis:
  /// n well-conditioned columns, the largest first); the generators whose absorption into it costs
  /// the hull least (priced with the LPs' multipliers, like box_cost) are absorbed
  /// (absorb_generators) until the limits can be met, every negligible column with them; then the
  /// rows are eliminated in order of row_weight (eliminate_constraints(max_constraints,
  /// row_weight)), the rounding box is absorbed into the basis too, and reduce_limits' lift
  /// reduction catches what is still over the limit. Without such a basis (fewer than n
  /// generators, or a nearly singular one) the cheapest generators by box_cost are boxed on the
  /// axes instead (box_generators). Why a basis: an axis box costs n new columns every time it is
  /// taken, and those columns, once mapped by A, are boxed again next step (the wrapping effect);
  /// absorbing into existing columns adds none. Measured on CORA's records with the default limits
  /// (docs/theory/constrained_zonotopes.md): mean hull width over the exact one on vehicle6 1.46 →
  /// 1.01 (200 steps), vehicle2 1.19 → 1.002. Same guarantee: an outer bound.
  ConstrainedZonotope reduce_limits(Eigen::Index max_generators, Eigen::Index max_constraints,
                                    ZonotopeReduction technique, const HullSensitivity& sensitivity) const;
  /// The generators `which` absorbed into the columns `basis` (n distinct indices, not in `which`,
  /// whose n × n block T of G is invertible): with g_j = T α_j + ρ_j and a_j = A_T α_j + β_j, every
  /// basis column k is scaled by s_k = 1 + Σ_j |α_jk| (in G and A), the residuals Σ_j |ρ_j| join
  /// the rounding box and Σ_j |β_j| the rows' slack (absorb_row_slack), all rounded outward. An
  /// outer bound of this set ([Scott2016] §4.3's lifted box, in the basis [T 0; A_T I] of the lift
  /// instead of the axes): ξ_T + Σ_j α_j ξ_j ranges over the box diag(s) B. No new column but row
  /// slack for rows without a private one. InvalidArgumentError "basis"/"which" otherwise.
  ConstrainedZonotope absorb_generators(const std::vector<Eigen::Index>& basis,
                                        const std::vector<Eigen::Index>& which) const;
  /// n columns of G for absorb_generators: the first n pivots of a column-pivoted QR of G (the
  /// largest columns, each as far from the span of the previous ones as possible), or none when G
  /// has fewer than n columns or their block's condition number exceeds 1e6.
  std::vector<Eigen::Index> absorbing_basis() const;
  /// The lift's box of generators `which` (distinct indices): x = c + G_rest ξ + diag(Σ_J |G_j|) η,
  /// A_rest ξ + diag(Σ_J |A_j|) ζ = b (the row slack through absorb_row_slack), rounded outward.
  /// An outer bound of this set (Girard's box, [Scott2016] §4.3's lifted form).
  ConstrainedZonotope box_generators(const std::vector<Eigen::Index>& which) const;

  /// The rounding box as generator columns diag(r) (exact) when it exceeds `relative` times the
  /// set's magnitude (max_i |c_i| + Σ_j |G_ij|); else the set unchanged. Why: a linear map can only
  /// carry r as a box (|K| r, the hull of K·box(r)), which wraps: r grows by up to ‖|K|‖∞ per map,
  /// geometrically in a filter even for a stable K (seen: 2.2× per step, 1e+90 after 300 steps);
  /// as columns it is mapped exactly. Long runs call this after each prediction.
  ConstrainedZonotope absorb_rounding(double relative = 1e-12) const;

  /// setbound's bounded mode: eliminate_constraints(max_constraints), then the lift reduction of
  /// reduce_cora to at most `max_generators` generators (>= n + max_constraints, "max_generators").
  /// A run of any length then has bounded memory and LP size. The rounding box becomes generator
  /// columns first (the result's rounding box is zero), so later linear maps move it exactly
  /// instead of wrapping it (|K| r grows without bound when ρ(|K|) > 1).
  ConstrainedZonotope reduce_limits(Eigen::Index max_generators, Eigen::Index max_constraints,
                                    ZonotopeReduction technique = ZonotopeReduction::Girard) const;

  /// CORA's reduction (conZonotope/reduce.m, spec §2.17): zero constraint rows dropped, then the
  /// lifted zonotope [c; −b] ⊕ [G; A]B in R^{n+n_c} is reduced with `technique` (Girard or PCA)
  /// to at most order·n + n_c generators, and split back. Only when there are more generators
  /// than that. Guaranteed: {x : (x, 0) ∈ reduced lift} ⊇ {x : (x, 0) ∈ lift} = Z, and the
  /// zonotope reduction rounds outward. `order` >= 1 ("order").
  ConstrainedZonotope reduce_cora(ZonotopeReduction technique, double order) const;

  // ---- Queries (certified; each solves LPs with BoxLP) -----------------------------------

  /// The interval hull: 2n LPs sharing one warm-started basis; contains the exact hull. An
  /// empty set gives lo = +inf, hi = −inf (the empty box).
  BoundingBox interval_hull() const;
  /// A certified upper bound of max_{x ∈ Z} dᵀx (−inf when Z is certified empty).
  double support(const Eigen::Ref<const Eigen::VectorXd>& d) const;
  /// Certified bounds of K x over Z, row by row (lo_k <= K_k x <= hi_k): the support function
  /// in ±K_k, all 2k LPs on one warm-started basis. The empty box when Z is certified empty.
  BoundingBox image_bounds(const Eigen::Ref<const Eigen::MatrixXd>& K) const;

  struct Emptiness {
    bool empty;                   ///< true only with a verified certificate
    bool conclusive;              ///< false: the LP could decide neither way (treated as not empty)
    Eigen::VectorXd certificate;  ///< y with yᵀb − ‖Aᵀy‖₁ > 0 (certified) when empty
    double margin;                ///< the certified lower bound of that quantity
  };
  /// Emptiness with a certificate ([Scott2016] §5: the fault-detection test).
  Emptiness emptiness() const;
  bool is_empty() const { return emptiness().empty; }

  /// x ∈ Z? Returns false only when a certificate of non-membership verifies (so a point on the
  /// boundary, or one the LP cannot separate, counts as a member: the guaranteed direction for
  /// containment tests).
  bool contains(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  // ---- The same queries on an LP the caller keeps ------------------------------------------
  // An estimator step asks several questions of one set (screening, emptiness, hull): these
  // overloads take an LP built on this set's rows (BoxLP(A, b), or one extended to them with
  // BoxLP::extend), so phase 1 runs once and every LP after the first is warm-started. Each
  // checks that `lp` has exactly this set's rows (InvalidArgumentError "lp").

  BoundingBox interval_hull(BoxLP& lp) const;
  /// The same, and what its LPs' multipliers say about each row and generator (HullSensitivity).
  BoundingBox interval_hull(BoxLP& lp, HullSensitivity& sensitivity) const;
  /// The same (sensitivity may be null), and the points the simplex found: column 2i (2i+1) is
  /// c + G ξ* of the LP of max x_i (min x_i). They are points of the set up to the simplex's
  /// feasibility tolerance and rounding, not certified: what they span is an inner estimate of
  /// the set (the estimators' margins of consistent readings). NaN columns where an LP did not
  /// reach optimality; no columns when the set is certified empty.
  BoundingBox interval_hull(BoxLP& lp, HullSensitivity* sensitivity, Eigen::MatrixXd& maximisers) const;
  BoundingBox image_bounds(const Eigen::Ref<const Eigen::MatrixXd>& K, BoxLP& lp) const;
  Emptiness emptiness(BoxLP& lp) const;

  /// Drops the rows that cut nothing ([Scott2016] §4.2's redundant constraints), certified by
  /// LPs on `lp`: a row with a variable ξ_j private to it and zero in G (a measurement's noise
  /// term, a slack) whose certified range over the set lies strictly inside (−1, 1) says nothing
  /// (the bound |ξ_j| <= 1 is never active, so ξ_j is free and the row with it can be projected
  /// out). Every such row is dropped at once (if each bound is inactive on the set, dropping all
  /// of them leaves the set unchanged), with the columns left zero. Exact: no rounding.
  ConstrainedZonotope remove_redundant_constraints(BoxLP& lp) const;

 private:
  void require_lp(const BoxLP& lp) const;
  ConstrainedZonotope(Eigen::VectorXd c, Eigen::MatrixXd G, Eigen::MatrixXd A, Eigen::VectorXd b,
                      Eigen::VectorXd r, bool /*trusted*/);
  /// The lift reduction to at most `limit` (>= n + n_c) non-zero generators (reduce_cora's core).
  /// The certified support in d with an LP already built on (A, b) and not certified empty.
  double support_with(BoxLP& lp, const Eigen::Ref<const Eigen::VectorXd>& d) const;
  ConstrainedZonotope reduce_lift(ZonotopeReduction technique, Eigen::Index limit) const;
  /// The interval hull on `lp`; the sensitivity too when asked (it costs O(n q m) more).
  BoundingBox hull_impl(BoxLP& lp, HullSensitivity* sensitivity, Eigen::MatrixXd* maximisers = nullptr) const;
  ConstrainedZonotope eliminate_impl(Eigen::Index max_constraints, const Eigen::VectorXd* row_weight) const;
  // The elimination loop works on one set in place (no set rebuilt, no finiteness scan per row:
  // the caller checks once at the end with require_no_overflow): rescale() on this set, and the
  // substitution of ξ_j from row i (pivot A_ij, |ξ_j| <= reach over the box) that drops row i and
  // column j. rescale() is a copy and rescale_in_place(); eliminate_constraints() runs the loop.
  void rescale_in_place();
  void eliminate_in_place(Eigen::Index i, Eigen::Index j, double reach);
  /// Throws NumericalError when an entry is not finite (overflow: operations on validated sets
  /// have no other way to one).
  void require_no_overflow() const;
  ConstrainedZonotope reduce_limits_impl(Eigen::Index max_generators, Eigen::Index max_constraints,
                                         ZonotopeReduction technique, const HullSensitivity* sensitivity) const;
  /// box_generators on the generators of least box_cost, as many as reduce_limits needs to meet
  /// max_generators after eliminating rows down to max_constraints (none when it already can).
  ConstrainedZonotope box_cheapest(Eigen::Index max_generators, Eigen::Index max_constraints,
                                   const Eigen::VectorXd& box_cost) const;
  /// The same with absorb_generators into `basis` (absorbing_basis()), priced by the LPs' multipliers;
  /// the negligible columns (lift norm <= 1e-9 of the largest) are absorbed whatever the limit.
  ConstrainedZonotope absorb_cheapest(Eigen::Index max_generators, Eigen::Index max_constraints,
                                      const HullSensitivity& sensitivity, const std::vector<Eigen::Index>& basis) const;
  /// absorb_generators in place, without the checks; with `rounding`, the rounding box diag(r) is
  /// absorbed as well and r becomes the (tiny) residual bound of that.
  void absorb_in_place(const std::vector<Eigen::Index>& basis, const std::vector<Eigen::Index>& which, bool rounding);

  Eigen::VectorXd c_;
  Eigen::MatrixXd G_;
  Eigen::MatrixXd A_;
  Eigen::VectorXd b_;
  Eigen::VectorXd r_;
};

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/sets/impl/constrained_zonotope.ipp"
#endif
