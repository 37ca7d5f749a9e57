#!/usr/bin/env python3
"""vtm_budget: static memory and worst-case stack of the flight libraries, per target.

    vtm_budget.py [--top N] [--json FILE] [--no-demangle] BUILD_DIR [BUILD_DIR ...]

For every CMake build directory given (one per target; the target name is VTM_TARGET_NAME
from its CMakeCache.txt) the tool

  1. finds the flight libraries: every libvtm_*.a in the tree whose objects were compiled
     with the flight policy (their CMakeFiles/<lib>.dir holds GCC's .su/.ci files);
  2. parses each archive and its ELF objects itself (tools/budget/elfparse.py: any
     width, any byte order, no target binutils) and sums the loaded sections into
     text / rodata / data / bss;
  3. reads GCC's -fstack-usage (.su) and -fcallgraph-info=su (.ci) files next to each
     object, builds one call graph over all flight libraries of the target, and computes
     for every externally visible function the worst-case stack: own frame plus the
     deepest chain of callees. Calls that leave the graph (libc, libstdc++, indirect
     and virtual calls) are listed as "+ unknown callees": their stack is not included.

Errors (exit status 1): recursion (any cycle in the call graph), a frame that is not
static (flight code must have static frames), an archive/object/.ci that does not
parse, or a build directory without flight libraries. Usage errors exit with 2.
See docs/budgets.md.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

sys.dont_write_bytecode = True  # keep the source tree free of __pycache__
sys.path.insert(0, str(Path(__file__).resolve().parent))
import elfparse  # noqa: E402  (shared with tools/checks/policy.py)

CATEGORIES = ("text", "rodata", "data", "bss")
INDIRECT = "__indirect_call"

_NODE_RE = re.compile(r'^node:\s*\{\s*title:\s*"((?:[^"\\]|\\.)*)"\s*label:\s*"((?:[^"\\]|\\.)*)"(.*)\}\s*$')
_EDGE_RE = re.compile(r'^edge:\s*\{\s*sourcename:\s*"((?:[^"\\]|\\.)*)"\s*targetname:\s*"((?:[^"\\]|\\.)*)"')
_FRAME_RE = re.compile(r"(\d+) bytes \(([^)]*)\)")


class UsageError(Exception):
    pass


@dataclass
class Func:
    key: str                 # mangled name, or "file:mangled" for file-local functions
    mangled: str
    label: str               # GCC's own printable name (first line of the .ci label)
    local: bool
    frame: int = 0
    qualifier: str = "static"
    locations: set[str] = field(default_factory=set)
    libraries: set[str] = field(default_factory=set)
    callees: set[str] = field(default_factory=set)       # keys of defined functions
    unresolved: set[str] = field(default_factory=set)    # mangled names / __indirect_call


@dataclass
class Library:
    name: str
    archive: Path
    objdir: Path | None
    objects: list[dict] = field(default_factory=list)
    totals: dict[str, int] = field(default_factory=lambda: {c: 0 for c in CATEGORIES})
    entry_points: set[str] = field(default_factory=set)
    has_callgraph: bool = False


@dataclass
class Target:
    name: str
    build_dir: Path
    machine: str = "?"
    libraries: list[Library] = field(default_factory=list)
    funcs: dict[str, Func] = field(default_factory=dict)
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    worst: dict[str, int | None] = field(default_factory=dict)
    unknown: dict[str, set[str]] = field(default_factory=dict)
    deepest: dict[str, str | None] = field(default_factory=dict)


# ----------------------------------------------------------------------------- discovery

def read_target_name(build_dir: Path) -> str:
    cache = build_dir / "CMakeCache.txt"
    if not cache.is_file():
        raise UsageError(f"{build_dir}: no CMakeCache.txt (not a CMake build directory)")
    for line in cache.read_text(errors="replace").splitlines():
        if line.startswith("VTM_TARGET_NAME:"):
            return line.split("=", 1)[1].strip() or "host"
    return "host"


def discover_libraries(build_dir: Path, warnings: list[str]) -> list[Library]:
    """libvtm_*.a built with the flight policy (.su files beside their objects)."""
    objdirs: dict[str, Path] = {}
    archives: dict[str, Path] = {}
    for root, dirs, files in os.walk(build_dir):
        dirs.sort()
        base = os.path.basename(root)
        if base.endswith(".dir") and os.path.basename(os.path.dirname(root)) == "CMakeFiles":
            objdirs.setdefault(base[:-4], Path(root))
        for f in sorted(files):
            if f.startswith("libvtm_") and f.endswith(".a"):
                archives.setdefault(f[3:-2], Path(root) / f)
    # Manifest written by the top-level CMakeLists.txt from the VTM_FLIGHT_LIBRARIES
    # property: "name<TAB>archive<TAB>object directory" per line (a bare name is accepted).
    manifest = build_dir / "vtm_flight_libraries.txt"
    if manifest.is_file():
        libs = []
        for lineno, line in enumerate(manifest.read_text().splitlines(), 1):
            fields = [f.strip() for f in line.split("\t")]
            if not fields[0]:
                continue
            name = fields[0]
            archive = Path(fields[1]) if len(fields) > 1 and fields[1] else archives.get(name)
            objdir = Path(fields[2]) if len(fields) > 2 and fields[2] else objdirs.get(name)
            if archive is None or not archive.is_file():
                warnings.append(f"{manifest}:{lineno}: {name}: archive not built; skipped")
                continue
            if objdir is None or not objdir.is_dir():
                warnings.append(f"{manifest}:{lineno}: {name}: object directory {objdir} missing; "
                                f"sizes only")
                objdir = archive.parent
            libs.append(Library(name=name, archive=archive, objdir=objdir))
        # The manifest is authoritative: other libvtm_*.a (test support, the determinism
        # suite's per-optimisation-level copies of vtm_core) are not flight libraries.
        return libs
    libs = []
    for name in sorted(archives):
        objdir = objdirs.get(name)
        if objdir is None or not any(objdir.rglob("*.su")):
            warnings.append(f"{archives[name]}: not compiled with the flight policy "
                            f"(no .su files); not a flight library, skipped")
            continue
        libs.append(Library(name=name, archive=archives[name], objdir=objdir))
    return libs


# ----------------------------------------------------------------------------- sizes

def measure_library(lib: Library, target: Target) -> dict[str, elfparse.ElfObject]:
    members: dict[str, elfparse.ElfObject] = {}
    for obj in elfparse.read_archive(lib.archive):
        sizes = obj.category_sizes()
        for c in CATEGORIES:
            lib.totals[c] += sizes[c]
        sections = {}
        for sec in obj.sections:
            if sec.category is not None and sec.size:
                sections[sec.name] = sections.get(sec.name, 0) + sec.size
        lib.objects.append({"name": obj.name, **sizes, "sections": sections})
        if obj.name in members:
            target.warnings.append(f"{lib.archive}: two members named {obj.name}")
        members[obj.name] = obj
        target.machine = f"{obj.machine_name}, ELF{obj.bits} {'big' if obj.big_endian else 'little'}-endian"
    return members


# ----------------------------------------------------------------------------- call graph

def _unescape(s: str) -> str:
    return s.replace('\\"', '"').replace("\\n", "\n").replace("\\\\", "\\")


def parse_ci(path: Path, obj: elfparse.ElfObject | None, lib: Library, target: Target) -> None:
    title_to_key: dict[str, str] = {}
    defined_here: list[str] = []
    edges: list[tuple[str, str]] = []
    lines = path.read_text(errors="replace").splitlines()
    if not lines or not lines[0].startswith("graph:"):
        raise elfparse.ParseError(f"{path}: not a GCC call-graph (VCG) file")
    for lineno, line in enumerate(lines, 1):
        line = line.strip()
        if line.startswith("node:"):
            m = _NODE_RE.match(line)
            if not m:
                raise elfparse.ParseError(f"{path}:{lineno}: unparsable node")
            title, label = m.group(1), _unescape(m.group(2))
            parts = label.split("\n")
            fm = _FRAME_RE.search(parts[-1]) if len(parts) >= 3 else None
            if fm is None:  # declared only ("shape : ellipse"): resolved against the graph
                title_to_key.setdefault(title, title)
                continue
            file_part, sep, mangled = title.rpartition(":")
            if not sep:
                mangled = title
            bind = obj.binding_of(mangled) if obj is not None else None
            local = bind == elfparse.STB_LOCAL or (bind is None and bool(sep))
            # File-local functions are keyed per object so equal names in two files stay apart.
            key = f"{lib.name}/{path.name[:-3]}:{mangled}" if local else mangled
            title_to_key[title] = key
            fn = target.funcs.get(key)
            if fn is None:
                fn = target.funcs[key] = Func(key=key, mangled=mangled, label=parts[0], local=local)
            frame, qual = int(fm.group(1)), fm.group(2)
            fn.frame = max(fn.frame, frame)
            if qual != "static":
                fn.qualifier = qual
            fn.locations.add(parts[1] if len(parts) > 1 else str(path))
            fn.libraries.add(lib.name)
            defined_here.append(key)
            if not local:
                lib.entry_points.add(key)
        elif line.startswith("edge:"):
            m = _EDGE_RE.match(line)
            if not m:
                raise elfparse.ParseError(f"{path}:{lineno}: unparsable edge")
            edges.append((m.group(1), m.group(2)))
    for src, dst in edges:
        skey = title_to_key.get(src)
        if skey is None or skey not in target.funcs:
            raise elfparse.ParseError(f"{path}: edge from unknown node {src}")
        dkey = title_to_key.get(dst, dst)
        target.funcs[skey].callees.add(dkey)  # resolved after all files are read


# Frames GCC reports as "dynamic,bounded" that are accepted, each with its reason. Only
# bounded frames can be exempted; an unbounded dynamic frame (alloca/VLA) is always an error.
BOUNDED_DYNAMIC_FRAME_EXEMPTIONS = (
    (re.compile(r"^/usr/include/stb/"),
     "stb_image (third-party PNG decoder) inside hal/file, the desk/HIL playback driver; "
     "not on a flight camera path; GCC bounds the frame"),
)


def parse_su(path: Path, target: Target) -> None:
    for lineno, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
        if not line.strip():
            continue
        fields = line.split("\t")
        if len(fields) != 3 or not fields[1].isdigit():
            raise elfparse.ParseError(f"{path}:{lineno}: unparsable stack-usage line")
        where_func, size, qual = fields
        if qual != "static":
            m = re.match(r"^(.*?:\d+:\d+):(.*)$", where_func)
            where, func = (m.group(1), m.group(2)) if m else (str(path), where_func)
            reason = next((r for rx, r in BOUNDED_DYNAMIC_FRAME_EXEMPTIONS if rx.search(where)), None)
            if qual == "dynamic,bounded" and reason is not None:
                print(f"vtm_budget: note: {where}: {func}: {qual} frame of {size} bytes accepted: {reason}",
                      file=sys.stderr)
                continue
            target.errors.append(f"{where}: dynamic-frame: {func} has a {qual} frame of {size} bytes "
                                 f"(flight code must have static frames)")


def resolve_edges(target: Target) -> None:
    for fn in target.funcs.values():
        raw, fn.callees = fn.callees, set()
        for c in raw:
            if c in target.funcs:
                fn.callees.add(c)
            else:
                fn.unresolved.add(c)


def strongly_connected(funcs: dict[str, Func]) -> list[list[str]]:
    """Tarjan's algorithm with an explicit stack. SCCs come out callees-first."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    out: list[list[str]] = []
    counter = 0
    for root in sorted(funcs):
        if root in index:
            continue
        work = [(root, iter(sorted(funcs[root].callees)))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, it = work[-1]
            advanced = False
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(funcs[w].callees))))
                    advanced = True
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            if advanced:
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                out.append(comp)
    return out


