#!/bin/sh
# Prints what a program linking the static libhgcd needs besides libhgcd and
# libccd: the OpenMP runtime and the C++ standard library of the compiler that
# built it, and libm, as linker flags any C or C++ compiler driver accepts
# (hgcd.pc's Libs.private; the Makefile and meson.build both call this, so
# their hgcd.pc agree). Usage: pc-libs-private.sh CXX [CXXFLAGS...]
set -eu
macros=$(printf '#include <cstddef>\n' | "$@" -x c++ -dM -E - 2>/dev/null) || {
    echo "pc-libs-private.sh: '$*' does not preprocess C++" >&2
    exit 1
}
case $macros in
    *_LIBCPP_VERSION*) cxxlib=-lc++ ;;
    *) cxxlib=-lstdc++ ;;
esac
case $macros in
    *__clang__*)
        # LLVM's libomp. Debian keeps libomp.so in /usr/lib/llvm-N/lib, outside
        # the linker's default path (clang -fopenmp adds it itself): name it.
        omp=-lomp
        if [ "$("$@" -print-file-name=libomp.so)" = libomp.so ]; then
            dir=$("$@" -print-resource-dir 2>/dev/null)/../..
            if [ -f "$dir/libomp.so" ]; then
                omp="-L$(cd "$dir" && pwd) -lomp"
            fi
        fi ;;
    *__GNUC__*) omp=-lgomp ;;
    *) omp=-fopenmp ;;
esac
echo "$omp $cxxlib -lm"
