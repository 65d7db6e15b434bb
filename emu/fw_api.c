/* fw_api.c: the firmware API (emu/api/fw_api.h) on top of gp_t: memory, charging, sends, errors. */
#include "gp.h"
#include "ring_payload.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


/* ---- local memory ---- */

void gp_record_error(gp_t *gp, const char *fmt, ...)
{
    if (gp->fw_error) {
        return;                   /* keep the first error */
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(gp->error, sizeof gp->error, fmt, ap);
    va_end(ap);
    gp->fw_error = true;
}

/* Under ASan, spare blocks and the unrequested tail of a reused block are
 * poisoned, so firmware overruns and uses after fw_free are still caught. */
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#define SPARE_POISON(p, n) ASAN_POISON_MEMORY_REGION((p), (n))
#define SPARE_UNPOISON(p, n) ASAN_UNPOISON_MEMORY_REGION((p), (n))
#else
#define SPARE_POISON(p, n) ((void)(p), (void)(n))
#define SPARE_UNPOISON(p, n) ((void)(p), (void)(n))
#endif

/* Blocks at least this large are kept on free for reuse: below it malloc
 * recycles memory itself (no fresh pages). */
#define SPARE_MIN_BYTES ((size_t)64 << 10)

/* Takes the smallest spare block holding `bytes` but not more than twice that
 * (so a small request does not pin a huge block); NULL if none. */
static gp_block_t *take_spare(gp_t *gp, size_t bytes, bool zero)
{
    gp_block_t *best = NULL;
    for (gp_block_t *b = gp->spare; b; b = b->next) {
        if (b->capacity_bytes >= bytes && b->capacity_bytes / 2 <= bytes &&
            (!best || b->capacity_bytes < best->capacity_bytes)) {
            best = b;
            if (b->capacity_bytes == bytes)
                break;                      /* the usual case: a buffer of a repeated size */
        }
    }
    if (!best)
        return NULL;
    if (best->prev)
        best->prev->next = best->next;
    else
        gp->spare = best->next;
    if (best->next)
        best->next->prev = best->prev;
    gp->spare_bytes -= best->capacity_bytes;
    SPARE_UNPOISON(best->align, bytes);
    if (zero)
        memset(best->align, 0, bytes);      /* fw_api.h: memory is zeroed */
    return best;
}

/* Whether `bytes` more fit local memory (the error is recorded if not). */
static bool block_fits(gp_t *gp, size_t bytes)
{
    if (bytes <= gp->mem_capacity_bytes - gp->mem_used_bytes)
        return true;
    gp_record_error(gp, "fw_alloc(%zu bytes) exceeds local memory: %llu of %llu bytes in use "
                    "(parameter gp.local_mem_bytes)", bytes,
                    (unsigned long long)gp->mem_used_bytes, (unsigned long long)gp->mem_capacity_bytes);
    return false;
}

/* Gives host block b an emulated address and makes it a live block of
 * `bytes`; false (error recorded, b untouched) when no address is left. */
static bool block_admit(gp_t *gp, gp_block_t *b, size_t bytes)
{
    if (gp_addr_alloc(&gp->addr, bytes, &b->emu_addr) != PP5_OK) {
        gp_record_error(gp, "fw_alloc(%zu bytes): %s", bytes, pp5_error_text());
        return false;
    }
    b->magic = GP_BLOCK_MAGIC;
    b->bytes = bytes;
    b->prev = NULL;
    b->next = gp->blocks;
    if (gp->blocks) {
        gp->blocks->prev = b;
    }
    gp->blocks = b;
    gp->mem_used_bytes += bytes;
    if (gp->mem_used_bytes > gp->mem_peak_bytes) {
        gp->mem_peak_bytes = gp->mem_used_bytes;
    }
    return true;
}

/* fw_alloc, and fw_alloc_copy without zeroing what the copy overwrites. */
static void *alloc_block(gp_t *gp, size_t bytes, bool zero)
{
    if (!block_fits(gp, bytes))
        return NULL;
    gp_block_t *b = bytes >= SPARE_MIN_BYTES ? take_spare(gp, bytes, zero) : NULL;
    if (!b) {
        size_t capacity = bytes ? bytes : 1;
        b = zero ? calloc(1, sizeof *b + capacity) : malloc(sizeof *b + capacity);
        if (!b) {
            gp_record_error(gp, "host out of memory emulating fw_alloc(%zu bytes)", bytes);
            return NULL;
        }
        b->host_base = b;
        b->capacity_bytes = capacity;
    }
    if (!block_admit(gp, b, bytes)) {
        free(b->host_base);
        return NULL;
    }
    return b->align;
}

void *fw_alloc(gp_t *gp, size_t bytes)
{
    return alloc_block(gp, bytes, true);
}

void *fw_alloc_copy(gp_t *gp, const void *src, size_t bytes)
{
    void *p = alloc_block(gp, bytes, false);
    if (p && bytes > 0)
        memcpy(p, src, bytes);
    return p;
}

/* The block header goes into the ring buffer's headroom, so the payload is
 * the block's memory as it stands. */
_Static_assert(offsetof(gp_block_t, align) <= RING_PAYLOAD_HEADROOM,
               "a GP block header must fit a ring payload's headroom");

void *fw_take_payload(gp_t *gp, const ring_msg_t *m)
{
    void *buf = gp->handling_payload;
    if (!buf || buf != m->payload || m->payload_bytes == 0)
        return fw_alloc_copy(gp, m->payload, m->payload_bytes);
    if (!block_fits(gp, m->payload_bytes))
        return NULL;
    gp_block_t *b = (gp_block_t *)((char *)buf - offsetof(gp_block_t, align));
    b->host_base = ring_payload_host_base(buf);
    b->capacity_bytes = m->payload_bytes;
    if (!block_admit(gp, b, m->payload_bytes))
        return NULL;               /* the buffer stays the message's, freed with it */
    gp->handling_payload = NULL;
    /* The spare block a copy would have taken goes back to the heap, where
     * the next payload's allocation finds it: kept, it would only sit
     * there while the host's memory grew. */
    gp_block_t *spare = m->payload_bytes >= SPARE_MIN_BYTES ? take_spare(gp, m->payload_bytes, false)
                                                            : NULL;
    if (spare)
        free(spare->host_base);
    return buf;
}

void fw_free(gp_t *gp, void *p)
{
    if (!p) {
        return;
    }
    gp_block_t *b = (gp_block_t *)((char *)p - offsetof(gp_block_t, align));
    if (gp_addr_release(&gp->addr, b->emu_addr, b->bytes) != PP5_OK)
        gp_record_error(gp, "fw_free: %s", pp5_error_text());
    b->magic = 0;
    if (b->prev) {
        b->prev->next = b->next;
    } else {
        gp->blocks = b->next;
    }
    if (b->next) {
        b->next->prev = b->prev;
    }
    gp->mem_used_bytes -= b->bytes;
    /* Host memory only: the emulated local memory is charged by `bytes` above.
     * A kept ring buffer goes back to the heap, where the next payload's
     * allocation finds it; as a spare it would only make the heap grow. */
    if (b->host_base == b && b->capacity_bytes >= SPARE_MIN_BYTES &&
        gp->spare_bytes + b->capacity_bytes <= gp->mem_capacity_bytes) {
        b->prev = NULL;
        b->next = gp->spare;
        if (gp->spare) {
            gp->spare->prev = b;
        }
        gp->spare = b;
        gp->spare_bytes += b->capacity_bytes;
        SPARE_POISON(b->align, b->capacity_bytes);
        return;
    }
    free(b->host_base);
}

uint64_t fw_mem_used_bytes(const gp_t *gp) { return gp->mem_used_bytes; }

/* ---- the firmware API (declared in fw_api.h) ---- */

unsigned fw_gp_index(const gp_t *gp) { return gp->index; }
const fw_machine_info_t *fw_machine_info(const gp_t *gp) { return &gp->info; }

const void *fw_host_data(const gp_t *gp, size_t *bytes)
{
    *bytes = gp->host_data_bytes;
    return gp->host_data;
}

void fw_set_state(gp_t *gp, void *state) { gp->state = state; }
void *fw_state(const gp_t *gp) { return gp->state; }

void fw_charge(gp_t *gp, const fw_ops_t *ops)
{
    gp_charge_cycles(gp, gp_cost_cycles(&gp->cost, ops));
    gp_cost_add(&gp->ops_total, ops);
}

/* The live block fw_alloc returned as `block_base`, or NULL (a firmware
 * error is recorded) when it is not one or [offset, offset + bytes) leaves it. */
static const gp_block_t *gp_block_of(gp_t *gp, const void *block_base, size_t offset, size_t bytes,
                                     const char *who)
{
    if (!block_base) {
        gp_record_error(gp, "%s: no block", who);
        return NULL;
    }
    const gp_block_t *b = (const gp_block_t *)((const char *)block_base - offsetof(gp_block_t, align));
    if (b->magic != GP_BLOCK_MAGIC) {
        gp_record_error(gp, "%s: %p is not a block fw_alloc returned", who, block_base);
        return NULL;
    }
    if (offset > b->bytes || bytes > b->bytes - offset) {
        gp_record_error(gp, "%s: bytes [%zu, %zu) outside the %zu-byte block", who, offset,
                        offset + bytes, b->bytes);
        return NULL;
    }
    return b;
}

void fw_dcache_access(gp_t *gp, fw_ops_t *ops, const void *block_base, size_t offset, size_t bytes,
                      int is_store)
{
    const gp_block_t *b = gp_block_of(gp, block_base, offset, bytes, "fw_dcache_access");
    if (!b || bytes == 0)
        return;
    uint64_t addr = b->emu_addr + offset;
    if (!gp_dcache_hit_most_recent(&gp->dcache, addr, bytes, is_store != 0, ops))
        gp_dcache_access(&gp->dcache, addr, bytes, is_store != 0, ops);
}

void fw_dcache_access_n(gp_t *gp, fw_ops_t *ops, const void *block_base, const size_t *offsets,
                        size_t n, size_t bytes, int is_store)
{
    if (n == 0 || bytes == 0)
        return;
    size_t last = 0;
    for (size_t i = 0; i < n; i++)
        last = offsets[i] > last ? offsets[i] : last;
    /* Every offset is at most the last, so one range check covers them all. */
    const gp_block_t *b = gp_block_of(gp, block_base, last, bytes, "fw_dcache_access_n");
    if (!b)
        return;
    for (size_t i = 0; i < n; i++) {
        uint64_t addr = b->emu_addr + offsets[i];
        if (!gp_dcache_hit_most_recent(&gp->dcache, addr, bytes, is_store != 0, ops))
            gp_dcache_access(&gp->dcache, addr, bytes, is_store != 0, ops);
    }
}

void fw_rx_deposit(gp_t *gp, fw_ops_t *ops, const void *block_base, size_t offset, size_t bytes)
{
    const gp_block_t *b = NULL;
    if (block_base && !(b = gp_block_of(gp, block_base, offset, bytes, "fw_rx_deposit")))
        return;
    if (bytes == 0)
        return;
    if (gp->rx_dma) {
        /* [U] the port wrote memory behind the cache: its stale lines go. */
        if (b)
            gp_dcache_invalidate(&gp->dcache, b->emu_addr + offset, bytes);
        return;
    }
    /* Programmed I/O: load a word from the port, store it; unrolled by 4. */
    uint64_t words = (bytes + 3) / 4;
    ops->loads += words;
    ops->stores += words;
    ops->int_ops += (words + 3) / 4;
    ops->branches += (words + 3) / 4;
    ops->ext_bytes += bytes;
    if (b)
        gp_dcache_access(&gp->dcache, b->emu_addr + offset, bytes, true, ops);
}

uint64_t fw_cycles(const gp_t *gp) { return gp->local_ps / gp->period_ps; }
uint64_t fw_time_ps(const gp_t *gp) { return gp->local_ps; }

static uint32_t gp_class_for(ring_addr_t dst, uint32_t kind)
{
    switch (dst.type) {
    case RING_NODE_RENDERER:
        return (kind == RING_MSG_RENDERER_WRITE_FIELD || kind == RING_MSG_RENDERER_WRITE_BS)
                   ? RING_CLASS_DATA : RING_CLASS_COMMAND;
    case RING_NODE_FB: return RING_CLASS_PIXELS;
    case RING_NODE_GP: return RING_CLASS_GP;
    default: return RING_CLASS_DATA;
    }
}

fw_status_t fw_send(gp_t *gp, ring_addr_t dst, uint32_t kind, const uint32_t args[RING_MSG_ARGS],
                    const void *payload, size_t payload_bytes)
{
    if (gp->fw_error) {
        return FW_ERROR;
    }
    if (payload_bytes > 0 && !payload) {
        return fw_fail(gp, "fw_send: %zu payload bytes but no payload", payload_bytes);
    }
    ring_msg_t m = ring_msg_make(ring_addr(RING_NODE_GP, gp->index), dst, kind,
                                 gp_class_for(dst, kind), args, payload, payload_bytes);
    gp_charge_cycles(gp, gp->send_cycles);   /* [U] gp.send_cycles */
    pp5_status_t st = gp->send(gp->send_ctx, gp, &m, gp->local_ps);
    if (st != PP5_OK) {
        return fw_fail(gp, "%s", pp5_error_text());
    }
    gp->msgs_sent++;
    gp->bytes_sent += payload_bytes;
    return FW_OK;
}

fw_status_t fw_fail(gp_t *gp, const char *fmt, ...)
{
    if (!gp->fw_error) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(gp->error, sizeof gp->error, fmt, ap);
        va_end(ap);
        gp->fw_error = true;
    }
    return FW_ERROR;
}


