#!/usr/bin/env bash
# The library's results must not depend on -ffast-math or -Ofast (src/common/ieee.hpp
# says why). Two checks, called by scripts/run-tests.sh:
# 1. The library built with CXXFLAGS="-Ofast", through the Makefile and
#    through meson (both take the flags that undo it from
#    src/common/ieee-flags.txt, after the user's), reports the same pairs as the
#    plain Makefile build: bench_hgcd, scene tetra, n = 100000,
#    2 threads, 3 ticks, the same counts (candidates, narrow and triangle
#    tests, pairs, containment), the same hash of the last tick's pairs, and
#    the counts of docs/scenes.md at the initial poses.
# 2. A build that compiles the sources some other way with either flag stops:
#    each library source is compiled with each, syntax only, and must stop with
#    ieee.hpp's message (a new source that forgets the include fails here).
set -euo pipefail
cd "$(dirname "$0")/.."
cxx=${CXX:-c++}
fail=0

results() {  # the JSON fields that describe what was found, not how fast
    python3 -c 'import json, sys
d = json.loads(sys.stdin.read())
print(" ".join("%s=%s" % (k, d[k]) for k in ("candidate_pairs", "narrow_tests", "triangle_tests", "colliding_pairs",
      "containment_pairs", "pairs_fnv", "initial_pairs", "initial_containment", "reference_ok")))'
}
for flags in "-O2 -g" "-Ofast"; do
    dir=build-make-ieee$(tr -dc 'a-zA-Z0-9' <<<"$flags")
    make -s -j"$(nproc 2>/dev/null || echo 2)" lib scene "$dir/hgcd.pc" BUILD="$dir" CXXFLAGS="$flags" >/dev/null
    # What libhgcd.a needs, from the hgcd.pc that make install would install.
    static_libs=$(pkg-config --static --libs "$dir/hgcd.pc" | sed 's/\(^\| \)-lhgcd\( \|$\)/ /')
    # shellcheck disable=SC2086
    cc -std=c99 -O2 -Iinclude -Iscene bench/bench_hgcd.c -o "$dir/bench_hgcd" "$dir/libhgcd_scene.a" "$dir/libhgcd.a" $static_libs
    got=$("$dir/bench_hgcd" --n 100000 --threads 2 --ticks 3 --check | results)
    echo "library built with CXXFLAGS=\"$flags\": $got"
    if [ "$flags" = "-O2 -g" ]; then plain=$got; elif [ "$got" != "$plain" ]; then
        echo "the -Ofast build reports other results than the plain one"
        fail=1
    fi
done
dir=build-meson-ieeeOfast
if [ ! -f "$dir/build.ninja" ]; then
    CXXFLAGS="-Ofast" meson setup "$dir" --buildtype=plain -Dtests=false >/dev/null
fi
meson compile -C "$dir" bench_hgcd >/dev/null
got=$("$dir/bench/bench_hgcd" --n 100000 --threads 2 --ticks 3 --check | results)
echo "library built by meson with CXXFLAGS=\"-Ofast\": $got"
if [ "$got" != "$plain" ]; then
    echo "the meson -Ofast build reports other results than the plain one"
    fail=1
fi
case "$plain" in *reference_ok=True*) ;; *) echo "the plain build misses the counts of docs/scenes.md"; fail=1 ;; esac
for f in src/*/*.cpp scene/scene.cpp; do
    for flag in -ffast-math -Ofast; do
        if out=$("$cxx" -std=c++17 -fopenmp "$flag" -fsyntax-only -Iinclude -Isrc -Iscene "$f" 2>&1); then
            echo "$f compiles with $flag: it must include src/common/ieee.hpp"
            fail=1
        elif ! grep -q "hgcd needs IEEE arithmetic" <<<"$out"; then
            echo "$f fails with $flag, but not on ieee.hpp's check:"
            echo "$out" | head -5
            fail=1
        fi
    done
done
[ "$fail" = 0 ] && echo "-Ofast builds (make, meson) report the same pairs; every library source compiled otherwise refuses -ffast-math and -Ofast"
exit "$fail"
