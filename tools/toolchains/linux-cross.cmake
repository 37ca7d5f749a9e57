# Shared body of the cross toolchain files (tools/toolchains/<target>.cmake). Each sets
#   VTM_CROSS_TRIPLE      GNU triple of the Debian cross compiler (aarch64-linux-gnu, ...)
#   VTM_CROSS_PROCESSOR   CMAKE_SYSTEM_PROCESSOR
#   VTM_CROSS_FLAGS       code-generation flags for everything built
#   VTM_CROSS_EMULATOR    qemu-user binary that runs the tests
#   VTM_CROSS_TARGET      the target's name in reports (VTM_TARGET_NAME)
# and includes this file. Executables are linked statically, so qemu-user runs them
# without a sysroot prefix, as a flight image would be one static binary.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR ${VTM_CROSS_PROCESSOR})
set(CMAKE_C_COMPILER ${VTM_CROSS_TRIPLE}-gcc)
set(CMAKE_CXX_COMPILER ${VTM_CROSS_TRIPLE}-g++)
set(CMAKE_C_FLAGS_INIT "${VTM_CROSS_FLAGS}")
set(CMAKE_CXX_FLAGS_INIT "${VTM_CROSS_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${VTM_CROSS_FLAGS} -static")
set(CMAKE_CROSSCOMPILING_EMULATOR ${VTM_CROSS_EMULATOR})
set(VTM_TARGET_NAME ${VTM_CROSS_TARGET} CACHE STRING "Target name" FORCE)
# Target libraries and headers come from the cross sysroot only; Eigen is header-only
# and target-independent, so the host's copy is used.
set(CMAKE_FIND_ROOT_PATH /usr/${VTM_CROSS_TRIPLE})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Host Eigen (header-only)")
