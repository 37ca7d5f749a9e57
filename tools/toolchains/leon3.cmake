# Cross toolchain: SPARC LEON3 (V8, 32-bit, big-endian); glibc from the sparc64 multilib is V8+, our own code is LEON3
# Debian packages: g++-sparc64-linux-gnu, g++-12-multilib-sparc64-linux-gnu, qemu-user. Tests run under qemu-user through CMAKE_CROSSCOMPILING_EMULATOR;
# executables are linked statically so qemu needs no sysroot prefix.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR sparc)
set(CMAKE_C_COMPILER sparc64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER sparc64-linux-gnu-g++)
set(CMAKE_C_FLAGS_INIT "-m32")
set(CMAKE_CXX_FLAGS_INIT "-m32")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-m32 -static")
# Flight libraries (vtm_flight_library, the determinism suite) are LEON3 code. The test
# harness (GoogleTest, test bodies) keeps the multilib's default V8+ code: with
# -mcpu=leon3, GCC emits atomics as `casa` with ASI 0x0A (LEON's user data space), which
# qemu-sparc32plus, emulating a V9 CPU, traps as a privileged action (trap 0x37);
# GoogleTest's death tests use such atomics. Flight code uses no atomics.
set(VTM_FLIGHT_CPU_FLAGS -mcpu=leon3)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-sparc32plus)
set(VTM_TARGET_NAME leon3 CACHE STRING "Target name" FORCE)
# Target libraries and headers come from the cross sysroot only; Eigen is header-only
# and target-independent, so the host's copy is used.
set(CMAKE_FIND_ROOT_PATH /usr/sparc64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Host Eigen (header-only)")
