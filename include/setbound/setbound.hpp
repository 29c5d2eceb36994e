// setbound — umbrella header of the C++ API (header-heavy, on Eigen).
//
// C++ users include this and link setbound::setbound; it also declares the C ABI
// (setbound.h) inside extern "C".
#pragma once

// setbound.h holds struct definitions and no include guard (cffi reads it as plain
// declarations), so it may enter a translation unit only once: the library's own C ABI helpers
// (cpp/c_api_common.hpp) include it too and define SETBOUND_C_API_DECLARED.
#ifndef SETBOUND_C_API_DECLARED
#define SETBOUND_C_API_DECLARED
extern "C" {
#include "setbound/setbound.h"
}
#endif

#include "setbound/core/error.hpp"
#include "setbound/core/linear_system.hpp"
#include "setbound/core/validate.hpp"
#include "setbound/sets/box.hpp"
#include "setbound/sets/ellipsoid.hpp"
#include "setbound/sets/interval.hpp"
#include "setbound/sets/inclusion.hpp"
#include "setbound/sets/interval_matrix.hpp"
#include "setbound/sets/polytope.hpp"
#include "setbound/sets/strip.hpp"
#include "setbound/sets/zonotope.hpp"
#include "setbound/estimators/ellipsoidal/descriptor.hpp"
#include "setbound/estimators/ellipsoidal/lmi_estimators.hpp"
#include "setbound/estimators/ellipsoidal/bounding_ellipsoid.hpp"
#include "setbound/estimators/interval/cora_interval_observer.hpp"
#include "setbound/estimators/polytopic/exact_hull.hpp"
#include "setbound/estimators/ellipsoidal/improved_correction.hpp"
#include "setbound/estimators/ellipsoidal/improved_estimator.hpp"
#include "setbound/estimators/point/kalman.hpp"
#include "setbound/estimators/measurement_check.hpp"
#include "setbound/estimators/zonotopic/pradius.hpp"
#include "setbound/estimators/zonotopic/volume_min.hpp"
#include "setbound/estimators/zonotopic/gain_estimator.hpp"
#include "setbound/estimators/zonotopic/observer.hpp"
#include "setbound/thesis/interval_observer.hpp"
#include "setbound/lmi/classes.hpp"
#include "setbound/lmi/lp.hpp"
#include "setbound/lmi/model.hpp"
#include "setbound/lmi/problem.hpp"
#include "setbound/lmi/scalar_search.hpp"
#include "setbound/lmi/solver.hpp"
#include "setbound/thesis/hinf_gain.hpp"
#include "setbound/thesis/eso_d.hpp"
#include "setbound/thesis/hinf_observer.hpp"
#include "setbound/thesis/lpv.hpp"
#include "setbound/thesis/plant.hpp"
#include "setbound/thesis/reading_screen.hpp"
#include "setbound/thesis/invariant.hpp"
