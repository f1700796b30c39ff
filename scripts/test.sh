#!/usr/bin/env bash
# Command 2: install what is missing, build, and run every test tier (unit, gl, ui, app, kernel, package),
# clang's thread-safety analysis, then every tier that needs no kernel (unit with ROS, gl, ui, app) and the UI
# monkey again under AddressSanitizer + UndefinedBehaviorSanitizer, the threaded tests under ThreadSanitizer,
# and the fuzz targets briefly.
set -euo pipefail
cd "$(dirname "$0")/.."

# How long each stage took, printed at the end whether the run passed or not: CI's time is the sum.
stage_start=$SECONDS
stages=()
stage_done() {
    stages+=("$(printf '%5d s  %s' $((SECONDS - stage_start)) "$1")")
    stage_start=$SECONDS
}
report_stages() {
    echo "test.sh: time per stage (${SECONDS} s in all)"
    printf '  %s\n' "${stages[@]}"
}
trap report_stages EXIT

./scripts/setup.sh
stage_done "setup"
jobs=$(nproc)

# Line tables only (-g1), as the viewer's build: enough for a backtrace and addr2line, and the build takes
# about a fifth less time than with full debug information.
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
    -DDC_BUILD_TESTS=ON -DDC_WERROR=ON >/dev/null
cmake --build build -j"$jobs"
stage_done "build"

# Every tier the issues require must have tests; an empty label would pass silently.
for label in unit gl ui app kernel package; do
    count=$(ctest --test-dir build -N -L "^${label}\$" | sed -n 's/^Total Tests: //p')
    if [ "${count:-0}" -eq 0 ]; then
        echo "test.sh: no tests carry the label '$label'" >&2
        exit 1
    fi
done
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 600
stage_done "every tier"
./scripts/thread-safety.sh build # clang's thread-safety analysis of the annotated shared state
stage_done "thread-safety analysis"

echo "test.sh: every tier that needs no kernel under ASan + UBSan: unit (ROS tests included), gl, ui and app"
# The sanitizer builds are made once and thrown away, so they build in batches of files (CMake's unity build,
# over twice as fast here) with line tables only (-g1: what a sanitizer's report needs).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DCMAKE_UNITY_BUILD=ON \
    -DDC_BUILD_TESTS=ON -DDC_WERROR=ON -DDC_SANITIZE=ON >/dev/null
cmake --build build-asan -j"$jobs" --target test_unit test_processing test_settings test_gl test_recording test_live \
    test_engine test_probe test_ui test_ros test_app
stage_done "ASan + UBSan build"
# Mesa's llvmpipe keeps allocations alive until process exit; leak checking stays on for the unit tier.
ASAN_OPTIONS=detect_leaks=1 ctest --test-dir build-asan --output-on-failure -j"$jobs" -L '^unit$'
ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-asan --output-on-failure -j"$jobs" -L '^gl$'
# The ui tier and the sanitized depthcloud itself, end to end (headless and in a window under Xvfb: source,
# engine, presenter, GL, input and the files it writes). Three app tests are left to the tiers above: they
# repeat what others here cover, at ten times the frames (a 300-frame run on the splat path, two benchmarks;
# SourcesPanelTest covers two cameras accumulating).
ASAN_OPTIONS=detect_leaks=0 ctest --test-dir build-asan --output-on-failure -j"$jobs" -L '^(ui|app)$' \
    -E '^(MonkeyTest\.|AppWindow\.SoftwareGlDrawsA640x480CameraOnTheSplatPath|Cli\.BenchReplayRunsOnSynthetic|BenchCamera\.ThePairAccumulating)'
# The UI monkey: the seeds that found crashes, then a fresh seed for a minute (its seed is printed first).
echo "test.sh: the UI monkey under ASan + UBSan"
(cd build-asan && ASAN_OPTIONS=detect_leaks=0 DC_MONKEY_SECONDS=60 ./tests/ui/test_ui --gtest_filter='MonkeyTest.*')
stage_done "ASan + UBSan tests"
./scripts/tsan.sh # the unit, recording and live tests under ThreadSanitizer
stage_done "ThreadSanitizer build and tests"
./scripts/fuzz.sh # libFuzzer targets of the recording reader and importers, 15 s each
stage_done "fuzz build and runs"
