# Compiler policy for flight code (fsw/ and hal/ interfaces). docs/flight-rules.md maps
# each flag to the rule it enforces.
#
#  - all warnings on and fatal, implicit conversions and old-style casts included;
#  - no exceptions, no RTTI (checked again at compile time by vtm/core/platform.hpp);
#  - IEEE arithmetic exactly as written: no contraction into FMA, no fast-math, Eigen
#    without explicit SIMD, so that results are bit-identical on every target;
#  - Eigen may not touch the heap, and its assertions go to VTM_ASSERT;
#  - -fstack-usage and -fcallgraph-info=su feed the stack budget (tools/budget);
#  - on x86-64, -maccumulate-outgoing-args: arguments beyond the six integer registers
#    go into space reserved in the caller's frame, as on every other target, instead of
#    being pushed (GCC reports a pushing frame as "dynamic,bounded", which the budget
#    rejects for flight code).
#  - with VTM_VECTORISER_DUMPS, GCC's vectoriser report beside each object (vector_guard).
add_library(vtm_flight_policy INTERFACE)
target_compile_options(vtm_flight_policy INTERFACE
  -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow -Wold-style-cast -Wcast-qual
  -Wnon-virtual-dtor -Woverloaded-virtual -Wdouble-promotion -Wnull-dereference
  -Wimplicit-fallthrough -Werror
  -fno-exceptions -fno-rtti
  -ffp-contract=off -fno-fast-math
  $<$<CXX_COMPILER_ID:GNU>:-fstack-usage>
  $<$<CXX_COMPILER_ID:GNU>:-fcallgraph-info=su>
  $<$<AND:$<CXX_COMPILER_ID:GNU>,$<STREQUAL:${CMAKE_SYSTEM_PROCESSOR},x86_64>>:-maccumulate-outgoing-args>
  $<$<AND:$<CXX_COMPILER_ID:GNU>,$<BOOL:${VTM_VECTORISER_DUMPS}>>:-fdump-tree-vect-details>
  ${VTM_FLIGHT_CPU_FLAGS})  # CPU flags for flight code only (set by a toolchain file)
target_compile_definitions(vtm_flight_policy INTERFACE
  EIGEN_DONT_VECTORIZE EIGEN_NO_MALLOC EIGEN_MAX_STATIC_ALIGN_BYTES=0
  VTM_FLIGHT_CODE=1)

# Ground and test code: same determinism flags (tests compare bits with flight code),
# warnings on, exceptions allowed (GoogleTest, OpenCV).
add_library(vtm_ground_policy INTERFACE)
target_compile_options(vtm_ground_policy INTERFACE
  -Wall -Wextra -Werror -ffp-contract=off -fno-fast-math)
target_compile_definitions(vtm_ground_policy INTERFACE EIGEN_DONT_VECTORIZE)

# vtm_flight_library(NAME SOURCES...): one static library per fsw/ module.
function(vtm_flight_library name)
  add_library(${name} STATIC ${ARGN})
  target_link_libraries(${name} PUBLIC vtm_flight_policy_public PRIVATE vtm_flight_policy)
  set_property(GLOBAL APPEND PROPERTY VTM_FLIGHT_LIBRARIES ${name})
endfunction()

# Definitions every user of a flight library must share with it (ODR: Eigen's
# configuration must be identical on both sides of a flight interface).
add_library(vtm_flight_policy_public INTERFACE)
target_compile_definitions(vtm_flight_policy_public INTERFACE
  EIGEN_DONT_VECTORIZE EIGEN_NO_MALLOC EIGEN_MAX_STATIC_ALIGN_BYTES=0)
target_link_libraries(vtm_flight_policy_public INTERFACE Eigen3::Eigen)
