#!/usr/bin/env bash
# Every library source must refuse to compile with -ffast-math or -Ofast
# (src/ieee.hpp says why): each src/*.cpp is compiled with each flag,
# syntax only, and must stop with ieee.hpp's message. A new source that
# forgets the include fails here. Called by scripts/run-tests.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
cxx=${CXX:-c++}
fail=0
for f in src/*.cpp; do
    for flag in -ffast-math -Ofast; do
        if out=$("$cxx" -std=c++17 -fopenmp "$flag" -fsyntax-only -Iinclude -Isrc "$f" 2>&1); then
            echo "$f compiles with $flag: it must include src/ieee.hpp"
            fail=1
        elif ! grep -q "hgcd needs IEEE arithmetic" <<<"$out"; then
            echo "$f fails with $flag, but not on ieee.hpp's check:"
            echo "$out" | head -5
            fail=1
        fi
    done
done
[ "$fail" = 0 ] && echo "every src/*.cpp refuses -ffast-math and -Ofast"
exit "$fail"
