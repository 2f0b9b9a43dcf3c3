#!/usr/bin/env bash
# Runs the API fuzzer for SECONDS (default FUZZ_SECONDS or 300) on the
# committed seeds (fuzz/corpus, read only) plus a working corpus of what it
# finds (build-fuzz/corpus, not committed). A crash, sanitizer report or
# oracle disagreement stops it with a non-zero status and leaves the input in
# build-fuzz/artifacts/. Usage: fuzz/run.sh [SECONDS]
#
# FUZZ_RUNS=N (the test suite's mode) runs N inputs from seed 1 with a fresh
# working corpus beside the committed seeds, and a per-input limit of 600 s
# instead of 30: an input of many detects at coordinates near 1e15 takes about
# 10 s under ASan with the GMP oracle, and a slow machine must not turn that
# into a failure. (The inputs still drift a little from run to run: some
# worlds run on 2 threads, whose coverage varies with scheduling, and coverage
# steers the mutations.) SECONDS then only caps the time. Without FUZZ_RUNS
# the seed comes from the clock and the working corpus grows from run to run,
# which is what a long `make fuzz` wants.
# FUZZ_TIMEOUT=S raises the per-input limit of that mode (30 s): on a machine
# busy with other work an input of many oracle checks can take minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${HGCD_FUZZ_BUILD:-build-fuzz}
seconds=${1:-${FUZZ_SECONDS:-300}}
bash fuzz/build.sh  # exits 77 (and so do we) when clang's libFuzzer runtime is missing
mkdir -p "$out/corpus" "$out/artifacts"
corpus="$out/corpus"
mode=(-timeout="${FUZZ_TIMEOUT:-30}")
if [ -n "${FUZZ_RUNS:-}" ]; then
    corpus=$(mktemp -d)
    trap 'rm -rf "$corpus"' EXIT
    mode=(-seed=1 -runs="$FUZZ_RUNS" -timeout=600)
fi
log="$out/fuzz.log"
export OMP_WAIT_POLICY=passive
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
set +e
"$out/fuzz_api" "$corpus" fuzz/corpus -max_total_time="$seconds" -max_len=600 "${mode[@]}" \
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
echo "fuzz: ${execs:-?} executions (${secs:-?}/s, at most ${seconds} s), no finding; corpus $(ls "$corpus" | wc -l) + $(ls fuzz/corpus | wc -l) seeds"
