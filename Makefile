# hgcd: plain build with only a C++ compiler (g++ or clang++) and make.
#   make                 libhgcd.a and libhgcd.so.MAJOR.MINOR.PATCH (soname libhgcd.so.MAJOR)
#                        plus libhgcd_mpi.a/.so (mpi/) when OpenMPI's mpicxx is found
#   make scene           build-make/libhgcd_scene.a: the reference scenes' generator (scene/),
#                        a support library for the demo, benchmarks, tests and Rust crate
#   make install         PREFIX=/usr/local LIBDIR= INCLUDEDIR= DESTDIR= : the product only
#                        (headers include/hgcd/*.h, both libraries, hgcd.pc)
#   make install-scene   the scene support library and its header beside them (see below)
#   make uninstall       removes what both install put there
#   make demo            the main job: builds and runs examples/demo (N=..., TICKS=..., THREADS=...)
#   make check           quick: the meson build (build/) and its CMocka suites; installs nothing
#   make test            every test (the suites, -Ofast, no AVX2, sanitizers, valgrind, fuzzing,
#                        this install, Rust); installs what is missing
#   make python          the Python module built in place (bindings/python): then
#                        PYTHONPATH=bindings/python python3 -c 'import hgcd' (PYTHON=... picks python)
#   make bench           benchmarks (bench/)
#   make fuzz            the API fuzzer for FUZZ_SECONDS
#   make deps            installs the packages make test needs
#   make clean           removes every build directory (build-make, build, build-*)
# The version is read from include/hgcd/hgcd_version.h, as meson does.

VERSION_H := include/hgcd/hgcd_version.h
MAJOR := $(shell sed -n 's/^\#define HGCD_VERSION_MAJOR \([0-9]*\)/\1/p' $(VERSION_H))
MINOR := $(shell sed -n 's/^\#define HGCD_VERSION_MINOR \([0-9]*\)/\1/p' $(VERSION_H))
PATCH := $(shell sed -n 's/^\#define HGCD_VERSION_PATCH \([0-9]*\)/\1/p' $(VERSION_H))
VERSION := $(MAJOR).$(MINOR).$(PATCH)

CXX ?= g++
CC ?= cc
PREFIX ?= /usr/local
LIBDIR ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
BUILD ?= build-make

CXXFLAGS ?= -O2 -g
# Every object, library and scene alike (as meson.build): position
# independent, since the same objects make both libraries; OpenMP; only what
# HGCD_API marks leaves a shared object.
BASE_CXXFLAGS := -std=c++17 -fPIC -fopenmp -fvisibility=hidden -Wall -Wextra \
                 -Iinclude -Isrc -MMD -MP
LIB_CPPFLAGS := -DHGCD_BUILDING_LIBRARY
# The library's results rest on IEEE arithmetic (src/common/ieee.hpp) whatever
# CXXFLAGS say: these flags come after CXXFLAGS and undo -ffast-math, -Ofast
# (and its store data races) and their parts, and forbid fused multiply-add
# so world vertices are the same bits everywhere (hgcd.h). The list is
# src/common/ieee-flags.txt, which meson.build reads too; those the compiler
# knows. scripts/check-ieee.sh checks an -Ofast build.
HGCD_IEEE_FLAGS := $(foreach f,$(shell cat src/common/ieee-flags.txt),$(shell $(CXX) $(f) -x c++ -fsyntax-only /dev/null 2>/dev/null && echo $(f)))

# Optional narrow phase through libccd (GJK/MPR for convex meshes): used when
# pkg-config knows `ccd` or its header is installed; CCD=no builds without it
# (switching needs `make clean`). Without it the library still builds and
# reports HGCD_ERROR_NOT_SUPPORTED for GJK/MPR requests.
CCD ?= auto
ifneq ($(CCD),no)
CCD_PC := $(shell pkg-config --exists ccd 2>/dev/null && echo yes)
HAVE_CCD := $(if $(CCD_PC),yes,$(shell test -f /usr/include/ccd/ccd.h && echo yes))
endif
ifeq ($(HAVE_CCD),yes)
CCD_LIBS := $(if $(CCD_PC),$(shell pkg-config --libs ccd),-lccd)
LIB_CPPFLAGS += -DHGCD_HAVE_CCD $(if $(CCD_PC),$(shell pkg-config --cflags ccd))
endif
LDLIBS_LIB := -fopenmp $(filter-out -lm,$(CCD_LIBS)) -lm

# What a program linking libhgcd.a needs besides libccd: the OpenMP runtime
# and C++ library of $(CXX), and libm (hgcd.pc's Libs.private; meson.build
# asks the same script).
RUNTIME_LIBS = $(shell sh scripts/pc-libs-private.sh $(CXX) $(CXXFLAGS))

