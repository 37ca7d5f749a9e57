# Cross toolchain: PowerPC 750, RAD750 class, big-endian.
# Debian packages: g++-powerpc-linux-gnu, qemu-user.
set(VTM_CROSS_TARGET ppc750)
set(VTM_CROSS_TRIPLE powerpc-linux-gnu)
set(VTM_CROSS_FLAGS "-mcpu=750")
set(VTM_CROSS_PROCESSOR powerpc)
set(VTM_CROSS_EMULATOR qemu-ppc)
include(${CMAKE_CURRENT_LIST_DIR}/linux-cross.cmake)
# qemu 7.2 raises SIGILL on the POWER9-only mffscrn/mffscrni that glibc's libm uses in
# sin/cos/atan2 (tests compare against them). A real 750 executes these encodings as
# plain mffs; tools/scripts/ppc_patch_mffscrn.py rewrites them so after linking.
set(VTM_POST_LINK_PATCH ${CMAKE_CURRENT_LIST_DIR}/../scripts/ppc_patch_mffscrn.py)
