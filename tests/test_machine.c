/* test_machine.c: the whole machine on the test pattern: image vs a native reference, frame-time hand calculation, determinism, budgets, report/timeline files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "harness.h"
#include "firmware/common/testpattern_gp.h"
#include "machine.h"
#include "pp_encode.h"
#include "report.h"
#include "stats.h"

/* Native reference of the scene in testpattern_gp.h, evaluated directly per
 * pixel with 64-bit integers (no QEE, no PP arithmetic). */
static void reference_pattern(unsigned w, unsigned h, uint8_t *rgb)
{
    int64_t W = w, H = h;
    int64_t dr = (255ll << 16) / (W - 1), eg = (255ll << 16) / (H - 1);
    int64_t maxd2 = (W / 2) * (W / 2) + (H / 2) * (H / 2);
    int64_t kb = (255ll << 20) / maxd2;
    for (int64_t y = 0; y < H; y++) {
        for (int64_t x = 0; x < W; x++) {
            int64_t c[3];
            c[0] = (x * dr) >> 16;
            c[1] = (y * eg) >> 16;
            c[2] = (kb * ((x - W / 2) * (x - W / 2) + (y - H / 2) * (y - H / 2))) >> 20;
            for (unsigned i = 0; i < TP_DISCS; i++) {
                tp_disc_t d = tp_disc(i, w, h);
                int64_t q = (x - d.cx) * (x - d.cx) + (y - d.cy) * (y - d.cy) - (int64_t)d.r * d.r;
                if (q < 0) {
                    int64_t k = (255ll << 16) / ((int64_t)d.r * d.r);
                    int64_t shade = (-q * k) >> 16;
                    for (int ch = 0; ch < 3; ch++) {
                        c[ch] = (d.colour >> ch) & 1 ? shade : 0;
                    }
                }
            }
            for (int ch = 0; ch < 3; ch++) {
                rgb[(y * W + x) * 3 + ch] = (uint8_t)c[ch];
            }
        }
    }
}

static pp5_status_t run_pattern(machine_t *m, const pp5_params_t *p, sched_stop_t *why)
{
    pp5_status_t st = machine_init(m, p);
    if (st == PP5_OK) {
        st = machine_load_all(m, &testpattern_program);
    }
    if (st == PP5_OK) {
        st = machine_run_setup(m, why);
    }
    if (st == PP5_OK) {
        st = machine_run_frame(m, why);
    }
    return st;
}

/* Compares the frame buffer with the native reference: one check, naming
 * how many bytes differ and the first pixel that does. */
static void check_image_matches_reference(const machine_t *m)
{
    unsigned w = m->params.fb_width, h = m->params.fb_height;
    uint8_t *ref = malloc((size_t)w * h * 3);
    REQUIRE(ref);
    reference_pattern(w, h, ref);
    const image8_t *img = fb_front(&m->fb);
    size_t bad = 0, first = 0;
    for (size_t i = 0; i < (size_t)w * h * 3; i++) {
        if (img->pixels[i] != ref[i] && bad++ == 0) {
            first = i;
        }
    }
    CHECK_MSG(bad == 0, "%zu of %zu bytes differ from the reference; first: pixel (%zu, %zu) "
              "channel %zu is %u, want %u", bad, (size_t)w * h * 3, first / 3 % w, first / 3 / w,
              first % 3, img->pixels[first], ref[first]);
    free(ref);
}

static void small_params(pp5_params_t *p)
{
    pp5_params_default(p);
    p->n_gp = 3;
    p->n_renderers = 2;
    p->fb_width = 384;
    p->fb_height = 256;   /* 6 regions over 2 renderers: 3 each */
}

