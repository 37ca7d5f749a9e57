#!/usr/bin/env bash
# Static analysis of flight code (fsw/ and hal/): clang-tidy (.clang-tidy at the repository
# root) and cppcheck (tools/checks/cppcheck-suppressions.txt). See docs/static-analysis.md.
#
#   tools/checks/static_analysis.sh BUILD_DIR [--tidy-only|--cppcheck-only]
#
# BUILD_DIR is a configured HOST build (it provides compile_commands.json; GCC-only flags
# such as -fcallgraph-info are dropped for clang-tidy). Exit status: 0 clean, 1 findings,
# 2 usage or missing tools.
set -euo pipefail

usage() { echo "usage: $0 BUILD_DIR [--tidy-only|--cppcheck-only]" >&2; exit 2; }
[[ $# -ge 1 && $# -le 2 ]] || usage
build_dir=$(cd "$1" 2>/dev/null && pwd) || { echo "static_analysis: $1: no such directory" >&2; exit 2; }
mode=${2:-all}
case "$mode" in all|--tidy-only|--cppcheck-only) ;; *) usage ;; esac
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
db="$build_dir/compile_commands.json"
[[ -f "$db" ]] || { echo "static_analysis: $db missing (configure with CMAKE_EXPORT_COMPILE_COMMANDS=ON)" >&2; exit 2; }
jobs=${VTM_ANALYSIS_JOBS:-2}

find_tool() { for t in "$@"; do command -v "$t" >/dev/null 2>&1 && { command -v "$t"; return 0; }; done; return 1; }
tidy=$(find_tool clang-tidy-14 clang-tidy) || { echo "static_analysis: clang-tidy not found" >&2; exit 2; }
cppcheck=$(find_tool cppcheck) || { echo "static_analysis: cppcheck not found" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/vtm-analysis.XXXXXX")
trap 'rm -rf "$work"' EXIT

# Flight translation units only (fsw/**.cpp, hal/**.cpp), with flags clang understands.
python3 - "$db" "$repo" "$work/compile_commands.json" <<'EOF'
import json, os, shlex, sys
db, repo, out = sys.argv[1], os.path.realpath(sys.argv[2]), sys.argv[3]
GCC_ONLY = ("-fcallgraph-info", "-fstack-usage", "-maccumulate-outgoing-args")
entries = []
for e in json.load(open(db)):
    f = os.path.realpath(os.path.join(e["directory"], e["file"]))
    rel = os.path.relpath(f, repo)
    if not (rel.startswith("fsw/") or rel.startswith("hal/")) or not rel.endswith(".cpp"):
        continue
    if not os.path.isfile(f):
        print(f"static_analysis: warning: {rel} is in the compilation database but not on disk "
              f"(re-run cmake); skipped", file=sys.stderr)
        continue
    args = e["arguments"] if "arguments" in e else shlex.split(e["command"])
    args = [a for a in args if not a.startswith(GCC_ONLY)]
    flight = "-DVTM_FLIGHT_CODE=1" in args
    # A file compiled by several targets is analysed once, with the flight library's flags.
    prev = next((x for x in entries if x["file"] == f), None)
    if prev is not None:
        if flight and "-DVTM_FLIGHT_CODE=1" not in prev["arguments"]:
            prev.update(directory=e["directory"], arguments=args)
        continue
    entries.append({"directory": e["directory"], "file": f, "arguments": args})
if not entries:
    sys.exit("static_analysis: no fsw/ or hal/ sources in the compilation database")
# Headers no .cpp includes yet (interfaces ahead of their drivers) would never be seen:
# give each such header a translation unit of its own. A header some flight .cpp includes
# (directly or through another header) is analysed there (HeaderFilterRegex); that every
# header is self-contained is checked by the compiler below (--syntax-only units).
# Flags of a generated unit: those of a flight TU plus every flight include directory.
import re
incs = []
search = []  # the same directories, absolute (a relative -I is relative to its entry's directory)
for e in entries:
    for i, a in enumerate(e["arguments"]):
        d = e["arguments"][i + 1] if a == "-I" else a[2:] if a.startswith("-I") else None
        if d and d not in incs:
            incs.append(d)
            search.append(os.path.join(e["directory"], d))
inc_re = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)
def resolve(name, from_file):
    for d in [os.path.dirname(from_file)] + search:
        c = os.path.realpath(os.path.join(d, name))
        if os.path.isfile(c):
            return c
    return None
seen, todo = set(), [e["file"] for e in entries]
while todo:  # bound: every file of fsw/ and hal/ once
    f = todo.pop()
    try:
        text = open(f, errors="replace").read()
    except OSError:
        continue
    for name in inc_re.findall(text):
        h = resolve(name, f)
        if h and h not in seen:
            seen.add(h)
            todo.append(h)
