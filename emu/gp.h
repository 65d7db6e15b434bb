/* gp.h: one graphics processor (Intel i860): program callbacks, local clock, local memory, ring port.
 *
 * A GP runs firmware (fw_program_t, see emu/api/fw_api.h) as run-to-
 * completion callbacks.  Its local clock (local_ps) advances by the cycles
 * the program charges (gp_cost) plus gp.send_cycles per message posted;
 * between callbacks it is idle.  Incoming messages wait in an inbox (FIFO)
 * and are handled one callback each, at max(arrival, local clock).
 * HOST_LOAD is handled by the GP itself: it reserves the program image and
 * copies the data into local memory, then runs on_start.
 *
 * Every message handed to on_message first costs gp.rx_msg_cycles (taking it
 * off the ring port); a payload the program keeps is declared with
 * fw_rx_deposit, free under DMA (gp.rx_dma = 1) and a copy loop under
 * programmed I/O.  Local-memory blocks have deterministic emulated addresses
 * (gp_addr.h) and accesses the program declares go through the data cache
 * (gp_dcache.h).
 *
 * Modelled: i860 time from counted operations, the data cache on declared
 * accesses, local memory capacity, message order, busy/idle time.  Not
 * modelled: the i860 instruction stream itself, accesses the program does not
 * declare (taken as hits), interrupts/OS overhead beyond gp.rx_msg_cycles,
 * contention between the ring port's DMA and the GP on the memory bus. */
#ifndef PP5_GP_H
#define PP5_GP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "fw_api.h"
#include "gp_addr.h"
#include "gp_cost.h"
#include "gp_dcache.h"
#include "pp5_time.h"
#include "pp5_sched.h"

typedef pp5_status_t (*gp_send_fn)(void *ctx, gp_t *gp, const ring_msg_t *msg, pp5_tick_t t);
/* Observer of busy spans (timeline): [start, end) running callback `what`. */
typedef void (*gp_trace_fn)(void *ctx, const gp_t *gp, const char *what, pp5_tick_t start,
                            pp5_tick_t end);

/* A local-memory allocation: header + the bytes (fw_api.c). */
typedef struct gp_block gp_block_t;
struct gp_block {
    gp_block_t *next, *prev;
    void *host_base;              /* what free() takes: the header itself, or the
                                     ring payload buffer it sits in (fw_take_payload) */
    size_t bytes;                 /* requested (what local memory is charged) */
    size_t capacity_bytes;        /* host bytes after the header (>= bytes when reused) */
    uint64_t emu_addr;            /* emulated local-memory address (gp_addr.h) */
    uint32_t magic;               /* GP_BLOCK_MAGIC while live (fw_dcache_access checks it) */
    max_align_t align[];          /* user memory follows, suitably aligned */
};
#define GP_BLOCK_MAGIC 0x6770626cu


/* One statistic a program published (fw_stat_declare). */
typedef struct {
    char name[32];
    fw_stat_kind_t kind;
    const char *unit, *meaning;   /* static strings of the program */
    uint64_t value;
} gp_stat_t;

typedef struct {
    ring_msg_t msg;       /* payload points at `payload_copy` */
    void *payload_copy;
} gp_inbox_item_t;

struct gp {
    unsigned index;
    const fw_program_t *prog;
    fw_machine_info_t info;
    gp_cost_t cost;
    pp5_tick_t period_ps;
    uint32_t send_cycles;
    uint32_t rx_msg_cycles;       /* gp.rx_msg_cycles */
    bool rx_dma;                  /* gp.rx_dma */
    gp_dcache_t dcache;           /* the i860's data cache */
    gp_addr_map_t addr;           /* emulated addresses of the blocks */

    pp5_tick_t local_ps;          /* the GP's clock */
    pp5_tick_t busy_ps;
    uint64_t busy_cycles;
    pp5_tick_t setup_busy_ps;     /* part of busy_ps spent in machine_run_setup */
    uint64_t setup_busy_cycles;
    fw_ops_t ops_total;
    fw_ops_t setup_ops;           /* part of ops_total charged in machine_run_setup */

    uint64_t mem_capacity_bytes, mem_used_bytes, mem_peak_bytes;
    gp_block_t *blocks;           /* every live allocation, freed at gp_free */
    /* Freed large blocks kept for reuse (host speed only: per-frame buffers
     * would otherwise come back as fresh pages, zeroed by page faults, every
     * frame); at most spare_bytes <= mem_capacity_bytes, freed at gp_free. */
    gp_block_t *spare;
    uint64_t spare_bytes;
    void *state;
    const void *host_data;
    size_t host_data_bytes;
    bool loaded, started;

    gp_inbox_item_t *inbox;       /* ring buffer */
    void *handling_payload;       /* the payload buffer of the message on_message is
                                     handling, until fw_take_payload keeps it */
    size_t inbox_head, inbox_count, inbox_cap;
    bool run_scheduled;

    uint64_t msgs_sent, msgs_received, bytes_sent;
    gp_stat_t stats[FW_MAX_STATS];    /* the program's named statistics */
    unsigned n_stats;
    bool fw_error;
    char error[256];

    sched_t *sched;
    gp_send_fn send;
    void *send_ctx;
    gp_trace_fn trace;
    void *trace_ctx;
};

pp5_status_t gp_init(gp_t *gp, unsigned index, const pp5_params_t *p, const fw_machine_info_t *info,
                     sched_t *sched, gp_send_fn send, void *send_ctx);
void gp_free(gp_t *gp);
void gp_set_program(gp_t *gp, const fw_program_t *prog);
/* A ring message for this GP arrived at `now`.  The GP takes ownership of
 * `payload_buf` (from ring_payload_alloc, holding msg->payload's bytes, e.g.
 * from ring_take_payload) instead of copying; NULL: it copies the payload. */
pp5_status_t gp_deliver_owned(gp_t *gp, const ring_msg_t *msg, void *payload_buf, pp5_tick_t now);
/* Charge raw cycles (used by the firmware API for sends). */
void gp_charge_cycles(gp_t *gp, uint64_t cycles);
bool gp_busy(const gp_t *gp, pp5_tick_t now);
/* Record the first firmware error of this GP (the run stops at the end of
 * the current callback). */
void gp_record_error(gp_t *gp, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
