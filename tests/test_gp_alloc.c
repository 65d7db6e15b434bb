/* test_gp_alloc.c: GP host-memory handling: fw_alloc / fw_free reuse of freed large blocks (memory
 * comes back zeroed, fw_alloc_copy's holds its source, local-memory accounting is by requested bytes, the
 * capacity limit is unchanged), payloads the GP keeps from the ring, and fw_take_payload against
 * fw_alloc_copy. */
#include <stdint.h>
#include <string.h>

#include "harness.h"
#include "machine.h"

/* The program's callbacks run inside machine_run_setup, on the test's own
 * thread, so they check directly; the count shows that every check ran. */
static int g_checks_run;
#define EXPECT(cond, ...) (g_checks_run++, CHECK_MSG(cond, __VA_ARGS__))

static int all_zero(const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (p[i])
            return 0;
    return 1;
}

/* Runs on GP 0 at setup: allocation patterns of a frame loop. */
static fw_status_t churn_start(gp_t *gp)
{
    const size_t big = 300000, image = 1024;
    for (int round = 0; round < 3; round++) {
        uint8_t *a = fw_alloc(gp, big);
        uint8_t *b = fw_alloc(gp, big - 1000 * (size_t)round);   /* slightly smaller each round */
        EXPECT(a && b, "round %d: both big blocks allocated", round);
        if (!a || !b)
            return FW_OK;
        EXPECT(all_zero(a, big) && all_zero(b, big - 1000 * (size_t)round),
               "round %d: the big blocks come back zeroed", round);
        EXPECT(fw_mem_used_bytes(gp) == image + 2 * big - 1000 * (uint64_t)round,
               "round %d: %llu bytes in use, want %llu", round,
               (unsigned long long)fw_mem_used_bytes(gp),
               (unsigned long long)(image + 2 * big - 1000 * (uint64_t)round));
        memset(a, 0xa5, big);
        memset(b, 0x5a, big - 1000 * (size_t)round);
        fw_free(gp, b);
        fw_free(gp, a);
        EXPECT(fw_mem_used_bytes(gp) == image, "round %d: %llu bytes in use after the frees, "
               "want the image's %zu", round, (unsigned long long)fw_mem_used_bytes(gp), image);
    }
    /* A much smaller request must not be served from (and dirty) a big block,
     * and still comes back zeroed. */
    uint8_t *small = fw_alloc(gp, 70000);
    EXPECT(small && all_zero(small, 70000), "a 70000-byte block after the big ones is zeroed");
    /* The capacity limit counts live bytes only, never the kept spare blocks:
     * 1024 + 70000 + 900000 <= 1000000. */
    uint8_t *large = fw_alloc(gp, 900000);
    EXPECT(large && all_zero(large, 900000), "a 900000-byte block fits beside the kept spares");
    EXPECT(fw_mem_used_bytes(gp) == image + 70000 + 900000, "%llu bytes in use, want %zu",
           (unsigned long long)fw_mem_used_bytes(gp), image + 70000 + 900000);
    fw_free(gp, large);
    fw_free(gp, small);
    /* fw_alloc_copy skips the zeroing but not the copy: from a reused block
     * (the freed ones above hold 0xa5 / 0x5a) it holds exactly the source */
    static uint8_t src[300000];   /* big */
    for (size_t i = 0; i < big; i++)
        src[i] = (uint8_t)(i * 7u + 3u);
    uint8_t *copy = fw_alloc_copy(gp, src, big);
    EXPECT(copy && memcmp(copy, src, big) == 0, "fw_alloc_copy holds its source");
    EXPECT(fw_mem_used_bytes(gp) == image + big, "%llu bytes in use with the copy, want %zu",
           (unsigned long long)fw_mem_used_bytes(gp), image + big);
    fw_free(gp, copy);
    return FW_OK;
}

static const fw_program_t churn_prog = {"churn", 1024, churn_start, NULL};

TEST(gp_alloc_reuse_zeroed_and_accounted)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 1;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    p.gp_local_mem_bytes = 1000000;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &churn_prog, NULL, 0) == PP5_OK);
    g_checks_run = 0;
    sched_stop_t why;
    CHECK_EQ(machine_run_setup(&m, &why), PP5_OK);
    CHECK_EQ(why, SCHED_STOP_IDLE);
    CHECK_EQ(g_checks_run, 3 * 4 + 3 + 2);
    CHECK_EQ(m.gp[0].mem_peak_bytes, 1024 + 70000 + 900000);
    machine_free(&m);
}

/* Messages to a GP: the GP now keeps the ring's payload buffer instead of
 * copying it.  Several messages in flight at once, the sender reusing its
 * buffer right after each send: every message must arrive with its own bytes. */
enum { XFER_MSGS = 6, XFER_BYTES = 70000 };
static int g_xfer_received;

static uint8_t xfer_byte(unsigned msg, size_t i)
{
    return (uint8_t)(msg * 37u + i * 11u + (i >> 8));
}

static fw_status_t xfer_start(gp_t *gp)
{
    if (fw_gp_index(gp) != 0)
        return FW_OK;
    static uint8_t buf[XFER_BYTES];
    for (unsigned k = 0; k < XFER_MSGS; k++) {
        for (size_t i = 0; i < XFER_BYTES; i++)
            buf[i] = xfer_byte(k, i);
        uint32_t args[RING_MSG_ARGS] = {k};
        fw_status_t st = fw_send(gp, ring_addr(RING_NODE_GP, 1), RING_MSG_GP_USER, args, buf,
                                 XFER_BYTES - k);
        if (st != FW_OK)
            return st;
    }
    memset(buf, 0xee, sizeof buf);
    return FW_OK;
}

