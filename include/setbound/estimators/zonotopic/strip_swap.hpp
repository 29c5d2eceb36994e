// setbound — the rounding terms shared by the two one-strip updates that replace a generator
// column: the zonotopic observer's Bravo strips (observer.hpp, bravo_update: VolMin-B, Bravo 2006
// Property 1) and ROPO's Vicino–Zappa step (parallelotope.hpp, strip_swap). Both take the strip
// update x' = x + λ(y − cᵀx) of p ⊕ G B ⊕ box(r), every column g_i ← g_i − λ cᵀg_i, and give the
// replaced column's place to σλ, with the bounds of the observer's strip_update for one strip.
//
// Only the terms both compute with the same operations in the same order live here, so that
// each estimator's results stay what they were bit for bit. The rest is the callers' on purpose:
// the box carried by K = I − λcᵀ is bounded by (1 + g)(I + |λ||c|ᵀ) r in the observer (O(n) per
// strip: the hot path) and by (|K̃| + dK) r with the computed n × n K̃ in ROPO (tighter: with
// the observer's whole box, ROPO's boxes grew up to 2 000× on tank30 and its sets changed), and
// the two add the new column's and the replaced column's terms in different orders.
#pragma once

#include <Eigen/Core>

namespace setbound {
namespace detail {

/// The new centre pn = p + λ(y − cᵀp) of the update above, and its rounding terms added to
/// `box` (which holds the caller's term for the old box): the centre's
/// 2g (|p| + |λ|(|y| + |c|ᵀ|p|) + |pn|) and the generators' 2g (w + |λ| |c|ᵀw) by rows
/// (w >= rs|G| before the update). g = γ(n + 5) (rounding_bounds::gamma: strip_update's
/// γ(n + q + 4) with q = 1), abs_lam = |λ|. pn and abs_p (left = |p|) are buffers: no allocation
/// once they have length n (the observer runs this per strip).
void strip_swap_terms(const Eigen::VectorXd& p, const Eigen::VectorXd& lam, const Eigen::VectorXd& abs_lam,
                      const Eigen::Ref<const Eigen::VectorXd>& c, double y, const Eigen::VectorXd& w, double g,
                      Eigen::VectorXd& pn, Eigen::VectorXd& abs_p, Eigen::VectorXd& box);

}  // namespace detail
}  // namespace setbound

// The definitions: inline here, or compiled once into libsetbound (core/config.hpp).
#if !defined(SETBOUND_SEPARATE_COMPILATION)
#include "setbound/estimators/zonotopic/impl/strip_swap.ipp"
#endif
