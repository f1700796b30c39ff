#!/usr/bin/env bash
# Builds the libFuzzer targets with Debian's clang (ASan + UBSan, checksums off) in build-fuzz and runs each
# for FUZZ_SECONDS (default 15) from the seed corpus in fuzz/corpus. Fails on any crash, leak or timeout;
# the input that caused it is left in build-fuzz/artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-15}
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -DFUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION"
cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DDC_FUZZ=ON \
    -DDC_BUILD_TESTS=OFF -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_targets
mkdir -p build-fuzz/artifacts
for corpus in recording frame_payload stray_text tum_text; do
    target=build-fuzz/fuzz/${corpus/recording/recording_reader}_fuzz
    work=build-fuzz/corpus/$corpus # grows between runs; the committed seeds stay as they are
    mkdir -p "$work"
    echo "fuzz.sh: $(basename "$target") for ${seconds}s"
    log=build-fuzz/$corpus.log
    if ! "$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
        -artifact_prefix=build-fuzz/artifacts/ "$work" "fuzz/corpus/$corpus" >"$log" 2>&1; then
        grep -E -A20 '^==[0-9]+==ERROR|SUMMARY|runtime error|deadly signal|out-of-memory|timeout' "$log" | head -60 >&2
        echo "fuzz.sh: $(basename "$target") failed; its input is in build-fuzz/artifacts/ (log: $log)" >&2
        exit 1
    fi
    grep -E '^stat::(number_of_executed_units|peak_rss_mb)' "$log"
done
echo "fuzz.sh: no crashes"