TEST(machine_test_pattern_matches_native_reference_small)
{
    pp5_params_t p;
    small_params(&p);
    machine_t m;
    sched_stop_t why;
    pp5_status_t st = run_pattern(&m, &p, &why);
    REQUIRE_MSG(st == PP5_OK, "run failed: %s", pp5_error_text());
    CHECK_EQ(why, SCHED_STOP_IDLE);
    CHECK_EQ(m.fb.blocks_received, 6);
    check_image_matches_reference(&m);
    /* Conservation: every byte sent was delivered, per class. */
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        CHECK_EQ(m.ring.bytes_sent[k], m.ring.bytes_delivered[k]);
    }
    CHECK_EQ(m.ring.bytes_sent[RING_CLASS_PIXELS], 6ull * (128 * 128 * 3 + p.ring_header_bytes));
    /* Invariant: class shares of the ring add up to the aggregate utilisation. */
    double sum = 0;
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        sum += stats_ring_class_utilization(&m, k);
    }
    CHECK_NEAR(sum, stats_ring_utilization(&m), 1e-12);
    CHECK(stats_ring_utilization(&m) > 0.0 && stats_ring_utilization(&m) <= 1.0);
    machine_free(&m);
}

/* Frame-time hand calculation (emu/ARCHITECTURE.md, "Test-pattern frame
 * time"), from the parameters only:
 *   ring term:     N regions of 128x128x3 bytes + header, each
 *                  t_pix = ceil(bytes / channel width) ring cycles; with C
 *                  channels some channel carries >= ceil(N / C) of them.
 *   renderer term: none of them can start before some region is finished;
 *                  every region's stream holds at least the background
 *                  (EN_ALL + three QEEs: 8 bits with 16 and 16 and 20
 *                  fraction bits), costed with the PP rows' formula
 *                  (fill + ceil((fraction + kept bits) / rate), PP_ISA.md),
 *                  plus the 24-cycle readout of SEND_PIXELS.
 *   T_hand = ceil(N / C) x t_pix + t_background  is a strict lower bound.
 * The rest (GP binning/encoding of the first region, command streams ~0.4 %
 * of the bytes, disc instructions of the first region, hop latency) stays
 * under 2 % of T_hand for the full 80-region screen. */
static void check_hand_calculation(const char *preset)
{
    pp5_params_t p;
    REQUIRE(pp5_params_preset(&p, preset) == PP5_OK);
    machine_t m;
    sched_stop_t why;
    pp5_status_t st = run_pattern(&m, &p, &why);
    REQUIRE_MSG(st == PP5_OK, "run failed: %s", pp5_error_text());
    uint64_t regions = (p.fb_width / 128) * (p.fb_height / 128);
    uint64_t wire = 128 * 128 * 3 + p.ring_header_bytes;
    uint64_t words = (wire + p.ring_width_bits / 8 - 1) / (p.ring_width_bits / 8);
    double t_pix = words / p.ring_clock_hz;
    uint64_t rate = p.pp.qee_bits_per_cycle;
    uint64_t bg_cycles = p.pp.enable_op_cycles + 3ull * p.pp.qee_fill_cycles + 2 * ((16 + 8 + rate - 1) / rate) +
                         (20 + 8 + rate - 1) / rate + 24ull * p.rport_cycles_per_bit;
    double t_hand = (double)((regions + p.ring_channels - 1) / p.ring_channels) * t_pix +
                    (double)bg_cycles / p.renderer_clock_hz;
    double t = stats_frame_time_s(&m);
    CHECK_MSG(t >= t_hand, "%s: frame %.9f s below the lower bound %.9f s", preset, t, t_hand);
    CHECK_MSG(t <= t_hand * 1.02, "%s: frame %.9f s more than 2%% above the hand value %.9f s", preset, t, t_hand);
    check_image_matches_reference(&m);
    machine_free(&m);
}

TEST(machine_test_pattern_frame_time_matches_hand_calculation_default)
{
    check_hand_calculation("default");
}

TEST(machine_test_pattern_frame_time_matches_hand_calculation_gaze_literal)
{
    check_hand_calculation("gaze1990-literal");
}

