/* test_qee.c: QEE values exact for every pixel of a region (negative, large and zero
 * coefficients, screen-edge, negative and extreme origins, wrap to n bits), checked
 * against an independent 128-bit evaluation in this file. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "pp_array.h"
#include "pp_encode.h"
#include "qee.h"
#include "renderer.h"

static renderer_t *qee_renderer(void)
{
    static renderer_t r;
    static bool ready;
    if (!ready) {
        pp_params_t p;
        pp_params_default(&p);
        if (renderer_init(&r, 3, &p) != PP5_OK)
            return NULL;
        ready = true;
    }
    renderer_reset(&r);
    return &r;
}

/* floor(Q / 2^shift) mod 2^n, in 128-bit arithmetic (independent of qee.c). */
static unsigned __int128 expect(const int32_t c[6], long x, long y, unsigned shift, unsigned n)
{
    __int128 X = x, Y = y;
    __int128 q = c[0] * X * X + c[1] * X * Y + c[2] * Y * Y + c[3] * X + c[4] * Y + (__int128)c[5];
    __int128 f = q >> shift;              /* arithmetic shift = floor division by 2^shift */
    unsigned __int128 mask = n >= 128 ? ~(unsigned __int128)0
                                      : (((unsigned __int128)1 << n) - 1);
    return (unsigned __int128)f & mask;
}

/* Runs one QEE into field [d, d+n) and compares all 16384 PPs (n <= 96, read in
 * 32-bit pieces).  Returns the number of wrong pixels. */
static unsigned check_region(renderer_t *r, const int32_t c[6], int x0, int y0, unsigned d,
                             unsigned n, unsigned shift)
{
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_qee(&s, d, n, shift, c[0], c[1], c[2], c[3], c[4], c[5]);
    renderer_set_region(r, x0, y0);
    renderer_exec_result_t res;
    bool ok = pp_stream_ok(&s) && renderer_execute(r, s.words, s.n_words, &res) == PP5_OK;
    pp_stream_free(&s);
    if (!CHECK_MSG(ok, "QEE execute: %s", pp5_error_text()))
        return PP_COUNT;
    uint32_t *piece = malloc(PP_COUNT * sizeof *piece);
    unsigned __int128 *got = calloc(PP_COUNT, sizeof *got);
    if (!piece || !got) {
        free(piece);
        free(got);
        return PP_COUNT;
    }
    for (unsigned lo = 0; lo < n; lo += 32) {
        unsigned bits = n - lo < 32 ? n - lo : 32;
        renderer_read_field(r, d + lo, bits, piece);
        for (unsigned p = 0; p < PP_COUNT; p++)
            got[p] |= (unsigned __int128)piece[p] << lo;
    }
    unsigned bad = 0;
    for (unsigned p = 0; p < PP_COUNT; p++) {
        long x = x0 + (long)(p % PP_ARRAY_DIM), y = y0 + (long)(p / PP_ARRAY_DIM);
        if (got[p] != expect(c, x, y, shift, n) && bad++ == 0)
            CHECK_MSG(false, "QEE pixel (%ld, %ld) n=%u shift=%u: got 0x%llx expected 0x%llx", x,
                      y, n, shift, (unsigned long long)got[p],
                      (unsigned long long)expect(c, x, y, shift, n));
    }
    free(piece);
    free(got);
    return bad;
}

