# Cross toolchain: riscv64 (rv64gc), RISC-V HPSC class.
# Debian packages: g++-riscv64-linux-gnu, qemu-user.
set(VTM_CROSS_TARGET riscv64)
set(VTM_CROSS_TRIPLE riscv64-linux-gnu)
set(VTM_CROSS_FLAGS "-march=rv64gc -mabi=lp64d")
set(VTM_CROSS_PROCESSOR riscv64)
set(VTM_CROSS_EMULATOR qemu-riscv64)
include(${CMAKE_CURRENT_LIST_DIR}/linux-cross.cmake)