def cycle_path(funcs: dict[str, Func], comp: list[str]) -> list[str]:
    """One concrete cycle inside a strongly connected component (BFS back to the start)."""
    members = set(comp)
    start = sorted(comp)[0]
    prev: dict[str, str] = {}
    queue = [start]
    seen = {start}
    while queue:
        v = queue.pop(0)
        for w in sorted(funcs[v].callees):
            if w == start:
                path = [v]
                while path[-1] != start:
                    path.append(prev[path[-1]])
                return list(reversed(path)) + [start]
            if w in members and w not in seen:
                seen.add(w)
                prev[w] = v
                queue.append(w)
    return [start, start]


def compute_worst_case(target: Target, name_of) -> None:
    funcs = target.funcs
    for comp in strongly_connected(funcs):
        cyclic = len(comp) > 1 or comp[0] in funcs[comp[0]].callees
        if cyclic:
            path = cycle_path(funcs, comp)
            where = sorted(funcs[path[0]].locations)[0] if funcs[path[0]].locations else "?"
            target.errors.append(f"{where}: recursion: call-graph cycle "
                                 + " -> ".join(name_of(k) for k in path))
            for k in comp:
                target.worst[k] = None
                target.unknown[k] = set(funcs[k].unresolved)
                target.deepest[k] = None
            continue
        k = comp[0]
        fn = funcs[k]
        best, best_child, unbounded = 0, None, False
        unknown = set(fn.unresolved)
        for c in fn.callees:
            wc = target.worst[c]
            unknown |= target.unknown[c]
            if wc is None:
                unbounded = True
            elif best_child is None or wc > best or (wc == best and c < best_child):
                best, best_child = wc, c
        target.worst[k] = None if unbounded else fn.frame + best
        target.unknown[k] = unknown
        target.deepest[k] = best_child


