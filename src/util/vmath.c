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
