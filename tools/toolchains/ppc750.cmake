# Cross toolchain: PowerPC 750, RAD750 class, big-endian
# Debian packages: g++-powerpc-linux-gnu, qemu-user. Tests run under qemu-user through CMAKE_CROSSCOMPILING_EMULATOR;
# executables are linked statically so qemu needs no sysroot prefix.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR powerpc)
set(CMAKE_C_COMPILER powerpc-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER powerpc-linux-gnu-g++)
set(CMAKE_C_FLAGS_INIT "-mcpu=750")
set(CMAKE_CXX_FLAGS_INIT "-mcpu=750")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-mcpu=750 -static")
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-ppc)
set(VTM_TARGET_NAME ppc750 CACHE STRING "Target name" FORCE)
# Target libraries and headers come from the cross sysroot only; Eigen is header-only
# and target-independent, so the host's copy is used.
set(CMAKE_FIND_ROOT_PATH /usr/powerpc-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(Eigen3_DIR /usr/share/eigen3/cmake CACHE PATH "Host Eigen (header-only)")
# qemu 7.2 raises SIGILL on the POWER9-only mffscrn/mffscrni that glibc's libm uses in
# sin/cos/atan2 (tests compare against them). A real 750 executes these encodings as
# plain mffs; tools/scripts/ppc_patch_mffscrn.py rewrites them so after linking.
set(VTM_POST_LINK_PATCH ${CMAKE_CURRENT_LIST_DIR}/../scripts/ppc_patch_mffscrn.py)
