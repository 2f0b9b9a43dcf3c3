#!/usr/bin/env bash
# Everything `make test` runs for the Python binding: builds the C library
# (make lib scene), installs the package with pip into a throw-away venv (system
# site packages for Debian's numpy, cffi and pip; no network), runs the pytest suite
# against that installed copy, then builds the module in place (make python)
# and runs the example from the build tree. HGCD_PYTHON names the interpreter (default: the
# first python3 that imports cffi and numpy, /usr/bin/python3 included).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}

python=${HGCD_PYTHON:-}
if [ -z "$python" ]; then
    for candidate in python3 /usr/bin/python3; do
        if "$candidate" -c 'import cffi, numpy' 2>/dev/null; then python=$candidate; break; fi
    done
fi
if [ -z "$python" ]; then
    echo "bindings/python/test.sh: no python3 with cffi and numpy (scripts/ensure-deps.sh test installs them)" >&2
    exit 1
fi

make -s -C "$repo" lib scene
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

echo "-- pip install ./bindings/python into a venv ($("$python" --version))"
# Debian's pip, run by the venv's python, installs into the venv (no copy of
# pip is made in it: that would take longer than the rest).
"$python" -m venv --system-site-packages --without-pip "$tmp/venv"
(cd "$tmp" && "$tmp/venv/bin/python" -m pip install -q --no-index "$here")
rm -rf "$here/build" "$here/hgcd.egg-info"  # pip's in-tree build leftovers

echo "-- pytest on the installed package"
(cd "$tmp" && "$tmp/venv/bin/python" -c 'import hgcd, sys; assert hgcd.__file__.startswith(sys.prefix), hgcd.__file__'
 "$tmp/venv/bin/python" -m pytest -q -p no:cacheprovider "$here/tests")

echo "-- the module built in place (make python), the example run from the build tree"
make -s -C "$repo" python PYTHON="$python" >/dev/null
PYTHONPATH="$here" "$python" "$here/examples/mesh_ticks.py" --n 60 --ticks 5 --out "$tmp/tick.png"
"$python" -c 'import sys; assert open(sys.argv[1], "rb").read(8) == b"\x89PNG\r\n\x1a\n"' "$tmp/tick.png"
