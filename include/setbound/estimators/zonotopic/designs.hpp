// setbound — offline gain designs of the intersection-free zonotopic observers of CORA's
// catalogue (spec cora_observers.md §2.10 PRad-E, §2.11 Nom-G), on setbound's LMI solver.
//
// Both return L = P⁻¹Y for the propagation X_{k+1} = (A − LC) X_k ⊕ … (observer.hpp); any L is
// guaranteed there, the design only decides the size. With W = E_w B (E_w: E compressed to full
// column rank) and V = F_v B (F_v: F compressed likewise):
//
//   PRad-E (Wang, Zhou, Puig, Cembrano, Wang, CCC 2017, eq. 17; H₋-type P-radius):
//     N(β) = [ βP          0        0        (PA − YC)ᵀ ]
//            [ 0           E_wᵀE_w  0        (PE_w)ᵀ    ]  ⪰ 0,   P ⪰ 0,   maximise trace P,
//            [ 0           0        F_vᵀF_v  (YF_v)ᵀ    ]
//            [ PA − YC     PE_w     YF_v     P          ]
//     i.e. ‖x⁺‖²_P ≤ β‖x‖²_P + ‖E_w w‖² + ‖F_v v‖²; β by CORA's bisection on (0, 1) to a width of
//     0.01 (infeasible → smaller β). CORA takes P, Y of the *last* solve whatever its status;
//     setbound takes the last feasible one (the largest feasible β of the bisection). trace P is
//     bounded only when E_w has full row rank (the E_w block forces E_wᵀ P E_w ⪯ E_wᵀE_w);
//     otherwise the design is refused.
//   Nom-G (Wang, Puig, Cembrano, Automatica 93, 2018, nominal observer): CORA solves the
//     feasibility problem [[μP, ·], [PA − YC, P]] ⪰ 0 with μ = 1 and no objective, whose feasible
//     set is a cone containing P = 0: the returned point is wherever the solver stops (spec §2.11).
//     setbound's design takes the analytic centre of the slice P ⪰ I, trace P ≤ 10 t* of that cone
//     (t* its least trace; max log det N + log det(P − I) + log(10 t* − trace P), N the LMI): a deterministic gain
//     strictly inside, with (A − LC)ᵀP(A − LC) ⪯ P. (The largest decay margin, the other obvious
//     choice, gives near dead-beat gains whose sets are up to 6× wider than CORA's on pedestrian4.)
//
// and the weights of the strip-based observers with fixed weights (PRad-B: all strips at once,
// PRad-A: one strip at a time), Λ = P⁻¹Y:
//
//   PRad-B (Le, Stoica, Alamo, Camacho, Dumur, ISIC 2013, eq. 17; spec §2.7):
//     M(β) = [ βP                 0        0        ·  ]
//            [ 0                  E_wᵀE_w  0        ·  ]  ⪰ 0,  P ⪰ 0,  (1 − β) P / ε − τ I ⪰ 0,  τ ≥ 0,
//            [ 0                  0        F_vᵀF_v  ·  ]  maximise τ,
//            [ (P − YC)A  (P − YC)E_w  YF_v     P  ]
//     ε = ‖rs|E|‖₂ + σᵀσ (the Euclidean norm of W's interval radius, not squared, as CORA), β by
//     the same bisection as PRad-E (the last feasible solve kept);
//   PRad-A (Le et al., Automatica 2013, single output): the PRad-B design for each output i alone
//     (C ← C_i, F_v ← σ_i, ε with σ_i²); column i of the result is λ_i.
//
// PRad-C and PRad-D: CORA's SDPs are unbounded / infeasible as coded (spec §2.8, §2.9); setbound
// solves the conditions of the papers with a bounded size criterion. E_w, F_v are here the
// non-zero columns of E, F themselves (the unit-box coordinates), e = x − x̂ the error, and the
// LMI (strip_weight_lmi in impl/designs.ipp)
//     [[sP, 0, 0, ·], [0, D_w, 0, ·], [0, 0, D_v, ·], [(P − YC)A, (P − YC)E_w, YF_v, P]] ⪰ 0
// says ‖(I − ΛC)(Ae + E_w w) − ΛF_v v‖²_P ≤ s‖e‖²_P + wᵀD_w w + vᵀD_v v. Applied to the
// generators of the estimate, its P-radius R obeys R²_{k+1} ≤ s R²_k + (bound of the last two terms
// on the unit box), so the estimate's P-radius tends to at most that bound over 1 − s and, with
// P ⪰ τI, its Euclidean radius to at most √(bound / ((1 − s) τ)).
//   PRad-C (Wang, Alamo, Puig, Cembrano, CDC 2018, eq. 18 with T = I, N = 0; spec §2.8):
//     D_w = Γ, D_v = Ω diagonal variables (wᵀΓw ≤ trace Γ on the box). CORA maximises trace P
//     over a cone (every constraint homogeneous: unbounded). setbound adds the budget
//     trace Γ + trace Ω ≤ 1 − s, which makes the unit P-ball invariant (R ≤ 1 ⇒ R⁺ ≤ 1), and
//     maximises τ with P ⪰ τI: the weight of least certified asymptotic radius 1/√τ.
//   PRad-D (Wang, Wang, Puig, Cembrano, IEEE TAC 2019, eq. 33 with T = I, N = 0; spec §2.9):
//     D_w = (1 − s)β I, D_v = (1 − s)(1 − β) I with β = 1/2 as CORA, i.e.
//     ‖e⁺‖²_P ≤ s‖e‖²_P + (1 − s)(β‖w‖² + (1 − β)‖v‖²), so R² tends to at most
//     β n_w + (1 − β) n_v. CORA's second condition (eq. 20 as coded, [[I, γP], [γP, P]] ⪯ 0)
//     can never hold (its (1,1) block is I); setbound maximises τ with P ⪰ τI in its place (the
//     same radius criterion as PRad-C; the asymptotic radius is √((β n_w + (1 − β) n_v)/τ)).
//     CORA fixes s (its α) = 1/2, which is infeasible whenever the error cannot contract by √½
//     per step; setbound chooses it.
//   Both: s ∈ (0, 1) by a scalar search of the largest τ (lmi/scalar_search.hpp), not CORA's
//   bisection on feasibility, which ends where τ vanishes (papers.md §0.4). ZonotopicGainDesign::beta
//   is s, ::objective is τ.
#pragma once

