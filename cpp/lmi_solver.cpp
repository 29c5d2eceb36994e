// setbound — the interior-point solver's member functions, compiled once for the library and
// its tests (see the note above InteriorPointSolver::setup in lmi/solver.hpp).
#undef SETBOUND_LMI_EXTERN_SOLVER
#define SETBOUND_LMI_SOLVER_INLINE
#include "setbound/lmi/solver.hpp"
