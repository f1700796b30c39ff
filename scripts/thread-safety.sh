#!/usr/bin/env bash
# Clang's thread-safety analysis over every translation unit that uses the annotated mutex (base/mutex.h) or
# the kit built on it (base/latest_slot.h, base/ordered_pool.h, whose templates are checked where used):
# each is compiled for syntax only, with its flags from the build's compile_commands.json, and any access
# to guarded state without its mutex is an error. Usage: scripts/thread-safety.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
command -v clang++ > /dev/null || { echo "thread-safety: clang++ is missing (apt-get install clang)" >&2; exit 2; }
[[ -f "$build/compile_commands.json" ]] || { echo "thread-safety: no $build/compile_commands.json" >&2; exit 2; }
/usr/bin/python3 - "$root" "$build/compile_commands.json" <<'PY'
import json, os, re, shlex, subprocess, sys
root, database = sys.argv[1], sys.argv[2]
# GCC's options that clang does not know.
gcc_only = re.compile(r"^-W(no-)?(error=)?(dangling-reference|maybe-uninitialized|class-memaccess|stringop-.*)$")
checked = failed = 0
seen = set()
for entry in json.load(open(database)):
    source = entry["file"]
    if not source.startswith(root + "/") or source.startswith(root + "/tests/") or source in seen:
        continue
    header = os.path.splitext(source)[0] + ".h"
    text = open(source).read() + (open(header).read() if os.path.exists(header) else "")
    kit = ("base/mutex.h", "base/latest_slot.h", "base/ordered_pool.h", "DC_GUARDED_BY")
    if not any(marker in text for marker in kit):
        continue
    seen.add(source)
    args = shlex.split(entry["command"])[1:]
    kept, skip = [], False
    for a in args:
        if skip:
            skip = False
            continue
        if a == "-o":
            skip = True
            continue
        if a == "-c" or gcc_only.match(a):
            continue
        kept.append(a)
    command = ["clang++", "-fsyntax-only", "-Wthread-safety", "-Wthread-safety-beta", "-Werror=thread-safety",
               "-Wno-unknown-warning-option"] + kept
    result = subprocess.run(command, cwd=entry["directory"], capture_output=True, text=True)
    checked += 1
    if result.returncode != 0:
        failed += 1
        sys.stderr.write(result.stderr)
print(f"thread-safety: {checked} translation units checked, {failed} failed")
sys.exit(1 if failed or not checked else 0)
PY
