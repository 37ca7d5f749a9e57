# Ground-side checks as build targets and tests. Include from the top-level CMakeLists.txt
# AFTER every flight library is declared (after add_subdirectory(fsw) / (hal)) and after
# enable_testing():
#     include(${CMAKE_CURRENT_SOURCE_DIR}/tools/checks/VtmChecks.cmake)
# Targets:  vtm_budget (Markdown table + budget.json in the build directory),
#           vtm_policy (include rules + forbidden symbols of this target's libraries).
# Tests:    policy.sources, policy.binaries, budget.stack (recursion / dynamic frames),
#           policy.selftest (the include rules on small trees, tools/checks/policy_test.py).
# docs/budgets.md, docs/static-analysis.md.
# The plain interpreter path, not the imported Python3::Interpreter target: ctest would
# run an imported executable through CMAKE_CROSSCOMPILING_EMULATOR in cross builds.
find_package(Python3 COMPONENTS Interpreter REQUIRED)
get_property(_vtm_flight_libs GLOBAL PROPERTY VTM_FLIGHT_LIBRARIES)

# vtm_budget.py and policy.py read ${CMAKE_BINARY_DIR}/vtm_flight_libraries.txt (written by
# the top-level CMakeLists.txt) and fall back to discovering libvtm_*.a with .su files.

set(_vtm_budget ${CMAKE_CURRENT_LIST_DIR}/../budget/vtm_budget.py)
set(_vtm_policy ${CMAKE_CURRENT_LIST_DIR}/policy.py)

add_custom_target(vtm_budget
  COMMAND ${Python3_EXECUTABLE} ${_vtm_budget} --json ${CMAKE_BINARY_DIR}/budget.json ${CMAKE_BINARY_DIR}
  DEPENDS ${_vtm_flight_libs}
  WORKING_DIRECTORY ${CMAKE_BINARY_DIR}
  COMMENT "Static memory and worst-case stack of the flight libraries (${VTM_TARGET_NAME})"
  VERBATIM)
add_custom_target(vtm_policy
  COMMAND ${Python3_EXECUTABLE} ${_vtm_policy} all ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR}
  DEPENDS ${_vtm_flight_libs}
  COMMENT "Include rules and forbidden symbols (${VTM_TARGET_NAME})"
  VERBATIM)

if(VTM_BUILD_TESTS)
  add_test(NAME policy.sources COMMAND ${Python3_EXECUTABLE} ${_vtm_policy} sources ${CMAKE_SOURCE_DIR})
  add_test(NAME policy.binaries COMMAND ${Python3_EXECUTABLE} ${_vtm_policy} binaries ${CMAKE_BINARY_DIR})
  add_test(NAME budget.stack COMMAND ${Python3_EXECUTABLE} ${_vtm_budget} --top 0 ${CMAKE_BINARY_DIR})
  add_test(NAME policy.selftest COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_LIST_DIR}/policy_test.py)
  # The tests read the archives: run them after the libraries are built (ctest after build).
  set_tests_properties(policy.sources policy.binaries policy.selftest budget.stack PROPERTIES LABELS "checks")
endif()