TEST(machine_runs_are_deterministic)
{
    pp5_params_t p;
    small_params(&p);
    machine_t a, b;
    sched_stop_t why;
    REQUIRE(run_pattern(&a, &p, &why) == PP5_OK);
    REQUIRE(run_pattern(&b, &p, &why) == PP5_OK);
    CHECK_EQ(a.frames[0].end_ps - a.frames[0].start_ps, b.frames[0].end_ps - b.frames[0].start_ps);
    CHECK_EQ(a.sched.events_run, b.sched.events_run);
    for (unsigned i = 0; i < a.n_rn; i++) {
        CHECK_MSG(a.rn[i].cycles == b.rn[i].cycles, "renderer %u cycles: %llu then %llu", i,
                  (unsigned long long)a.rn[i].cycles, (unsigned long long)b.rn[i].cycles);
        CHECK_MSG(a.rn[i].busy_ps == b.rn[i].busy_ps, "renderer %u busy_ps: %llu then %llu", i,
                  (unsigned long long)a.rn[i].busy_ps, (unsigned long long)b.rn[i].busy_ps);
    }
    for (unsigned i = 0; i < a.n_gp; i++) {
        CHECK_MSG(a.gp[i].busy_cycles == b.gp[i].busy_cycles, "GP %u busy cycles: %llu then %llu",
                  i, (unsigned long long)a.gp[i].busy_cycles,
                  (unsigned long long)b.gp[i].busy_cycles);
    }
    for (unsigned c = 0; c < a.ring.n_channels; c++) {
        CHECK_MSG(a.ring.ch[c].bytes == b.ring.ch[c].bytes, "ring channel %u bytes: %llu then %llu",
                  c, (unsigned long long)a.ring.ch[c].bytes, (unsigned long long)b.ring.ch[c].bytes);
        CHECK_MSG(a.ring.ch[c].busy_ps == b.ring.ch[c].busy_ps,
                  "ring channel %u busy_ps: %llu then %llu", c,
                  (unsigned long long)a.ring.ch[c].busy_ps, (unsigned long long)b.ring.ch[c].busy_ps);
    }
    CHECK(memcmp(fb_front(&a.fb)->pixels, fb_front(&b.fb)->pixels, (size_t)p.fb_width * p.fb_height * 3) == 0);
    machine_free(&a);
    machine_free(&b);
}

TEST(machine_budget_exceeded_names_busy_units)
{
    pp5_params_t p;
    small_params(&p);
    p.sim_budget_s = 1e-5;      /* 10 us: far less than one 614 us region transfer */
    machine_t m;
    sched_stop_t why;
    pp5_status_t st = run_pattern(&m, &p, &why);
    CHECK_EQ(st, PP5_E_MACHINE);
    CHECK_EQ(why, SCHED_STOP_BUDGET_EXCEEDED);
    CHECK(strstr(pp5_error_text(), "budget") != NULL);
    CHECK(strstr(pp5_error_text(), "renderer") != NULL || strstr(pp5_error_text(), "GP") != NULL ||
          strstr(pp5_error_text(), "ring") != NULL);
    machine_free(&m);
}

TEST(machine_more_gps_than_renderers_and_fewer)
{
    pp5_params_t p;
    small_params(&p);
    p.n_gp = 1;                  /* one GP drives both renderers */
    machine_t m;
    sched_stop_t why;
    REQUIRE(run_pattern(&m, &p, &why) == PP5_OK);
    check_image_matches_reference(&m);
    machine_free(&m);
    p.n_gp = 5;
    p.n_renderers = 1;           /* four idle GPs, one renderer does all 6 regions */
    REQUIRE(run_pattern(&m, &p, &why) == PP5_OK);
    check_image_matches_reference(&m);
    CHECK_EQ(m.rn[0].messages, 18);
    machine_free(&m);
}

