/* gp_dcache.c: the i860 data cache model of one GP (lookups, LRU replacement, write-backs, invalidation). */
#include "gp_dcache.h"

#include <stdlib.h>
#include <string.h>

pp5_status_t gp_dcache_init(gp_dcache_t *c, uint32_t bytes, uint32_t line_bytes, uint32_t ways)
{
    memset(c, 0, sizeof *c);
    uint64_t way_bytes = (uint64_t)line_bytes * ways;
    uint64_t sets = way_bytes ? bytes / way_bytes : 0;
    if (line_bytes == 0 || (line_bytes & (line_bytes - 1)) != 0 || sets == 0 ||
        sets * way_bytes != bytes || (sets & (sets - 1)) != 0)
        return pp5_fail(PP5_E_CONFIG, "data cache of %u bytes, %u-byte lines, %u ways: not a "
                        "power-of-two number of whole sets", bytes, line_bytes, ways);
    while ((1u << c->line_shift) < line_bytes)
        c->line_shift++;
    c->ways = ways;
    c->sets = (uint32_t)sets;
    c->set_mask = sets - 1;
    c->entry = calloc((size_t)sets * ways, sizeof *c->entry);
    if (!c->entry)
        return pp5_fail(PP5_E_NOMEM, "out of memory for a %u-line data cache", (unsigned)(sets * ways));
    return PP5_OK;
}

void gp_dcache_free(gp_dcache_t *c)
{
    free(c->entry);
    memset(c, 0, sizeof *c);
}

void gp_dcache_reset(gp_dcache_t *c)
{
    memset(c->entry, 0, (size_t)c->sets * c->ways * sizeof *c->entry);
}

void gp_dcache_access(gp_dcache_t *c, uint64_t addr, uint64_t bytes, bool store, fw_ops_t *ops)
{
    uint64_t line = addr >> c->line_shift, last = (addr + bytes - 1) >> c->line_shift;
    uint32_t ways = c->ways;
    for (; line <= last; line++) {
        uint64_t *set = c->entry + (size_t)(line & c->set_mask) * ways;
        uint64_t key = line + 1, e;
        uint32_t w = 0;
        while (w < ways && (set[w] & ~GP_DCACHE_DIRTY) != key)
            w++;
        if (w < ways) {
            ops->dcache_hits++;
            e = set[w];
        } else {
            /* Miss: the least recently used way (the last) makes room. */
            ops->dcache_misses++;
            w = ways - 1;
            if (set[w] & GP_DCACHE_DIRTY)
                ops->dcache_writebacks++;
            e = key;
        }
        if (store)
            e |= GP_DCACHE_DIRTY;
        /* The line becomes the most recently used of its set (w is at most
         * a few ways: a plain loop beats a library call). */
        for (; w > 0; w--)
            set[w] = set[w - 1];
        set[0] = e;
    }
}

void gp_dcache_invalidate(gp_dcache_t *c, uint64_t addr, uint64_t bytes)
{
    if (bytes == 0)
        return;
    uint64_t first = addr >> c->line_shift, last = (addr + bytes - 1) >> c->line_shift;
    /* A range longer than the cache touches every set: scan the cache once
     * instead of every line of the range. */
    if (last - first >= (uint64_t)c->sets * c->ways) {
        for (size_t i = 0; i < (size_t)c->sets * c->ways; i++) {
            uint64_t line = (c->entry[i] & ~GP_DCACHE_DIRTY) - 1;
            if (c->entry[i] && line >= first && line <= last)
                c->entry[i] = 0;
        }
    } else {
        for (uint64_t line = first; line <= last; line++) {
            uint64_t *set = c->entry + (size_t)(line & c->set_mask) * c->ways;
            for (uint32_t w = 0; w < c->ways; w++)
                if ((set[w] & ~GP_DCACHE_DIRTY) == line + 1)
                    set[w] = 0;
        }
    }
    /* Keep each set's valid lines first (most recent first), empty ways last,
     * so that a miss always takes an empty way before evicting. */
    for (uint32_t s = 0; s < c->sets; s++) {
        uint64_t *set = c->entry + (size_t)s * c->ways;
        uint32_t k = 0;
        for (uint32_t w = 0; w < c->ways; w++)
            if (set[w])
                set[k++] = set[w];
        while (k < c->ways)
            set[k++] = 0;
    }
}

uint64_t gp_dcache_lines_present(const gp_dcache_t *c)
{
    uint64_t n = 0;
    for (size_t i = 0; i < (size_t)c->sets * c->ways; i++)
        n += c->entry[i] != 0;
    return n;
}
