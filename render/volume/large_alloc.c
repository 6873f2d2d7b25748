/* Memory for the grids that the passes sample at random-ish places on every slice. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* madvise */
#endif
#include "renderer_internal.h"

#include <stdlib.h>
#ifdef __linux__
#include <sys/mman.h>
#endif

/* An oblique slice through a 256^3 grid of four fields (268 MB) touches every z-layer, 1 MB apart:
 * with 4 KiB pages nearly every trilinear corner row misses the TLB. Aligned to 2 MiB and marked
 * for transparent huge pages (where the kernel offers them only on request), the same grid needs
 * 128 page entries instead of 65536. Freed with free(). */
void *sl__huge_alloc(size_t bytes)
{
  const size_t huge = (size_t)2 << 20;
  void *p = NULL;
  if (bytes < huge) return malloc(bytes);
  const size_t rounded = (bytes + huge - 1) / huge * huge;
  if (posix_memalign(&p, huge, rounded)) return NULL;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  (void)madvise(p, rounded, MADV_HUGEPAGE); /* advice only: without it the pages are small */
#endif
  return p;
}
