/* pp_encode.h: firmware-facing encoder of PP instruction streams (one emit function per instruction).
 *
 * Firmware builds a stream here and sends it to a renderer (RENDERER_EXEC); the
 * word format and the semantics/cost of each instruction are in emu/pp_isa.h
 * and emu/PP_ISA.md.  Field addresses are bit addresses in the 208-bit pixel
 * memory; n is a width in bits.  The renderer validates the 208-bit budget; the
 * encoder only checks that each value fits its 8-bit word field.  An error
 * (value out of range, out of memory) is sticky: the stream records the first
 * message and later emits do nothing; check pp_stream_ok() before sending.
 * This header may include only standard headers and emu/api/ (firmware sees
 * nothing else). */
#ifndef PP5_PP_ENCODE_H
#define PP5_PP_ENCODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    uint32_t *words;
    size_t n_words;
    size_t cap_words;
    size_t n_instructions;
    bool failed;
    char error[120];
} pp_stream_t;

/* Compare conditions for pp_emit_cmp / pp_emit_cmpi (same values as pp_isa.h). */
enum {
    PP_CMP_EQ = 0, PP_CMP_NE, PP_CMP_LTU, PP_CMP_GEU, PP_CMP_LTS, PP_CMP_GES
};

void pp_stream_init(pp_stream_t *s);
void pp_stream_free(pp_stream_t *s);
void pp_stream_clear(pp_stream_t *s);            /* keep the buffer, drop the words */
bool pp_stream_ok(const pp_stream_t *s);
const char *pp_stream_error(const pp_stream_t *s);

/* Enable register (all PPs) */
void pp_emit_en_all(pp_stream_t *s);                 /* E = 1 */
void pp_emit_en_flag(pp_stream_t *s);                /* E = F */
void pp_emit_en_and(pp_stream_t *s);                 /* E &= F */
void pp_emit_en_andn(pp_stream_t *s);                /* E &= ~F */
void pp_emit_en_or(pp_stream_t *s);                  /* E |= F */
void pp_emit_en_not(pp_stream_t *s);                 /* E = ~E */
/* Flag (written only where E) */
void pp_emit_f_set(pp_stream_t *s, unsigned value);  /* F = value & 1 */
void pp_emit_f_not(pp_stream_t *s);
void pp_emit_f_ld(pp_stream_t *s, unsigned a);       /* F = mem[a] */
void pp_emit_f_st(pp_stream_t *s, unsigned d);       /* mem[d] = F */
/* n-bit operations (written only where E) */
void pp_emit_copy(pp_stream_t *s, unsigned d, unsigned a, unsigned n);
void pp_emit_not(pp_stream_t *s, unsigned d, unsigned a, unsigned n);
void pp_emit_and(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n);
void pp_emit_or(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n);
void pp_emit_xor(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n);
/* imm: n bits, word k holds bits 32k..32k+31 (n_imm_words >= ceil(n/32)). */
void pp_emit_seti_wide(pp_stream_t *s, unsigned d, unsigned n, const uint32_t *imm);
void pp_emit_seti(pp_stream_t *s, unsigned d, unsigned n, uint64_t imm);  /* n <= 64 */
void pp_emit_sel(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n); /* d = F?a:b */
void pp_emit_shl(pp_stream_t *s, unsigned d, unsigned a, unsigned n, unsigned k);
void pp_emit_shr(pp_stream_t *s, unsigned d, unsigned a, unsigned n, unsigned k);
void pp_emit_sar(pp_stream_t *s, unsigned d, unsigned a, unsigned n, unsigned k);
void pp_emit_add(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n);
void pp_emit_sub(pp_stream_t *s, unsigned d, unsigned a, unsigned b, unsigned n);
void pp_emit_addi(pp_stream_t *s, unsigned d, unsigned a, unsigned n, uint64_t imm); /* n <= 64 */
void pp_emit_addi_wide(pp_stream_t *s, unsigned d, unsigned a, unsigned n, const uint32_t *imm);
void pp_emit_cmp(pp_stream_t *s, unsigned cond, unsigned a, unsigned b, unsigned n);
void pp_emit_cmpi(pp_stream_t *s, unsigned cond, unsigned a, unsigned n, uint64_t imm); /* n <= 64 */
void pp_emit_cmpi_wide(pp_stream_t *s, unsigned cond, unsigned a, unsigned n, const uint32_t *imm);
/* d(n) = ext(a(m)) * ext(b(m)) mod 2^n; ext = sign extension if is_signed. */
void pp_emit_mul(pp_stream_t *s, unsigned d, unsigned n, unsigned a, unsigned b, unsigned m,
                 bool is_signed);
/* d(n) = ext(a(m)) * imm mod 2^n (imm sign-extended to n bits). */
void pp_emit_muli(pp_stream_t *s, unsigned d, unsigned n, unsigned a, unsigned m, bool is_signed,
                  int32_t imm);
/* d(n) = floor((A x^2 + B x y + C y^2 + D x + E y + F) / 2^shift) mod 2^n, for the
 * PP's screen x, y (renderer region origin + column/row); 0 <= shift <= 63. */
void pp_emit_qee(pp_stream_t *s, unsigned d, unsigned n, unsigned shift, int32_t A, int32_t B,
                 int32_t C, int32_t D, int32_t E, int32_t F);
/* Backing store (asynchronous, 32-bit blocks 0..127; written only where E). */
void pp_emit_bsload(pp_stream_t *s, unsigned d, unsigned block);   /* mem[d..d+32) = bs[block] */
void pp_emit_bsstore(pp_stream_t *s, unsigned block, unsigned a);  /* bs[block] = mem[a..a+32) */
void pp_emit_bswait(pp_stream_t *s);

#endif
