#!/usr/bin/env python3
"""vector_guard: flight code that GCC 12.2 would vectorise wrongly on the scalar targets.

    vector_guard.py BUILD_DIR [--jobs N]

GCC 12.2 (Debian 12's cross compilers) turns the high half of a narrow product, e.g.
`(a[i] * b[i]) >> 8` over bytes, into a vector multiply-high (`.MULH`) even where the target
has no vector unit; the "vector" is then a 32-bit word and the word's own multiply-high
(ppc `mulhwu`, arm `umull`) gives wrong bytes. Measured here (2026-12-06) at -O3 on
ppc750, leon3, riscv64 and armhf (x86-64 and aarch64 are right): GCC bug 106322, fixed in
GCC 12.3. docs/build.md "Compiler bugs" has the reproducer.

The check reads the vectoriser's report (-fdump-tree-vect-details) of every flight source
(fsw/, hal/) of BUILD_DIR's compile_commands.json and reports each loop where the
vectoriser recognised the pattern, as `file:line: vector-mulh: ...`. A source built with
the report on (cmake -DVTM_VECTORISER_DUMPS=ON: the report lies beside its object, no
report there means no loop to vectorise) is read as built; any other is recompiled with the
report to a scratch directory. Exit 1 when there is any finding, 2 on a usage error or a
source built with the report whose object is missing, 0 when clean. Standard library only
(python3).
"""

from __future__ import annotations

import glob
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

sys.dont_write_bytecode = True

PATTERN = "vect_recog_mulhs_pattern: detected"


def flight_entries(build: Path, root: Path) -> list[dict]:
    db = build / "compile_commands.json"
    if not db.is_file():
        raise ValueError(f"{db}: no compile_commands.json (configure the build first)")
    entries = json.loads(db.read_text())
    keep = []
    for e in entries:
        rel = os.path.relpath(e["file"], root)
        if rel.startswith(("fsw/", "hal/")):
            keep.append(e)
    return keep


def scan(dump: Path, root: Path) -> set[str]:
    found = set()
    for line in dump.read_text(errors="replace").splitlines():
        if PATTERN in line:
            where = line.split(": note:")[0]
            found.add(f"{os.path.relpath(where, root)}: vector-mulh: a narrow product's high half "
                      f"(GCC 12.2 miscompiles it on ppc750, leon3, riscv64, armhf); widen the "
                      f"product or keep the loop scalar (docs/build.md \"Compiler bugs\")")
    return found


def built_dumps(entry: dict, args: list[str]) -> list[Path] | None:
    """The reports the build wrote beside the object, or None when it wrote none."""
    if "-fdump-tree-vect-details" not in args or "-o" not in args:
        return None
    obj = Path(entry["directory"]) / args[args.index("-o") + 1]
    if not obj.is_file():
        raise ValueError(f"{obj}: not built (build the target before the guard)")
    stem = obj.name[:-2] if obj.name.endswith(".o") else obj.name
    # GCC names it <object without .o>.<source suffix>.<pass>t.vect
    return sorted(obj.parent.glob(f"{glob.escape(stem)}.*t.vect"))


def findings_of(entry: dict, root: Path, scratch: Path) -> list[str]:
    args = shlex.split(entry["command"])
    if args and os.path.basename(args[0]) == "ccache":
        args = args[1:]
    built = built_dumps(entry, args)
    if built is not None:
        return sorted({f for d in built for f in scan(d, root)})
    if "-o" in args:
        i = args.index("-o")
        args[i + 1] = os.devnull
    dump = scratch / (re.sub(r"[^A-Za-z0-9]", "_", entry["file"]) + ".vect")
    args.append(f"-fdump-tree-vect-details={dump}")
    run = subprocess.run(args, cwd=entry["directory"], capture_output=True, text=True)
    if run.returncode != 0:
        return [f"{entry['file']}: vector-mulh: the compiler failed: {run.stderr.strip()[:300]}"]
    found = set()
    if dump.exists():
        found = scan(dump, root)
        dump.unlink()
    return sorted(found)


def main(argv: list[str]) -> int:
    if len(argv) < 2:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    build = Path(argv[1]).resolve()
    jobs = os.cpu_count() or 1
    if "--jobs" in argv:
        jobs = int(argv[argv.index("--jobs") + 1])
    root = Path(__file__).resolve().parent.parent.parent
    try:
        entries = flight_entries(build, root)
    except ValueError as e:
        print(f"vector_guard: {e}", file=sys.stderr)
        return 2
    try:
        with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(lambda e: findings_of(e, root, Path(tmp)), entries))
    except ValueError as e:
        print(f"vector_guard: {e}", file=sys.stderr)
        return 2
    lines = sorted({l for r in results for l in r})
    for line in lines:
        print(line)
    read = sum(1 for e in entries if "-fdump-tree-vect-details" in e["command"])
    print(f"vector_guard: {len(entries)} flight sources of {build.name} ({read} reports read as built, "
          f"{len(entries) - read} recompiled), {len(lines)} findings")
    return 1 if lines else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
