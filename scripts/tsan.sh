#!/usr/bin/env bash
# The ThreadSanitizer tier: builds only the test targets listed below with -fsanitize=thread in build-tsan
# and runs each as one process (TSan's start-up per test would cost more than the tests), failing on the
# first data race, lock-order inversion or thread leak. Adding a target is one line in `targets`.
set -euo pipefail
cd "$(dirname "$0")/.."
targets=(
    test_unit      # sessions, the synthetic device's render-ahead threads, latest-wins slots,
                   # the ordered pool, accumulation worker
    test_recording # the recorder's ordered pool (encoders, the in-order writer), replay
    test_live      # the V4L2 capture thread over the fake driver, the camera-list watcher
)
# The engine's tests (frame processor, instrument: three threads around one demand), where the tree has them.
if [ -f tests/engine/CMakeLists.txt ]; then
    targets+=(test_engine)
fi
start=$(date +%s)
# -O1 runs the tests several times faster under TSan; batches of files (unity build) and line tables only
# (-g1) halve the build, as for the ASan build in test.sh.
cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DCMAKE_UNITY_BUILD=ON \
    -DDC_BUILD_TESTS=ON -DDC_WERROR=ON -DDC_TSAN=ON >/dev/null
cmake --build build-tsan -j"$(nproc)" --target "${targets[@]}"
built=$(date +%s)
# scripts/tsan.supp: only libraries we do not build (GDAL, FFmpeg), each with its reason.
export TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/scripts/tsan.supp ${TSAN_OPTIONS:-}"
# The engine's stress tests run their sources, demand changes, seeks and source switches this long.
export DC_ENGINE_STRESS_SECONDS=${DC_ENGINE_STRESS_SECONDS:-10}
for target in "${targets[@]}"; do
    binary=$(find build-tsan/tests -name "$target" -type f -executable | head -1)
    [ -n "$binary" ] || { echo "tsan.sh: $target was not built" >&2; exit 1; }
    echo "tsan.sh: $target"
    "$binary" --gtest_brief=1
done
echo "tsan.sh: no data races (build $((built - start)) s, tests $(($(date +%s) - built)) s)"
