/* huge_alloc.h: large arrays read at random, on 2 MB pages where the host
 * offers them (transparent huge pages).
 *
 * Why: a walk that jumps across a few megabytes (the simplifiers' per-face
 * and per-corner records, render/mesh/ARCHITECTURE.md "Speed") misses the
 * TLB on nearly every read with 4 KB pages, and on a virtual machine a TLB
 * miss walks two page tables.  A few MB on 2 MB pages take a handful of TLB
 * entries and fault in with a few page faults instead of thousands.
 *
 * The arrays are mapped on their own, not taken from malloc: memory malloc
 * hands out again later keeps the huge-page advice of the range it lies
 * in, and malloc's heap grows to the size of blocks freed before it, so
 * advice given through malloc spreads to whatever runs next. */
#ifndef PP5_HUGE_ALLOC_H
#define PP5_HUGE_ALLOC_H

#include <stdbool.h>
#include <stddef.h>

/* An array of `bytes`, zeroed if asked, or NULL; aligned to a 64-byte
 * cache line at least.  From 2 MB up it is mapped on its own, aligned to
 * 2 MB, with the kernel asked for huge pages (advice only); smaller arrays
 * come from aligned_alloc. */
void *huge_alloc(size_t bytes, bool zero);
/* Releases an array of huge_alloc (bytes: as it was asked for). */
void huge_free(void *p, size_t bytes);
/* A larger array from huge_alloc holding the first `used` bytes of old
 * (old_bytes long), which is released; NULL (old kept) if out of memory. */
void *huge_grow(void *old, size_t used, size_t old_bytes, size_t bytes);

#endif
