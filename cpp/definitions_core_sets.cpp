// setbound — the out-of-line definitions of the C++ API (core and sets), compiled once into
// libsetbound (SETBOUND_SEPARATE_COMPILATION, see include/setbound/core/config.hpp). Each .ipp
// is included by exactly one of the cpp/definitions_*.cpp files; they are balanced for build time.
#include "setbound/core/impl/error.ipp"
#include "setbound/core/impl/validate.ipp"
#include "setbound/core/impl/state.ipp"
#include "setbound/core/impl/linear_system.ipp"
#include "setbound/sets/impl/interval.ipp"
#include "setbound/sets/impl/interval_matrix.ipp"
#include "setbound/sets/impl/box.ipp"
#include "setbound/sets/impl/inclusion.ipp"
#include "setbound/sets/impl/ellipsoid.ipp"
#include "setbound/sets/impl/strip.ipp"
#include "setbound/sets/impl/zonotope_reduction.ipp"
#include "setbound/sets/impl/zonotope.ipp"
#include "setbound/sets/impl/box_lp.ipp"
#include "setbound/sets/impl/constrained_zonotope.ipp"
#include "setbound/sets/impl/polytope.ipp"
#include "setbound/sets/impl/polygon_projection.ipp"
