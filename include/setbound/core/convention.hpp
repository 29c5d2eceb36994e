#pragma once
// Which behaviour an estimator of CORA's catalogue follows (issue 22, spec cora_observers.md §1.3).
// One enum for every family, so that the C ABI has one pair of constants (SB_CONVENTION_*).

namespace setbound {

/// `Setbound`: the papers' algorithm, guaranteed after rounding (the default everywhere).
/// `Cora`: CORA's behaviour where it differs from the papers (to reproduce CORA's saved numbers).
/// The values are the C ABI's.
enum class Convention { Setbound = 0, Cora = 1 };

}  // namespace setbound
