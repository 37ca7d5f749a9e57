# Cross toolchain: riscv64 (rv64gc), RISC-V HPSC class
# Debian packages: g++-riscv64-linux-gnu, qemu-user. Tests run under qemu-user through CMAKE_CROSSCOMPILING_EMULATOR;
# executables are linked statically so qemu needs no sysroot prefix.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR riscv64)
set(CMAKE_C_COMPILER riscv64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER riscv64-linux-gnu-g++)
set(CMAKE_C_FLAGS_INIT "-march=rv64gc -mabi=lp64d")
set(CMAKE_CXX_FLAGS_INIT "-march=rv64gc -mabi=lp64d")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-march=rv64gc -mabi=lp64d -static")
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-riscv64)
set(VTM_TARGET_NAME riscv64 CACHE STRING "Target name" FORCE)
# Target libraries and headers come from the cross sysroot only; Eigen is header-only
# and target-independent, so the host's copy is used.
set(CMAKE_FIND_ROOT_PATH /usr/riscv64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Host Eigen (header-only)")