TEST(qee_hand_values_wrap_and_floor)
{
    renderer_t *r = qee_renderer();
    REQUIRE(r);
    /* Constant F only: every pixel gets F's bits.  Hand values:
     * 300 mod 256 = 44; -1 mod 256 = 255; floor(-3 / 2) = -2 -> 254;
     * floor(7 / 4) = 1. */
    struct { int32_t F; unsigned n, shift; uint32_t want; } cases[] = {
        {300, 8, 0, 44}, {-1, 8, 0, 255}, {-3, 8, 1, 254}, {7, 4, 2, 1},
        {INT32_MIN, 32, 0, 0x80000000u}, {INT32_MAX, 32, 31, 0},
    };
    uint32_t *v = malloc(PP_COUNT * sizeof *v);
    REQUIRE(v);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        pp_stream_t s;
        pp_stream_init(&s);
        pp_emit_qee(&s, 10, cases[i].n, cases[i].shift, 0, 0, 0, 0, 0, cases[i].F);
        REQUIRE(renderer_execute(r, s.words, s.n_words, NULL) == PP5_OK);
        pp_stream_free(&s);
        renderer_read_field(r, 10, cases[i].n, v);
        CHECK_EQ(v[0], cases[i].want);
        CHECK_EQ(v[PP_COUNT - 1], cases[i].want);
    }
    /* Linear ramp Q = x at origin (256, 512): PP in column c holds 256 + c. */
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_qee(&s, 0, 16, 0, 0, 0, 0, 1, 0, 0);
    renderer_set_region(r, 256, 512);
    REQUIRE(renderer_execute(r, s.words, s.n_words, NULL) == PP5_OK);
    pp_stream_free(&s);
    renderer_read_field(r, 0, 16, v);
    CHECK_EQ(v[0], 256);
    CHECK_EQ(v[127], 383);
    CHECK_EQ(v[5 * 128 + 7], 263);
    free(v);
}

TEST(qee_exact_for_every_pixel_of_a_region)
{
    renderer_t *r = qee_renderer();
    REQUIRE(r);
    /* Coefficient sets: a disc (x-cx)^2 + (y-cy)^2 - R^2, a tilted plane, mixed
     * signs, extreme magnitudes, a pure cross term. */
    static const int32_t sets[][6] = {
        {1, 0, 1, -2 * 700, -2 * 500, 700 * 700 + 500 * 500 - 90 * 90},
        {0, 0, 0, 37, -91, 123456},
        {-3, 5, -7, 1000, -2000, -123456},
        {INT32_MAX, INT32_MIN, INT32_MAX, INT32_MIN, INT32_MAX, INT32_MIN},
        {INT32_MIN, INT32_MAX, INT32_MIN, INT32_MAX, INT32_MIN, INT32_MAX},
        {0, 1, 0, 0, 0, 0},
    };
    /* Origins: top-left, bottom-right region of a 1280x1024 screen, off-screen
     * negative, and the limits of the exact range. */
    static const int origins[][2] = {{0, 0}, {1152, 896}, {-128, -300}, {8064, 8064},
                                     {-8064, -8064}};
    /* (n, shift): small, 32-bit, wide (> 64 bits: sign-extension region), fraction. */
    static const unsigned widths[][2] = {{8, 0}, {32, 0}, {20, 12}, {90, 0}, {17, 63}};
    unsigned bad = 0, runs = 0, levels = 0;
    for (int level = 0; level < PP_KERNEL_LEVELS; level++) {
        /* Every kernel copy the host has; a missing one is named. */
        if (!pp_kernel_level_available((pp_kernel_level_t)level)) {
            printf("   note: this host or build has no %s kernels; they are not checked here\n",
                   pp_kernel_level_name((pp_kernel_level_t)level));
            continue;
        }
        pp_array_set_kernels(r->array, (pp_kernel_level_t)level);
        levels++;
        for (size_t c = 0; c < sizeof sets / sizeof sets[0]; c++)
            for (size_t o = 0; o < sizeof origins / sizeof origins[0]; o++)
                for (size_t w = 0; w < sizeof widths / sizeof widths[0]; w++) {
                    unsigned n = widths[w][0], sh = widths[w][1];
                    unsigned d = (unsigned)((c * 7 + o * 3 + w) % (PP_MEM_BITS - n + 1));
                    bad += check_region(r, sets[c], origins[o][0], origins[o][1], d, n, sh);
                    runs++;
                }
    }
    pp_array_set_kernels(r->array, pp_kernel_level_best());
    CHECK_EQ(bad, 0);
    CHECK_EQ(runs, levels * 150);
}