TEST(machine_test_pattern_cli_writes_image_report_and_timeline)
{
    const char *dir = pp5_test_outdir();
    char cmd[1024], out[600], err[600];
    snprintf(out, sizeof out, "%s/stdout.txt", dir);
    snprintf(err, sizeof err, "%s/stderr.txt", dir);
    snprintf(cmd, sizeof cmd,
             "test-pattern --set fb.width=256 --set fb.height=256 --set renderer.count=2 --set gp.count=2 "
             "--out %s/p.png --report %s/r.json --timeline %s/t.json", dir, dir, dir);
    REQUIRE(pp5_test_run_cli(cmd, out, err) == 0);
    char path[600];
    snprintf(path, sizeof path, "%s/p.png", dir);
    image8_t img;
    REQUIRE(png_read(path, &img, 3) == PP5_OK);
    CHECK_EQ(img.width, 256);
    uint8_t *ref = malloc(256 * 256 * 3);
    REQUIRE(ref != NULL);
    reference_pattern(256, 256, ref);
    CHECK(memcmp(ref, img.pixels, 256 * 256 * 3) == 0);
    free(ref);
    image8_free(&img);
    /* Both JSON files parse (python3 -m json.tool) and carry the stable keys. */
    snprintf(cmd, sizeof cmd, "python3 -m json.tool %s/r.json > /dev/null 2>&1 && python3 -m json.tool %s/t.json > /dev/null 2>&1",
             dir, dir);
    int rc = system(cmd);
    if (rc != 0 && system("python3 -c 1 > /dev/null 2>&1") != 0) {
        SKIP("python3 is not available to validate the JSON");
    }
    CHECK_EQ(rc, 0);
    snprintf(path, sizeof path, "%s/r.json", dir);
    char *r = pp5_test_read_file(path);
    REQUIRE(r != NULL);
    const char *keys[] = { "\"frame_time_s\"", "\"busy_s\"", "\"cycles\"", "\"utilization\"", "\"by_class\"",
                           "\"by_channel\"", "\"machine\"", "\"ring.channels\"", "\"pp5_version\"", "\"command_line\"" };
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        CHECK_MSG(strstr(r, keys[i]) != NULL, "report lacks %s", keys[i]);
    }
    free(r);
    snprintf(path, sizeof path, "%s/t.json", dir);
    char *t = pp5_test_read_file(path);
    REQUIRE(t != NULL);
    CHECK(strstr(t, "\"traceEvents\"") != NULL && strstr(t, "\"ring channel 7\"") != NULL &&
          strstr(t, "\"renderer 1\"") != NULL && strstr(t, "\"frame buffer\"") != NULL &&
          strstr(t, "\"GP 1\"") != NULL);
    free(t);
}

TEST(machine_bad_options_fail_cleanly)
{
    CHECK(pp5_test_run_cli("test-pattern --set ring.channels=0", NULL, NULL) == 2);
    CHECK(pp5_test_run_cli("test-pattern --preset nope", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("test-pattern --config /nonexistent/x.cfg", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("test-pattern --out /nonexistent/dir/p.png --set fb.width=128 --set fb.height=128 "
                           "--set renderer.count=1 --set gp.count=1", NULL, NULL) != 0);
}

/* ---- renderer data paths: WRITE_FIELD, EXEC, READ_FIELD, WRITE_BS, READ_BS ---- */

static uint32_t g_words[PP_COUNT];
static int g_replies;
/* Per reply: the first PP whose word is wrong, -1 when all are right, -2
 * before the reply came. */
static long g_field_bad, g_bs_bad;

static fw_status_t io_message(gp_t *gp, const ring_msg_t *msg)
{
    ring_addr_t r0 = ring_addr(RING_NODE_RENDERER, 0);
    uint32_t me = ring_addr_pack(ring_addr(RING_NODE_GP, fw_gp_index(gp)));
    if (msg->kind == RING_MSG_FRAME_START) {
        for (uint32_t i = 0; i < PP_COUNT; i++) {
            g_words[i] = (i * 7u) & 0xffffu;
        }
        uint32_t wf[RING_MSG_ARGS] = { 0, 16, 0, 0, 0, 0 };
        if (fw_send(gp, r0, RING_MSG_RENDERER_WRITE_FIELD, wf, g_words, sizeof g_words) != FW_OK) {
            return FW_ERROR;
        }
        pp_stream_t s;
        pp_stream_init(&s);
        pp_emit_en_all(&s);
        pp_emit_addi(&s, 16, 0, 16, 5);          /* field[16..32) = field[0..16) + 5 */
        fw_status_t rc = fw_send(gp, r0, RING_MSG_RENDERER_EXEC, NULL, s.words, s.n_words * 4);
        pp_stream_free(&s);
        uint32_t rf[RING_MSG_ARGS] = { 16, 16, me, 42, 0, 0 };
        uint32_t wb[RING_MSG_ARGS] = { 3, 0, 0, 0, 0, 0 };
        uint32_t rb[RING_MSG_ARGS] = { 3, 0, me, 43, 0, 0 };
        if (rc == FW_OK) {
            rc = fw_send(gp, r0, RING_MSG_RENDERER_READ_FIELD, rf, NULL, 0);
        }
        if (rc == FW_OK) {
            rc = fw_send(gp, r0, RING_MSG_RENDERER_WRITE_BS, wb, g_words, sizeof g_words);
        }
        if (rc == FW_OK) {
            rc = fw_send(gp, r0, RING_MSG_RENDERER_READ_BS, rb, NULL, 0);
        }
        return rc;
    }
    if (msg->kind == RING_MSG_RENDERER_DATA && msg->payload_bytes == sizeof g_words) {
        const uint32_t *v = msg->payload;
        long bad = -1;
        for (uint32_t i = 0; i < PP_COUNT && bad < 0; i++) {
            if (v[i] != (msg->args[0] == 42 ? ((g_words[i] + 5u) & 0xffffu) : g_words[i]))
                bad = i;
        }
        if (msg->args[0] == 42) {
            g_field_bad = bad;
        } else if (msg->args[0] == 43) {
            g_bs_bad = bad;
        }
        g_replies++;
        return FW_OK;
    }
    return fw_fail(gp, "unexpected message kind %u", msg->kind);
}

static const fw_program_t io_prog = { "renderer-io", 1024, NULL, io_message };

TEST(machine_renderer_field_and_backing_store_round_trip)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 1;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_all(&m, &io_prog) == PP5_OK);
    sched_stop_t why;
    pp5_status_t st = machine_run_setup(&m, &why);
    REQUIRE(st == PP5_OK);
    g_replies = 0;
    g_field_bad = g_bs_bad = -2;
    st = machine_run_frame(&m, &why);
    REQUIRE_MSG(st == PP5_OK, "frame failed: %s", pp5_error_text());
    CHECK_EQ(g_replies, 2);
    CHECK_MSG(g_field_bad == -1, "READ_FIELD reply (field + 5): first wrong PP %ld (-2: none came)",
              g_field_bad);
    CHECK_MSG(g_bs_bad == -1, "READ_BS reply: first wrong PP %ld (-2: none came)", g_bs_bad);
    /* Port cycles: write 16 + read 16 bit-planes, write + read one 32-bit block. */
    CHECK_EQ(m.rn[0].port_cycles, (16 + 16 + 32 + 32) * p.rport_cycles_per_bit);
    /* DATA class: two 64 KiB writes from the GP and two 64 KiB replies. */
    CHECK_EQ(m.ring.bytes_sent[RING_CLASS_DATA], 4ull * (PP_COUNT * 4 + p.ring_header_bytes));
    CHECK_EQ(m.ring.bytes_delivered[RING_CLASS_DATA], m.ring.bytes_sent[RING_CLASS_DATA]);
    machine_free(&m);
}

