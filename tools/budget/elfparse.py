"""Minimal reader for `ar` archives and ELF relocatable objects (standard library only).

Used by tools/budget/vtm_budget.py (section sizes) and tools/checks/policy.py (undefined
symbols). It deliberately does not call the target's binutils: the ground machine reads
objects of every flight target (32/64-bit, little/big-endian) with the same code.

Supported: System V / GNU `ar` archives (long-name table "//", symbol tables "/" and
"/SYM64/"), BSD long names ("#1/len"); ELF32 and ELF64, either byte order, section
headers and .symtab. Thin archives are rejected (their members live outside the file).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass, field
from pathlib import Path

# Section header types and flags (ELF gABI).
SHT_NULL = 0
SHT_PROGBITS = 1
SHT_SYMTAB = 2
SHT_STRTAB = 3
SHT_NOBITS = 8
SHT_INIT_ARRAY = 14
SHT_FINI_ARRAY = 15
SHT_PREINIT_ARRAY = 16
SHF_WRITE = 0x1
SHF_ALLOC = 0x2
SHF_EXECINSTR = 0x4
SHF_TLS = 0x400

SHN_UNDEF = 0
SHN_LORESERVE = 0xFF00
SHN_ABS = 0xFFF1
SHN_COMMON = 0xFFF2
SHN_XINDEX = 0xFFFF

STB_LOCAL, STB_GLOBAL, STB_WEAK = 0, 1, 2
STT_NOTYPE, STT_OBJECT, STT_FUNC, STT_SECTION, STT_FILE = 0, 1, 2, 3, 4

EM_NAMES = {2: "sparc", 3: "x86", 18: "sparc32plus", 20: "ppc", 21: "ppc64", 40: "arm",
            43: "sparcv9", 62: "x86-64", 183: "aarch64", 243: "riscv"}


class ParseError(Exception):
    """The input is not a well-formed archive or ELF object."""


@dataclass
class Section:
    name: str
    type: int
    flags: int
    size: int
    offset: int
    link: int
    entsize: int

    @property
    def category(self) -> str | None:
        """Budget category: text, rodata, data, bss, or None (not loaded)."""
        if not self.flags & SHF_ALLOC:
            return None
        if self.type == SHT_NOBITS:
            return "bss"
        if self.flags & SHF_EXECINSTR:
            return "text"
        if self.flags & SHF_WRITE:
            return "data"
        return "rodata"


@dataclass
class Symbol:
    name: str
    value: int
    size: int
    bind: int
    type: int
    shndx: int

    @property
    def undefined(self) -> bool:
        return self.shndx == SHN_UNDEF and self.name != ""

    @property
    def defined(self) -> bool:
        return self.shndx != SHN_UNDEF


@dataclass
class ElfObject:
    name: str
    bits: int
    big_endian: bool
    machine: int
    sections: list[Section] = field(default_factory=list)
    symbols: list[Symbol] = field(default_factory=list)

    @property
    def machine_name(self) -> str:
        return EM_NAMES.get(self.machine, f"em{self.machine}")

    def category_sizes(self) -> dict[str, int]:
        """Bytes per budget category. Common symbols (SHN_COMMON) count as bss."""
        sizes = {"text": 0, "rodata": 0, "data": 0, "bss": 0}
        for sec in self.sections:
            cat = sec.category
            if cat is not None:
                sizes[cat] += sec.size
        for sym in self.symbols:
            if sym.shndx == SHN_COMMON:
                sizes["bss"] += sym.size
        return sizes

    def undefined_symbols(self) -> list[str]:
        return [s.name for s in self.symbols if s.undefined]

    def binding_of(self, name: str) -> int | None:
        """Binding of the *defined* symbol `name` (STB_*), or None if not defined here."""
        best = None
        for sym in self.symbols:
            if sym.name == name and sym.defined and sym.type in (STT_FUNC, STT_NOTYPE, STT_OBJECT):
                if best is None or sym.bind != STB_LOCAL:
                    best = sym.bind
        return best


def parse_elf(data: bytes, name: str = "<elf>") -> ElfObject:
    if len(data) < 52 or data[:4] != b"\x7fELF":
        raise ParseError(f"{name}: not an ELF file")
    ei_class, ei_data = data[4], data[5]
    if ei_class not in (1, 2) or ei_data not in (1, 2):
        raise ParseError(f"{name}: bad ELF class/data ({ei_class}, {ei_data})")
    bits = 32 if ei_class == 1 else 64
    end = "<" if ei_data == 1 else ">"
    try:
        if bits == 32:
            (e_type, e_machine, _ver, _entry, _phoff, e_shoff, _flags, _ehsize, _phentsize,
             _phnum, e_shentsize, e_shnum, e_shstrndx) = struct.unpack_from(end + "HHIIIIIHHHHHH", data, 16)
            sh_fmt = end + "IIIIIIIIII"
        else:
            (e_type, e_machine, _ver, _entry, _phoff, e_shoff, _flags, _ehsize, _phentsize,
             _phnum, e_shentsize, e_shnum, e_shstrndx) = struct.unpack_from(end + "HHIQQQIHHHHHH", data, 16)
            sh_fmt = end + "IIQQQQIIQQ"
        obj = ElfObject(name=name, bits=bits, big_endian=(ei_data == 2), machine=e_machine)
        if e_shoff == 0:
            return obj
        if e_shentsize < struct.calcsize(sh_fmt):
            raise ParseError(f"{name}: section header entry too small ({e_shentsize})")

        def shdr(i: int) -> tuple:
            return struct.unpack_from(sh_fmt, data, e_shoff + i * e_shentsize)

        # Extended numbering: real counts live in section header 0.
        sh0 = shdr(0)
        if e_shnum == 0:
            e_shnum = sh0[5]
        if e_shstrndx == SHN_XINDEX:
            e_shstrndx = sh0[6]
        raw = [shdr(i) for i in range(e_shnum)]
        shstr_off, shstr_size = raw[e_shstrndx][4], raw[e_shstrndx][5]

        def cstr(off: int, base: int, limit: int) -> str:
            if off >= limit:
                raise ParseError(f"{name}: string offset {off} out of range")
            stop = data.index(b"\0", base + off, base + limit)
            return data[base + off:stop].decode("utf-8", "replace")

        for (sh_name, sh_type, sh_flags, _addr, sh_offset, sh_size, sh_link, _info, _align,
             sh_entsize) in raw:
            obj.sections.append(Section(cstr(sh_name, shstr_off, shstr_size) if shstr_size else "",
                                        sh_type, sh_flags, sh_size, sh_offset, sh_link, sh_entsize))
        for sec in obj.sections:
            if sec.type != SHT_SYMTAB:
                continue
            strsec = obj.sections[sec.link]
            entsize = sec.entsize or (16 if bits == 32 else 24)
            count = sec.size // entsize
            for i in range(count):
                off = sec.offset + i * entsize
                if bits == 32:
                    st_name, st_value, st_size, st_info, _other, st_shndx = struct.unpack_from(
                        end + "IIIBBH", data, off)
                else:
                    st_name, st_info, _other, st_shndx, st_value, st_size = struct.unpack_from(
                        end + "IBBHQQ", data, off)
                sym_name = cstr(st_name, strsec.offset, strsec.size) if st_name else ""
                obj.symbols.append(Symbol(sym_name, st_value, st_size, st_info >> 4, st_info & 0xF,
                                          st_shndx))
        return obj
    except (struct.error, IndexError, ValueError) as exc:
        raise ParseError(f"{name}: truncated or corrupt ELF ({exc})") from exc


def iter_archive(data: bytes, name: str = "<archive>"):
    """Yields (member_name, member_bytes) for every regular member of an `ar` archive."""
    if data.startswith(b"!<thin>\n"):
        raise ParseError(f"{name}: thin archives are not supported")
    if not data.startswith(b"!<arch>\n"):
        raise ParseError(f"{name}: not an ar archive")
    pos = 8
    longnames = b""
    while pos < len(data):
        if pos + 60 > len(data):
            raise ParseError(f"{name}: truncated member header at {pos}")
        hdr = data[pos:pos + 60]
        if hdr[58:60] != b"`\n":
            raise ParseError(f"{name}: bad member header magic at {pos}")
        raw_name = hdr[0:16].decode("ascii", "replace").rstrip(" ")
        try:
            size = int(hdr[48:58].decode("ascii").strip())
        except ValueError as exc:
            raise ParseError(f"{name}: bad member size at {pos}") from exc
        body_start = pos + 60
        body = data[body_start:body_start + size]
        if len(body) != size:
            raise ParseError(f"{name}: truncated member at {pos}")
        pos = body_start + size + (size & 1)  # members are 2-byte aligned
        if raw_name in ("/", "/SYM64/", "__.SYMDEF", "__.SYMDEF SORTED"):
            continue  # symbol index
        if raw_name == "//":
            longnames = body
            continue
        if raw_name.startswith("#1/"):  # BSD: name follows the header
            nlen = int(raw_name[3:])
            member_name = body[:nlen].rstrip(b"\0").decode("utf-8", "replace")
            body = body[nlen:]
        elif raw_name.startswith("/") and raw_name[1:].isdigit():  # GNU long name
            off = int(raw_name[1:])
            stop = longnames.find(b"/\n", off)
            if stop < 0:
                stop = longnames.find(b"\n", off)
            member_name = longnames[off:stop if stop >= 0 else None].decode("utf-8", "replace")
        else:
            member_name = raw_name[:-1] if raw_name.endswith("/") else raw_name
        yield member_name, body


def read_archive(path: Path) -> list[ElfObject]:
    """Parses every ELF member of the archive at `path`."""
    data = Path(path).read_bytes()
    objects = []
    for member, body in iter_archive(data, str(path)):
        if body[:4] != b"\x7fELF":
            continue  # e.g. an LLVM bitcode member; not expected in flight libraries
        objects.append(parse_elf(body, member))
    return objects
