// setbound — thesis Chapter 1 invariant sets (Loukkas 2018, §1.3.3; spec thesis.md §3.3–3.6):
//   ellipsoid_bounding_box               (Def 1.5, eq 1.40)
//   expanded_ellipsoid_levels            (eqs 1.57–1.58: c_out and c_in of Ψ̄(μ) and Ψ̄⁺(μ))
//   polyhedral_rpi_between_ellipsoids    (§3.5 [reconstructed]: Ψ̄⁺ ⊆ Φ_v ⊆ Ψ̄)
//   contraction_rate                     (β: smallest β with AᵀPA ≼ β²P)
//   mrpi_outer_shrinking / mrpi_outer_shrinking_boxes   (Algorithm 1, eqs 1.59–1.72)
// See docs/thesis_invariant.md for the guarantees, assumptions and costs.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/ellipsoid.hpp"
#include "setbound/sets/interval_matrix.hpp"
#include "setbound/sets/polytope.hpp"
#include "setbound/thesis/hinf_gain.hpp"

namespace setbound::thesis {

/// Options of polyhedral_rpi_between_ellipsoids.
struct PolyhedralRpiOptions {
  /// Upper bound on the number of vertices of Φ_v; exceeding it throws InfeasibleError
  /// (c_in/c_out too close to 1 for this dimension: choose a larger μ).
  int max_vertices = 10000;
};

namespace detail {

void require_levels(double c_in, double c_out);

/// Symmetric square root T = P^{1/2} and its inverse (P symmetric positive definite).
void sqrt_and_inverse(const Eigen::MatrixXd& P, Eigen::MatrixXd& T, Eigen::MatrixXd& Tinv);

}  // namespace detail

/// Levels of the expanded ellipsoid Ψ̄(μ) and of its one-step image Ψ̄⁺(μ) (eqs 1.57–1.58):
///   c_out = μ·λ_max(P)·γ²·w̄ᵀw̄,   c_in = (μ·λ_max(P) − μ + 1)·γ²·w̄ᵀw̄,   μ > 1.
/// P is the BRL matrix (§3.4), gamma the BRL γ, wbar_sq = w̄ᵀw̄ = Σ w̄_i².
struct EllipsoidLevels {
  double c_in = 0;
  double c_out = 0;
};
EllipsoidLevels expanded_ellipsoid_levels(const Eigen::MatrixXd& P, double gamma,
                                                 double wbar_sq, double mu);

/// §3.5 [reconstructed]: a polytope Φ_v with {xᵀPx ≤ c_in} ⊆ Φ_v ⊆ {xᵀPx ≤ c_out}, c_in < c_out.
///   Whitening z = P^{1/2}x turns both ellipsoids into balls of radii r_in = √c_in, r_out = √c_out.
///   n = 1: the interval; n = 2: a regular N-gon with vertices on the outer circle; n ≥ 3: the
///   polar (V-rep) form of the spec's cutting-plane loop: start from the cross-polytope ±R·e_i,
///   and while a facet of the hull is closer to the origin than r_in add the outer-sphere points
///   ±R·u at its unit normal u; repeat. A margin of min(1e-6, 1 % of the relative gap) is kept on both sides so that the
///   result is certified in floating point: the function checks vᵀPv ≤ c_out for every vertex
///   and √(c_in·hᵀP⁻¹h) ≤ b for every facet of the returned H-rep, and throws NumericalError if
///   either fails (P too ill-conditioned). The polytope is symmetric about the origin.
/// Throws on: P not symmetric positive definite ("P: ..."), c_in ≤ 0 or c_out ≤ c_in, more
/// more vertices than opt.max_vertices (InfeasibleError).
Polytope polyhedral_rpi_between_ellipsoids(const Eigen::MatrixXd& P, double c_in,
                                                  double c_out,
                                                  const PolyhedralRpiOptions& opt = {});

/// Def 1.5 / eq 1.40: the tightest axis-aligned box around {x : (x−c)ᵀP(x−c) ≤ ρ},
/// c ± sqrt(diag(ρP⁻¹)) (half-widths rounded outward by Ellipsoid::box_inflation). Each bound is
/// attained at x* = c ± √ρ·P⁻¹e_i/√((P⁻¹)_ii). The thesis's printed box of Ex 1.3/1.4 used diag(P)
/// and is wrong (spec §3.3).
Box ellipsoid_bounding_box(const Eigen::MatrixXd& P, const Eigen::VectorXd& c, double rho);

/// β = the smallest β ≥ 0 with AᵀPA ≼ β²P, i.e. sqrt(λ_max of the pair (AᵀPA, P)) (eq 1.67–1.69).
/// Then ‖A x‖_P ≤ β‖x‖_P, so A^kΨ ⊆ β^kΨ for every P-level set Ψ. The value is rounded up by a
/// relative 1e-10 (it is computed from an eigenvalue problem). Throws when A is not square/finite
/// ("A: ..."), P not symmetric positive definite ("P: ...").
double contraction_rate(const Eigen::MatrixXd& A, const Eigen::MatrixXd& P);

/// Stop rules of Algorithm 1 (ε is always a RADIUS: 𝔹(ε) = {x : ‖x‖₂ ≤ ε}).
enum class MrpiStopRule {
  /// [reconstructed, rigorous] β^k·sqrt(c_out/λ_min(P)) ≤ ε, which implies A^kΦ_0 ⊆ 𝔹(ε).
  Radius,
  /// Ex 1.5: the shrinking index ρ̄_k = β^k·sqrt(μ·λ_max(P)/λ_min(P)) ≤ ε (relative precision).
  ShrinkingIndex,
  /// [proposed] max over the vertices v of Φ_0 of ‖A^k v‖₂ ≤ ε: exact for A^kΦ_0 ⊆ 𝔹(ε).
  VertexNorm,
};

struct MrpiOptions {
  MrpiStopRule stop = MrpiStopRule::Radius;
  /// μ of the shrinking index ρ̄_k (reporting; and the ShrinkingIndex stop rule).
  double mu = 1.0;
  /// k* larger than this throws InfeasibleError.
  int max_iterations = 500;
};

/// Result of Algorithm 1. Index k runs over 0…k*.
struct MrpiShrinking {
  std::vector<Polytope> sets;            // Φ_k (empty in the box-only variant)
  std::vector<Box> boxes;                // [Φ_k] = box(A^kΦ_0) + Σ_{i<k} box(A^iEΔ), outward rounded
  std::vector<double> radius_bound;      // β^k·sqrt(c_out/λ_min(P)) ≥ max ‖A^kΦ_0‖
  std::vector<double> vertex_radius;     // max_v ‖A^k v‖ over the vertices of Φ_0 (exact radius)
  std::vector<double> shrinking_index;   // ρ̄_k = β^k·sqrt(μ·λ_max(P)/λ_min(P))
  int k_star = 0;
  double beta = 0;
};

namespace detail {

void check_mrpi_inputs(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Box& delta,
                              const Polytope& Phi0, const Eigen::MatrixXd& P, double c_out,
                              double eps, const MrpiOptions& opt);

/// The scalar sequences and k*; fills everything but sets/boxes.
MrpiShrinking mrpi_schedule(const Eigen::MatrixXd& A, const Polytope& Phi0, const Eigen::MatrixXd& P,
                                   double c_out, double eps, const MrpiOptions& opt);

/// [Φ_k] for k = 0…K (rigorous, outward rounded): box(A^kΦ_0) + Σ_{i<k} box(A^iEΔ), with the
/// powers A^k kept as interval matrices.
std::vector<Box> mrpi_boxes(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E, const Box& delta,
                                   const Polytope& Phi0, int K);

/// Corners of the box Δ mapped by E (columns), deduplicated for zero-width components.
Eigen::MatrixXd mapped_corners(const Eigen::MatrixXd& E, const Box& delta);

}  // namespace detail

/// The box-only variant (for Ch. 4): same schedule and k*, boxes [Φ_k] only (no polytope hulls;
/// cost O(k*·(p + m)·n²) with p the vertex count of Φ_0).
MrpiShrinking mrpi_outer_shrinking_boxes(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                                const Box& delta, const Polytope& Phi0,
                                                const Eigen::MatrixXd& P, double c_out, double eps,
                                                const MrpiOptions& opt = {});

/// Algorithm 1 (eqs 1.59–1.72) from a given Φ_0 (usually polyhedral_rpi_between_ellipsoids):
///   Φ_{k+1} = AΦ_k ⊕ EΔ (V-rep: all sums A v_i + E d_j over the corners d_j of Δ, then a Qhull
///   hull), until the stop rule holds (k* ≥ 1). P is the BRL matrix of A (§3.4), c_out the level
///   of the outer ellipsoid Ψ̄ ⊇ Φ_0 (checked), eps a RADIUS (see MrpiStopRule).
/// Guarantees (exact arithmetic; the boxes are also rigorous under rounding): Φ_{k+1} ⊆ Φ_k when
/// Φ_0 is RPI; each Φ_k is RPI; Ω_k ⊆ Φ_k; A^{k*}Φ_0 ⊆ 𝔹(eps) for the Radius and VertexNorm rules.
/// Throws: shapes/NaN ("A", "E", "delta", "Phi0", "P"), delta empty/unbounded/not containing 0,
/// eps ≤ 0, β ≥ 1 (A not Schur or P not a Lyapunov matrix), k* > max_iterations.
MrpiShrinking mrpi_outer_shrinking(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                          const Box& delta, const Polytope& Phi0,
                                          const Eigen::MatrixXd& P, double c_out, double eps,
                                          const MrpiOptions& opt = {});

/// Everything Algorithm 1 computes from the data.
struct MrpiDesign {
  BrlRpi brl;              // step 1: P and the minimum γ of LMI (1.48)
  EllipsoidLevels levels;  // c_in, c_out of Ψ̄⁺(μ), Ψ̄(μ) (1.57–1.58)
  double mu = 0;
  Polytope phi_v;          // step 2: Ψ̄⁺ ⊆ Φ_v ⊆ Ψ̄
  MrpiShrinking shrinking; // steps 3–5 (shrinking.sets.back() = Φ_{k*})
};

/// Algorithm 1 from the data: x⁺ = A x + E w with |w_i| ≤ wbar_i (Δ = [−w̄, w̄]); BRL (1.48),
/// Φ_v between Ψ̄⁺(μ) and Ψ̄(μ) (μ > 1), then the shrinking iteration with stop radius eps.
/// opt.mu is overwritten by mu (the shrinking index uses the μ of the construction). With
/// boxes_only = true the polytopes Φ_k (k ≥ 1) are not built.
MrpiDesign mrpi_outer_shrinking(const Eigen::MatrixXd& A, const Eigen::MatrixXd& E,
                                       const Eigen::VectorXd& wbar, double mu, double eps,
                                       MrpiOptions opt = {}, bool boxes_only = false,
                                       const PolyhedralRpiOptions& popt = {},
                                       const HinfOptions& hopt = {});

}  // namespace setbound::thesis

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/thesis/impl/invariant.ipp"
#endif
