/* gp_addr.c: first-fit emulated-address allocator of one GP's local memory. */
#include "gp_addr.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

static uint64_t gp_addr_round(uint64_t bytes)
{
    uint64_t b = bytes ? bytes : 1;
    return (b + GP_ADDR_ALIGN - 1) / GP_ADDR_ALIGN * GP_ADDR_ALIGN;
}

void gp_addr_init(gp_addr_map_t *a)
{
    memset(a, 0, sizeof *a);
}

void gp_addr_free_map(gp_addr_map_t *a)
{
    free(a->free);
    memset(a, 0, sizeof *a);
}

static void gp_addr_remove(gp_addr_map_t *a, size_t i)
{
    memmove(a->free + i, a->free + i + 1, (a->n_free - i - 1) * sizeof *a->free);
    a->n_free--;
}

pp5_status_t gp_addr_alloc(gp_addr_map_t *a, uint64_t bytes, uint64_t *addr)
{
    uint64_t need = gp_addr_round(bytes);
    for (size_t i = 0; i < a->n_free; i++) {
        gp_addr_range_t *r = &a->free[i];
        if (r->end - r->start >= need) {
            *addr = r->start;
            r->start += need;
            if (r->start == r->end)
                gp_addr_remove(a, i);
            return PP5_OK;
        }
    }
    /* Above everything (no free range ends at the top: release lowers it). */
    uint64_t at = a->top;
    if (at > UINT64_MAX - need)
        return pp5_fail(PP5_E_RANGE, "GP address space exhausted");
    *addr = at;
    a->top = at + need;
    if (a->top > a->top_peak)
        a->top_peak = a->top;
    return PP5_OK;
}

pp5_status_t gp_addr_release(gp_addr_map_t *a, uint64_t addr, uint64_t bytes)
{
    uint64_t start = addr, end = addr + gp_addr_round(bytes);
    if (end > a->top)
        return pp5_fail(PP5_E_RANGE, "GP address block [%llu, %llu) lies above the top %llu",
                        (unsigned long long)start, (unsigned long long)end,
                        (unsigned long long)a->top);
    /* Position of the first free range after the block. */
    size_t lo = 0, hi = a->n_free;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (a->free[mid].start < start)
            lo = mid + 1;
        else
            hi = mid;
    }
    bool merge_prev = lo > 0 && a->free[lo - 1].end == start;
    bool merge_next = lo < a->n_free && a->free[lo].start == end;
    if ((lo > 0 && a->free[lo - 1].end > start) || (lo < a->n_free && a->free[lo].start < end))
        return pp5_fail(PP5_E_RANGE, "GP address block at %llu freed twice", (unsigned long long)start);
    if (merge_prev && merge_next) {
        a->free[lo - 1].end = a->free[lo].end;
        gp_addr_remove(a, lo);
    } else if (merge_prev) {
        a->free[lo - 1].end = end;
    } else if (merge_next) {
        a->free[lo].start = start;
    } else {
        if (a->n_free == a->cap_free) {
            size_t cap = a->cap_free ? a->cap_free * 2 : 64;
            gp_addr_range_t *nr = realloc(a->free, cap * sizeof *nr);
            if (!nr)
                return pp5_fail(PP5_E_NOMEM, "out of memory for the GP address map");
            a->free = nr;
            a->cap_free = cap;
        }
        memmove(a->free + lo + 1, a->free + lo, (a->n_free - lo) * sizeof *a->free);
        a->free[lo].start = start;
        a->free[lo].end = end;
        a->n_free++;
    }
    /* A free range that reaches the top lowers it. */
    if (a->n_free > 0 && a->free[a->n_free - 1].end == a->top) {
        a->top = a->free[a->n_free - 1].start;
        a->n_free--;
    }
    return PP5_OK;
}

uint64_t gp_addr_top_peak(const gp_addr_map_t *a)
{
    return a->top_peak;
}
