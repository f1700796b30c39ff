#!/usr/bin/env bash
# Builds the libFuzzer targets with Debian's clang (ASan + UBSan, checksums off) in build-fuzz and runs each
# from the seed corpus in fuzz/corpus: for FUZZ_SECONDS (default 15) each, or, with FUZZ_RUNS=N, for exactly
# N executions each (the endurance run: FUZZ_RUNS=2500000). Fails on any crash, leak or timeout; the input
# that caused it is left in build-fuzz/artifacts/. FUZZ_MERGE=1 then merges what the run found into the
# committed corpus, minimised (only inputs that add coverage).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-15}
limit=(-max_total_time="$seconds")
[ -n "${FUZZ_RUNS:-}" ] && limit=(-runs="$FUZZ_RUNS")
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION"
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DDC_FUZZ=ON -DCMAKE_UNITY_BUILD=ON \
    -DDC_BUILD_TESTS=OFF -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_targets
mkdir -p build-fuzz/artifacts
total=0
for corpus in recording frame_payload stray_text tum_text uvc_metadata mcap_reader cdr db3_store; do
    target=build-fuzz/fuzz/${corpus/recording/recording_reader}_fuzz
    work=build-fuzz/corpus/$corpus # grows between runs; the committed seeds stay as they are
    mkdir -p "$work"
    echo "fuzz.sh: $(basename "$target") (${limit[*]})"
    log=build-fuzz/$corpus.log
    if ! "$target" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
        -artifact_prefix=build-fuzz/artifacts/ "$work" "fuzz/corpus/$corpus" >"$log" 2>&1; then
        grep -E -A20 '^==[0-9]+==ERROR|SUMMARY|runtime error|deadly signal|out-of-memory|timeout' "$log" | head -60 >&2
        echo "fuzz.sh: $(basename "$target") failed; its input is in build-fuzz/artifacts/ (log: $log)" >&2
        exit 1
    fi
    grep -E '^stat::(number_of_executed_units|peak_rss_mb)' "$log"
    total=$((total + $(sed -n 's/^stat::number_of_executed_units: *//p' "$log")))
    if [ "${FUZZ_MERGE:-0}" = 1 ]; then
        "$target" -merge=1 -max_len=65536 "fuzz/corpus/$corpus" "$work" >>"$log" 2>&1
        echo "fuzz.sh: fuzz/corpus/$corpus now holds $(ls "fuzz/corpus/$corpus" | wc -l) inputs"
    fi
done
echo "fuzz.sh: no crashes, no leaks, $total executions in all"
