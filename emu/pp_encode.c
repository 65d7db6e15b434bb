/* pp_encode.c: builds PP instruction streams word by word (formats in pp_isa.h). */
#include "pp_encode.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pp_isa.h"

void pp_stream_init(pp_stream_t *s)
{
    memset(s, 0, sizeof *s);
}

void pp_stream_free(pp_stream_t *s)
{
    free(s->words);
    memset(s, 0, sizeof *s);
}

void pp_stream_clear(pp_stream_t *s)
{
    s->n_words = 0;
    s->n_instructions = 0;
    s->failed = false;
    s->error[0] = '\0';
}

bool pp_stream_ok(const pp_stream_t *s)
{
    return !s->failed;
}

const char *pp_stream_error(const pp_stream_t *s)
{
    return s->failed ? s->error : "";
}

static void stream_fail(pp_stream_t *s, const char *fmt, ...)
{
    if (s->failed)
        return;
    s->failed = true;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->error, sizeof s->error, fmt, ap);
    va_end(ap);
}

/* Reserves `count` words; false (and a sticky error) when memory runs out. */
static bool stream_reserve(pp_stream_t *s, size_t count)
{
    if (s->failed)
        return false;
    if (s->n_words + count <= s->cap_words)
        return true;
    size_t cap = s->cap_words ? s->cap_words : 64;
    while (cap < s->n_words + count) {
        if (cap > ((size_t)-1) / 2 / sizeof(uint32_t)) {
            stream_fail(s, "PP stream too large");
            return false;
        }
        cap *= 2;
    }
    uint32_t *w = realloc(s->words, cap * sizeof *w);
    if (!w) {
        stream_fail(s, "out of memory growing a PP stream to %zu words", cap);
        return false;
    }
    s->words = w;
    s->cap_words = cap;
    return true;
}

static bool fits8(pp_stream_t *s, const char *op, const char *field, unsigned v)
{
    if (v > 255) {
        stream_fail(s, "%s: %s = %u does not fit the 8-bit field", op, field, v);
        return false;
    }
    return true;
}

/* Emits word 0, word 1 (if two_words) and `n_imm` immediate words. */
static void emit(pp_stream_t *s, const char *name, unsigned op, unsigned n, unsigned d,
                 unsigned x, bool two_words, unsigned a, unsigned b, unsigned m, unsigned mod,
                 const uint32_t *imm, size_t n_imm)
{
    if (s->failed)
        return;
    if (!fits8(s, name, "n", n) || !fits8(s, name, "d", d) || !fits8(s, name, "x", x) ||
        !fits8(s, name, "a", a) || !fits8(s, name, "b", b) || !fits8(s, name, "m", m))
        return;
    if (!stream_reserve(s, 2 + n_imm))
        return;
    s->words[s->n_words++] = (uint32_t)op << 24 | (uint32_t)n << 16 | (uint32_t)d << 8 | x;
    if (two_words)
        s->words[s->n_words++] = (uint32_t)a << 24 | (uint32_t)b << 16 | (uint32_t)m << 8 | mod;
    for (size_t i = 0; i < n_imm; i++)
        s->words[s->n_words++] = imm[i];
    s->n_instructions++;
}

static void emit_1w(pp_stream_t *s, const char *name, unsigned op, unsigned x)
{
    emit(s, name, op, 0, 0, x, false, 0, 0, 0, 0, NULL, 0);
}

void pp_emit_en_all(pp_stream_t *s) { emit_1w(s, "EN_ALL", PP_OP_EN_ALL, 0); }
void pp_emit_en_flag(pp_stream_t *s) { emit_1w(s, "EN_FLAG", PP_OP_EN_FLAG, 0); }
void pp_emit_en_and(pp_stream_t *s) { emit_1w(s, "EN_AND", PP_OP_EN_AND, 0); }
void pp_emit_en_andn(pp_stream_t *s) { emit_1w(s, "EN_ANDN", PP_OP_EN_ANDN, 0); }
void pp_emit_en_or(pp_stream_t *s) { emit_1w(s, "EN_OR", PP_OP_EN_OR, 0); }
void pp_emit_en_not(pp_stream_t *s) { emit_1w(s, "EN_NOT", PP_OP_EN_NOT, 0); }
void pp_emit_f_set(pp_stream_t *s, unsigned value) { emit_1w(s, "F_SET", PP_OP_F_SET, value & 1u); }
void pp_emit_f_not(pp_stream_t *s) { emit_1w(s, "F_NOT", PP_OP_F_NOT, 0); }

void pp_emit_f_ld(pp_stream_t *s, unsigned a)
{
    emit(s, "F_LD", PP_OP_F_LD, 0, 0, 0, true, a, 0, 0, 0, NULL, 0);
}

void pp_emit_f_st(pp_stream_t *s, unsigned d)
{
    emit(s, "F_ST", PP_OP_F_ST, 0, d, 0, true, 0, 0, 0, 0, NULL, 0);
}

static void emit_dab(pp_stream_t *s, const char *name, unsigned op, unsigned d, unsigned a,
                     unsigned b, unsigned n, unsigned x)
{
    emit(s, name, op, n, d, x, true, a, b, 0, 0, NULL, 0);
}

void pp_emit_copy(pp_stream_t *s, unsigned d, unsigned a, unsigned n)
{
    emit_dab(s, "COPY", PP_OP_COPY, d, a, 0, n, 0);
}

void pp_emit_not(pp_stream_t *s, unsigned d, unsigned a, unsigned n)
{
    emit_dab(s, "NOT", PP_OP_NOT, d, a, 0, n, 0);
}

