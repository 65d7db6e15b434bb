/* fw_api.h: the narrow firmware API: everything a GP program may do.
 *
 * GP programs (firmware/gp, firmware/pp, firmware/common) may include only
 * emu/api/ and firmware/common/ (tests/test_layers.c) and may call only what
 * emu/api/ declares (the Makefile's link check), so this header, ring_msg.h and
 * pp_encode.h are all they can see (STYLE L2): a program cannot touch a
 * renderer's pixel memory except by sending ring messages.
 *
 * Execution model.  A program is a set of callbacks that run to completion:
 * on_start once after the host has loaded the GP (HOST_LOAD arrived), and
 * on_message for every ring message addressed to this GP.  Native C does the
 * work; the program CHARGES it with the operations it really performed
 * (fw_ops_t counts, most easily via the counting helpers fw_fadd, fw_fmul, ...)
 * and fw_charge() converts them into i860 cycles with the cited cost table
 * (emu/gp_cost.h).  The GP's local clock advances by those cycles; a message
 * sent with fw_send() leaves at the GP's local time at the moment of the call.
 * A frame begins for the program when the host's FRAME_START message
 * (args[0] = frame number) reaches on_message.
 *
 * Memory.  fw_alloc() takes bytes from the GP's local memory, whose capacity
 * is the parameter gp.local_mem_bytes ([U], facts §2).  Past the capacity it
 * returns NULL and records a firmware error: the run stops with
 * PP5_E_FIRMWARE, never a silent success.  Memory is zeroed.
 *
 * Errors.  Callbacks return FW_OK or an error made by fw_fail(), which stops
 * the machine with that message (stop reason FIRMWARE_ERROR). */
#ifndef PP5_FW_API_H
#define PP5_FW_API_H

#include <stddef.h>
#include <stdint.h>
#include "ring_msg.h"

typedef int fw_status_t;
#define FW_OK 0
#define FW_ERROR (-1)

typedef struct gp gp_t;     /* opaque to firmware: one graphics processor */

/* Operation counts of a piece of work.  Single-precision FP unless named
 * otherwise.  loads/stores are instructions: each costs its issue clock, a
 * load whose value the next instruction uses at once (load_use) also the
 * load-use delay.  Whether the data were in the data cache is declared apart
 * (fw_dcache_access), as line lookups: hits cost nothing more, misses and
 * write-backs pay the external bus.  ext_bytes are other bytes moved over the
 * external bus (programmed I/O from the ring port). */
typedef struct {
    uint64_t fadd;       /* FP add/subtract/compare (adder pipeline) */
    uint64_t fmul;       /* FP multiply (multiplier pipeline) */
    uint64_t fdiv;       /* FP divide: no i860 instruction, reciprocal + Newton */
    uint64_t fsqrt;      /* FP square root: reciprocal sqrt + Newton */
    uint64_t loads;      /* integer or FP loads */
    uint64_t stores;     /* integer or FP stores */
    uint64_t int_ops;    /* integer ALU, shifts, address arithmetic, moves */
    uint64_t branches;   /* taken or not-taken branches, calls, returns */
    uint64_t ext_bytes;  /* bytes over the external bus outside cache fills (port reads) */
    uint64_t load_use;   /* of the loads, those whose value the next instruction needs */
    uint64_t dcache_hits;       /* data-cache line lookups that hit */
    uint64_t dcache_misses;     /* ... that missed: a line fill over the external bus */
    uint64_t dcache_writebacks; /* written lines evicted by a miss: a line over the bus */
} fw_ops_t;

/* What a program may know about the machine it runs on. */
typedef struct {
    unsigned n_gp;
    unsigned n_renderers;
    unsigned screen_width, screen_height;   /* frame buffer pixels */
    unsigned region_width, region_height;   /* one renderer's PP array (128 x 128) */
    unsigned pp_mem_bits;                   /* bits of pixel memory per PP (208) */
    unsigned pp_bs_blocks;                  /* 32-bit backing-store blocks per PP (128) */
    uint64_t local_mem_bytes;               /* this GP's memory capacity */
} fw_machine_info_t;

typedef struct {
    const char *name;
    /* Stand-in size of the program's i860 binary, loaded by the host over
     * the ring and counted against local memory ([U]: native C has no i860
     * image; the program states a plausible size). */
    size_t image_bytes;
    fw_status_t (*on_start)(gp_t *gp);
    fw_status_t (*on_message)(gp_t *gp, const ring_msg_t *msg);
} fw_program_t;

/* Identity and machine facts. */
unsigned fw_gp_index(const gp_t *gp);
const fw_machine_info_t *fw_machine_info(const gp_t *gp);

/* The data block the host loaded for this GP (may be empty). */
const void *fw_host_data(const gp_t *gp, size_t *bytes);

/* Per-GP program state: a pointer the program keeps between callbacks
 * (normally memory from fw_alloc). */
void fw_set_state(gp_t *gp, void *state);
void *fw_state(const gp_t *gp);

/* Local memory (see above). fw_free returns the bytes to the pool. */
void *fw_alloc(gp_t *gp, size_t bytes);
/* fw_alloc filled with a copy of `bytes` at src instead of zeros (host
 * speed: a received unit or a built stream is not zeroed first). */
void *fw_alloc_copy(gp_t *gp, const void *src, size_t bytes);
/* The payload of the message on_message is handling (its msg argument) as
 * a block of local memory: what fw_alloc_copy(gp, msg->payload,
 * msg->payload_bytes) returns, charged, addressed and freed the same.  The
 * host keeps the ring's buffer instead of copying it when it can (host
 * speed only); msg->payload is then the block itself, valid until fw_free. */
