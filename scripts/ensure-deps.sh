#!/usr/bin/env bash
# Installs the Debian packages a target needs, when it can (root or sudo);
# otherwise prints exactly what to run. `check` (make check) never installs:
# it names what is missing and fails. Usage: ensure-deps.sh demo|check|test|bench
set -euo pipefail
target=${1:-test}

# command-or-file (or file pattern) to check : Debian package
need=("g++:g++" "make:make")
case "$target" in
  demo) ;;
  check)
    need+=("meson:meson" "ninja:ninja-build" "pkg-config:pkg-config"
           "/usr/include/cmocka.h:libcmocka-dev" "/usr/include/*/gmp.h:libgmp-dev") ;;
  test)
    need+=("meson:meson" "ninja:ninja-build" "pkg-config:pkg-config"
           "/usr/include/cmocka.h:libcmocka-dev" "/usr/include/*/gmp.h:libgmp-dev"
           "/usr/include/ccd/ccd.h:libccd-dev" "bindgen:bindgen" "clang:clang"
           "valgrind:valgrind" "cargo:cargo" "/usr/include/tiny_obj_loader.h:libtinyobjloader-dev"
           "/usr/include/assimp/Importer.hpp:libassimp-dev"
           # hgcd_mpi (mpi/) and its tests on 1 to 4 ranks:
           "mpicxx:libopenmpi-dev" "mpirun:openmpi-bin"
           # ThreadSanitizer run (LLVM OpenMP + Archer) and the libFuzzer target:
           "/usr/lib/llvm-14/lib/libarcher.so:libomp-dev"
           "/usr/lib/llvm-14/lib/clang/14.0.6/lib/linux/libclang_rt.fuzzer-x86_64.a:libclang-rt-14-dev"
           # The Python binding (bindings/python/test.sh): its build, a venv to pip-install
           # into, pytest, and the example's mesh reader and plotting.
           "/usr/include/python3*/Python.h:python3-dev" "/usr/lib/python3/dist-packages/pip/__init__.py:python3-pip"
           "/usr/lib/python3/dist-packages/cffi/__init__.py:python3-cffi"
           "/usr/lib/python3/dist-packages/numpy/__init__.py:python3-numpy"
           "/usr/lib/python3/dist-packages/setuptools/__init__.py:python3-setuptools"
           "/usr/lib/python3/dist-packages/pytest/__init__.py:python3-pytest"
           "/usr/lib/python3/dist-packages/matplotlib/__init__.py:python3-matplotlib"
           "/usr/lib/python3/dist-packages/meshio/__init__.py:python3-meshio") ;;
  bench)
    need+=("meson:meson" "ninja:ninja-build" "pkg-config:pkg-config"
           "/usr/include/ccd/ccd.h:libccd-dev"
           "/usr/include/fcl/config.h:libfcl-dev" "/usr/include/bullet/btBulletCollisionCommon.h:libbullet-dev"
           "/usr/include/ode/ode.h:libode-dev" "python3:python3"
           "/usr/include/embree3/rtcore.h:libembree-dev"
           "/usr/include/tiny_obj_loader.h:libtinyobjloader-dev" "/usr/include/assimp/Importer.hpp:libassimp-dev"
           "mpicxx:libopenmpi-dev" "mpirun:openmpi-bin") ;;
  *) echo "usage: $0 demo|check|test|bench" >&2; exit 2 ;;
esac

missing=()
for item in "${need[@]}"; do
  what=${item%%:*}; pkg=${item##*:}
  # A path may be a pattern (gmp.h sits under the multiarch directory).
  if [[ $what == /* ]]; then compgen -G "$what" >/dev/null || missing+=("$pkg")
  else command -v "$what" >/dev/null 2>&1 || missing+=("$pkg"); fi
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

if [[ $target == check ]]; then
  echo "hgcd: make check needs these Debian packages: ${missing[*]}. Run:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
echo "hgcd: installing missing Debian packages: ${missing[*]}" >&2
if [[ $(id -u) -eq 0 ]]; then sudo=""
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then sudo="sudo"
else
  echo "hgcd: cannot install as $(id -un). Run:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