# Optional MPI library hgcd_mpi (mpi/, hgcd/hgcd_mpi.h): built beside libhgcd
# when OpenMPI's compiler wrapper mpicxx is found (Debian libopenmpi-dev);
# MPI=no never builds it. libhgcd itself never depends on MPI.
MPI ?= auto
ifneq ($(MPI),no)
MPICXX ?= $(shell command -v mpicxx 2>/dev/null)
endif
ifneq ($(MPICXX),)
MPI_OBJS := $(patsubst mpi/%.cpp,$(BUILD)/mpi/%.o,$(wildcard mpi/*.cpp))
MPI_STATIC := $(BUILD)/libhgcd_mpi.a
MPI_SHARED := $(BUILD)/libhgcd_mpi.so.$(VERSION)
MPI_LIBS := $(MPI_STATIC) $(MPI_SHARED)
endif

SRCS := $(wildcard src/*/*.cpp)
OBJS := $(patsubst src/%.cpp,$(BUILD)/obj/%.o,$(SRCS))
STATIC := $(BUILD)/libhgcd.a
SHARED := $(BUILD)/libhgcd.so.$(VERSION)
SONAME := libhgcd.so.$(MAJOR)
MAP := src/api/hgcd.map
# The reference scenes' generator (scene/): a support library for the demo,
# benchmarks, tests and the Rust crate, not part of libhgcd.
SCENE_LIB := $(BUILD)/libhgcd_scene.a

.PHONY: all lib scene install install-scene uninstall demo check test bench fuzz clean deps python FORCE

all: lib
lib: $(STATIC) $(SHARED) $(MPI_LIBS)
scene: $(SCENE_LIB)

$(BUILD)/obj/%.o: src/%.cpp | $(BUILD)
	@mkdir -p $(dir $@)
	$(CXX) $(BASE_CXXFLAGS) $(LIB_CPPFLAGS) $(CXXFLAGS) $(HGCD_IEEE_FLAGS) -c $< -o $@

$(BUILD)/scene/scene.o: scene/scene.cpp | $(BUILD)
	@mkdir -p $(dir $@)
	$(CXX) $(BASE_CXXFLAGS) -Iscene $(CXXFLAGS) $(HGCD_IEEE_FLAGS) -c $< -o $@

$(SCENE_LIB): $(BUILD)/scene/scene.o
	rm -f $@
	ar rcs $@ $^

$(BUILD)/mpi/%.o: mpi/%.cpp | $(BUILD)
	@mkdir -p $(dir $@)
	$(MPICXX) $(BASE_CXXFLAGS) -Impi $(LIB_CPPFLAGS) $(CXXFLAGS) $(HGCD_IEEE_FLAGS) -c $< -o $@

$(MPI_STATIC): $(MPI_OBJS)
	rm -f $@
	ar rcs $@ $^

$(MPI_SHARED): $(MPI_OBJS) $(SHARED) mpi/hgcd_mpi.map
	$(MPICXX) -shared -Wl,-soname,libhgcd_mpi.so.$(MAJOR) -Wl,--version-script=mpi/hgcd_mpi.map -o $@ \
	    $(MPI_OBJS) -L$(BUILD) -lhgcd -fopenmp $(LDFLAGS)
	ln -sf libhgcd_mpi.so.$(VERSION) $(BUILD)/libhgcd_mpi.so.$(MAJOR)
	ln -sf libhgcd_mpi.so.$(MAJOR) $(BUILD)/libhgcd_mpi.so

-include $(OBJS:.o=.d) $(BUILD)/scene/scene.d $(MPI_OBJS:.o=.d)

$(BUILD):
	mkdir -p $(BUILD)

# libhgcd-static-deps.txt: the libraries besides the runtimes that the
# archive needs (libccd), by name, for the Rust crate's build script.
$(STATIC): $(OBJS)
	rm -f $@
	ar rcs $@ $^
	echo '$(patsubst -l%,%,$(filter -l%,$(CCD_LIBS)))' > $(BUILD)/libhgcd-static-deps.txt

$(SHARED): $(OBJS) $(MAP)
	$(CXX) -shared -Wl,-soname,$(SONAME) -Wl,--version-script=$(MAP) -o $@ $(OBJS) $(LDFLAGS) $(LDLIBS_LIB)
	ln -sf libhgcd.so.$(VERSION) $(BUILD)/$(SONAME)
	ln -sf $(SONAME) $(BUILD)/libhgcd.so

# hgcd.pc from hgcd.pc.in (meson.build fills the same template); libdir and
# includedir relative to ${prefix} when under it. Written on every install
# (PREFIX, CXX or libccd may have changed since), kept when the same.
$(BUILD)/hgcd.pc: FORCE | $(BUILD)
	sed -e 's|@prefix@|$(PREFIX)|' -e 's|@libdir@|$(LIBDIR)|' -e 's|@includedir@|$(INCLUDEDIR)|' \
	    -e 's|^libdir=$(PREFIX)/|libdir=$${prefix}/|' -e 's|^includedir=$(PREFIX)/|includedir=$${prefix}/|' \
	    -e 's|@version@|$(VERSION)|' \
	    -e 's|@requires_private@|$(if $(CCD_PC),ccd)|' \
	    -e 's|@libs_private@|$(strip $(if $(CCD_PC),,$(CCD_LIBS)) $(RUNTIME_LIBS))|' hgcd.pc.in > $@.tmp
	if cmp -s $@.tmp $@; then rm $@.tmp; else mv $@.tmp $@; fi

install: lib $(BUILD)/hgcd.pc
	install -d $(DESTDIR)$(INCLUDEDIR)/hgcd $(DESTDIR)$(LIBDIR)/pkgconfig
	install -m 644 include/hgcd/*.h $(DESTDIR)$(INCLUDEDIR)/hgcd/
	install -m 644 $(STATIC) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(SHARED) $(DESTDIR)$(LIBDIR)/
	ln -sf libhgcd.so.$(VERSION) $(DESTDIR)$(LIBDIR)/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(LIBDIR)/libhgcd.so
	install -m 644 $(BUILD)/hgcd.pc $(DESTDIR)$(LIBDIR)/pkgconfig/
ifneq ($(MPICXX),)
	install -m 644 mpi/hgcd/hgcd_mpi.h $(DESTDIR)$(INCLUDEDIR)/hgcd/
	install -m 644 $(MPI_STATIC) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(MPI_SHARED) $(DESTDIR)$(LIBDIR)/
	ln -sf libhgcd_mpi.so.$(VERSION) $(DESTDIR)$(LIBDIR)/libhgcd_mpi.so.$(MAJOR)
	ln -sf libhgcd_mpi.so.$(MAJOR) $(DESTDIR)$(LIBDIR)/libhgcd_mpi.so
endif

# `make install` leaves the scene generator out: it is not the product (not
# in hgcd.h, static only, no ABI promise), only the tool that builds the
# reference scenes of docs/scenes.md for the repository's demo, benchmarks,
# tests and Rust crate. install-scene is for building those against an
# installed hgcd: libhgcd_scene.a beside libhgcd (where the Rust crate's
# build script looks for it) and hgcd/hgcd_scene.h beside hgcd.h.
install-scene: $(SCENE_LIB)
	install -d $(DESTDIR)$(INCLUDEDIR)/hgcd $(DESTDIR)$(LIBDIR)
	install -m 644 scene/hgcd/hgcd_scene.h $(DESTDIR)$(INCLUDEDIR)/hgcd/
	install -m 644 $(SCENE_LIB) $(DESTDIR)$(LIBDIR)/

FORCE:

uninstall:
	rm -rf $(DESTDIR)$(INCLUDEDIR)/hgcd
	rm -f $(DESTDIR)$(LIBDIR)/libhgcd.a $(DESTDIR)$(LIBDIR)/libhgcd.so* $(DESTDIR)$(LIBDIR)/pkgconfig/hgcd.pc
	rm -f $(DESTDIR)$(LIBDIR)/libhgcd_mpi.a $(DESTDIR)$(LIBDIR)/libhgcd_mpi.so*
	rm -f $(DESTDIR)$(LIBDIR)/libhgcd_scene.a

# The main job: scene `tetra` of docs/scenes.md through the C API.
N ?= 200000
TICKS ?= 5
THREADS ?= 0
$(BUILD)/demo: examples/demo.c $(SCENE_LIB) $(STATIC) | $(BUILD)
	$(CC) -std=c99 -O2 -Wall -Iinclude -Iscene $< -o $@ $(SCENE_LIB) $(STATIC) $(filter-out -lm,$(CCD_LIBS)) $(RUNTIME_LIBS)

demo:
	bash scripts/ensure-deps.sh demo
	$(MAKE) $(BUILD)/demo
	$(BUILD)/demo --n $(N) --ticks $(TICKS) --threads $(THREADS)

deps:
	bash scripts/ensure-deps.sh test

# The quick check: the meson build in build/ (debugoptimized; make test
# reuses it) and every CMocka suite it defines. Installs no package: names
# what is missing instead.
check:
	bash scripts/ensure-deps.sh check
	[ -f build/build.ninja ] || meson setup build --buildtype=debugoptimized
	meson compile -C build
	meson test -C build --print-errorlogs

test:
	bash scripts/ensure-deps.sh test
	bash scripts/run-tests.sh

# The Python binding built in place, against this build's libraries
# (pip install ./bindings/python installs it instead). PYTHON: the first
# python3 that imports cffi and numpy, unless given.
PYTHON = $(shell for p in python3 /usr/bin/python3; do $$p -c 'import cffi, numpy' 2>/dev/null && echo $$p && break; done)
python: lib scene
	HGCD_LIB_DIR=$(BUILD) HGCD_INCLUDE_DIR=include:scene $(PYTHON) bindings/python/hgcd_build.py

bench:
	bash scripts/ensure-deps.sh bench
	bash scripts/run-bench.sh

# The API fuzzer (fuzz/fuzz_api.cpp: libFuzzer, ASan, UBSan, GMP oracle) for
# FUZZ_SECONDS; what it finds goes to build-fuzz/corpus, crashes to
# build-fuzz/artifacts.
FUZZ_SECONDS ?= 300
fuzz:
	bash scripts/ensure-deps.sh test
	bash fuzz/run.sh $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD) build build-* bindings/python/build bindings/python/build-cffi bindings/python/hgcd.egg-info
	rm -f bindings/python/hgcd/_hgcd*.so
