# Cross toolchain: 32-bit ARM hard-float, Cortex-A9 class
# Debian packages: g++-arm-linux-gnueabihf, qemu-user. Tests run under qemu-user through CMAKE_CROSSCOMPILING_EMULATOR;
# executables are linked statically so qemu needs no sysroot prefix.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-linux-gnueabihf-gcc)
set(CMAKE_CXX_COMPILER arm-linux-gnueabihf-g++)
set(CMAKE_C_FLAGS_INIT "-mcpu=cortex-a9 -mfpu=vfpv3-d16 -mfloat-abi=hard")
set(CMAKE_CXX_FLAGS_INIT "-mcpu=cortex-a9 -mfpu=vfpv3-d16 -mfloat-abi=hard")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-mcpu=cortex-a9 -mfpu=vfpv3-d16 -mfloat-abi=hard -static")
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-arm)
set(VTM_TARGET_NAME armhf CACHE STRING "Target name" FORCE)
# Target libraries and headers come from the cross sysroot only; Eigen is header-only
# and target-independent, so the host's copy is used.
set(CMAKE_FIND_ROOT_PATH /usr/arm-linux-gnueabihf)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Host Eigen (header-only)")
