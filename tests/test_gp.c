/* test_gp.c: GP cost model from counted operations, local-memory limit, firmware errors. */
#include <math.h>
#include <string.h>
#include "harness.h"
#include "gp_cost.h"
#include "machine.h"

/* ---- kernels written here, counting their real operations ---- */

static float dot_counted(fw_ops_t *o, const float *a, const float *b, int n)
{
    float s = 0.0f;
    for (int i = 0; i < n; i++) {
        fw_branch(o);                  /* loop test */
        fw_int(o, 1);                  /* i++ (pointer bump) */
        float x = fw_fload(o, &a[i]);
        float y = fw_fload_use(o, &b[i]);      /* the multiply needs it next */
        s = fw_fadd(o, s, fw_fmul(o, x, y));
    }
    return s;
}

static float lerp(fw_ops_t *o, float a, float b, float t)
{
    return fw_fadd(o, a, fw_fmul(o, t, fw_fsub(o, b, a)));
}

/* Trilinear interpolation in a 2x2x2 cell c[z][y][x]. */
static float trilinear_counted(fw_ops_t *o, const float c[2][2][2], float tx, float ty, float tz)
{
    float v[2][2];
    for (int z = 0; z < 2; z++) {
        for (int y = 0; y < 2; y++) {
            v[z][y] = lerp(o, fw_fload(o, &c[z][y][0]), fw_fload(o, &c[z][y][1]), tx);
        }
    }
    return lerp(o, lerp(o, v[0][0], v[0][1], ty), lerp(o, v[1][0], v[1][1], ty), tz);
}

TEST(gp_cost_dot_product_counts_match_an_independent_count)
{
    float a[100], b[100];
    double want = 0;
    for (int i = 0; i < 100; i++) {
        a[i] = (float)(i % 7) - 3.0f;
        b[i] = (float)(i % 5) * 0.5f;
        want += (double)a[i] * b[i];
    }
    fw_ops_t o = {0};
    float got = dot_counted(&o, a, b, 100);
    CHECK_NEAR(got, want, 1e-3);
    /* Per iteration: 1 mul, 1 add, 2 loads (one used at once), 1 int op, 1 branch. */
    CHECK_EQ(o.fmul, 100);
    CHECK_EQ(o.fadd, 100);
    CHECK_EQ(o.loads, 200);
    CHECK_EQ(o.load_use, 100);
    CHECK_EQ(o.int_ops, 100);
    CHECK_EQ(o.branches, 100);

    pp5_params_t p;
    pp5_params_default(&p);
    gp_cost_t c;
    gp_cost_init(&c, &p);
    /* Table by hand with the defaults (load stall 1 per load used at once,
     * branch bubble 1, no dual issue): core = 100 + 200 + 100*1 + 100*2 =
     * 600; fp = 100 + 100 = 200. */
    CHECK_EQ(gp_cost_cycles(&c, &o), 800);
    p.i860_dual_issue = 1;        /* core and FP overlap: max(600, 200) */
    gp_cost_init(&c, &p);
    CHECK_EQ(gp_cost_cycles(&c, &o), 600);
}

TEST(gp_cost_trilinear_counts_match_an_independent_count)
{
    float c[2][2][2] = {{{0, 1}, {2, 3}}, {{4, 5}, {6, 7}}};   /* value = x + 2y + 4z */
    fw_ops_t o = {0};
    float v = trilinear_counted(&o, c, 0.25f, 0.5f, 0.75f);
    CHECK_NEAR(v, 0.25 + 2 * 0.5 + 4 * 0.75, 1e-6);
    /* 7 lerps x (sub + mul + add), 8 corner loads. */
    CHECK_EQ(o.fadd, 14);
    CHECK_EQ(o.fmul, 7);
    CHECK_EQ(o.loads, 8);
    pp5_params_t p;
    pp5_params_default(&p);
    p.i860_load_stall_cycles = 2;
    p.i860_fdiv_cycles = 40;
    gp_cost_t cost;
    gp_cost_init(&cost, &p);
    /* No corner load is used at once (its pair partner and the weight are
     * independent), so the stall of 2 is never paid: core = 8; fp = 14 + 7
     * = 21; sum 29. */
    CHECK_EQ(o.load_use, 0);
    CHECK_EQ(gp_cost_cycles(&cost, &o), 29);
    fw_ops_t d = { .fdiv = 2, .fsqrt = 1, .ext_bytes = 10 };
    /* 2 * 40 + 31 (default fsqrt) + ceil(10 / 4) = 114 */
    CHECK_EQ(gp_cost_cycles(&cost, &d), 114);
}

