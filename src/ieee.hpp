// Every file whose results rest on IEEE double rounding includes this: the
// exact predicates and their filters (geometry.cpp, narrow.cpp, bvh.cpp),
// the grid's window and reach margins (grid.cpp), the bounding spheres'
// margins and the motion formula of SCENES.md (world.cpp), the scene
// generator's bit-exact arithmetic (scene.cpp). -ffast-math (and
// -Ofast) would let the compiler reorder, contract and drop those roundings,
// so the reported pairs would depend on the compiler: refuse to build.
// (-ffp-contract=off, in meson.build and the Makefile, keeps FMA out too.)
#pragma once
#if defined(__FAST_MATH__) || defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__
#error "hgcd needs IEEE arithmetic: build without -ffast-math / -Ofast"
#endif
