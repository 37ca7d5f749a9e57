// Compile-time proof of the flight build policy. Every fsw/ header includes this one
// (directly or through status.hpp), so a flight library built with exceptions, RTTI or
// FP contraction switched back on fails to compile rather than quietly changing.
#pragma once

#if defined(VTM_FLIGHT_CODE)
#  if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
#    error "flight code must be built with -fno-exceptions (docs/flight-rules.md)"
#  endif
#  if defined(__GXX_RTTI) || defined(__cpp_rtti)
#    error "flight code must be built with -fno-rtti (docs/flight-rules.md)"
#  endif
#  if defined(__FAST_MATH__)
#    error "flight code must not be built with -ffast-math (docs/flight-rules.md)"
#  endif
#  if !defined(EIGEN_DONT_VECTORIZE) || !defined(EIGEN_NO_MALLOC)
#    error "flight code needs EIGEN_DONT_VECTORIZE and EIGEN_NO_MALLOC (docs/flight-rules.md)"
#  endif
#endif
