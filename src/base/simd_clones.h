// RAYCAST_SIMD_CLONES, written before a function's definition: on x86, with GCC or Clang, the
// function is compiled three times, for AVX-512, for AVX2 and for the baseline the whole program
// is built for (SSE2), and the dynamic loader picks the widest one this CPU runs, once, when the
// program starts (target_clones: an ifunc, no test per call). Elsewhere it is a plain function.
//
// It is for the code around the traversal kernels whose plain loops over arrays the compiler
// turns into SIMD instructions (shading a packet's hits, making sample points, converting colours
// to bytes): eight or sixteen lanes a step instead of SSE2's four, and the integer multiplies of
// the hashes, which SSE2 cannot do four at a time. The kernels themselves are compiled per
// instruction set in their own files (scene/*_avx512.cpp and the others).
//
// Every copy gives the same bits: each does the same IEEE operations in the same order, only more
// of them per instruction. The build forbids contracting a multiply and an add into one fused
// operation (-ffp-contract=off, CMakeLists.txt), which AVX2's machines could otherwise use, and the
// compiler reorders no float arithmetic without -ffast-math.
//
// A cloned function is not inlined into its callers: put it on functions that do a whole batch of
// work per call, and give the helpers they call [[gnu::always_inline]] or the same macro (a helper
// compiled apart runs the baseline's instructions).
#pragma once

#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__) && defined(__ELF__)
#define RAYCAST_SIMD_CLONES [[gnu::target_clones("avx512f", "avx2", "default")]]
#else
#define RAYCAST_SIMD_CLONES
#endif
