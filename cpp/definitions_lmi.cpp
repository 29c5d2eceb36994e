// setbound — the out-of-line definitions of the C++ API (the LMI layer), compiled once into
// libsetbound (SETBOUND_SEPARATE_COMPILATION, see include/setbound/core/config.hpp). Each .ipp
// is included by exactly one of the cpp/definitions_*.cpp files; they are balanced for build time.
#include "setbound/lmi/impl/kernels.ipp"
#include "setbound/lmi/impl/classes.ipp"
#include "setbound/lmi/impl/model.ipp"
#include "setbound/lmi/impl/problem.ipp"
#include "setbound/lmi/impl/solver.ipp"
#include "setbound/lmi/impl/lp.ipp"
#include "setbound/lmi/impl/l1.ipp"
#include "setbound/lmi/impl/scalar_search.ipp"