#include <Eigen/Core>
#include <string>

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/lmi/solver.hpp"

namespace setbound {

/// An offline observer gain and its certificate.
struct ZonotopicGainDesign {
  Eigen::MatrixXd gain;  ///< n_x × n_y, L = P⁻¹Y
  Eigen::MatrixXd P, Y;  ///< the LMI variables at the solution
  double beta = 0.0;     ///< PRad-B/C/D/E: the contraction β (PRad-A: of the last output); Nom-G: μ = 1
  double objective = 0;  ///< PRad-E, Nom-G: trace P; PRad-A/B/C/D: τ (PRad-A: of the last output)
  Eigen::MatrixXd lmi;   ///< the design's main LMI matrix at the solution (⪰ 0 up to the solver's accuracy)
};

enum class ZonotopicGainMethod { PRadE = 1, NomG = 2, PRadB = 3, PRadA = 4, PRadC = 5, PRadD = 6 };

namespace detail {

/// The verdicts of a design's LMI solves: a design that found no solution says whether the LMI
/// was shown infeasible or the solver stopped undecided (its iteration or time limit, numerical
/// trouble) — "infeasible" only with a certificate for every solve.
struct SolveTally {
  int solved = 0, infeasible = 0, undecided = 0;
  lmi::SolveStatus last_undecided = lmi::SolveStatus::Optimal;
  std::string limit;  // the limit the last undecided solve stopped at, when it was one
  /// count(status), and which limit (time or iterations) a solve that stopped undecided reached.
  bool count(const lmi::SolveResult& r, const lmi::SolverOptions& o) {
    if (r.status == lmi::SolveStatus::MaxIterations) limit = limit_reached(r, o);
    return count(r.status);
  }
  /// "the time limit of 30 s" / "the iteration limit of 100" for a solve that stopped at one.
  static std::string limit_reached(const lmi::SolveResult& r, const lmi::SolverOptions& o) {
    if (r.solve_time >= o.time_limit || r.iterations < o.max_iterations) {
      std::string t = std::to_string(o.time_limit);
      t.erase(t.find_last_not_of('0') + 1);
      if (!t.empty() && t.back() == '.') t.pop_back();
      return "the time limit of " + t + " s per solve";
    }
    return "the iteration limit of " + std::to_string(o.max_iterations) + " per solve";
  }
  /// Records one solve; true when it gave a usable point (optimal or inaccurate).
  bool count(lmi::SolveStatus s) {
    if (s == lmi::SolveStatus::Optimal || s == lmi::SolveStatus::Inaccurate) return ++solved, true;
    if (s == lmi::SolveStatus::Infeasible) return ++infeasible, false;
    ++undecided;
    last_undecided = s;
    return false;
  }
  /// Why the last undecided solve stopped, and what to do about it (the parenthesis of the
  /// designs' NumericalError messages).
  std::string undecided_reason() const {
    return std::string(lmi::status_name(last_undecided)) + ": " +
           (last_undecided == lmi::SolveStatus::MaxIterations && !limit.empty()
                ? "it reached " + limit
                : std::string("the solver's iteration or time limit, or numerical trouble")) +
           "; the solver options of design_zonotopic_gain (max_iterations, time_limit) raise the limits";
  }
  /// Throws the error of a search over `what` (beta, the contraction) that found no solution.
  [[noreturn]] void fail(const std::string& who, const std::string& what) const {
    if (undecided == 0)
      throw InfeasibleError(who + ": the LMI is infeasible for every " + what + " in (0, 1)");
    throw NumericalError(who + ": no " + what + " in (0, 1) gave a solution: the LMI solver stopped undecided at " +
                         std::to_string(undecided) + " of " + std::to_string(undecided + infeasible) + " values (" +
                         undecided_reason() + ") and proved infeasibility at " + std::to_string(infeasible));
  }
};

}  // namespace detail

/// The PRad-A, PRad-B, PRad-C, PRad-D, PRad-E or Nom-G design (see designs.hpp). PRad-A returns
/// the P and Y of its last output. `solver`: the options of every LMI solve (the defaults stop a
/// solve after 100 iterations or 30 s; checked first: InvalidArgumentError for a bad value). Throws InfeasibleError with the reason when no gain exists (no β / μ feasible, every
/// solve with a certificate; unbounded trace P), NumericalError when no solve gave a solution
/// and some stopped undecided (iteration or time limit, numerical trouble: the message counts
/// them), DimensionError / InvalidArgumentError for an unsuitable system (an interval A).
ZonotopicGainDesign design_zonotopic_gain(const LinearSystem& sys, ZonotopicGainMethod method,
                                          const lmi::SolverOptions& solver = {});

}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/zonotopic/impl/designs.ipp"
#endif