/* RENDERER_READ_BS_BOX: a box of a block seen as a 64 x 32 x 8 array. */
#define BOX_BX 64
#define BOX_BY 32
#define BOX_BZ 8
static uint32_t g_box_words[PP_COUNT];
static int g_box_replies, g_box_bad;
static unsigned g_box[6];      /* x0, y0, z0, sx, sy, sz of the request */

static fw_status_t box_message(gp_t *gp, const ring_msg_t *msg)
{
    ring_addr_t r0 = ring_addr(RING_NODE_RENDERER, 0);
    if (msg->kind == RING_MSG_FRAME_START) {
        for (uint32_t i = 0; i < PP_COUNT; i++)
            g_box_words[i] = i * 2654435761u;
        uint32_t wb[RING_MSG_ARGS] = {5, 0, 0, 0, 0, 0};
        uint32_t rb[RING_MSG_ARGS] = {5, BOX_BX | BOX_BZ << 8 | BOX_BY << 16,
                                      ring_addr_pack(ring_addr(RING_NODE_GP, fw_gp_index(gp))), 7,
                                      g_box[0] | g_box[2] << 8 | g_box[1] << 16,
                                      g_box[3] | g_box[4] << 8 | g_box[5] << 16};
        fw_status_t rc = fw_send(gp, r0, RING_MSG_RENDERER_WRITE_BS, wb, g_box_words,
                                 sizeof g_box_words);
        return rc == FW_OK ? fw_send(gp, r0, RING_MSG_RENDERER_READ_BS_BOX, rb, NULL, 0) : rc;
    }
    if (msg->kind != RING_MSG_RENDERER_DATA || msg->args[0] != 7)
        return fw_fail(gp, "unexpected message kind %u", msg->kind);
    g_box_replies++;
    const uint32_t *v = msg->payload;
    size_t n = (size_t)g_box[3] * g_box[4] * g_box[5];
    if (msg->payload_bytes != n * 4)
        return fw_fail(gp, "box reply of %zu bytes", msg->payload_bytes);
    size_t k = 0;
    for (unsigned z = 0; z < g_box[5]; z++)
        for (unsigned y = 0; y < g_box[4]; y++)
            for (unsigned x = 0; x < g_box[3]; x++, k++) {
                size_t i = ((size_t)(g_box[2] + z) * BOX_BY + g_box[1] + y) * BOX_BX + g_box[0] + x;
                g_box_bad += v[k] != g_box_words[i];
            }
    return FW_OK;
}

