/* vmath.c - aligned, padded arrays for the kernel loops (see vmath.h). */
#include "vmath.h"

#include <stdlib.h>
#include <string.h>

double *vm_alloc(size_t n)
{
    size_t bytes = vm_pad(n > 0 ? n : 1) * sizeof(double);
    bytes = (bytes + VM_ALIGN - 1) / VM_ALIGN * VM_ALIGN;
    double *p = aligned_alloc(VM_ALIGN, bytes);
    if (p)
        memset(p, 0, bytes);
    return p;
}

#ifndef SUNMC_BUILD_FLAGS
#define SUNMC_BUILD_FLAGS "-"
#endif

const char *vm_isa(void)
{
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && defined(__GLIBC__) && \
    defined(_OPENMP) && !defined(VM_FORCE_BASELINE)
#if __GLIBC_PREREQ(2, 35)
    __builtin_cpu_init();
    if (__builtin_cpu_supports("x86-64-v3"))
        return "avx2";
#endif
#endif
    return "baseline";
}

int vm_forced_baseline(void)
{
#ifdef VM_FORCE_BASELINE
    return 1;
#else
    return 0;
#endif
}

const char *vm_build_id(void)
{
#ifdef __VERSION__
    return "cc " __VERSION__ ", " SUNMC_BUILD_FLAGS;
#else
    return "cc ?, " SUNMC_BUILD_FLAGS;
#endif
}
