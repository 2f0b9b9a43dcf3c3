// Every library source includes this. Their results rest on IEEE double
// rounding and on NaN and infinity behaving as IEEE says: the exact
// predicates and their filters (geometry.cpp, narrow.cpp, bvh.cpp), the
// grid's window, floor and reach margins (grid.cpp), the bodies' boxes and
// the motion formula of SCENES.md (world.cpp, mesh.cpp), the
// scene generator's bit-exact arithmetic (scene.cpp), and the refusal of
// non-finite input (std::isfinite in capi.cpp, world.cpp, mesh.cpp,
// ccd_narrow.cpp, which -ffinite-math-only may fold to true). -ffast-math
// (and -Ofast) would let the compiler reorder, contract and drop those
// roundings and checks, so the reported pairs would depend on the compiler:
// refuse to build. (-ffp-contract=off, in meson.build and the Makefile,
// keeps FMA out too.) scripts/check-ieee.sh checks that every source refuses.
#pragma once
#if defined(__FAST_MATH__) || defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "hgcd needs IEEE arithmetic: build without -ffast-math / -Ofast"
#endif
