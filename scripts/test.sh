#!/usr/bin/env bash
# Command 2: install what is missing, build, and run every test tier (unit, gl, ui, app, kernel, package),
# clang's thread-safety analysis, then the unit (with ROS) and gl tiers, the headless app and the UI monkey
# again under AddressSanitizer + UndefinedBehaviorSanitizer, the threaded tests under ThreadSanitizer, and the
# fuzz targets briefly.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
jobs=$(nproc)

cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDC_BUILD_TESTS=ON -DDC_WERROR=ON >/dev/null
cmake --build build -j"$jobs"

# Every tier the issues require must have tests; an empty label would pass silently.
for label in unit gl ui app kernel package; do
    count=$(ctest --test-dir build -N -L "^${label}\$" | sed -n 's/^Total Tests: //p')
    if [ "${count:-0}" -eq 0 ]; then
        echo "test.sh: no tests carry the label '$label'" >&2
        exit 1
    fi
done
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 600
./scripts/thread-safety.sh build # clang's thread-safety analysis of the annotated shared state

echo "test.sh: the unit tier (ROS tests included), the gl tier and the headless app under ASan + UBSan"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DDC_BUILD_TESTS=ON -DDC_WERROR=ON -DDC_SANITIZE=ON >/dev/null
cmake --build build-asan -j"$jobs" --target test_unit test_processing test_settings test_gl test_recording test_live \
    test_engine test_probe test_ui test_ros test_app
# Mesa's llvmpipe keeps allocations alive until process exit; leak checking stays on for the unit tier.
ASAN_OPTIONS=detect_leaks=1 ctest --test-dir build-asan --output-on-failure -j"$jobs" -L '^unit$'
ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-asan --output-on-failure -j"$jobs" -L '^gl$'
# The sanitized depthcloud itself, end to end: source, engine, presenter, GL and the files it writes.
ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-asan --output-on-failure -j"$jobs" -R '^AppHeadless\.'
# The UI monkey: the seeds that found crashes, then a fresh seed for a minute (its seed is printed first).
echo "test.sh: the UI monkey under ASan + UBSan"
(cd build-asan && ASAN_OPTIONS=detect_leaks=0 DC_MONKEY_SECONDS=60 ./tests/ui/test_ui --gtest_filter='MonkeyTest.*')
./scripts/tsan.sh # the unit, recording and live tests under ThreadSanitizer
./scripts/fuzz.sh # libFuzzer targets of the recording reader and importers, 15 s each
