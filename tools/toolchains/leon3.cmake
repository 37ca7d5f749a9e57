# Cross toolchain: SPARC LEON3 (V8, 32-bit, big-endian).
# Debian packages: g++-sparc64-linux-gnu, g++-12-multilib-sparc64-linux-gnu, qemu-user.
set(VTM_CROSS_TARGET leon3)
set(VTM_CROSS_TRIPLE sparc64-linux-gnu)
set(VTM_CROSS_FLAGS "-m32")
set(VTM_CROSS_PROCESSOR sparc)
set(VTM_CROSS_EMULATOR qemu-sparc32plus)
include(${CMAKE_CURRENT_LIST_DIR}/linux-cross.cmake)
# Flight libraries (vtm_flight_library, the determinism suite) are LEON3 code. The test
# harness (GoogleTest, test bodies) keeps the multilib's default V8+ code: with
# -mcpu=leon3, GCC emits atomics as `casa` with ASI 0x0A (LEON's user data space), which
# qemu-sparc32plus, emulating a V9 CPU, traps as a privileged action (trap 0x37);
# GoogleTest's death tests use such atomics. Flight code uses no atomics.
set(VTM_FLIGHT_CPU_FLAGS -mcpu=leon3)