void *fw_take_payload(gp_t *gp, const ring_msg_t *msg);
void fw_free(gp_t *gp, void *p);
uint64_t fw_mem_used_bytes(const gp_t *gp);

/* Charge work: the GP's local clock advances by gp_cost_cycles(ops). */
void fw_charge(gp_t *gp, const fw_ops_t *ops);

/* The data cache (emu/gp_dcache.h: i860.dcache_* parameters).  The program
 * declares an access of `bytes` at `offset` inside a block that fw_alloc
 * returned (`block_base`, the pointer fw_alloc gave, never a pointer into
 * it); the lookups of the lines it touches are added to ops->dcache_hits,
 * dcache_misses and dcache_writebacks, which fw_charge turns into bus
 * cycles.  Every block has an emulated address (deterministic, from the
 * order of fw_alloc/fw_free), so the outcome never depends on the host.  A
 * block that fw_alloc did not return, or a range outside it, is a firmware
 * error.  Accesses not declared count as hits (small tables, state). */
void fw_dcache_access(gp_t *gp, fw_ops_t *ops, const void *block_base, size_t offset,
                      size_t bytes, int is_store);
/* n accesses of `bytes` each at offsets[0], ..., offsets[n - 1] of one
 * block, in that order: the same lookups, in the same order, as n calls of
 * fw_dcache_access (host speed: the block is checked once). */
void fw_dcache_access_n(gp_t *gp, fw_ops_t *ops, const void *block_base, const size_t *offsets,
                        size_t n, size_t bytes, int is_store);

/* Ring delivery.  Every received message costs the GP gp.rx_msg_cycles
 * when it is handed to on_message (taking it off the port: [U] facts open
 * question 5).  A program that keeps a payload (copies it into local memory
 * at block_base + offset, block_base from fw_alloc, or NULL when it uses the
 * payload where the port left it) declares the bytes with fw_rx_deposit,
 * which adds what getting them there cost: nothing more when the ring port
 * writes memory itself (gp.rx_dma = 1; the lines it overwrote leave the data
 * cache), and under programmed I/O (gp.rx_dma = 0) the copy loop: per 32-bit
 * word a load from the port (4 bytes over the external bus) and a store
 * through the data cache, plus a loop test per 4 words. */
void fw_rx_deposit(gp_t *gp, fw_ops_t *ops, const void *block_base, size_t offset, size_t bytes);
/* The GP's local clock in i860 cycles since power-on, and in picoseconds. */
uint64_t fw_cycles(const gp_t *gp);
uint64_t fw_time_ps(const gp_t *gp);

/* Send a message over the ring at the GP's current local time.  The payload
 * is copied.  The traffic class is chosen from kind and destination
 * (commands to renderers, pixels to the FB, GP_USER to GPs...). */
fw_status_t fw_send(gp_t *gp, ring_addr_t dst, uint32_t kind,
                    const uint32_t args[RING_MSG_ARGS],
                    const void *payload, size_t payload_bytes);

/* Named statistics.  A program publishes what it counts (rays, cycles per
 * phase, the times its phases ended) as named statistics of its GP; the host
 * and the reports read them from emu's statistics registry (emu/stats.h:
 * "gp.G.prog.NAME"), never from the program's memory.  fw_stat_declare
 * returns the handle of NAME (declaring it the first time; at most
 * FW_MAX_STATS per GP, names up to 31 characters); fw_stat_add adds to a
 * counter, fw_stat_set stores a value such as an emulated time.  Publishing is
 * bookkeeping of the emulation: it costs the GP no cycles. */
#define FW_MAX_STATS 64
typedef int fw_stat_t;
typedef enum { FW_STAT_COUNTER, FW_STAT_VALUE } fw_stat_kind_t;
fw_stat_t fw_stat_declare(gp_t *gp, const char *name, fw_stat_kind_t kind, const char *unit,
                          const char *meaning);
void fw_stat_add(gp_t *gp, fw_stat_t id, uint64_t n);
void fw_stat_set(gp_t *gp, fw_stat_t id, uint64_t value);

/* Record a firmware error (printf-style) and return FW_ERROR. */
fw_status_t fw_fail(gp_t *gp, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Counting helpers: do the operation AND count it, so charged work is the
 * work actually performed. */
static inline float fw_fadd(fw_ops_t *o, float a, float b) { o->fadd++; return a + b; }
static inline float fw_fsub(fw_ops_t *o, float a, float b) { o->fadd++; return a - b; }
static inline float fw_fmul(fw_ops_t *o, float a, float b) { o->fmul++; return a * b; }
static inline float fw_fdiv(fw_ops_t *o, float a, float b) { o->fdiv++; return a / b; }
static inline float fw_fload(fw_ops_t *o, const float *p) { o->loads++; return *p; }
/* A load whose value the next instruction uses at once (gp_cost.h). */
static inline float fw_fload_use(fw_ops_t *o, const float *p)
{
    o->loads++;
    o->load_use++;
    return *p;
}
static inline void fw_fstore(fw_ops_t *o, float *p, float v) { o->stores++; *p = v; }
static inline int32_t fw_iload(fw_ops_t *o, const int32_t *p) { o->loads++; return *p; }
static inline void fw_istore(fw_ops_t *o, int32_t *p, int32_t v) { o->stores++; *p = v; }
static inline int32_t fw_iadd(fw_ops_t *o, int32_t a, int32_t b)
{
    o->int_ops++;
    return (int32_t)((uint32_t)a + (uint32_t)b);   /* wraps like the i860 */
}
static inline void fw_int(fw_ops_t *o, uint64_t n) { o->int_ops += n; }
static inline void fw_branch(fw_ops_t *o) { o->branches++; }

#endif
