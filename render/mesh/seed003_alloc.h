/* seed003_alloc.h: large arrays of seed 003 on huge pages.
 *
 * Why: seed 003 reads its per-corner records at random (an edge costed or
 * re-queued anywhere on the mesh), so with 4 KB pages nearly every such
 * read also misses the TLB, and on a virtual machine a TLB miss walks two
 * page tables.  An array of a few MB on 2 MB pages is covered by a handful
 * of TLB entries and faults in with a few page faults instead of
 * thousands.  To 1 % of the bunny this cut the time by 12-16 % for the
 * first two arrays (ARCHITECTURE.md, "Seed 003 ... decisions").
 *
 * The arrays are mapped on their own, not taken from malloc: memory malloc
 * hands out again later (to another simplifier in the same process) keeps
 * the huge-page advice of the range it lies in, and malloc's heap grows to
 * the size of blocks freed before it, so advice given through malloc
 * spread to whatever ran next. */
#ifndef PP5_SEED003_ALLOC_H
#define PP5_SEED003_ALLOC_H

#include <stdbool.h>
#include <stddef.h>

/* An array of `bytes`, zeroed if asked, or NULL.  From 2 MB up it is
 * mapped on its own, aligned to 2 MB, with the kernel asked for huge
 * pages (where it has them); smaller arrays come from malloc. */
void *s003_alloc_big(size_t bytes, bool zero);
/* Releases an array of s003_alloc_big (bytes: as it was asked for). */
void s003_free_big(void *p, size_t bytes);
/* A larger array from s003_alloc_big holding the first `used` bytes of
 * old (old_bytes long), which is released; NULL (old kept) if out of
 * memory. */
void *s003_grow_big(void *old, size_t used, size_t old_bytes, size_t bytes);

#endif