/* ---- named statistics ---- */

fw_stat_t fw_stat_declare(gp_t *gp, const char *name, fw_stat_kind_t kind, const char *unit,
                          const char *meaning)
{
    for (unsigned i = 0; i < gp->n_stats; i++)
        if (strcmp(gp->stats[i].name, name) == 0)
            return (fw_stat_t)i;
    if (gp->n_stats == FW_MAX_STATS || strlen(name) >= sizeof gp->stats[0].name) {
        gp_record_error(gp, "fw_stat_declare(\"%s\"): more than %d statistics or a name over "
                        "%zu characters", name, FW_MAX_STATS, sizeof gp->stats[0].name - 1);
        return -1;
    }
    gp_stat_t *st = &gp->stats[gp->n_stats];
    snprintf(st->name, sizeof st->name, "%s", name);
    st->kind = kind;
    st->unit = unit;
    st->meaning = meaning;
    st->value = 0;
    return (fw_stat_t)gp->n_stats++;
}

void fw_stat_add(gp_t *gp, fw_stat_t id, uint64_t n)
{
    if (id >= 0 && (unsigned)id < gp->n_stats)
        gp->stats[id].value += n;
}

void fw_stat_set(gp_t *gp, fw_stat_t id, uint64_t value)
{
    if (id >= 0 && (unsigned)id < gp->n_stats)
        gp->stats[id].value = value;
}
