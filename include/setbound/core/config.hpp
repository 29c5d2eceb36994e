// setbound — how the C++ API is compiled: header-only, or against the compiled library.
//
// Every header declares its classes and functions; the bodies of everything that is not a
// template or a one-line accessor live next to it in impl/<header>.ipp. Two ways to use them:
//
// * Header-only (the default, CMake target setbound::headers): each header includes its .ipp
//   at the end and the definitions are `inline`. Nothing to link but Eigen, NLopt and Qhull;
//   every translation unit instantiates the Eigen code of the bodies it sees, which costs
//   about six minutes of compile time for the umbrella header <setbound/setbound.hpp>.
// * Compiled (define SETBOUND_SEPARATE_COMPILATION; CMake target setbound::setbound defines it
//   for you): the headers stop at the declarations and the definitions come from libsetbound,
//   where cpp/definitions_*.cpp compile every .ipp exactly once. A program that includes one
//   estimator header then compiles in seconds (figures in docs/cpp_usage.md).
//
// Use one way for a whole program: mixing them is an ODR violation.
#pragma once

#if defined(SETBOUND_SEPARATE_COMPILATION)
#define SETBOUND_INLINE
#else
#define SETBOUND_INLINE inline
#endif