static const fw_program_t box_prog = {"box-read", 1024, NULL, box_message};

static pp5_status_t run_box(const unsigned box[6], machine_t *m)
{
    memcpy(g_box, box, sizeof g_box);
    g_box_replies = g_box_bad = 0;
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 1;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    pp5_status_t st = machine_init(m, &p);
    sched_stop_t why;
    if (st == PP5_OK)
        st = machine_load_all(m, &box_prog);
    if (st == PP5_OK)
        st = machine_run_setup(m, &why);
    return st == PP5_OK ? machine_run_frame(m, &why) : st;
}

TEST(machine_renderer_box_read_ships_only_the_box)
{
    machine_t m;
    const unsigned box[6] = {8, 4, 2, 8, 8, 3};
    REQUIRE_MSG(run_box(box, &m) == PP5_OK, "frame failed: %s", pp5_error_text());
    CHECK_EQ(g_box_replies, 1);
    CHECK_EQ(g_box_bad, 0);
    /* The renderer reads the whole block out (32 bit planes) for a write and a box. */
    CHECK_EQ(m.rn[0].port_cycles, 2 * 32 * m.params.rport_cycles_per_bit);
    /* DATA class: the 64 KiB write and a reply of 8 x 8 x 3 words. */
    CHECK_EQ(m.ring.bytes_sent[RING_CLASS_DATA],
             (PP_COUNT * 4 + m.params.ring_header_bytes) + (8 * 8 * 3 * 4 + m.params.ring_header_bytes));
    machine_free(&m);
    /* A box reaching past the block is a firmware error naming it. */
    const unsigned outside[6] = {60, 0, 0, 8, 8, 1};
    CHECK(run_box(outside, &m) == PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "READ_BS_BOX") != NULL);
    machine_free(&m);
}

static fw_status_t bad_exec_message(gp_t *gp, const ring_msg_t *msg)
{
    uint32_t junk[2] = { 0xffffffffu, 0xffffffffu };   /* not a valid instruction */
    return fw_send(gp, ring_addr(RING_NODE_RENDERER, 0), RING_MSG_RENDERER_EXEC, NULL, junk, sizeof junk);
}

static const fw_program_t bad_exec_prog = { "bad-exec", 1024, NULL, bad_exec_message };

TEST(machine_illegal_instruction_stream_is_a_firmware_error)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 1;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_all(&m, &bad_exec_prog) == PP5_OK);
    sched_stop_t why;
    REQUIRE(machine_run_setup(&m, &why) == PP5_OK);
    pp5_status_t st = machine_run_frame(&m, &why);
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK_EQ(why, SCHED_STOP_FIRMWARE_ERROR);
    CHECK(strstr(pp5_error_text(), "renderer 0") != NULL);
    machine_free(&m);
}

