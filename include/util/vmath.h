/* vmath.h - vectorised transcendental functions for the kernel loops.
 *
 * The per-unit work is dominated by sin, cos, tan, atan, atan2, asin, hypot
 * and log (a unit of
 * the ESS needs about 250,000 of them).  Kernel files (the Makefile's
 * KERNEL_SRC, compiled with -DSUNMC_VMATH -fno-math-errno
 * -fno-trapping-math -fno-builtin-sin -fno-builtin-cos) write their loops
 * over arrays as
 *     VM_SIMD for (size_t i = 0; i < n; i++) ...
 * and GCC calls glibc's vector math library (libmvec: 2 lanes with SSE4,
 * 4 with AVX2) for these functions instead of libm's scalar ones.  Nothing
 * here relaxes IEEE semantics: NaN compares and isfinite() work as
 * everywhere else (-fno-math-errno only stops errno being set,
 * -fno-trapping-math only lets GCC assume no floating-point traps).
 *
 * Instruction set: the build's baseline is plain x86-64 (every 64-bit x86);
 * a function marked VM_KERNEL is compiled twice, for that baseline and for
 * x86-64-v3 (AVX2 + FMA: Intel from 2013, AMD from 2015), and the loader
 * picks the one the CPU runs (GCC target_clones).  All threads take the same
 * one, so the output is byte-identical for any thread count on a machine.
 *
 * Lanes must not depend on where a point sits in an array: a loop's scalar
 * remainder would call libm instead of libmvec.  Kernels therefore run
 * their loops over counts padded to VM_PAD, on arrays aligned to VM_ALIGN
 * (vm_pad, vm_alloc), so every point goes through the same vector code.
 * Elsewhere (no SUNMC_VMATH, other compilers or C libraries) the same
 * loops are plain scalar code.
 */
#ifndef SUNMC_VMATH_H
#define SUNMC_VMATH_H

#include <math.h>
#include <stddef.h>

#define VM_PAD 8     /* loop counts are multiples of this (AVX-512 width) */
#define VM_ALIGN 64  /* bytes */

#if defined(SUNMC_VMATH) && defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    defined(__GLIBC__) && defined(_OPENMP)
#if __GLIBC_PREREQ(2, 35)
#define VM_LIBMVEC 1
#pragma omp declare simd notinbranch
double sin(double) __attribute__((const));
#pragma omp declare simd notinbranch
double cos(double) __attribute__((const));
#pragma omp declare simd notinbranch
double tan(double) __attribute__((const));
#pragma omp declare simd notinbranch
double atan(double) __attribute__((const));
#pragma omp declare simd notinbranch
double atan2(double, double) __attribute__((const));
#pragma omp declare simd notinbranch
double log(double) __attribute__((const));
#pragma omp declare simd notinbranch
double asin(double) __attribute__((const));
#pragma omp declare simd notinbranch
double hypot(double, double) __attribute__((const));
#endif
#endif

/* Sanitizer checks are calls GCC cannot vectorise around: a kernel built
 * with them would take libm's scalar path and round differently, so the
 * sanitizer build of the tests would not reproduce the plain build's
 * numbers.  Kernels are left uninstrumented (they are loops over arrays of
 * vm_pad(n) values; valgrind covers them). */
#if defined(VM_LIBMVEC) && defined(VM_FORCE_BASELINE)
/* `make KERNEL_ISA=baseline`: one path on every CPU (a cluster of mixed
 * nodes whose shards must merge). */
#define VM_NOSAN __attribute__((no_sanitize("address", "undefined")))
#define VM_KERNEL VM_NOSAN
#elif defined(VM_LIBMVEC)
#define VM_NOSAN __attribute__((no_sanitize("address", "undefined")))
#define VM_KERNEL __attribute__((target_clones("default", "arch=x86-64-v3"))) VM_NOSAN
#else
#define VM_NOSAN
#define VM_KERNEL
#endif
/* For a function inlined into a kernel (and into its scalar callers, which
 * must then carry VM_NOSAN too: GCC inlines only between functions with
 * the same sanitizer settings). */
#define VM_INLINE static inline __attribute__((always_inline)) VM_NOSAN

#define VM_SIMD _Pragma("omp simd")

/* The kernel path this process runs: "avx2" (x86-64-v3, chosen by the
 * loader on a CPU that has it) or "baseline".  Its last bits differ, so it
 * is part of a result's identity (manifest.ini kernel_isa). */
const char *vm_isa(void);

/* 1 in a binary whose kernels were built for the baseline only
 * (VM_FORCE_BASELINE: sunmc-baseline, or `make KERNEL_ISA=baseline`). */
int vm_forced_baseline(void);

/* The build's identity: compiler version and the flags that move a
 * result's last bits (manifest.ini build). */
const char *vm_build_id(void);

/* x where keep is true, else +0 (NaN and inf included): a select that GCC
 * vectorises inside a kernel loop, as it needs x in every lane (with
 * "keep ? x : 0" it moves the computation of x under a branch). */
static inline __attribute__((always_inline)) double vm_keep(int keep, double x)
{
    union {
        double d;
        unsigned long long u;
    } v = {.d = x};
    v.u &= 0ULL - (unsigned long long)(keep != 0);
    return v.d;
}

/* cond ? a : b, both computed (the same reason as vm_keep). */
static inline __attribute__((always_inline)) double vm_select(int cond, double a, double b)
{
    union {
        double d;
        unsigned long long u;
    } x = {.d = a}, y = {.d = b};
    unsigned long long m = 0ULL - (unsigned long long)(cond != 0);
    x.u = (x.u & m) | (y.u & ~m);
    return x.d;
}

/* n rounded up to a multiple of VM_PAD. */
static inline size_t vm_pad(size_t n)
{
    return (n + VM_PAD - 1) / VM_PAD * VM_PAD;
}

/* Zeroed array of vm_pad(n) doubles aligned to VM_ALIGN (free with free()). */
double *vm_alloc(size_t n);

#endif
