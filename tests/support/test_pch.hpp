// The test executables' precompiled header (tests/CMakeLists.txt, vtm_add_test): what
// nearly every test file includes, parsed once per build instead of once per file.
// GoogleTest and Eigen are about 3 s of parsing in each of some 190 test files, 40 % of a
// test file's compile time (docs/build.md "CI time"). A file that must see Eigen
// configured otherwise (no_heap_guard_test.cpp and bundle_dense_test.cpp undefine
// EIGEN_NO_MALLOC) is compiled without it (ALONE in vtm_add_test, which configure enforces).
// Nothing here may depend on a test's own macros.
#pragma once

#include "vtm/core/eigen.hpp"  // first: it configures Eigen's assertions

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>
