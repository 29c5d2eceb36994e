// setbound — the out-of-line definitions of the C++ API (the thesis' observers and invariant sets), compiled once into
// libsetbound (SETBOUND_SEPARATE_COMPILATION, see include/setbound/core/config.hpp). Each .ipp
// is included by exactly one of the cpp/definitions_*.cpp files; they are balanced for build time.
#include "setbound/thesis/impl/plant.ipp"
#include "setbound/thesis/impl/reading_screen.ipp"
#include "setbound/thesis/impl/hinf_gain.ipp"
#include "setbound/thesis/impl/hinf_observer.ipp"
#include "setbound/thesis/impl/eso_d.ipp"
#include "setbound/thesis/impl/interval_observer.ipp"
#include "setbound/thesis/impl/invariant.ipp"
#include "setbound/thesis/impl/lpv.ipp"
#include "setbound/estimators/interval/impl/cora_interval_observer.ipp"