/* Host threads run the renderers' functional steps; nothing may change. */
TEST(machine_results_identical_for_1_2_and_4_host_threads)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 4;
    p.n_renderers = 6;
    p.fb_width = 512;
    p.fb_height = 384;          /* 12 regions over 6 renderers */
    machine_t ref;
    sched_stop_t why;
    REQUIRE(run_pattern(&ref, &p, &why) == PP5_OK);
    check_image_matches_reference(&ref);
    unsigned counts[] = { 2, 4 };
    for (size_t k = 0; k < 2; k++) {
        p.sim_host_threads = counts[k];
        machine_t m;
        REQUIRE(run_pattern(&m, &p, &why) == PP5_OK);
        CHECK(m.pool_running);
        CHECK_EQ(m.frames[0].end_ps - m.frames[0].start_ps, ref.frames[0].end_ps - ref.frames[0].start_ps);
        CHECK_EQ(m.sched.events_run, ref.sched.events_run);
        unsigned t = counts[k];
        for (unsigned i = 0; i < m.n_rn; i++) {
            CHECK_MSG(m.rn[i].cycles == ref.rn[i].cycles, "%u threads: renderer %u cycles differ", t, i);
            CHECK_MSG(m.rn[i].busy_ps == ref.rn[i].busy_ps, "%u threads: renderer %u busy_ps differs",
                      t, i);
            CHECK_MSG(m.rn[i].r.stats.instructions == ref.rn[i].r.stats.instructions,
                      "%u threads: renderer %u instruction count differs", t, i);
        }
        for (unsigned c = 0; c < m.ring.n_channels; c++) {
            CHECK_MSG(m.ring.ch[c].busy_ps == ref.ring.ch[c].busy_ps,
                      "%u threads: ring channel %u busy_ps differs", t, c);
            CHECK_MSG(m.ring.ch[c].bytes == ref.ring.ch[c].bytes,
                      "%u threads: ring channel %u bytes differ", t, c);
        }
        CHECK(memcmp(fb_front(&m.fb)->pixels, fb_front(&ref.fb)->pixels, (size_t)p.fb_width * p.fb_height * 3) == 0);
        machine_free(&m);
    }
    machine_free(&ref);
}

TEST(machine_threaded_firmware_error_stops_cleanly)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 1;
    p.n_renderers = 2;
    p.fb_width = 128;
    p.fb_height = 128;
    p.sim_host_threads = 3;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_all(&m, &bad_exec_prog) == PP5_OK);
    sched_stop_t why;
    REQUIRE(machine_run_setup(&m, &why) == PP5_OK);
    pp5_status_t st = machine_run_frame(&m, &why);
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "renderer 0") != NULL);
    CHECK(!m.pool_running);
    machine_free(&m);
}

/* The statistics registry against the units it reads: a difference of two
 * snapshots around a frame equals the machine's own record of that frame
 * (ring bytes by class, counted by the ring as it sends), and the renderers'
 * per-class cycles reach the registry under their names. */
TEST(machine_stats_snapshots_and_differences_match_the_frame_record)
{
    pp5_params_t p;
    small_params(&p);
    machine_t m;
    sched_stop_t why;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_all(&m, &testpattern_program) == PP5_OK);
    REQUIRE(machine_run_setup(&m, &why) == PP5_OK);
    stats_t before, after, d;
    REQUIRE(stats_collect(&before, &m) == PP5_OK);
    REQUIRE(machine_run_frame(&m, &why) == PP5_OK);
    REQUIRE(stats_collect(&after, &m) == PP5_OK);
    REQUIRE(stats_diff(&d, &before, &after) == PP5_OK);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        double sent = stats_valuef(&d, "ring.by_class.%s.bytes_sent", stats_class_name(k));
        CHECK_MSG(sent == (double)m.frames[0].bytes_by_class[k], "class %s: %.0f vs %llu",
                  stats_class_name(k), sent, (unsigned long long)m.frames[0].bytes_by_class[k]);
    }
    CHECK(stats_value(&d, "ring.by_class.pixels.bytes_sent") > 0);
    CHECK_EQ(stats_value(&d, "sim.frames"), 1);
    /* A formula describes the whole run: it is not in a difference. */
    CHECK(stats_find(&d, "ring.utilization") == NULL);
    CHECK(stats_find(&after, "ring.utilization") != NULL);
    for (unsigned r = 0; r < m.n_rn; r++) {
        double qee = stats_valuef(&after, "renderer.%u.pp.cycles_by_class.qee", r);
        CHECK(qee > 0);
        CHECK_EQ(qee, m.rn[r].r.stats.class_cycles[PP_CLASS_QEE]);
    }
    CHECK(stats_value(&after, "no.such.statistic") == 0.0 && !stats_find(&after, "no.such"));
    stats_free(&before);
    stats_free(&after);
    stats_free(&d);
    machine_free(&m);
}
