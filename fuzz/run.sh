#!/usr/bin/env bash
# Runs the API fuzzer for SECONDS (default FUZZ_SECONDS or 300) on the
# committed seeds (fuzz/corpus, read only) plus a working corpus of what it
# finds (build-fuzz/corpus, not committed). A crash, sanitizer report or
# oracle disagreement stops it with a non-zero status and leaves the input in
# build-fuzz/artifacts/. Usage: fuzz/run.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
out=${HGCD_FUZZ_BUILD:-build-fuzz}
seconds=${1:-${FUZZ_SECONDS:-300}}
bash fuzz/build.sh  # exits 77 (and so do we) when clang's libFuzzer runtime is missing
mkdir -p "$out/corpus" "$out/artifacts"
log="$out/fuzz.log"
export OMP_WAIT_POLICY=passive
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
set +e
"$out/fuzz_api" "$out/corpus" fuzz/corpus -max_total_time="$seconds" -max_len=600 -timeout=30 \
    -rss_limit_mb=2560 -print_final_stats=1 -artifact_prefix="$out/artifacts/" >"$log" 2>&1
rc=$?
set -e
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
secs=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
grep -E '^fuzz_api:|FUZZ FINDING|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error|known bug' "$log" | sort | uniq -c | sort -rn | head -20 || true
if [ $rc -ne 0 ]; then
    tail -n 60 "$log"
    echo "fuzz: FAILED after ${execs:-?} executions; input in $out/artifacts/ (log: $log)" >&2
    exit 1
fi
echo "fuzz: ${execs:-?} executions in ${seconds} s (${secs:-?}/s), no finding; corpus $(ls "$out/corpus" | wc -l) + $(ls fuzz/corpus | wc -l) seeds"