void pp_emit_and(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n)
{
    emit_dab(s, "AND", PP_OP_AND, d, a, b, n, 0);
}

void pp_emit_or(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n)
{
    emit_dab(s, "OR", PP_OP_OR, d, a, b, n, 0);
}

void pp_emit_xor(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n)
{
    emit_dab(s, "XOR", PP_OP_XOR, d, a, b, n, 0);
}

void pp_emit_sel(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n)
{
    emit_dab(s, "SEL", PP_OP_SEL, d, a, b, n, 0);
}

void pp_emit_shl(pp_stream_t *s, unsigned d, unsigned a, unsigned n, unsigned k)
{
    emit_dab(s, "SHL", PP_OP_SHL, d, a, 0, n, k);
}

void pp_emit_shr(pp_stream_t *s, unsigned d, unsigned a, unsigned n, unsigned k)
{
    emit_dab(s, "SHR", PP_OP_SHR, d, a, 0, n, k);
}

void pp_emit_sar(pp_stream_t *s, unsigned d, unsigned a, unsigned n, unsigned k)
{
    emit_dab(s, "SAR", PP_OP_SAR, d, a, 0, n, k);
}

void pp_emit_add(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n)
{
    emit_dab(s, "ADD", PP_OP_ADD, d, a, b, n, 0);
}

void pp_emit_sub(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n)
{
    emit_dab(s, "SUB", PP_OP_SUB, d, a, b, n, 0);
}


void pp_emit_cmp(pp_stream_t *s, unsigned cond, unsigned a, unsigned b, unsigned n)
{
    emit_dab(s, "CMP", PP_OP_CMP, 0, a, b, n, cond);
}

/* Number of immediate words for an n-bit constant. */
static size_t imm_words(unsigned n)
{
    return (n + 31) / 32;
}

/* A 64-bit constant as the immediate words of an n-bit field (n <= 64). */
static bool imm64(pp_stream_t *s, const char *name, unsigned n, uint64_t v, uint32_t out[2])
{
    if (n > 64) {
        stream_fail(s, "%s: n = %u needs the _wide form (more than 64 bits)", name, n);
        return false;
    }
    out[0] = (uint32_t)v;
    out[1] = (uint32_t)(v >> 32);
    return true;
}

void pp_emit_seti_wide(pp_stream_t *s, unsigned d, unsigned n, const uint32_t *imm)
{
    emit(s, "SETI", PP_OP_SETI, n, d, 0, true, 0, 0, 0, 0, imm, imm_words(n));
}

void pp_emit_seti(pp_stream_t *s, unsigned d, unsigned n, uint64_t imm)
{
    uint32_t w[2];
    if (imm64(s, "SETI", n, imm, w))
        pp_emit_seti_wide(s, d, n, w);
}

void pp_emit_addi_wide(pp_stream_t *s, unsigned d, unsigned a, unsigned n, const uint32_t *imm)
{
    emit(s, "ADDI", PP_OP_ADDI, n, d, 0, true, a, 0, 0, 0, imm, imm_words(n));
}

void pp_emit_addi(pp_stream_t *s, unsigned d, unsigned a, unsigned n, uint64_t imm)
{
    uint32_t w[2];
    if (imm64(s, "ADDI", n, imm, w))
        pp_emit_addi_wide(s, d, a, n, w);
}

void pp_emit_cmpi_wide(pp_stream_t *s, unsigned cond, unsigned a, unsigned n, const uint32_t *imm)
{
    emit(s, "CMPI", PP_OP_CMPI, n, 0, cond, true, a, 0, 0, 0, imm, imm_words(n));
}

void pp_emit_cmpi(pp_stream_t *s, unsigned cond, unsigned a, unsigned n, uint64_t imm)
{
    uint32_t w[2];
    if (imm64(s, "CMPI", n, imm, w))
        pp_emit_cmpi_wide(s, cond, a, n, w);
}

void pp_emit_mul(pp_stream_t *s, unsigned d, unsigned n, unsigned a, unsigned b, unsigned m,
                 bool is_signed)
{
    emit(s, "MUL", PP_OP_MUL, n, d, 0, true, a, b, m, is_signed ? 1u : 0u, NULL, 0);
}

void pp_emit_muli(pp_stream_t *s, unsigned d, unsigned n, unsigned a, unsigned m, bool is_signed,
                  int32_t imm)
{
    uint32_t w = (uint32_t)imm;
    emit(s, "MULI", PP_OP_MULI, n, d, 0, true, a, 0, m, is_signed ? 1u : 0u, &w, 1);
}

void pp_emit_qee(pp_stream_t *s, unsigned d, unsigned n, unsigned shift, int32_t A, int32_t B,
                 int32_t C, int32_t D, int32_t E, int32_t F)
{
    uint32_t w[6] = {(uint32_t)A, (uint32_t)B, (uint32_t)C, (uint32_t)D, (uint32_t)E, (uint32_t)F};
    emit(s, "QEE", PP_OP_QEE, n, d, shift, true, 0, 0, 0, 0, w, 6);
}

void pp_emit_bsload(pp_stream_t *s, unsigned d, unsigned block)
{
    emit(s, "BSLOAD", PP_OP_BSLOAD, 0, d, block, true, 0, 0, 0, 0, NULL, 0);
}

void pp_emit_bsstore(pp_stream_t *s, unsigned block, unsigned a)
{
    emit(s, "BSSTORE", PP_OP_BSSTORE, 0, 0, block, true, a, 0, 0, 0, NULL, 0);
}

void pp_emit_bswait(pp_stream_t *s) { emit_1w(s, "BSWAIT", PP_OP_BSWAIT, 0); }
