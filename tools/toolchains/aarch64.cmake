# Cross toolchain: aarch64, Cortex-A53 class (HPSC-like application cores).
# Debian packages: g++-aarch64-linux-gnu, qemu-user.
set(VTM_CROSS_TARGET aarch64)
set(VTM_CROSS_TRIPLE aarch64-linux-gnu)
set(VTM_CROSS_FLAGS "-mcpu=cortex-a53")
set(VTM_CROSS_PROCESSOR aarch64)
set(VTM_CROSS_EMULATOR qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/linux-cross.cmake)
