#!/usr/bin/env python3
"""policy: layering and flight-rule checks on the VTM source tree and on built flight libraries.

    policy.py sources  REPO_ROOT          # include rules (layering, allowed std headers; tools/ and
                                          # tests/: no relative includes, tools/ not on tests/)
    policy.py binaries BUILD_DIR [...]    # forbidden symbols in the flight libraries' objects
    policy.py all      REPO_ROOT BUILD_DIR [...]

One line per finding, `file:line: rule: text`; exit status 1 when there is any finding,
2 on a usage error, 0 when clean. The rules are the tables below; docs/static-analysis.md
explains them. Standard library only (python3).
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from pathlib import Path

sys.dont_write_bytecode = True  # keep the source tree free of __pycache__
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "budget"))
import elfparse  # noqa: E402  (tools/budget/elfparse.py: shared with vtm_budget.py)
from vtm_budget import UsageError, discover_libraries  # noqa: E402

# =============================================================================================
# Rule table 1: C++ standard headers.
#
# Flight code (fsw/, hal/ interfaces, hal drivers) may include only these. Everything not
# listed is refused; FORBIDDEN_STD below gives the reason for the usual suspects.
# The heap is policed again on the objects (rule table 3), so an allowed header whose
# allocating parts get used (e.g. std::stable_sort in <algorithm>) is still caught there.
# =============================================================================================
FLIGHT_STD = {
    "algorithm",         # std::min/max/clamp/fill/copy; NOT stable_sort/inplace_merge (heap, caught by binaries)
    "array",
    "bit",               # (C++20) kept for when the toolchains move
    "cfloat", "climits", "cmath", "cstddef", "cstdint", "cinttypes",
    "cstring",           # memcpy/memset/memcmp
    "cstdlib",           # std::abort (assert hook) and std::abs; malloc & co. are caught by binaries
    "initializer_list", "iterator", "limits",
    "new",               # placement new into Arena storage only
    "numeric", "optional", "string_view", "tuple", "type_traits", "utility",
}
# Extra headers for hal drivers (hal/<driver>/...): they talk to the operating system.
DRIVER_STD = {"cstdio", "ctime", "cerrno", "csignal", "cstdarg"}
# POSIX/C system headers a driver may use (hal/posix, hal/file, hal/link, ...).
DRIVER_SYSTEM = re.compile(r"^(unistd|fcntl|errno|time|signal|poll|termios|stdio|string|"
                           r"sys/[a-z_]+|netinet/[a-z_]+|arpa/[a-z_]+|netdb|sched)\.h$")

FORBIDDEN_STD = {
    "iostream": "prints and allocates; flight code reports through Status and EventLog",
    "ostream": "prints", "istream": "reads streams", "iomanip": "prints",
    "cstdio": "prints/opens files: only hal drivers may use stdio",
    "fstream": "file streams allocate and may throw",
    "sstream": "string streams allocate",
    "thread": "no threads unless their partition is fixed (none in fsw/ yet)",
    "mutex": "no threads", "condition_variable": "no threads", "future": "no threads",
    "atomic": "no threads", "shared_mutex": "no threads",
    "random": "use vtm/core/random.hpp (same bits on every target)",
    "chrono": "time comes from hal::Clock",
    "ctime": "time comes from hal::Clock",
    "exception": "built with -fno-exceptions", "stdexcept": "built with -fno-exceptions",
    "typeinfo": "built with -fno-rtti", "typeindex": "built with -fno-rtti",
    "any": "type erasure allocates and needs RTTI",
    "regex": "allocates, unbounded time",
    "functional": "std::function allocates; pass a function pointer or a template parameter",
    "memory": "owning smart pointers allocate (std::addressof/std::align: write them in vtm/core "
              "or move this header to FLIGHT_STD if ever needed)",
    "memory_resource": "allocators", "scoped_allocator": "allocators",
    "string": "allocates; use std::string_view or fixed char arrays",
    "vector": "grows on the heap; use vtm::FixedVector", "deque": "heap", "list": "heap",
    "forward_list": "heap", "map": "heap", "multimap": "heap", "set": "heap",
    "unordered_map": "heap", "unordered_set": "heap", "queue": "heap (deque)",
    "stack": "heap (deque)", "valarray": "heap", "bitset": "throws std::out_of_range",
    "variant": "may throw bad_variant_access", "locale": "heap", "codecvt": "heap",
    "cassert": "use VTM_ASSERT (routed to the assert hook)", "assert.h": "use VTM_ASSERT",
    "csetjmp": "non-local jumps", "setjmp.h": "non-local jumps", "cfenv": "floating-point mode "
    "is fixed for the whole program",
}

# =============================================================================================
# Rule table 2: layers. Each zone (first matching path prefix) lists what its files may
# include besides the std headers above. Quoted or angled project headers are matched by
# their path prefix; an include of a file next to the includer ("local.hpp") is allowed.
# =============================================================================================
HAL_INTERFACE = re.compile(r"^hal/[a-z_]+\.hpp$")           # hal/include/hal/*.hpp
HAL_DRIVERS = ("file", "posix", "sim", "link")                # hal/<driver>/...: add new ones here
EIGEN_GATE = "fsw/core/include/vtm/core/eigen.hpp"            # the only file that includes <Eigen/...>


@dataclass(frozen=True)
class Zone:
    prefix: str
    std: frozenset
    allowed: tuple                 # regexes of project headers this zone may include
    system: re.Pattern | None = None
    why: str = ""
    # fsw/ module headers (vtm/<module>/...) the zone may include besides `allowed`:
    # "own" (the module of the including file), "all" (every folder of fsw/) or "".
    modules: str = ""


def _rx(*patterns: str) -> tuple:
    return tuple(re.compile(p) for p in patterns)


ZONES = [
    # The layering of docs/flight-rules.md R12: the two fsw/ `why` texts are quoted there word
    # for word (tools/checks/policy_test.py checks it).
    # Executives: the only part of fsw/ that sees hal interfaces (hal::Camera&, ...) and the
    # only one that combines modules.
    Zone("fsw/app/", frozenset(FLIGHT_STD), _rx(HAL_INTERFACE.pattern),
         why="fsw/app: vtm/core/, vtm/app/ and the modules' vtm/<module>/ headers, and the hal interfaces "
             "hal/*.hpp (never a hal driver, sim/, tools/ or OpenCV)",
         modules="all"),
    # A module (fsw/core, fsw/stereo, ...): fsw/core, itself and the modules it links (MODULE_DEPS).
    Zone("fsw/", frozenset(FLIGHT_STD), _rx(r"^vtm/core/"),
         why="fsw/<module>: vtm/core/ (Eigen through vtm/core/eigen.hpp), its own vtm/<module>/ "
             "headers and those of the modules its CMake target links (target_link_libraries in "
             "fsw/<module>/CMakeLists.txt, no cycles); shared types go to fsw/core, fsw/app combines "
             "modules",
         modules="own"),
    Zone("hal/include/", frozenset(FLIGHT_STD), _rx(r"^vtm/core/", HAL_INTERFACE.pattern),
         why="hal interfaces: fsw/core and other hal interfaces only"),
    Zone("hal/src/", frozenset(FLIGHT_STD), _rx(r"^vtm/core/", HAL_INTERFACE.pattern),
         why="hal interfaces: fsw/core and other hal interfaces only"),
    Zone("hal/sim/", frozenset(FLIGHT_STD | DRIVER_STD), _rx(r"^vtm/core/", r"^hal/", r"^sim/"),
         DRIVER_SYSTEM, why="hal/sim: the only flight-side user of sim/"),
    Zone("hal/", frozenset(FLIGHT_STD | DRIVER_STD), _rx(r"^vtm/core/", r"^hal/"), DRIVER_SYSTEM,
         why="hal drivers: stdio and POSIX allowed; no sim/, OpenCV or tools/"),
    # The simulated world shares fsw/core types and nothing else of the flight side.
    Zone("sim/", frozenset(), _rx(r"^vtm/core/", r"^sim/"), None,
         why="sim/: may share vtm/core types only"),
]
GROUND_ZONES = ("sim/",)   # ground-side C++: any std/system header, only project layering checked
PROJECT_PREFIXES = ("vtm/", "hal/", "sim/", "fsw/", "tools/")

# Third-party headers a zone may include, each with its reason (path prefix -> header -> why).
THIRD_PARTY = {
    "hal/file/": {
        "stb_image.h": "PNG decoding for frame playback (Debian libstb-dev); its allocator is "
                       "routed to a static pool (hal/file/src/stb_config.hpp), checked by "
                       "`policy.py binaries`",
    },
}

# Project prefixes refused everywhere under the zones above, whatever the zone allows.
ALWAYS_FORBIDDEN = [
    (re.compile(r"^(opencv2?|cv)/|^opencv"), "OpenCV appears only under tests/ and benchmarks"),
    (re.compile(r"^tools/|^CLI/"), "ground tools are not flight code"),
    (re.compile(r"^(gtest|gmock)/"), "test frameworks belong to tests/"),
    (re.compile(r"^(gdal|ogr_|cpl_)"), "GDAL (GeoTIFF) belongs to the ground tools, tools/ground only"),
]

# The folders of fsw/ (core, app and the modules), set by check_sources from the tree.
FSW_MODULES: set[str] = set()
# module -> the fsw modules its library links (target_link_libraries(vtm_<module> ... vtm_<x>)
# in fsw/<module>/CMakeLists.txt), set by check_sources: a module may include those headers.
MODULE_DEPS: dict[str, set[str]] = {}
LINK_RE = re.compile(r"target_link_libraries\s*\(\s*vtm_(\w+)([^)]*)\)", re.S)


def read_module_deps(root: Path) -> list[str]:
    """Fills MODULE_DEPS from the fsw CMake files; returns findings for dependency cycles."""
    MODULE_DEPS.clear()
    for m in FSW_MODULES:
        cmake = root / "fsw" / m / "CMakeLists.txt"
        text = cmake.read_text(errors="replace") if cmake.is_file() else ""
        deps = set()
        for lib, args in LINK_RE.findall(text):
            if lib == m:
                deps |= {d for d in re.findall(r"\bvtm_(\w+)", args) if d in FSW_MODULES and d != m}
        MODULE_DEPS[m] = deps
    findings = []
    for start in sorted(MODULE_DEPS):  # a cycle: start reaches itself through its links
        seen, todo = set(), list(MODULE_DEPS[start])
        while todo:  # bounded by the number of modules
            d = todo.pop()
            if d == start:
                findings.append(f"fsw/{start}/CMakeLists.txt: module-cycle: vtm_{start} reaches itself "
                                "through the modules it links")
                break
            if d not in seen:
                seen.add(d)
                todo.extend(MODULE_DEPS.get(d, ()))
    return findings

# Direct Eigen includes are allowed only in the gate header (which configures it for flight).
EIGEN_INCLUDE = re.compile(r"^(Eigen|unsupported/Eigen)(/|$)")

INCLUDE_RE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
INCLUDE_ANY_RE = re.compile(r"^\s*#\s*include\b")
SOURCE_EXT = {".hpp", ".h", ".cpp", ".cc", ".cxx", ".hh", ".ipp", ".inl"}


def _strip_comments(lines: list[str]) -> list[str]:
    out, in_block = [], False
    for line in lines:
        res, i = "", 0
        while i < len(line):
            if in_block:
                j = line.find("*/", i)
                if j < 0:
                    i = len(line)
                else:
                    in_block, i = False, j + 2
            elif line.startswith("/*", i):
                in_block, i = True, i + 2
            elif line.startswith("//", i):
                break
            else:
                res += line[i]
                i += 1
        out.append(res)
    return out


def check_include(rel: str, path: Path, kind: str, header: str) -> str | None:
    """Returns 'rule: text' for a forbidden include, or None."""
    zone = next((z for z in ZONES if rel.startswith(z.prefix)), None)
    if zone is None:
        return None
    for rx, why in ALWAYS_FORBIDDEN:
        if rx.search(header):
            return f"include-layer: {header} is forbidden here ({why})"
    if kind == '"' and (path.parent / header).is_file():
        return None  # private header next to the includer
    for prefix, headers in THIRD_PARTY.items():
        if rel.startswith(prefix) and header in headers:
            return None
    if zone.prefix in GROUND_ZONES:
        # Ground-side C++: any std/system/Eigen header; only project layering is checked.
        if not header.startswith(PROJECT_PREFIXES):
            return None
        if any(rx.search(header) for rx in zone.allowed):
            return None
        return f"include-layer: {header} is not allowed in {zone.prefix} ({zone.why})"
    if EIGEN_INCLUDE.match(header):
        if rel == EIGEN_GATE:
            return None
        return f"include-eigen: include \"vtm/core/eigen.hpp\" instead of <{header}> (flight Eigen configuration)"
    if ("/" not in header and "." not in header) or header in FORBIDDEN_STD:
        # A standard C++ header (or one of the C headers listed as forbidden).
        if header in zone.std:
            return None
        why = FORBIDDEN_STD.get(header, "not in the flight allow-list, tools/checks/policy.py FLIGHT_STD")
        return f"include-std: <{header}> is not allowed in {zone.prefix} ({why})"
    if zone.system is not None and kind == "<" and zone.system.match(header):
        return None
    if any(rx.search(header) for rx in zone.allowed):
        return None
    if zone.modules:
        own = rel.split("/")[1]
        names = FSW_MODULES if zone.modules == "all" else {own} | MODULE_DEPS.get(own, set())
        m = FSW_MODULE_HEADER.match(header)
        if m and m.group(1) in names:
            return None
    if header.startswith("sim/"):
        return f"include-layer: {header}: sim/ may be used only by hal/sim"
    if HAL_DRIVER_RE.match(header):
        return f"include-layer: {header}: hal drivers are chosen by the build, never included by {zone.prefix}"
    return f"include-layer: {header} is not allowed in {zone.prefix} ({zone.why})"


HAL_DRIVER_RE = re.compile(r"^hal/(" + "|".join(HAL_DRIVERS) + r")/")
FSW_MODULE_HEADER = re.compile(r"^vtm/([a-z_]+)/")

# =============================================================================================
# Rule table 2b: code rules on flight sources (fsw/, hal/), comments stripped.
#  - loop-bound: a `while`/`do` loop or `for (;;)` must state its bound in a `// bound:`
#    comment on its line or the line above (a `for` over a counted range states it itself);
#    the `do { ... } while (false)` macro idiom is not a loop.
#  - no-goto: goto obscures control flow (Power of Ten rule 1).
#  - eigen-fixed: no dynamic-size Eigen types (heap) in flight code.
# =============================================================================================
LOOP_RE = re.compile(r"\bwhile\s*\(|\bdo\s*\{|\bdo\s*$|\bfor\s*\(\s*;\s*;")
MACRO_IDIOM_RE = re.compile(r"\bwhile\s*\(\s*(false|0)\s*\)")
BOUND_COMMENT_RE = re.compile(r"//\s*bound:")
GOTO_RE = re.compile(r"\bgoto\b")
EIGEN_DYNAMIC_RE = re.compile(r"\bEigen::Dynamic\b|\b(Matrix|Vector|RowVector|Array)X[dfi]?\b")


def check_code(rel: str, raw: list[str], lines: list[str]) -> list[str]:
    findings = []
    for i, line in enumerate(lines):
        lineno = i + 1
        if LOOP_RE.search(line) and not MACRO_IDIOM_RE.search(line):
            # `do {` of the macro idiom: its `while (false)` closes it a few lines below.
            closes_idiom = re.search(r"\bdo\b", line) and any(
                MACRO_IDIOM_RE.search(x) for x in lines[i + 1:i + 12])
            stated = BOUND_COMMENT_RE.search(raw[i]) or (i > 0 and BOUND_COMMENT_RE.search(raw[i - 1]))
            if not closes_idiom and not stated:
                findings.append(f"{rel}:{lineno}: loop-bound: while/do/for(;;) loop without a "
                                f"'// bound: ...' comment stating its bound")
        if GOTO_RE.search(line):
            findings.append(f"{rel}:{lineno}: no-goto: goto is not allowed in flight code")
        if EIGEN_DYNAMIC_RE.search(line):
            findings.append(f"{rel}:{lineno}: eigen-fixed: dynamic-size Eigen type in flight code")
    return findings


def check_sources(root: Path) -> list[str]:
    findings = []
    if not (root / "fsw").is_dir():
        raise UsageError(f"{root}: no fsw/ directory (not the repository root?)")
    FSW_MODULES.clear()
    FSW_MODULES.update(d.name for d in (root / "fsw").iterdir() if d.is_dir())
    findings.extend(read_module_deps(root))
    for top in ("fsw", "hal", "sim"):
        for path in sorted((root / top).rglob("*")):
            if path.suffix not in SOURCE_EXT or not path.is_file():
                continue
            rel = path.relative_to(root).as_posix()
            raw = path.read_text(errors="replace").splitlines()
            lines = _strip_comments(raw)
            if top in ("fsw", "hal"):
                findings.extend(check_code(rel, raw, lines))
            for lineno, line in enumerate(lines, 1):
                m = INCLUDE_RE.match(line)
                if m is None:
                    if INCLUDE_ANY_RE.match(line):
                        findings.append(f"{rel}:{lineno}: include-literal: computed #include is not allowed")
                    continue
                problem = check_include(rel, path, m.group(1), m.group(2).strip())
                if problem:
                    findings.append(f"{rel}:{lineno}: {problem}")
    return findings + check_ground(root)


# =============================================================================================
# Rule table 2c: every C/C++ source of the tree (fsw/, hal/, sim/, tools/, tests/), and the
# CMake files of tools/.
#  - include-relative: no ".." in an #include path. A header of another folder is reached
#    through the include path of a library the target links, so the dependency shows in
#    CMake (a "../vtm/exit_codes.hpp" hid that vtm-sim used a header of tools/vtm).
#  - tools-tests: tools/ never depends on tests/: no include of a header that exists only
#    under tests/ (tests/support, tests/<area>/include, ...) or is named by a tests/ path,
#    and no tools/ CMake file names a tests/ path or links a library defined under tests/
#    (shared ground code such as the OpenCV peers lives in tools/, e.g. tools/peer).
# =============================================================================================
GROUND_TOPS = ("fsw", "hal", "sim", "tools", "tests")
GROUND_EXT = SOURCE_EXT | {".c"}
CMAKE_LIBRARY_RE = re.compile(r"\badd_library\s*\(\s*([A-Za-z0-9_.+-]+)")
CMAKE_TESTS_PATH_RE = re.compile(r"(\$\{(PROJECT_SOURCE_DIR|CMAKE_SOURCE_DIR|CMAKE_CURRENT_SOURCE_DIR|"
                                 r"CMAKE_CURRENT_LIST_DIR)\}|\.\.)/(\.\./)*tests(/|\b)")


def _cmake_files(top: Path) -> list[Path]:
    return sorted(p for p in top.rglob("*") if p.is_file() and (p.name == "CMakeLists.txt" or p.suffix == ".cmake"))


def _strip_cmake_comments(text: str) -> list[str]:
    return [line.split("#", 1)[0] for line in text.splitlines()]


def check_ground(root: Path) -> list[str]:
    findings = []
    sources = {top: sorted(p for p in (root / top).rglob("*") if p.is_file() and p.suffix in GROUND_EXT)
               for top in GROUND_TOPS if (root / top).is_dir()}
    # Headers that exist under tests/ and nowhere else: their include names are every
    # trailing part of the path (tests/peer/include/vtm/peer/x.hpp -> "vtm/peer/x.hpp", ...).
    def suffixes(paths: list[Path]) -> set[str]:
        out = set()
        for p in paths:
            parts = p.relative_to(root).parts
            out.update("/".join(parts[i:]) for i in range(1, len(parts)))
        return out
    test_headers = suffixes(sources.get("tests", []))
    other_headers = suffixes([p for top, ps in sources.items() if top != "tests" for p in ps])
    only_in_tests = test_headers - other_headers
    for top, paths in sources.items():
        for path in paths:
            rel = path.relative_to(root).as_posix()
            lines = _strip_comments(path.read_text(errors="replace").splitlines())
            for lineno, line in enumerate(lines, 1):
                m = INCLUDE_RE.match(line)
                if m is None:
                    continue
                header = m.group(2).strip()
                if ".." in header.split("/"):
                    findings.append(f"{rel}:{lineno}: include-relative: \"{header}\": no '..' in an include "
                                    f"path; include the header by the include path of the library that holds it")
                    continue
                if top == "tools" and (header.startswith("tests/") or
                                       (header in only_in_tests and not (path.parent / header).is_file())):
                    findings.append(f"{rel}:{lineno}: tools-tests: {header} is a header of tests/; tools/ never "
                                    f"depends on tests/ (move shared code to a tools/ library)")
    if (root / "tests").is_dir() and (root / "tools").is_dir():
        test_libraries = set()
        for cm in _cmake_files(root / "tests"):
            for line in _strip_cmake_comments(cm.read_text(errors="replace")):
                test_libraries.update(n for n in CMAKE_LIBRARY_RE.findall(line) if "$" not in n)
        names = re.compile(r"(?<![A-Za-z0-9_.+-])(" + "|".join(sorted(map(re.escape, test_libraries))) +
                           r")(?![A-Za-z0-9_.+-])") if test_libraries else None
        for cm in _cmake_files(root / "tools"):
            rel = cm.relative_to(root).as_posix()
            for lineno, line in enumerate(_strip_cmake_comments(cm.read_text(errors="replace")), 1):
                if CMAKE_TESTS_PATH_RE.search(line):
                    findings.append(f"{rel}:{lineno}: tools-tests: names a path under tests/; tools/ never "
                                    f"depends on tests/")
                hit = names.search(line) if names else None
                if hit:
                    findings.append(f"{rel}:{lineno}: tools-tests: {hit.group(1)} is a library of tests/; "
                                    f"tools/ never depends on tests/ (move it to a tools/ library)")
    return findings


# =============================================================================================
# Rule table 3: symbols a flight object may not reference (undefined in the object: the
# linker would pull them from libc/libstdc++). (rule, matcher, text).
# =============================================================================================
HEAP_EXACT = {"malloc", "calloc", "realloc", "reallocarray", "free", "aligned_alloc",
              "posix_memalign", "memalign", "valloc", "pvalloc", "strdup", "strndup"}
FORBIDDEN_SYMBOLS = [
    ("heap", lambda s: s in HEAP_EXACT, "C heap allocation"),
    ("heap", lambda s: s.startswith(("_Znw", "_Zna")), "operator new (placement new is inline and "
     "never appears here)"),
    ("heap", lambda s: s.startswith(("_Zdl", "_Zda")),
     "operator delete; a deleting destructor (class with a public virtual destructor) references it: "
     "give interfaces a protected non-virtual destructor and make implementations final"),
    ("exceptions", lambda s: s in ("__cxa_allocate_exception", "__cxa_throw", "__cxa_rethrow",
                                   "__cxa_begin_catch", "__cxa_end_catch", "__gxx_personality_v0",
                                   "_Unwind_Resume"), "exception machinery"),
    ("exceptions", lambda s: re.match(r"^_ZSt\d+__throw_", s) is not None,
     "a std:: throw helper (the library code can throw; under -fno-exceptions it aborts)"),
    ("rtti", lambda s: s == "__dynamic_cast", "dynamic_cast"),
    ("rtti", lambda s: s.startswith(("_ZTI", "_ZTS", "_ZTVN10__cxxabiv1")), "typeinfo reference"),
    ("threads", lambda s: s.startswith(("_ZNSt6thread", "_ZNSt7jthread")) or s in
     ("pthread_create", "pthread_join", "pthread_detach", "thrd_create"), "thread creation"),
    ("stdio", lambda s: s in ("printf", "fprintf", "vprintf", "vfprintf", "puts", "fputs", "putchar",
                              "perror", "__printf_chk", "__fprintf_chk")
     or s.startswith(("_ZSt4cout", "_ZSt4cerr", "_ZSt4clog")), "printing from flight code"),
]
# Symbols an object may *define* only when a forbidden feature is on.
FORBIDDEN_DEFINED = [
    ("rtti", lambda s: s.startswith("_ZTI"), "typeinfo emitted (RTTI is on?)"),
]

# Exemptions: library -> {symbol: reason}. Every entry needs a reason a reviewer accepts.
EXEMPTIONS: dict[str, dict[str, str]] = {
    # Example (none needed today):
    # "vtm_hal_file": {"printf": "debug dump of the pose log, ground playback only"},
}


_CI_EDGE_RE = re.compile(r'^edge:\s*\{\s*sourcename:\s*"([^"]*)"\s*targetname:\s*"([^"]*)"')


def _callers(lib, member: str) -> dict[str, set[str]]:
    """symbol -> functions calling it, from the GCC call graph (.ci) of one object."""
    out: dict[str, set[str]] = {}
    for ci in lib.objdir.rglob(member[:-2] + ".ci") if member.endswith(".o") else ():
        for line in ci.read_text(errors="replace").splitlines():
            m = _CI_EDGE_RE.match(line.strip())
            if m:
                out.setdefault(m.group(2), set()).add(m.group(1).rpartition(":")[2])
    return out


def _demangle(names: set[str]) -> dict[str, str]:
    import shutil
    import subprocess
    names = sorted(n for n in names if n.startswith("_Z"))
    tool = shutil.which("c++filt")
    if not names or tool is None:
        return {}
    try:
        out = subprocess.run([tool], input="\n".join(names) + "\n", capture_output=True, text=True,
                             check=True).stdout.splitlines()
    except (OSError, subprocess.CalledProcessError):
        return {}
    return dict(zip(names, out)) if len(out) == len(names) else {}


def check_binaries(build_dir: Path) -> list[str]:
    if not build_dir.is_dir():
        raise UsageError(f"{build_dir}: not a directory")
    warnings: list[str] = []
    libs = discover_libraries(build_dir, warnings)
    if not libs:
        return [f"{build_dir}:0: binaries: no flight libraries (libvtm_*.a with .su files) found; build them first"]
    findings = []
    for lib in libs:
        exempt = EXEMPTIONS.get(lib.name, {})
        try:
            objects = elfparse.read_archive(lib.archive)
        except (elfparse.ParseError, OSError) as exc:
            findings.append(f"{lib.archive}:0: parse: {exc}")
            continue
        for obj in objects:
            where = f"{lib.archive}({obj.name})"
            callers = None
            for sym in obj.symbols:
                if not sym.name:
                    continue
                table = FORBIDDEN_SYMBOLS if sym.undefined else (
                    FORBIDDEN_DEFINED if sym.defined and sym.type != elfparse.STT_SECTION else [])
                for rule, match, text in table:
                    if match(sym.name) and sym.name not in exempt:
                        ref = "references" if sym.undefined else "defines"
                        if callers is None:
                            callers = _callers(lib, obj.name)
                        names = _demangle({sym.name} | callers.get(sym.name, set()))
                        pretty = f"{sym.name} [{names[sym.name]}]" if sym.name in names else sym.name
                        via = callers.get(sym.name)
                        via_txt = (" from " + ", ".join(names.get(c, c) for c in sorted(via))) if via else ""
                        findings.append(f"{where}:0: {rule}: {lib.name} {ref} {pretty}{via_txt} ({text})")
                        break
    return sorted(set(findings))


USAGE = __doc__.split("\n\n")[1]


def main(argv: list[str]) -> int:
    if len(argv) < 2 or argv[0] not in ("sources", "binaries", "all") or argv[0] in ("-h", "--help"):
        print("usage:\n" + USAGE, file=sys.stderr)
        return 2
    mode, args = argv[0], [Path(a) for a in argv[1:]]
    findings: list[str] = []
    try:
        if mode in ("sources", "all"):
            findings += check_sources(args[0])
            args = args[1:] if mode == "all" else []
            if mode == "sources" and len(argv) > 2:
                raise UsageError("sources takes one REPO_ROOT")
        if mode == "all" and not args:
            raise UsageError("all needs REPO_ROOT and at least one BUILD_DIR")
        if mode in ("binaries", "all"):
            for d in args:
                findings += check_binaries(d)
    except UsageError as exc:
        print(f"policy: {exc}", file=sys.stderr)
        return 2
    for f in findings:
        print(f)
    if findings:
        print(f"policy: {len(findings)} finding(s)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