static fw_status_t xfer_message(gp_t *gp, const ring_msg_t *msg)
{
    if (msg->kind != RING_MSG_GP_USER)
        return FW_OK;
    unsigned k = msg->args[0];
    const uint8_t *p = msg->payload;
    g_xfer_received++;
    if (!CHECK_MSG(k < XFER_MSGS && msg->payload_bytes == XFER_BYTES - k,
                   "message %u: %zu bytes, want %d", k, msg->payload_bytes, XFER_BYTES - (int)k))
        return FW_OK;
    size_t i = 0;
    while (i < msg->payload_bytes && p[i] == xfer_byte(k, i))
        i++;
    CHECK_MSG(i == msg->payload_bytes, "message %u: byte %zu is %u, want %u", k, i,
              i < msg->payload_bytes ? p[i] : 0, i < msg->payload_bytes ? xfer_byte(k, i) : 0);
    return FW_OK;
}

static const fw_program_t xfer_prog = {"xfer", 1024, xfer_start, xfer_message};

/* Runs `prog` on both GPs of a small machine (GP 0 sends, GP 1 receives)
 * through setup; the caller frees m. */
static void run_two_gps(machine_t *m, const fw_program_t *prog)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 2;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    REQUIRE(machine_init(m, &p) == PP5_OK);
    REQUIRE(machine_load_program(m, 1, prog, NULL, 0) == PP5_OK);
    REQUIRE(machine_load_program(m, 0, prog, NULL, 0) == PP5_OK);
    g_xfer_received = 0;
    sched_stop_t why;
    CHECK_EQ(machine_run_setup(m, &why), PP5_OK);
    CHECK_EQ(why, SCHED_STOP_IDLE);
    CHECK_EQ(g_xfer_received, XFER_MSGS);
}

TEST(gp_alloc_delivered_payloads_intact)
{
    machine_t m;
    run_two_gps(&m, &xfer_prog);
    machine_free(&m);
}

/* fw_take_payload keeps the ring's buffer as a block of local memory.  It
 * must be the block fw_alloc_copy would give: the same bytes, the same
 * local-memory use and the same data-cache outcome (emulated addresses,
 * not host ones), run once taking and once copying. */
static bool g_keep_take;
static fw_ops_t g_keep_ops;
static uint64_t g_keep_peak;

static fw_status_t keep_message(gp_t *gp, const ring_msg_t *msg)
{
    if (msg->kind != RING_MSG_GP_USER)
        return FW_OK;
    unsigned k = msg->args[0];
    uint64_t before = fw_mem_used_bytes(gp);
    const uint8_t *block = g_keep_take ? fw_take_payload(gp, msg)
                                       : fw_alloc_copy(gp, msg->payload, msg->payload_bytes);
    g_xfer_received++;
    if (!EXPECT(block != NULL, "message %u: a block", k))
        return FW_OK;
    EXPECT(fw_mem_used_bytes(gp) == before + msg->payload_bytes,
           "message %u: %llu bytes more in use, want %zu", k,
           (unsigned long long)(fw_mem_used_bytes(gp) - before), msg->payload_bytes);
    size_t i = 0;
    while (i < msg->payload_bytes && block[i] == xfer_byte(k, i))
        i++;
    EXPECT(i == msg->payload_bytes, "message %u: byte %zu of the block differs", k, i);
    if (fw_mem_used_bytes(gp) > g_keep_peak)
        g_keep_peak = fw_mem_used_bytes(gp);
    /* Taking twice copies the second time, from the block itself. */
    const uint8_t *again = g_keep_take ? fw_take_payload(gp, msg) : NULL;
    if (g_keep_take)
        EXPECT(again && again != block && memcmp(again, block, msg->payload_bytes) == 0,
               "message %u: a second take is a copy of the same bytes", k);
    for (size_t off = 0; off + 4 <= msg->payload_bytes; off += 4096 + 4 * k)
        fw_dcache_access(gp, &g_keep_ops, block, off, 4, 0);
    fw_free(gp, (void *)again);
    fw_charge(gp, &g_keep_ops);
    /* every other block lives on, so that later ones get other addresses */
    if (k % 2)
        fw_free(gp, (void *)block);
    return FW_OK;
}

static const fw_program_t keep_prog = {"keep", 1024, xfer_start, keep_message};

static void run_keep(bool take, fw_ops_t *ops, uint64_t *gp1_cycles, uint64_t *peak)
{
    g_keep_take = take;
    memset(&g_keep_ops, 0, sizeof g_keep_ops);
    g_keep_peak = 0;
    machine_t m;
    run_two_gps(&m, &keep_prog);
    *ops = g_keep_ops;
    *gp1_cycles = m.gp[1].local_ps / m.gp[1].period_ps;
    *peak = g_keep_peak;
    machine_free(&m);
}

TEST(gp_alloc_taken_payload_is_the_copy_it_replaces)
{
    fw_ops_t taken, copied;
    uint64_t cyc_taken, cyc_copied, peak_taken, peak_copied;
    run_keep(true, &taken, &cyc_taken, &peak_taken);
    run_keep(false, &copied, &cyc_copied, &peak_copied);
    CHECK(copied.dcache_misses > 0);
    CHECK_EQ(taken.dcache_hits, copied.dcache_hits);
    CHECK_EQ(taken.dcache_misses, copied.dcache_misses);
    CHECK_EQ(taken.dcache_writebacks, copied.dcache_writebacks);
    CHECK_EQ(cyc_taken, cyc_copied);
    CHECK_EQ(peak_taken, peak_copied);
}