/* The load-use and bus terms of gp_cost.h, worked by hand from the table. */
TEST(gp_cost_load_use_and_cache_terms_by_hand)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.i860_load_stall_cycles = 2;
    p.i860_dcache_line_bytes = 32;
    p.i860_ext_bus_bytes_per_cycle = 4;
    p.i860_dcache_miss_cycles = 6;
    gp_cost_t c;
    gp_cost_init(&c, &p);
    fw_ops_t o = { .loads = 10, .load_use = 3, .dcache_hits = 7, .dcache_misses = 3,
                   .dcache_writebacks = 1, .ext_bytes = 10 };
    /* issue: 10 loads + 3 x 2 stall = 16; bus: ceil(10/4) = 3, 3 misses x
     * (6 + 32/4) = 42, 1 write-back x 8 = 8: 53; hits cost nothing. */
    CHECK_EQ(gp_cost_bus_cycles(&c, &o), 53);
    CHECK_EQ(gp_cost_cycles(&c, &o), 16 + 53);
    /* A 64-byte line over a 16-byte bus: 4 cycles each; dual issue does not
     * hide the bus (a fill stalls the i860). */
    p.i860_dcache_line_bytes = 64;
    p.i860_dcache_bytes = 8192;
    p.i860_ext_bus_bytes_per_cycle = 16;
    p.i860_dual_issue = 1;
    gp_cost_init(&c, &p);
    fw_ops_t m = { .fadd = 100, .loads = 20, .dcache_misses = 2, .dcache_writebacks = 2 };
    CHECK_EQ(gp_cost_cycles(&c, &m), 100 + 2 * (6 + 4) + 2 * 4);
}

/* ---- programs running on a small machine ---- */

static float g_a[64], g_b[64];
static uint64_t g_cycles_seen;

static fw_status_t dot_start(gp_t *gp)
{
    fw_ops_t o = {0};
    volatile float r = dot_counted(&o, g_a, g_b, 64);
    (void)r;
    fw_charge(gp, &o);
    g_cycles_seen = fw_cycles(gp);
    return FW_OK;
}

static const fw_program_t dot_prog = { "dot", 1024, dot_start, NULL };

static void small_params(pp5_params_t *p)
{
    pp5_params_default(p);
    p->n_gp = 2;
    p->n_renderers = 1;
    p->fb_width = 128;
    p->fb_height = 128;
}

TEST(gp_program_time_comes_from_charged_operations)
{
    pp5_params_t p;
    small_params(&p);
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &dot_prog, NULL, 0) == PP5_OK);
    sched_stop_t why;
    pp5_status_t st = machine_run_setup(&m, &why);
    CHECK_EQ(st, PP5_OK);
    CHECK_EQ(why, SCHED_STOP_IDLE);
    /* 64 iterations x 8 cycles (see the dot-product test); local clock
     * starts when the HOST_LOAD arrives. */
    CHECK_EQ(m.gp[0].busy_cycles, 64 * 8);
    CHECK_EQ(m.gp[0].busy_ps, 64 * 8 * 25000ull);
    pp5_tick_t arrival = m.gp[0].local_ps - m.gp[0].busy_ps;
    CHECK_EQ(g_cycles_seen, arrival / 25000 + 64 * 8);
    /* HOST_LOAD: 1024 image bytes + 8 header = 258 words x 50 ns, 1 hop. */
    CHECK_EQ(arrival, 258ull * 50000 + 50000);
    CHECK_EQ(m.ring.bytes_sent[RING_CLASS_HOST], 1032);
    machine_free(&m);
}