TEST(qee_respects_enable)
{
    renderer_t *r = qee_renderer();
    REQUIRE(r);
    /* E = (x is odd): F_LD of bit 0 of a QEE'd x, EN_FLAG; then QEE F=5 into [40,48). */
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_qee(&s, 0, 8, 0, 0, 0, 0, 1, 0, 0);
    pp_emit_f_ld(&s, 0);
    pp_emit_en_flag(&s);
    pp_emit_qee(&s, 40, 8, 0, 0, 0, 0, 0, 0, 5);
    pp_emit_en_all(&s);
    REQUIRE(pp_stream_ok(&s));
    REQUIRE(renderer_execute(r, s.words, s.n_words, NULL) == PP5_OK);
    pp_stream_free(&s);
    uint32_t *v = malloc(PP_COUNT * sizeof *v);
    REQUIRE(v);
    renderer_read_field(r, 40, 8, v);
    unsigned p = 0;
    while (p < PP_COUNT && v[p] == ((p % 2) ? 5u : 0u))
        p++;
    CHECK_MSG(p == PP_COUNT, "PP %u (column %u) holds %u", p, p % PP_ARRAY_DIM,
              p < PP_COUNT ? v[p] : 0);
    free(v);
}

TEST(qee_serial_adder_matches_direct_formula)
{
    /* The reference executor's bit-serial adder vs qee_value, random points. */
    uint64_t s = 12345;
    int wrong_value = -1, wrong_sign = -1;      /* the first failing point of each kind */
    for (int t = 0; t < 2000; t++) {
        s ^= s << 13; s ^= s >> 7; s ^= s << 17;
        qee_coeffs_t q = {(int32_t)s, (int32_t)(s >> 32), (int32_t)(s >> 16), (int32_t)(s * 3),
                          (int32_t)(s * 5), (int32_t)(s * 7)};
        int x = (int)(s % 16383) - 8191, y = (int)((s >> 20) % 16383) - 8191;
        int64_t v = qee_value(&q, x, y);
        qee_serial_t ser;
        qee_serial_start(&ser, &q, x, y);
        uint64_t got = 0;
        for (unsigned k = 0; k < 64; k++)
            got |= (uint64_t)qee_serial_next_bit(&ser) << k;
        if (got != (uint64_t)v && wrong_value < 0)
            wrong_value = t;
        if (qee_serial_next_bit(&ser) != ((uint64_t)v >> 63) && wrong_sign < 0)
            wrong_sign = t;       /* bit 64 must repeat the sign */
    }
    CHECK_MSG(wrong_value < 0, "point %d: the 64 serial bits differ from qee_value", wrong_value);
    CHECK_MSG(wrong_sign < 0, "point %d: the bit after bit 63 is not the sign", wrong_sign);
}

TEST(qee_origin_outside_exact_range_is_a_firmware_error)
{
    renderer_t *r = qee_renderer();
    REQUIRE(r);
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_qee(&s, 0, 8, 0, 1, 1, 1, 1, 1, 1);
    renderer_set_region(r, 8065, 0);
    CHECK_EQ(renderer_execute(r, s.words, s.n_words, NULL), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "QEE") != NULL);
    renderer_set_region(r, 0, INT_MIN);
    CHECK_EQ(renderer_execute(r, s.words, s.n_words, NULL), PP5_E_FIRMWARE);
    renderer_set_region(r, -8064, 8064);
    CHECK_EQ(renderer_execute(r, s.words, s.n_words, NULL), PP5_OK);
    renderer_set_region(r, 0, 0);
    CHECK_EQ(renderer_execute(r, s.words, s.n_words, NULL), PP5_OK);
    pp_stream_free(&s);
}
