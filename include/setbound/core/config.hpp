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

/// Hot loops compiled twice where the compiler can dispatch at run time (GCC >= 12 / Clang >= 14,
/// x86-64 Linux: ifunc): for AVX2 and for the baseline, so the library stays runnable on any
/// x86-64 and uses 4-wide vectors where the CPU has them. Without FMA on purpose: GCC contracts
/// a * b + c into an FMA whenever the target has one (even in ISO C++ mode), which would make the
/// results depend on the CPU; with AVX2 alone both clones do the same operations, bit for bit.
/// Define SETBOUND_NO_KERNEL_CLONES to disable (SETBOUND_HAS_KERNEL_CLONES: also the LMI kernels'
/// clones, lmi/kernels.hpp).
#if defined(__x86_64__) && defined(__linux__) && !defined(SETBOUND_NO_KERNEL_CLONES) && \
    ((defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12) || (defined(__clang__) && __clang_major__ >= 14))
#define SETBOUND_HAS_KERNEL_CLONES 1
#else
#define SETBOUND_HAS_KERNEL_CLONES 0
#endif
#if SETBOUND_HAS_KERNEL_CLONES
#define SETBOUND_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SETBOUND_AVX2_CLONES
#endif
