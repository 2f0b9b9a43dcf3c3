#!/usr/bin/env bash
# Tests of the Rust bindings: the single entry point `make test` calls.
#
#   1. builds the C library (make -C <repo> lib) if build-make/libhgcd.a is
#      missing or out of date;
#   2. checks that hgcd-sys/src/bindings.rs is what bindgen generates today
#      (hgcd-sys/generate.sh --check; skipped with a message without bindgen);
#   3. cargo test --workspace --offline (layout tests, raw and safe API tests,
#      doc tests including the compile-fail borrow/Sync checks);
#   4. runs the example once with a small n;
#   5. if valgrind is installed (and HGCD_RUST_VALGRIND is not 0): the misuse
#      tests under valgrind, failing on memory errors or definite leaks.
#
# Environment: HGCD_LIB_DIR (default <repo>/build-make) is passed on to
# hgcd-sys/build.rs; CARGO_TARGET_DIR is bindings/rust/target.
# Exits non-zero on any failure.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)

if [ -d "$HOME/.cargo/bin" ]; then
    export PATH="$HOME/.cargo/bin:$PATH"
fi
if ! command -v cargo >/dev/null 2>&1; then
    echo "FAIL: cargo is not installed (rustup, or apt-get install cargo)" >&2
    exit 1
fi

export CARGO_TARGET_DIR="$here/target"
export CARGO_NET_OFFLINE=true

step() { printf '\n== rust: %s\n' "$*"; }

# 1. The C library.
if [ -z "${HGCD_LIB_DIR:-}" ]; then
    lib="$root/build-make/libhgcd.a"
    if [ ! -f "$lib" ]; then
        step "building the C library ($lib is missing)"
        make -C "$root" lib scene
    elif ! make -q -C "$root" lib scene >/dev/null 2>&1; then
        step "rebuilding the C library (out of date)"
        make -C "$root" lib scene
    fi
    export HGCD_LIB_DIR="$root/build-make"
fi
step "linking libhgcd from HGCD_LIB_DIR=$HGCD_LIB_DIR"

# 2. Regeneration check of the bindgen output.
step "bindgen regeneration check"
bash "$here/hgcd-sys/generate.sh" --check

# 3. Both crates.
cd "$here"
step "cargo test --workspace --offline"
cargo test --workspace --offline

# 4. The example, once, small.
step "cargo run --example tetra -- 2000 2"
cargo run --offline -p hgcd --example tetra -- 2000 2

# 5. Memory check of the misuse tests.
if [ "${HGCD_RUST_VALGRIND:-1}" != 0 ] && command -v valgrind >/dev/null 2>&1; then
    step "valgrind: misuse tests (memory errors and definite leaks fail)"
    bin=$(cargo test --offline -p hgcd --test misuse --no-run --message-format=json 2>/dev/null |
        sed -n 's/.*"executable":"\([^"]*\)".*/\1/p' | tail -1)
    if [ -z "$bin" ] || [ ! -x "$bin" ]; then
        echo "FAIL: cannot find the misuse test executable" >&2
        exit 1
    fi
    valgrind -q --leak-check=full --errors-for-leak-kinds=definite --error-exitcode=9 \
        "$bin" --test-threads=1 -q
else
    step "valgrind check skipped (valgrind not installed or HGCD_RUST_VALGRIND=0)"
fi

step "all Rust binding checks passed"