static int g_alloc_failed;

static fw_status_t greedy_start(gp_t *gp)
{
    void *a = fw_alloc(gp, 40000);
    void *b = fw_alloc(gp, 20000);   /* 1024 + 40000 + 20000 > 60000 */
    g_alloc_failed = (a != NULL && b == NULL);
    return FW_OK;                    /* ignores the failure: must still stop */
}

static const fw_program_t greedy_prog = { "greedy", 1024, greedy_start, NULL };

TEST(gp_local_memory_limit_is_a_firmware_error)
{
    pp5_params_t p;
    small_params(&p);
    p.gp_local_mem_bytes = 60000;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 1, &greedy_prog, NULL, 0) == PP5_OK);
    sched_stop_t why;
    pp5_status_t st = machine_run_setup(&m, &why);
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK_EQ(why, SCHED_STOP_FIRMWARE_ERROR);
    CHECK(g_alloc_failed);
    CHECK(strstr(pp5_error_text(), "GP 1") != NULL);
    CHECK(strstr(pp5_error_text(), "gp.local_mem_bytes") != NULL);
    machine_free(&m);
}

TEST(gp_host_load_larger_than_memory_fails)
{
    pp5_params_t p;
    small_params(&p);
    p.gp_local_mem_bytes = 8192;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    static uint8_t data[10000];
    REQUIRE(machine_load_program(&m, 0, &dot_prog, data, sizeof data) == PP5_OK);
    sched_stop_t why;
    pp5_status_t st = machine_run_setup(&m, &why);
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "HOST_LOAD") != NULL);
    machine_free(&m);
}

static fw_status_t bad_send_start(gp_t *gp)
{
    return fw_send(gp, ring_addr(RING_NODE_RENDERER, 99), RING_MSG_RENDERER_EXEC, NULL, NULL, 0);
}

static const fw_program_t bad_send_prog = { "bad-send", 1024, bad_send_start, NULL };

TEST(gp_send_to_a_missing_node_is_a_firmware_error)
{
    pp5_params_t p;
    small_params(&p);
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &bad_send_prog, NULL, 0) == PP5_OK);
    sched_stop_t why;
    pp5_status_t st = machine_run_setup(&m, &why);
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "renderer 99") != NULL);
    machine_free(&m);
}

/* Ping-pong: GP 0 sends B bytes to GP 1, which answers; the round trip must
 * equal 2 x (serialisation + hops x hop latency) + GP send and receive costs. */
static pp5_tick_t g_pong_time;

static fw_status_t ping_start(gp_t *gp)
{
    if (fw_gp_index(gp) != 0) {
        return FW_OK;
    }
    static uint8_t payload[392];        /* + 8 header = 400 bytes = 100 words */
    return fw_send(gp, ring_addr(RING_NODE_GP, 1), RING_MSG_GP_USER, NULL, payload, sizeof payload);
}

static fw_status_t ping_message(gp_t *gp, const ring_msg_t *msg)
{
    if (msg->kind != RING_MSG_GP_USER) {
        return FW_OK;
    }
    if (fw_gp_index(gp) == 1) {
        return fw_send(gp, ring_addr(RING_NODE_GP, 0), RING_MSG_GP_USER, NULL, msg->payload, msg->payload_bytes);
    }
    g_pong_time = fw_time_ps(gp);
    return FW_OK;
}

static const fw_program_t ping_prog = { "ping", 1024, ping_start, ping_message };

