# Install rules and the exported CMake package `vtm` (docs/install.md).
#
# `cmake --install <build dir> --prefix <dir>` installs, for the build's target:
#   lib/libvtm_<module>.a                 every flight library (the flight-library manifest)
#                                         and the simulated world under hal/sim (sim/)
#   include/...                           their public headers, as the tree has them
#   lib/cmake/vtm/vtmConfig.cmake         find_package(vtm): one imported target per module,
#   lib/cmake/vtm/vtmTargets*.cmake       vtm::<module> (vtm::core, vtm::stereo, vtm::app,
#   lib/cmake/vtm/vtmConfigVersion.cmake  vtm::hal_file, ...), each with its dependencies
#
# The module CMakeLists keep naming their include directory once (a source path); here
# each exported target's interface is split into that path for the build tree and
# include/ for the installed tree, so no module repeats the install layout.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

get_property(vtm_install_flight GLOBAL PROPERTY VTM_FLIGHT_LIBRARIES)
# hal/sim (the simulated camera driver) links the simulated world; it is installed with it.
set(vtm_install_targets ${vtm_install_flight} vtm_sim_terrain vtm_sim_render vtm_sim_scenario
    vtm_flight_policy_public vtm_flight_policy)

set(vtm_install_include_dirs "")
foreach(lib IN LISTS vtm_install_targets)
  string(REGEX REPLACE "^vtm_" "" export_name ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${export_name})
  get_target_property(dirs ${lib} INTERFACE_INCLUDE_DIRECTORIES)
  if(NOT dirs)
    continue()
  endif()
  set(split "")
  foreach(dir IN LISTS dirs)
    list(APPEND split "$<BUILD_INTERFACE:${dir}>")
    list(APPEND vtm_install_include_dirs ${dir})
  endforeach()
  list(APPEND split "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>")
  set_target_properties(${lib} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${split}")
endforeach()
list(REMOVE_DUPLICATES vtm_install_include_dirs)

# A consumer's own translation units inline our headers' arithmetic (Eigen, templates):
# they get the determinism flags the flight code is built with, so that the same call
# gives the same bits in their build as in ours (docs/flight-rules.md).
target_compile_options(vtm_flight_policy_public INTERFACE
  $<INSTALL_INTERFACE:$<$<COMPILE_LANG_AND_ID:CXX,GNU,Clang>:-ffp-contract=off;-fno-fast-math>>)

install(TARGETS ${vtm_install_targets} EXPORT vtmTargets COMPONENT vtm
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(dir IN LISTS vtm_install_include_dirs)
  install(DIRECTORY ${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT vtm
          FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")
endforeach()

set(vtm_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/vtm)
install(EXPORT vtmTargets NAMESPACE vtm:: DESTINATION ${vtm_cmake_dir} COMPONENT vtm)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/vtmConfig.cmake.in
  ${CMAKE_BINARY_DIR}/vtmConfig.cmake INSTALL_DESTINATION ${vtm_cmake_dir})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/vtmConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/vtmConfig.cmake ${CMAKE_BINARY_DIR}/vtmConfigVersion.cmake
        DESTINATION ${vtm_cmake_dir} COMPONENT vtm)
