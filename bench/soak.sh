#!/usr/bin/env bash
# The soak run: bench_soak (a churning world checked for aliased ids, bounded
# memory and the oracle's pairs) in a release build, not part of make test.
#
#   bench/soak.sh [bench_soak options]   defaults: --ticks 100000 --bodies 2000
#                                        --churn 20 --check-every 1000 --threads 1
# Prints bench_soak's progress and its JSON line; exits non-zero on a failure.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-deps.sh test
if [ -f build-bench/build.ninja ]; then
    meson configure build-bench -Dbuildtype=release -Dtests=false >/dev/null
else
    meson setup build-bench --buildtype=release -Dtests=false >/dev/null
fi
meson compile -C build-bench bench/bench_soak >/dev/null
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(--ticks 100000 --bodies 2000 --churn 20 --check-every 1000 --threads 1)
OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive} build-bench/bench/bench_soak "${args[@]}"