base = next(e for e in entries if "/hal/" in e["file"]) if any("/hal/" in e["file"] for e in entries) else entries[0]
hdr_dir = os.path.join(os.path.dirname(out), "headers")
n_hdr = 0
all_units = []
for top in ("fsw", "hal"):
    for root, _dirs, files in os.walk(os.path.join(repo, top)):
        for name in sorted(files):
            if not name.endswith((".hpp", ".h")) or "/include/" not in root + "/":
                continue
            hdr = os.path.realpath(os.path.join(root, name))
            tu = os.path.join(hdr_dir, os.path.relpath(hdr, repo).replace("/", "__") + ".cpp")
            os.makedirs(hdr_dir, exist_ok=True)
            with open(tu, "w") as fh:
                fh.write(f'#include "{hdr}"  // generated by static_analysis.sh\n')
            args = [a for a in base["arguments"]]
            src_i = args.index("-c") + 1 if "-c" in args else len(args) - 1
            args[src_i] = tu
            if "-o" in args:
                args[args.index("-o") + 1] = tu + ".o"
            args = args[:1] + [f"-I{d}" for d in incs] + args[1:]
            unit = {"directory": base["directory"], "file": tu, "arguments": args}
            all_units.append(unit)
            if hdr not in seen:
                entries.append(unit)
                n_hdr += 1
json.dump(all_units, open(os.path.join(os.path.dirname(out), "header_units.json"), "w"), indent=1)
# clang-tidy's matchers walk the whole AST, Eigen's instantiations included, once per unit:
# the flight .cpp files of one directory that share their flags are analysed together, in
# one generated unit that includes them all (a module's unit instead of one per file: 6x
# less time, docs/static-analysis.md "Module units"). A file that defines or undefines a macro
# (it would change the files after it) stays alone; a unit that does not compile (two
# files with a same-named internal symbol) is analysed file by file (the runner below).
flight = entries[:len(entries) - n_hdr]
groups = {}
for e in flight:
    a = list(e["arguments"])
    if "-o" in a:
        i = a.index("-o"); del a[i:i + 2]
    a = [x for x in a if x != "-c" and os.path.realpath(os.path.join(e["directory"], x)) != e["file"]]
    text = open(e["file"], errors="replace").read()
    alone = re.search(r'^\s*#\s*(define|undef)\b', text, re.M) is not None
    key = (e["directory"], os.path.dirname(e["file"]), tuple(a), e["file"] if alone else "")
    groups.setdefault(key, []).append(e)
unit_dir = os.path.join(os.path.dirname(out), "units")
units, members = [], {}
for (directory, src_dir, args, _alone), es in groups.items():
    if len(es) == 1:
        units.append(es[0])
        continue
    name = os.path.relpath(src_dir, repo).replace("/", "__") + f"__{len(units)}.cpp"
    path = os.path.join(unit_dir, name)
    os.makedirs(unit_dir, exist_ok=True)
    with open(path, "w") as fh:
        fh.write("// generated by static_analysis.sh: the files of one module, analysed together\n")
        for e in sorted(es, key=lambda x: x["file"]):
            fh.write(f'#include "{e["file"]}"  // NOLINT(bugprone-suspicious-include)\n')
    units.append({"directory": directory, "file": path, "arguments": list(args) + ["-c", path]})
    members[path] = [e["file"] for e in es]
units += entries[len(entries) - n_hdr:]
json.dump(members, open(os.path.join(os.path.dirname(out), "unit_members.json"), "w"), indent=1)
json.dump(units, open(out, "w"), indent=1)
# The per-file database: the fallback for a module unit that does not compile, and cppcheck's.
os.makedirs(os.path.join(os.path.dirname(out), "files"), exist_ok=True)
json.dump(entries, open(os.path.join(os.path.dirname(out), "files", "compile_commands.json"), "w"), indent=1)
print(f"static_analysis: {len(entries) - n_hdr} flight translation units in {len(units) - n_hdr} analysis units, "
      f"{n_hdr} headers no unit includes, {len(all_units)} headers checked self-contained",
      file=sys.stderr)
EOF

# The generated header TUs live under $work: give them the repository's configuration.
cp "$repo/.clang-tidy" "$work/.clang-tidy"

status=0

if [[ "$mode" != "--cppcheck-only" ]]; then
  # Every flight header compiles on its own (the build's compiler and flags, syntax only).
  echo "== self-contained headers"
  python3 - "$work/header_units.json" "$work/headers.cmds" <<'EOF'
import json, shlex, sys
with open(sys.argv[2], "w") as out:
    for u in json.load(open(sys.argv[1])):
        a = list(u["arguments"])
        if "-o" in a:
            i = a.index("-o"); del a[i:i + 2]
        a = [x for x in a if x != "-c"] + ["-fsyntax-only"]
        out.write("cd " + shlex.quote(u["directory"]) + " && " + " ".join(shlex.quote(x) for x in a) + "\n")
EOF
  xargs -P "$jobs" -d '\n' -n 1 sh -c 'eval "$0" 2>&1 || echo "static_analysis: header unit failed: $0"' \
    < "$work/headers.cmds" > "$work/headers.log" || true
  if grep -q "header unit failed" "$work/headers.log"; then
    cat "$work/headers.log"; status=1
  fi
  echo "self-contained headers: $(wc -l < "$work/headers.cmds") checked, $(grep -c "header unit failed" "$work/headers.log" || true) failed"
