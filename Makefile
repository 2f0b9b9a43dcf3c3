# hgcd: plain build with only a C++ compiler (g++ or clang++) and make.
#   make                 libhgcd.a and libhgcd.so.MAJOR.MINOR.PATCH (soname libhgcd.so.MAJOR)
#   make install         PREFIX=/usr/local DESTDIR= : headers, libraries, hgcd.pc
#   make demo            the main job: builds and runs examples/demo (N=..., TICKS=..., THREADS=...)
#   make test            every test (meson + CMocka, sanitizers, Rust); installs what is missing
#   make bench           benchmarks (bench/)
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

# -ffp-contract=off: no fused multiply-add, so world vertices are the same
# bits everywhere (see hgcd.h). HGCD_IEEE_FLAGS come after CXXFLAGS and undo
# -ffast-math, -Ofast (and its store data races) and their parts: the
# library's results rest on IEEE arithmetic (src/ieee.hpp) whatever CXXFLAGS
# say (scripts/check-ieee.sh checks an -Ofast build).
CXXFLAGS ?= -O2 -g
HGCD_CXXFLAGS := -std=c++17 -fPIC -fopenmp -fvisibility=hidden \
                 -Wall -Wextra -Iinclude -Isrc -DHGCD_BUILDING_LIBRARY -MMD -MP
# (The list is src/common/ieee-flags.txt, which meson.build reads too; those
# the compiler knows.)
HGCD_IEEE_FLAGS := $(foreach f,$(shell cat src/common/ieee-flags.txt),$(shell $(CXX) $(f) -x c++ -fsyntax-only /dev/null 2>/dev/null && echo $(f)))
LDLIBS_LIB := -fopenmp -lm

# Optional narrow phase through libccd (GJK/MPR for convex meshes): used when
# pkg-config knows `ccd` or its header is installed; CCD=no builds without it
# (switching needs `make clean`). Without it the library still builds and
# reports HGCD_ERROR_NOT_SUPPORTED for GJK/MPR requests.
CCD ?= auto
ifneq ($(CCD),no)
HAVE_CCD := $(shell pkg-config --exists ccd 2>/dev/null && echo yes || { test -f /usr/include/ccd/ccd.h && echo yes; })
endif
ifeq ($(HAVE_CCD),yes)
CCD_LIBS := $(shell pkg-config --libs ccd 2>/dev/null || echo -lccd)
HGCD_CXXFLAGS += -DHGCD_HAVE_CCD $(shell pkg-config --cflags ccd 2>/dev/null)
LDLIBS_LIB += $(CCD_LIBS)
endif

SRCS := $(wildcard src/*/*.cpp)
OBJS := $(patsubst src/%.cpp,$(BUILD)/obj/%.o,$(SRCS))
STATIC := $(BUILD)/libhgcd.a
SHARED := $(BUILD)/libhgcd.so.$(VERSION)
SONAME := libhgcd.so.$(MAJOR)
# The reference scenes' generator (scene/): a support library for the demo,
# not part of libhgcd.
SCENE_LIB := $(BUILD)/libhgcd_scene.a
MAP := src/api/hgcd.map

.PHONY: all lib scene install uninstall demo test bench clean deps

all: lib
lib: $(STATIC) $(SHARED)
scene: $(SCENE_LIB)

$(BUILD)/obj/%.o: src/%.cpp | $(BUILD)
	@mkdir -p $(dir $@)
	$(CXX) $(HGCD_CXXFLAGS) $(CXXFLAGS) $(HGCD_IEEE_FLAGS) -c $< -o $@

$(BUILD)/scene/scene.o: scene/scene.cpp | $(BUILD)
	@mkdir -p $(dir $@)
	$(CXX) $(HGCD_CXXFLAGS) -Iscene $(CXXFLAGS) $(HGCD_IEEE_FLAGS) -c $< -o $@

$(SCENE_LIB): $(BUILD)/scene/scene.o
	rm -f $@
	ar rcs $@ $^

-include $(OBJS:.o=.d) $(BUILD)/scene/scene.d

$(BUILD):
	mkdir -p $(BUILD)

$(STATIC): $(OBJS)
	rm -f $@
	ar rcs $@ $^
	echo '$(patsubst -l%,%,$(filter -l%,$(CCD_LIBS)))' > $(BUILD)/libhgcd-static-deps.txt

$(SHARED): $(OBJS) $(MAP)
	$(CXX) -shared -Wl,-soname,$(SONAME) -Wl,--version-script=$(MAP) -o $@ $(OBJS) $(LDFLAGS) $(LDLIBS_LIB)
	ln -sf libhgcd.so.$(VERSION) $(BUILD)/$(SONAME)
	ln -sf $(SONAME) $(BUILD)/libhgcd.so

$(BUILD)/hgcd.pc: Makefile
	printf 'prefix=%s\nlibdir=%s\nincludedir=%s\n\nName: hgcd\nDescription: Parallel exact collision detection between many triangle meshes\nVersion: %s\nLibs: -L$${libdir} -lhgcd\nLibs.private: -lgomp -lstdc++ -lm %s\nCflags: -I$${includedir}\n' \
	  '$(PREFIX)' '$(LIBDIR)' '$(INCLUDEDIR)' '$(VERSION)' '$(CCD_LIBS)' > $@

install: lib $(BUILD)/hgcd.pc
	install -d $(DESTDIR)$(INCLUDEDIR)/hgcd $(DESTDIR)$(LIBDIR)/pkgconfig
	install -m 644 include/hgcd/*.h $(DESTDIR)$(INCLUDEDIR)/hgcd/
	install -m 644 $(STATIC) $(DESTDIR)$(LIBDIR)/
	install -m 755 $(SHARED) $(DESTDIR)$(LIBDIR)/
	ln -sf libhgcd.so.$(VERSION) $(DESTDIR)$(LIBDIR)/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(LIBDIR)/libhgcd.so
	install -m 644 $(BUILD)/hgcd.pc $(DESTDIR)$(LIBDIR)/pkgconfig/

uninstall:
	rm -rf $(DESTDIR)$(INCLUDEDIR)/hgcd
	rm -f $(DESTDIR)$(LIBDIR)/libhgcd.a $(DESTDIR)$(LIBDIR)/libhgcd.so* $(DESTDIR)$(LIBDIR)/pkgconfig/hgcd.pc

# The main job: the tetra scene of SCENES.md through the C API.
N ?= 200000
TICKS ?= 5
THREADS ?= 0
$(BUILD)/demo: examples/demo.c $(SCENE_LIB) $(STATIC) | $(BUILD)
	$(CC) -std=c99 -O2 -Wall -Iinclude -Iscene $< -o $@ $(SCENE_LIB) $(STATIC) -fopenmp -lstdc++ -lm $(CCD_LIBS)

demo:
	bash scripts/ensure-deps.sh demo
	$(MAKE) $(BUILD)/demo
	$(BUILD)/demo --n $(N) --ticks $(TICKS) --threads $(THREADS)

deps:
	bash scripts/ensure-deps.sh test

test:
	bash scripts/ensure-deps.sh test
	bash scripts/run-tests.sh

bench:
	bash scripts/ensure-deps.sh bench
	bash scripts/run-bench.sh

# The API fuzzer (fuzz/fuzz_api.cpp: libFuzzer, ASan, UBSan, GMP oracle) for
# FUZZ_SECONDS; what it finds goes to build-fuzz/corpus, crashes to
# build-fuzz/artifacts.
FUZZ_SECONDS ?= 300
.PHONY: fuzz
fuzz:
	bash scripts/ensure-deps.sh test
	bash fuzz/run.sh $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD) build build-*
