// setbound — the out-of-line definitions of the C++ API (CORA's catalogue: ROPO's parallelotopes and
// the Rauch–Tung–Striebel smoother), compiled once into libsetbound (SETBOUND_SEPARATE_COMPILATION,
// see include/setbound/core/config.hpp). Each .ipp is included by exactly one of the
// cpp/definitions_*.cpp files.
#include "setbound/estimators/zonotopic/impl/parallelotope.ipp"
#include "setbound/estimators/point/impl/rts_smoother.ipp"