fi

if [[ "$mode" != "--cppcheck-only" ]]; then
  echo "== clang-tidy ($tidy, config $repo/.clang-tidy)"
  # One clang-tidy per analysis unit, $jobs at once, each into its own log; the header filter
  # also admits the flight .cpp files a module unit includes.
  filter='.*/(fsw|hal)/.*\.(h|hpp|cpp)$'
  tidy_units() {  # DB_DIR LOG_DIR FILE...
    local db_dir=$1 log_dir=$2; shift 2
    mkdir -p "$log_dir"
    printf '%s\n' "$@" | xargs -P "$jobs" -d '\n' -n 1 sh -c \
      'log="$3/$(echo "$4" | tr / _).log"; "$0" --quiet -p "$1" --header-filter="$2" "$4" > "$log" 2>&1 || touch "$log.failed"' \
      "$tidy" "$db_dir" "$filter" "$log_dir"
  }
  mapfile -t files < <(python3 -c 'import json,sys; [print(e["file"]) for e in json.load(open(sys.argv[1]))]' "$work/compile_commands.json")
  tidy_units "$work" "$work/tidy-logs" "${files[@]}"
  # A module unit that does not compile: its files one by one.
  mapfile -t again < <(python3 - "$work/unit_members.json" "$work/tidy-logs" <<'EOF'
import json, os, sys
for unit, files in json.load(open(sys.argv[1])).items():
    log = os.path.join(sys.argv[2], unit.replace("/", "_") + ".log")
    if "clang-diagnostic-error" in open(log, errors="replace").read():
        os.rename(log, log + ".did-not-compile")
        if os.path.exists(log + ".failed"):
            os.remove(log + ".failed")
        print("\n".join(files))
EOF
)
  if [[ ${#again[@]} -gt 0 ]]; then
    echo "clang-tidy: ${#again[@]} file(s) of module units that did not compile together, analysed one by one"
    tidy_units "$work/files" "$work/tidy-logs" "${again[@]}"
  fi
  cat "$work"/tidy-logs/*.log > "$work/tidy.log"
  if ls "$work"/tidy-logs/*.failed > /dev/null 2>&1; then
    status=1
  fi
  # One line per finding (a header seen from several translation units is reported once),
  # without colour codes.
  sed -E 's/\x1b\[[0-9;]*m//g' "$work/tidy.log" \
    | grep -E '^[^ ].*:[0-9]+:[0-9]+: (warning|error): ' | sed 's/,-warnings-as-errors\]/]/' \
    | sort -u >"$work/tidy.findings" || true
  # Diagnostics without a location (e.g. a translation unit that does not compile).
  sed -E 's/\x1b\[[0-9;]*m//g' "$work/tidy.log" | grep -E '^(error|Error while processing)' \
    | sort -u >>"$work/tidy.findings" || true
  cat "$work/tidy.findings"
  n=$(wc -l <"$work/tidy.findings")
  echo "clang-tidy: $n finding(s)"
  [[ "$n" == 0 ]] || status=1
  if [[ $status -ne 0 && "$n" == 0 ]]; then
    echo "clang-tidy failed without a diagnostic; its log:"; sed -E 's/\x1b\[[0-9;]*m//g' "$work/tidy.log"
  fi
fi

if [[ "$mode" != "--tidy-only" ]]; then
  echo "== cppcheck ($($cppcheck --version))"
  # Eigen is header-only and huge: cppcheck sees the flight sources with their own include
  # paths but without -isystem directories (their headers are treated as missing system
  # headers, which is suppressed). --library=posix knows clock_gettime & co.
  python3 - "$work/files/compile_commands.json" "$work/cppcheck_db.json" <<'EOF'
import json, sys
entries = json.load(open(sys.argv[1]))
for e in entries:
    args, out, skip = e["arguments"], [], False
    for a in args:
        if skip:
            skip = False
            continue
        if a == "-isystem":
            skip = True
            continue
        if a.startswith("-isystem"):
            continue
        out.append(a)
    e["arguments"] = out
json.dump(entries, open(sys.argv[2], "w"), indent=1)
EOF
  if ! "$cppcheck" --project="$work/cppcheck_db.json" \
      --enable=warning,style,performance,portability --inline-suppr --error-exitcode=1 \
      --std=c++17 --language=c++ --library=posix -j "$jobs" --quiet \
      --suppressions-list="$repo/tools/checks/cppcheck-suppressions.txt" \
      --suppress='*:/usr/include/*' --suppress=missingIncludeSystem \
      --cppcheck-build-dir="$work" \
      --template='{file}:{line}:{column}: {severity}: {message} [{id}]' \
      2>"$work/cppcheck.log"; then
    status=1
  fi
  cat "$work/cppcheck.log"
  echo "cppcheck: $(grep -c ': \(error\|warning\|style\|performance\|portability\|information\): ' "$work/cppcheck.log" || true) finding(s)"
fi

exit $status
