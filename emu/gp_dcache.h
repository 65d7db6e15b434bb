/* gp_dcache.h: the i860 on-chip data cache of one GP: set-associative, LRU within a set, write-back, write-allocate.
 *
 * Geometry from the parameter table: i860.dcache_bytes (8 KB [C], facts §8
 * S19), i860.dcache_line_bytes (32 [U]) and i860.dcache_ways (2 [U]); the
 * line size and associativity are not known (facts §8, open question 9).
 * sets = bytes / (line x ways), a power of two; an address's set is its line
 * number modulo sets.  Addresses are the GP's emulated local-memory addresses
 * (gp_addr.h), never host pointers, so hits and misses are the same on every
 * host.
 *
 * An access of `bytes` at `addr` looks up every line it touches, one lookup
 * per line: a present line is a hit (it becomes the most recent of its set);
 * an absent one is a miss, which fills the line over the external bus and
 * evicts the least recently used line of the set, a write-back when that line
 * was written.  A store that misses allocates the line like a load
 * (write-allocate) and marks it written.  The policies within a set (LRU,
 * write-back, write-allocate) are [U]: no source describes them.
 *
 * Not modelled: the 128-bit cache-to-register bus width (a lookup costs
 * nothing beyond the load or store instruction that declares it), pipelined
 * pfld loads that bypass the cache, the instruction cache (4 KB), bus
 * contention with the ring port's DMA, and coherence: a DMA into memory
 * simply invalidates the lines it overwrites (gp_dcache_invalidate). */
#ifndef PP5_GP_DCACHE_H
#define PP5_GP_DCACHE_H

#include <stdbool.h>
#include <stdint.h>
#include "fw_api.h"
#include "util/status.h"

typedef struct {
    uint32_t line_shift;          /* log2 of the line size in bytes */
    uint32_t ways, sets;
    uint64_t set_mask;            /* sets - 1 */
    /* sets x ways entries, most recently used first within a set: 0 = empty,
     * else (line number + 1) with GP_DCACHE_DIRTY set once written. */
    uint64_t *entry;
} gp_dcache_t;

#define GP_DCACHE_DIRTY (1ull << 63)

/* Geometry as validated by pp5_params_validate; the cache starts empty. */
pp5_status_t gp_dcache_init(gp_dcache_t *c, uint32_t bytes, uint32_t line_bytes, uint32_t ways);
void gp_dcache_free(gp_dcache_t *c);
/* Empties the cache (every line invalid, nothing written back). */
void gp_dcache_reset(gp_dcache_t *c);
/* Looks up every line of [addr, addr + bytes) (bytes > 0) and adds the
 * lookups to ops->dcache_hits / dcache_misses / dcache_writebacks. */
void gp_dcache_access(gp_dcache_t *c, uint64_t addr, uint64_t bytes, bool store, fw_ops_t *ops);
/* gp_dcache_access's commonest case without the call: an access inside one
 * line that is already the most recent of its set (a hit that changes no
 * order).  True when it was that case and has been counted. */
static inline bool gp_dcache_hit_most_recent(gp_dcache_t *c, uint64_t addr, uint64_t bytes,
                                             bool store, fw_ops_t *ops)
{
    uint64_t line = addr >> c->line_shift;
    if (((addr + bytes - 1) >> c->line_shift) != line)
        return false;
    uint64_t *first = c->entry + (size_t)(line & c->set_mask) * c->ways;
    if ((*first & ~GP_DCACHE_DIRTY) != line + 1)
        return false;
    ops->dcache_hits++;
    if (store)
        *first |= GP_DCACHE_DIRTY;
    return true;
}
/* Drops the lines of [addr, addr + bytes) without writing them back (memory
 * there was just overwritten by the ring port). */
void gp_dcache_invalidate(gp_dcache_t *c, uint64_t addr, uint64_t bytes);
/* Lines present (for tests). */
uint64_t gp_dcache_lines_present(const gp_dcache_t *c);

#endif
