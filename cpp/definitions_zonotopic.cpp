// setbound — the out-of-line definitions of the C++ API (zonotopic estimators), compiled once into
// libsetbound (SETBOUND_SEPARATE_COMPILATION, see include/setbound/core/config.hpp). Each .ipp
// is included by exactly one of the cpp/definitions_*.cpp files; they are balanced for build time.
#include "setbound/estimators/impl/measurement_check.ipp"
#include "setbound/estimators/impl/zonotopic.ipp"
#include "setbound/estimators/impl/pradius.ipp"
#include "setbound/estimators/impl/volume_min.ipp"
#include "setbound/estimators/impl/exact_hull.ipp"
#include "setbound/estimators/impl/constrained_zonotopic.ipp"
#include "setbound/estimators/zonotopic/impl/observer.ipp"
#include "setbound/estimators/zonotopic/impl/designs.ipp"
