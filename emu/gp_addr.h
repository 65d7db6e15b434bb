/* gp_addr.h: emulated addresses of a GP's local-memory blocks: a deterministic first-fit allocator over the address space.
 *
 * Every fw_alloc block gets an emulated address, so that the data cache
 * (gp_dcache.h) sees the same addresses on every host and every run: they
 * depend only on the program's sequence of fw_alloc and fw_free calls, never
 * on host pointers.  Blocks are aligned to GP_ADDR_ALIGN bytes (the
 * firmware's own allocator is assumed to align to a cache line, [U]) and
 * placed first-fit from address 0 in the free ranges, which merge again when
 * blocks are freed.
 *
 * The model never fails an allocation for fragmentation (gp.local_mem_bytes
 * counts requested bytes, fw_api.c): when no free range below the highest
 * block is large enough, the block goes above it, so addresses can reach
 * past gp.local_mem_bytes; gp_addr_top_peak() reports how far they went. */
#ifndef PP5_GP_ADDR_H
#define PP5_GP_ADDR_H

#include <stddef.h>
#include <stdint.h>
#include "util/status.h"

#define GP_ADDR_ALIGN 32u

typedef struct {
    uint64_t start, end;          /* [start, end) */
} gp_addr_range_t;

typedef struct {
    gp_addr_range_t *free;        /* free ranges below `top`, sorted, never adjacent */
    size_t n_free, cap_free;
    uint64_t top;                 /* everything at or above is free */
    uint64_t top_peak;            /* highest `top` seen */
} gp_addr_map_t;

void gp_addr_init(gp_addr_map_t *a);
void gp_addr_free_map(gp_addr_map_t *a);
/* Address of a new block of `bytes` (rounded up to GP_ADDR_ALIGN). */
pp5_status_t gp_addr_alloc(gp_addr_map_t *a, uint64_t bytes, uint64_t *addr);
/* Returns the block at addr (of the same `bytes` it was allocated with). */
pp5_status_t gp_addr_release(gp_addr_map_t *a, uint64_t addr, uint64_t bytes);
/* The highest end of any block so far. */
uint64_t gp_addr_top_peak(const gp_addr_map_t *a);

#endif
