/*
 * Guest program for tools/qemu/selftest.sh: runs a loop of a known number of
 * instructions N times (N from argv[1]). The loop body lies between the global labels
 * counted_loop_begin and counted_loop_end, so the script can count its instructions
 * in the disassembly (K) and check that the plugin's counts for N = 1000 and N = 2000
 * differ by exactly 1000 * K.
 */
#include <stdlib.h>

int main(int argc, char **argv) {
    unsigned long n = argc > 1 ? strtoul(argv[1], NULL, 10) : 1;
    unsigned long acc = 0;
#if defined(__powerpc__)
    __asm__ volatile(
        "mtctr %1\n"
        ".globl counted_loop_begin\n"
        "counted_loop_begin:\n"
        "addi %0, %0, 3\n"
        "xori %0, %0, 5\n"
        "rlwinm %0, %0, 1, 0, 30\n"
        "bdnz counted_loop_begin\n"
        ".globl counted_loop_end\n"
        "counted_loop_end:\n"
        : "+r"(acc)
        : "r"(n)
        : "ctr");
#else
#error "counted_loop.c: PowerPC guest only"
#endif
    return (int)(acc & 1U);
}