# ----------------------------------------------------------------------------- names

class Demangler:
    def __init__(self, enabled: bool):
        self.tool = shutil.which("c++filt") if enabled else None
        self.cache: dict[str, str] = {}

    def prime(self, names: set[str]) -> None:
        todo = sorted(n for n in names if n not in self.cache and n.startswith("_Z"))
        if not todo or self.tool is None:
            return
        try:
            out = subprocess.run([self.tool], input="\n".join(todo) + "\n", capture_output=True,
                                 text=True, check=True).stdout.splitlines()
        except (OSError, subprocess.CalledProcessError):
            return
        if len(out) == len(todo):
            self.cache.update(zip(todo, out))

    def __call__(self, mangled: str, fallback: str | None = None) -> str:
        if mangled in self.cache:
            return self.cache[mangled]
        return fallback or mangled


# ----------------------------------------------------------------------------- driver

def analyse(build_dir: Path, demangler: Demangler) -> Target:
    if not build_dir.is_dir():
        raise UsageError(f"{build_dir}: not a directory")
    target = Target(name=read_target_name(build_dir), build_dir=build_dir)
    target.libraries = discover_libraries(build_dir, target.warnings)
    if not target.libraries:
        target.errors.append(f"{build_dir}: parse: no flight libraries (libvtm_*.a with .su files) "
                             f"found; build them first")
        return target
    for lib in target.libraries:
        try:
            members = measure_library(lib, target)
            cis = sorted(lib.objdir.rglob("*.ci"))
            sus = sorted(lib.objdir.rglob("*.su"))
            # Only files whose object is in the archive (stale ones from removed sources are ignored).
            for su in sus:
                if su.name[:-3] + ".o" in members:
                    parse_su(su, target)
            seen = set()
            for ci in cis:
                member = ci.name[:-3] + ".o"
                if member not in members:
                    continue
                seen.add(member)
                obj_path = ci.with_name(member)
                obj = elfparse.parse_elf(obj_path.read_bytes(), str(obj_path)) if obj_path.is_file() \
                    else members[member]
                parse_ci(ci, obj, lib, target)
            lib.has_callgraph = bool(seen)
            for missing in sorted(set(members) - seen):
                target.warnings.append(f"{lib.name}: {missing}: no .ci call-graph file "
                                       f"(not compiled with -fcallgraph-info=su?); its stack is unknown")
        except (elfparse.ParseError, OSError) as exc:
            target.errors.append(f"{lib.archive}: parse: {exc}")
    resolve_edges(target)
    mangled = {f.mangled for f in target.funcs.values()}
    for f in target.funcs.values():
        mangled |= f.unresolved
    demangler.prime(mangled)
    compute_worst_case(target, lambda k: name_of(target, demangler, k))
    return target


