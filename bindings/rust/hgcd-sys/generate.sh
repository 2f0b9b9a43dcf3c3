#!/usr/bin/env bash
# Regenerates hgcd-sys/src/bindings.rs from include/hgcd/hgcd.h with the bindgen
# CLI (Debian's `bindgen` package), so the committed file is reproducible.
#
#   generate.sh            rewrite src/bindings.rs
#   generate.sh --check    regenerate into a temporary file and compare it with
#                          the committed src/bindings.rs: exit 1 (with a diff)
#                          when they differ, 0 when identical. Prints "SKIP: ..."
#                          and exits 0 when bindgen (or rustfmt) is not
#                          installed, or when the installed bindgen is not the
#                          version that produced the committed file (different
#                          bindgen versions print different code); set
#                          HGCD_BINDGEN_STRICT=1 to make those cases fail.
#
# Determinism: every option that changes the output is pinned below. bindgen's
# own rustfmt step is switched off (--no-rustfmt-bindings: by default bindgen
# formats only if it happens to find a rustfmt, and with whatever rustfmt.toml
# it finds); the raw output is then formatted explicitly by `rustfmt` with the
# pinned rustfmt-bindings.toml beside this script. Environment: BINDGEN and
# RUSTFMT name the tools (defaults: bindgen, rustfmt from PATH or ~/.cargo/bin).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
out="$here/src/bindings.rs"
mode=write
case "${1:-}" in
    "") ;;
    --check) mode=check ;;
    *) echo "usage: $0 [--check]" >&2; exit 2 ;;
esac

skip_or_fail() {
    if [ "${HGCD_BINDGEN_STRICT:-0}" = 1 ]; then
        echo "FAIL: $1 (HGCD_BINDGEN_STRICT=1)" >&2
        exit 1
    fi
    echo "SKIP: $1"
    exit 0
}

find_tool() { # name, env override
    if [ -n "${2:-}" ]; then echo "$2"; return; fi
    if command -v "$1" >/dev/null 2>&1; then command -v "$1"; return; fi
    if [ -x "$HOME/.cargo/bin/$1" ]; then echo "$HOME/.cargo/bin/$1"; return; fi
    echo ""
}
BINDGEN=$(find_tool bindgen "${BINDGEN:-}")
RUSTFMT=$(find_tool rustfmt "${RUSTFMT:-}")

if [ -z "$BINDGEN" ] || ! "$BINDGEN" --version >/dev/null 2>&1; then
    [ "$mode" = check ] && skip_or_fail "bindgen is not installed (apt-get install bindgen): bindings.rs regeneration not checked"
    echo "error: bindgen is not installed (apt-get install bindgen)" >&2
    exit 1
fi
if [ -z "$RUSTFMT" ] || ! "$RUSTFMT" --version >/dev/null 2>&1; then
    [ "$mode" = check ] && skip_or_fail "rustfmt is not installed: bindings.rs regeneration not checked"
    echo "error: rustfmt is not installed (rustup component add rustfmt)" >&2
    exit 1
fi

# "bindgen 0.60.1" -> "0.60.1"
bindgen_version=$("$BINDGEN" --version | awk '{print $2}')
if [ "$mode" = check ] && [ -f "$out" ]; then
    committed_version=$(sed -n '1s/.*rust-bindgen \([0-9.]*\).*/\1/p' "$out")
    if [ "$committed_version" != "$bindgen_version" ]; then
        skip_or_fail "installed bindgen $bindgen_version is not bindgen $committed_version that generated src/bindings.rs: regeneration cannot be byte-identical"
    fi
fi

tmp=$(mktemp)
trap 'rm -f "$tmp" "$tmp.raw"' EXIT

# Run from the repo root with a relative header path: nothing host-specific can
# leak into the output.
(
    cd "$root"
    "$BINDGEN" bindings/rust/hgcd-sys/wrapper.h \
        --no-rustfmt-bindings \
        --rust-target 1.47 \
        --allowlist-function 'hgcd_.*' \
        --allowlist-type 'hgcd_.*' \
        --allowlist-var 'HGCD_.*' \
        --size_t-is-usize \
        --no-prepend-enum-name \
        --translate-enum-integer-types \
        --no-copy '^hgcd_world$' \
        --with-derive-partialeq \
        --with-derive-eq \
        --with-derive-hash \
        -- -x c -std=c99 -Iinclude -Iscene
) > "$tmp.raw"
"$RUSTFMT" --config-path "$here/rustfmt-bindings.toml" --emit stdout < "$tmp.raw" > "$tmp"

if [ "$mode" = write ]; then
    cp "$tmp" "$out"
    echo "wrote $out (bindgen $bindgen_version)"
    exit 0
fi

if [ ! -f "$out" ]; then
    echo "FAIL: $out does not exist; run $here/generate.sh" >&2
    exit 1
fi
if cmp -s "$tmp" "$out"; then
    echo "ok: src/bindings.rs is identical to a fresh bindgen $bindgen_version generation"
    exit 0
fi
echo "FAIL: src/bindings.rs differs from a fresh generation from include/hgcd/hgcd.h" >&2
echo "      (run bindings/rust/hgcd-sys/generate.sh and commit the result):" >&2
diff -u "$out" "$tmp" | head -60 >&2 || true
exit 1
