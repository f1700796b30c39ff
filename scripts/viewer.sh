#!/usr/bin/env bash
# Command 1: install what is missing, build, and run the viewer on the built-in synthetic depth camera.
# With no display it runs headless and writes the panels as PNGs plus summary.json instead.
# Extra arguments go to depthcloud (e.g. --source synthetic:640x480@30).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    -DDC_BUILD_TESTS=OFF >/dev/null
cmake --build build -j"$(nproc)" --target depthcloud
exec ./build/tool/depthcloud "$@"