_STRUCTOR_RE = re.compile(r"(C[1-3]|D[0-2])E")
_STRUCTOR_KIND = {"C1": "complete", "C2": "base", "C3": "allocating",
                  "D0": "deleting", "D1": "complete", "D2": "base"}


def name_of(target: Target, dm: Demangler, key: str) -> str:
    fn = target.funcs.get(key)
    if fn is None:
        return "<indirect call>" if key == INDIRECT else dm(key)
    name = dm(fn.mangled, fn.label)
    if "::~" in name or re.search(r"::(\w+)::\1\(", name):
        # Constructor and destructor variants share one printable name; say which one.
        m = None
        for m in _STRUCTOR_RE.finditer(fn.mangled):
            pass
        if m is not None:
            name += f" [{_STRUCTOR_KIND[m.group(1)]}]"
    return name


def brief(name: str) -> str:
    """Name without its parameter list (the last top-level parenthesised group), for chains."""
    depth, start, cut = 0, -1, -1
    for i, ch in enumerate(name):
        if ch in "<(":
            if ch == "(" and depth == 0 and not name[:i].endswith("operator"):
                start = i
            depth += 1
        elif ch in ">)":
            depth -= 1
            if ch == ")" and depth == 0 and start >= 0 and not name[start:i + 1] == "(anonymous namespace)":
                cut = start
    if cut < 0:
        return name
    tag = name[name.rfind(" ["):] if name.endswith("]") else ""
    return name[:cut] + "()" + tag


