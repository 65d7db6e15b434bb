/* vr_shade_pp.c: the per-frame specular shading of the 3D mip map as a PP instruction stream (fixed point, 208-bit pixel memory). */
#include "common/vr_shade_pp.h"

/* Pixel-memory layout (bit addresses, 200 of the 208 bits, facts §3.1):
 *   A 0..31 and N 32..63 (loaded from backing store), D 64..87 (N.H, 24-bit
 *   signed; later reused as W = alpha and S = scaled power), X 88..103 (Q15
 *   |N.H|), Y 104..119 (power), Q 120..151 (products), O 152..183 (output),
 *   C 184..199 (one channel with carry room). */
enum {
    F_A = 0, F_N = 32, F_D = 64, F_W = 64, F_S = 80, F_X = 88, F_Y = 104, F_Q = 120, F_O = 152,
    F_C = 184,
    /* moving object, diffuse stage: shade (18 bits) in O's bits, channel in D's */
    F_SH = 152, F_C18 = 64
};

/* D = N . (three immediates), then |D| (two-sided) or max(D, 0). */
static void emit_dot_abs(pp_stream_t *st, const int32_t v[3], int two_sided)
{
    pp_emit_muli(st, F_D, 24, F_N, 10, true, v[0]);
    pp_emit_muli(st, F_Q, 24, F_N + 10, 10, true, v[1]);
    pp_emit_add(st, F_D, F_D, F_Q, 24);
    pp_emit_muli(st, F_Q, 24, F_N + 20, 10, true, v[2]);
    pp_emit_add(st, F_D, F_D, F_Q, 24);
    pp_emit_cmpi(st, PP_CMP_LTS, F_D, 24, 0);
    pp_emit_en_flag(st);
    if (two_sided) {
        pp_emit_not(st, F_D, F_D, 24);
        pp_emit_addi(st, F_D, F_D, 24, 1);
    } else {
        pp_emit_seti(st, F_D, 24, 0);
    }
    pp_emit_en_all(st);
}

/* Moving object: A's channels *= ka + kd |N.L| (Q15), saturated, in place. */
static void emit_diffuse(pp_stream_t *st, const vr_shade_consts_t *c)
{
    emit_dot_abs(st, c->l, c->two_sided);
    pp_emit_addi(st, F_D, F_D, 24, 32);          /* rounded >> 6 */
    pp_emit_copy(st, F_X, F_D + 6, 16);
    pp_emit_muli(st, F_Q, 32, F_X, 16, false, c->kd15);
    pp_emit_addi(st, F_Q, F_Q, 32, 16384);       /* rounded >> 15 */
    pp_emit_seti(st, F_SH, 18, 0);
    pp_emit_copy(st, F_SH, F_Q + 15, 17);
    pp_emit_addi(st, F_SH, F_SH, 18, (uint64_t)c->ka15);
    pp_emit_cmpi(st, PP_CMP_EQ, F_N, 30, 0);
    pp_emit_en_flag(st);
    pp_emit_seti(st, F_SH, 18, (uint64_t)(c->ka15 + c->kd15));
    pp_emit_en_all(st);
    for (unsigned k = 0; k < 3; k++) {
        pp_emit_seti(st, F_C18, 18, 0);
        pp_emit_copy(st, F_C18, F_A + 8 * k, 8);
        pp_emit_mul(st, F_Q, 32, F_C18, F_SH, 18, false);
        pp_emit_addi(st, F_Q, F_Q, 32, 16384);
        pp_emit_copy(st, F_C, F_Q + 15, 16);
        pp_emit_cmpi(st, PP_CMP_GEU, F_C, 16, 256);
        pp_emit_en_flag(st);
        pp_emit_seti(st, F_C, 16, 255);
        pp_emit_en_all(st);
        pp_emit_copy(st, F_A + 8 * k, F_C, 8);
    }
}

static void emit_power(pp_stream_t *st, int e)
{
    int top = 0;
    while ((e >> (top + 1)) != 0)
        top++;
    pp_emit_copy(st, F_Y, F_X, 16);
    for (int b = top - 1; b >= 0; b--) {
        pp_emit_mul(st, F_Q, 32, F_Y, F_Y, 16, false);
        pp_emit_copy(st, F_Y, F_Q + 15, 16);
        if ((e >> b) & 1) {
            pp_emit_mul(st, F_Q, 32, F_Y, F_X, 16, false);
            pp_emit_copy(st, F_Y, F_Q + 15, 16);
        }
    }
}

size_t vr_pp_shade_stream(pp_stream_t *st, const vr_shade_consts_t *c, const uint32_t *slots,
                          size_t n_slots)
{
    size_t before = st->n_instructions;
    pp_emit_en_all(st);
    for (size_t i = 0; i < n_slots; i++) {
        unsigned base = slots[i] * VR_BLOCKS_PER_SLOT_SPECULAR;
        pp_emit_bsload(st, F_A, base);
        pp_emit_bsload(st, F_N, base + 1);
        if (c->diffuse_on)
            emit_diffuse(st, c);
        /* D = |N.H|: three signed 10-bit normal components times immediates. */
        emit_dot_abs(st, c->h, c->two_sided);
        /* X = D >> 6 (field addressing), then Y = X^e in Q15. */
        pp_emit_copy(st, F_X, F_D + 6, 16);
        emit_power(st, c->exponent);
        /* S = (Y * ks8) >> 15; Q = S * alpha + 128; spec = Q >> 8. */
        pp_emit_muli(st, F_Q, 32, F_Y, 16, false, c->ks8);
        pp_emit_copy(st, F_S, F_Q + 15, 16);
        pp_emit_seti(st, F_W, 16, 0);
        pp_emit_copy(st, F_W, F_A + 24, 8);
        pp_emit_mul(st, F_Q, 24, F_S, F_W, 16, false);
        pp_emit_addi(st, F_Q, F_Q, 24, 128);
        /* Each channel: C = channel + spec, saturate at 255. */
        for (unsigned k = 0; k < 3; k++) {
            pp_emit_seti(st, F_C, 16, 0);
            pp_emit_copy(st, F_C, F_A + 8 * k, 8);
            pp_emit_add(st, F_C, F_C, F_Q + 8, 16);
            pp_emit_cmpi(st, PP_CMP_GEU, F_C, 16, 256);
            pp_emit_en_flag(st);
            pp_emit_seti(st, F_C, 16, 255);
            pp_emit_en_all(st);
            pp_emit_copy(st, F_O + 8 * k, F_C, 8);
        }
        pp_emit_copy(st, F_O + 24, F_A + 24, 8);
        pp_emit_bsstore(st, base + 2, F_O);
    }
    pp_emit_bswait(st);
    return st->n_instructions - before;
}
