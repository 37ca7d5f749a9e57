# Cross toolchain: 32-bit ARM hard-float, Cortex-A9 class.
# Debian packages: g++-arm-linux-gnueabihf, qemu-user.
set(VTM_CROSS_TARGET armhf)
set(VTM_CROSS_TRIPLE arm-linux-gnueabihf)
set(VTM_CROSS_FLAGS "-mcpu=cortex-a9 -mfpu=vfpv3-d16 -mfloat-abi=hard")
set(VTM_CROSS_PROCESSOR arm)
set(VTM_CROSS_EMULATOR qemu-arm)
include(${CMAKE_CURRENT_LIST_DIR}/linux-cross.cmake)