def entry_rows(target: Target, lib: Library, dm: Demangler) -> list[dict]:
    rows = []
    for key in lib.entry_points:
        fn = target.funcs[key]
        path, k = [], key
        while k is not None and len(path) < 64:
            path.append(name_of(target, dm, k))
            k = target.deepest.get(k)
        rows.append({
            "symbol": fn.mangled,
            "name": name_of(target, dm, key),
            "frame": fn.frame,
            "worst_case": target.worst.get(key),
            "unknown_callees": sorted(name_of(target, dm, u) for u in target.unknown.get(key, ())),
            "deepest_path": path,
            "location": sorted(fn.locations)[0] if fn.locations else "",
        })
    rows.sort(key=lambda r: (r["worst_case"] is not None, -(r["worst_case"] or 0), r["name"]))
    return rows


def short(name: str, limit: int = 70) -> str:
    return name if len(name) <= limit else name[:limit - 1] + "…"


def md_escape(s: str) -> str:
    return s.replace("|", "\\|")


def render_markdown(target: Target, dm: Demangler, top: int) -> str:
    out = [f"## Target `{target.name}` ({target.machine})", "",
           f"Build directory: `{target.build_dir}`", "",
           "| library | text | rodata | data | bss |", "|---|---:|---:|---:|---:|"]
    total = {c: 0 for c in CATEGORIES}
    for lib in target.libraries:
        out.append(f"| {lib.name} | " + " | ".join(str(lib.totals[c]) for c in CATEGORIES) + " |")
        for c in CATEGORIES:
            total[c] += lib.totals[c]
    out.append("| **total** | " + " | ".join(f"**{total[c]}**" for c in CATEGORIES) + " |")
    out.append("")
    for lib in target.libraries:
        rows = entry_rows(target, lib, dm)
        shown = rows[:top] if top > 0 else rows
        out.append(f"### `{lib.name}` worst-case stack (bytes), top {len(shown)} of {len(rows)} entry points")
        out.append("")
        if not lib.has_callgraph:
            out.append("_no call-graph information_")
            out.append("")
            continue
        if not rows:
            out.append("_no externally visible functions_")
            out.append("")
            continue
        out.append("| entry point | frame | worst case | deepest chain | notes |")
        out.append("|---|---:|---:|---|---|")
        for r in shown:
            wc = "RECURSION" if r["worst_case"] is None else str(r["worst_case"])
            chain = " → ".join(short(brief(p), 50) for p in r["deepest_path"][1:]) or "—"
            notes = ""
            if r["unknown_callees"]:
                notes = "+ unknown callees: " + ", ".join(brief(u) for u in r["unknown_callees"])
            out.append(f"| {md_escape(short(r['name']))} | {r['frame']} | {wc} | {md_escape(chain)} | "
                       f"{md_escape(notes)} |")
        out.append("")
    if target.errors or target.warnings:
        out.append("### Findings")
        out.append("")
        for e in target.errors:
            out.append(f"- ERROR: {md_escape(e)}")
        for w in target.warnings:
            out.append(f"- warning: {md_escape(w)}")
        out.append("")
    return "\n".join(out)


def to_json(target: Target, dm: Demangler) -> dict:
    return {
        "target": target.name,
        "build_dir": str(target.build_dir),
        "machine": target.machine,
        "libraries": [{
            "name": lib.name,
            "archive": str(lib.archive),
            **lib.totals,
            "objects": lib.objects,
            "entry_points": entry_rows(target, lib, dm),
        } for lib in target.libraries],
        "errors": target.errors,
        "warnings": target.warnings,
    }


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build_dirs", nargs="+", type=Path, metavar="BUILD_DIR")
    ap.add_argument("--top", type=int, default=10, help="entry points shown per library (0 = all)")
    ap.add_argument("--json", type=Path, metavar="FILE", help="also write the results as JSON")
    ap.add_argument("--no-demangle", action="store_true", help="do not run c++filt")
    args = ap.parse_args(argv)
    dm = Demangler(not args.no_demangle)
    targets = []
    try:
        for d in args.build_dirs:
            targets.append(analyse(d, dm))
    except UsageError as exc:
        print(f"vtm_budget: {exc}", file=sys.stderr)
        return 2
    print("# VTM flight-library budget\n")
    print("Sizes in bytes, summed over the objects of each static library (before linking).")
    print("Worst-case stack = own frame + deepest chain of known callees; "
          "'+ unknown callees' are not included.\n")
    for t in targets:
        print(render_markdown(t, dm, args.top))
    if args.json:
        args.json.write_text(json.dumps({"targets": [to_json(t, dm) for t in targets]}, indent=2) + "\n")
    status = 0
    for t in targets:
        for e in t.errors:
            print(f"vtm_budget: {t.name}: ERROR: {e}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
