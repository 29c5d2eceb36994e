// setbound — the out-of-line definitions of the C++ API (zonotopic estimators), compiled once into
// libsetbound (SETBOUND_SEPARATE_COMPILATION, see include/setbound/core/config.hpp). Each .ipp
// is included by exactly one of the cpp/definitions_*.cpp files; they are balanced for build time.
#include "setbound/estimators/impl/measurement_check.ipp"
#include "setbound/estimators/zonotopic/impl/gain_estimator.ipp"
#include "setbound/estimators/zonotopic/impl/pradius.ipp"
#include "setbound/estimators/zonotopic/impl/volume_min.ipp"
#include "setbound/estimators/polytopic/impl/exact_hull.ipp"
#include "setbound/estimators/constrained_zonotopic/impl/estimator.ipp"
#include "setbound/estimators/zonotopic/impl/observer.ipp"
#include "setbound/estimators/zonotopic/impl/strip_swap.ipp"
#include "setbound/estimators/zonotopic/impl/designs.ipp"
