/* Memory for large grids (sl_large_alloc.h): on huge pages where the passes sample them at
 * random-ish places on every slice or the loader writes them whole, zero until written where most
 * of a storm is clear air. */
#ifndef _DEFAULT_SOURCE
#define _DEFAULT_SOURCE /* madvise */
#endif
#include "sl_large_alloc.h"

#include <stdint.h>
#include <stdlib.h>
#ifdef __linux__
#include <sys/mman.h>
#endif

#define HUGE_PAGE ((size_t)2 << 20)

/* Transparent huge pages for the whole 2 MiB pages inside [p, p + bytes) (where the kernel offers
 * them only on request), or not (huge 0); advice only: without it the pages are small. */
static void advise_huge(const void *p, size_t bytes, int huge)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE) && defined(MADV_NOHUGEPAGE)
  const uintptr_t lo = ((uintptr_t)p + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
  const uintptr_t hi = ((uintptr_t)p + bytes) / HUGE_PAGE * HUGE_PAGE;
  if (hi > lo) (void)madvise((void *)lo, hi - lo, huge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
#else
  (void)p, (void)bytes, (void)huge;
#endif
}

void sl__advise_huge_reads(const void *p, size_t bytes) { advise_huge(p, bytes, 1); }

void sl__advise_reads_done(const void *p, size_t bytes) { advise_huge(p, bytes, 0); }

/* An oblique slice through a 256^3 grid of four fields (268 MB) touches every z-layer, 1 MB apart:
 * with 4 KiB pages nearly every trilinear corner row misses the TLB. Aligned to 2 MiB and marked
 * for transparent huge pages, the same grid needs 128 page entries instead of 65536. */
void *sl__huge_alloc(size_t bytes)
{
  void *p = NULL;
  if (bytes < HUGE_PAGE) return malloc(bytes);
  const size_t rounded = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
  if (posix_memalign(&p, HUGE_PAGE, rounded)) return NULL;
  advise_huge(p, rounded, 1);
  return p;
}

/* calloc, whose blocks this large are fresh anonymous mappings that it does not clear (the
 * kernel's pages are zero): a page is mapped when first written, and a read of one never written
 * maps the shared zero page. A 1000 x 1000 x 160 storm's four fields are 2.56 GB, of which its
 * clouds fill a quarter. Not aligned (free() must take calloc's own pointer), so the huge pages
 * are the ones wholly inside. */
void *sl__huge_calloc(size_t bytes)
{
  void *p = calloc(1, bytes ? bytes : 1);
  if (p && bytes >= 2 * HUGE_PAGE) advise_huge(p, bytes, 1);
  return p;
}
