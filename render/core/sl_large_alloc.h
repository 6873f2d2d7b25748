/* Memory for large grids: the renderer's extinction grids and light states, the loader's work
 * arrays, and advice for a loaded storm's fields. */
#ifndef SL_LARGE_ALLOC_H
#define SL_LARGE_ALLOC_H

#include <stddef.h>

/* `bytes` aligned to 2 MiB and advised for transparent huge pages (large_alloc.c); not cleared.
 * Freed with free(). */
void *sl__huge_alloc(size_t bytes);

/* `bytes` that read as zero, advised for transparent huge pages where whole ones fit, whose pages
 * take memory only once written: a storm's fields are mostly clear air, which then costs nothing.
 * Freed with free(). */
void *sl__huge_calloc(size_t bytes);

/* Advice for memory about to be read whole, much of which may never have been written (a loaded
 * storm's fields, calloc's): huge pages, so that a read of an unwritten 2 MiB maps the kernel's
 * shared zero page in one fault instead of 512 (the 1000 x 1000 x 80 synthetic cumulonimbus's
 * render: 1.13M minor faults against 1.50M without it). Pages written already stay as they are;
 * memory is unchanged. */
void sl__advise_huge_reads(const void *p, size_t bytes);

/* sl__advise_huge_reads taken back once the read is done: the kernel's khugepaged would otherwise
 * gather, over the minutes of a long session, every partly written 2 MiB of a loaded storm into a
 * whole huge page (the loader writes only where there is cloud), and its memory would grow. */
void sl__advise_reads_done(const void *p, size_t bytes);

#endif