TEST(gp_ring_ping_pong_round_trip_matches_the_parameters)
{
    pp5_params_t p;
    small_params(&p);
    p.ring_hop_cycles = 5;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    /* Load GP 1 first so it is running before the ping arrives. */
    REQUIRE(machine_load_program(&m, 1, &ping_prog, NULL, 0) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &ping_prog, NULL, 0) == PP5_OK);
    sched_stop_t why;
    pp5_status_t st = machine_run_setup(&m, &why);
    REQUIRE(st == PP5_OK);
    /* GP 0 starts when its load arrives: two 1032-byte loads from the host
     * (258 words each, sequential on the host's transmitter), 1 hop. */
    pp5_tick_t word = 50000, hop = 5 * word, send = 16 * 25000ull, rx = p.gp_rx_msg_cycles * 25000ull;
    pp5_tick_t gp0_start = 2 * 258 * word + 1 * hop;
    /* Ring positions: host 0, GP0 1, GP1 2, renderer 3, FB 4 (5 nodes):
     * GP0 -> GP1 is 1 hop, GP1 -> GP0 is 4 hops.  Each GP takes its message
     * off the port (gp.rx_msg_cycles) before its program sees it. */
    pp5_tick_t want = gp0_start + send + 100 * word + 1 * hop + rx + send + 100 * word + 4 * hop + rx;
    CHECK_EQ(g_pong_time, want);
    machine_free(&m);
}

static fw_status_t bad_pixels_start(gp_t *gp)
{
    static uint8_t rgb[16 * 16 * 3];
    uint32_t args[RING_MSG_ARGS] = { 120, 0, 16, 16, 0, 0 };   /* x 120..135 on a 128-wide screen */
    return fw_send(gp, ring_addr(RING_NODE_FB, 0), RING_MSG_FB_PIXELS, args, rgb, sizeof rgb);
}

static const fw_program_t bad_pixels_prog = { "bad-pixels", 1024, bad_pixels_start, NULL };

static fw_status_t good_pixels_start(gp_t *gp)
{
    static uint8_t rgb[16 * 8 * 3];
    for (size_t i = 0; i < sizeof rgb; i++) {
        rgb[i] = (uint8_t)(i * 3);
    }
    uint32_t args[RING_MSG_ARGS] = { 100, 50, 16, 8, 0, 0 };
    return fw_send(gp, ring_addr(RING_NODE_FB, 0), RING_MSG_FB_PIXELS, args, rgb, sizeof rgb);
}

static const fw_program_t good_pixels_prog = { "good-pixels", 1024, good_pixels_start, NULL };

TEST(gp_pixels_to_the_frame_buffer_are_checked_and_placed)
{
    pp5_params_t p;
    small_params(&p);
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &bad_pixels_prog, NULL, 0) == PP5_OK);
    sched_stop_t why;
    pp5_status_t st = machine_run_setup(&m, &why);
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "frame buffer") != NULL && strstr(pp5_error_text(), "outside") != NULL);
    machine_free(&m);

    p.fb_double_buffered = 0;    /* blocks are visible at once */
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &good_pixels_prog, NULL, 0) == PP5_OK);
    st = machine_run_setup(&m, &why);
    REQUIRE(st == PP5_OK);
    const image8_t *img = fb_front(&m.fb);
    /* Pixel (row 2, col 5) of the block lands at (105, 52); its red byte is
     * block byte (2*16 + 5)*3. */
    CHECK_EQ(img->pixels[(52 * 128 + 105) * 3], (uint8_t)((2 * 16 + 5) * 3 * 3));
    CHECK_EQ(img->pixels[(49 * 128 + 105) * 3], 0);
    CHECK_EQ(m.fb.pixels_received, 16 * 8);
    CHECK_EQ(m.ring.bytes_sent[RING_CLASS_PIXELS], 16 * 8 * 3 + p.ring_header_bytes);
    machine_free(&m);
}
