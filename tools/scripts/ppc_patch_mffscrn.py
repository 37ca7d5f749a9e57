#!/usr/bin/env python3
"""Rewrite POWER9-only mffscrn/mffscrni instructions in a 32-bit big-endian PowerPC
ELF executable into plain mffs, in place.

Why: glibc's powerpc libm (sin, cos, atan2, ...) uses mffscrn/mffscrni to save and set
the rounding mode; qemu 7.2 raises SIGILL on them under -cpu 750 semantics. A real
PowerPC 750 decodes these encodings as mffs (the extra fields are ignored), so the
rewrite reproduces what the flight processor does. Only test executables on the ppc750
target are patched (tools/toolchains/ppc750.cmake); flight code never calls libm
transcendentals (it uses vtm/core/math.hpp).

Encoding (Power ISA 3.0): primary opcode 63, extended opcode 583 in bits 21-30 (IBM
numbering); mffs has 0 in bits 11-15 and 16-20, mffscrn has 22 and mffscrni 23 in bits
11-15. We clear bits 11-20 of every such word in executable sections.
"""
import struct
import sys

SHF_EXECINSTR = 0x4
SHT_NOBITS = 8


def patch(path: str) -> int:
    with open(path, "rb") as f:
        data = bytearray(f.read())
    if data[:4] != b"\x7fELF" or data[4] != 1 or data[5] != 2:
        sys.exit(f"{path}: not a 32-bit big-endian ELF file")
    shoff, = struct.unpack_from(">I", data, 0x20)
    shentsize, shnum = struct.unpack_from(">HH", data, 0x2E)
    patched = 0
    for i in range(shnum):
        _name, typ, flags, _addr, off, size = struct.unpack_from(">IIIIII", data, shoff + i * shentsize)
        if not flags & SHF_EXECINSTR or typ == SHT_NOBITS:
            continue
        for p in range(off, off + size - 3, 4):
            w, = struct.unpack_from(">I", data, p)
            if (w >> 26) == 63 and ((w >> 1) & 0x3FF) == 583 and ((w >> 16) & 0x1F) != 0:
                struct.pack_into(">I", data, p, w & ~(0x3FF << 11))
                patched += 1
    if patched:
        with open(path, "wb") as f:
            f.write(data)
    return patched


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: ppc_patch_mffscrn.py EXECUTABLE")
    patch(sys.argv[1])
