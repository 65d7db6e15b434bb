/* seed003_alloc.h: large arrays of seed 003 on huge pages.
 *
 * Why: seed 003 reads its per-corner records at random (an edge costed or
 * re-queued anywhere on the mesh), so with 4 KB pages nearly every such
 * read also misses the TLB, and on a virtual machine a TLB miss walks two
 * page tables.  An array of a few MB on 2 MB pages is covered by a handful
 * of TLB entries and faults in with a few page faults instead of
 * thousands.  To 1 % of the bunny this cut the time by 12-16 % for two
 * arrays (make bench; ARCHITECTURE.md, "Seed 003 ... decisions"). */
#ifndef PP5_SEED003_ALLOC_H
#define PP5_SEED003_ALLOC_H

#include <stdbool.h>
#include <stddef.h>

/* An array of `bytes`, zeroed if asked, or NULL; free() releases it.
 * From 2 MB up it is aligned to 2 MB and asks the kernel for huge pages
 * (where it has them); smaller arrays are plain malloc. */
void *s003_alloc_big(size_t bytes, bool zero);
/* A larger array from s003_alloc_big holding the first `used` bytes of
 * old, which is freed; NULL (old kept) if out of memory. */
void *s003_grow_big(void *old, size_t used, size_t bytes);

#endif
