// setbound — P-radius gain design for the zonotopic estimator ([Le2013], papers.md §3.2–3.3).
//
// For strip j (in the chosen order) the design solves, at a fixed β and for every vertex G of
// [A] (the LMI is affine in A, so the vertices suffice, §3.4):
//
//   max τ  s.t.  (1 − β) P / (ψ + Σ_{l≤j} φ_l²) ⪰ τ I,   τ ≥ 0,
//   [ βP                                                  (K G)ᵀ M  ]
//   [      F_wᵀF_w                                        (K F_w)ᵀ M ]
//   [             φ_0² …                                   (K_{l+1} φ_l λ_l)ᵀ M … ]  ⪰ 0,   M = P − c_j Yᵀ,
//   [                    φ_j²                              φ_j Yᵀ    ]
//   [ sym                                                 P          ]
//
// with λ_j = P⁻¹Y. Approach 1 ("sequential", §3.2) designs every strip alone: K = I and no
// earlier strips. Approach 2 ("coupled", §3.3) designs strip j with λ_0 … λ_{j−1} fixed, K =
// κ_{j−1} ⋯ κ_0 (κ_l = I − λ_l c_lᵀ) and one diagonal block per earlier strip. The LMI certifies
// the P-radius recursion L_k ≤ β L_{k−1} + ψ + Σ φ² (§3.2), so τ is the smallest eigenvalue of
// the normalised limit ellipsoid; β is chosen by a scalar search maximising τ (§0.4: never the
// largest feasible β). The gains only set the size of the estimates: the zonotopic estimator
// is guaranteed for any λ.
//
// In the LinearSystem model, F_w is the state-disturbance matrix E (zero columns dropped, and
// compressed to full column rank: only F_w F_wᵀ and range(F_w) matter for the LMI), ψ =
// max_{γ ∈ B^{n_ω}} ‖Eγ‖² over the box vertices, and φ_i = Σ_j |F_ij| is the strip half-width.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/lmi/scalar_search.hpp"
#include "setbound/lmi/solver.hpp"

namespace setbound {

enum class PRadiusApproach { Sequential = 1, Coupled = 2 };

struct PRadiusOptions {
  PRadiusApproach approach = PRadiusApproach::Sequential;
  std::vector<Eigen::Index> strip_order;  ///< empty: 0, 1, …, n_y − 1
  /// Approach 2 only: try all n_y! orders and keep the one whose last strip has the largest τ
  /// (that τ certifies the P-radius bound of a whole correction cycle). Needs n_y <= 7.
  bool try_all_orders = false;
  double beta_lo = 1e-3, beta_hi = 1.0 - 1e-3;
  lmi::ScalarSearchOptions search{};
};

struct PRadiusDesign {
  PRadiusApproach approach = PRadiusApproach::Sequential;
  std::vector<Eigen::Index> strip_order;
  Eigen::MatrixXd lambdas;            ///< n_y × n_x; row i is λ_i of output i
  std::vector<Eigen::MatrixXd> P;     ///< per output i
  Eigen::VectorXd beta, tau;          ///< per output i
  double psi = 0.0;                   ///< max ‖F_w γ‖² over the disturbance box
};

namespace detail {

/// ψ = max over γ ∈ {−1, 1}^{n_ω} of ‖E γ‖² (a convex maximum over a box: vertices; the ±
/// symmetry halves the list).
double disturbance_psi(const Eigen::MatrixXd& E);

/// A full-column-rank F̃ with F̃ F̃ᵀ = E Eᵀ (range and Gram matrix are all the LMI uses).
Eigen::MatrixXd compress_disturbance(const Eigen::MatrixXd& E);

}  // namespace detail

/// Designs λ_i for every output (papers.md §3.2 / §3.3). Throws InfeasibleError naming the
/// strip when no β in the search interval gives a contracting design.
PRadiusDesign design_pradius(const LinearSystem& sys, const PRadiusOptions& opt = {});

namespace detail {
PRadiusDesign design_pradius_best_order(const LinearSystem& sys, PRadiusOptions opt);
}  // namespace detail

/// The estimator's gain rule for a design: λ_i of the strip's output, fixed offline.
inline ZonotopeGain pradius_gain(const PRadiusDesign& design) { return ZonotopeGain::fixed(design.lambdas); }

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/zonotopic/impl/pradius.ipp"
#endif
