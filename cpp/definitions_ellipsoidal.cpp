// setbound — the out-of-line definitions of the C++ API (ellipsoidal estimators), compiled once into
// libsetbound (SETBOUND_SEPARATE_COMPILATION, see include/setbound/core/config.hpp). Each .ipp
// is included by exactly one of the cpp/definitions_*.cpp files; they are balanced for build time.
#include "setbound/estimators/ellipsoidal/impl/common.ipp"
#include "setbound/estimators/ellipsoidal/impl/lmi_estimators.ipp"
#include "setbound/estimators/ellipsoidal/impl/descriptor.ipp"
#include "setbound/estimators/ellipsoidal/impl/improved_correction.ipp"
#include "setbound/estimators/ellipsoidal/impl/improved_estimator.ipp"
#include "setbound/estimators/point/impl/kalman.ipp"
#include "setbound/estimators/ellipsoidal/impl/bounding_ellipsoid.ipp"
