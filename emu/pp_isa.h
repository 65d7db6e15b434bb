/* pp_isa.h: the PP instruction words (formats drawn below), the opcode enum and
 * table expanded from pp_isa.def, the decoder/validator and the disassembler.
 *
 * A renderer executes a stream of 32-bit words (emu/api/pp_encode.h builds them).
 * Every instruction starts with word 0; PP_FMT_2W instructions add word 1; some
 * add immediate words (pp_isa.def, column imm_words).
 *
 *   word 0    31        24 23        16 15         8 7          0
 *            +------------+------------+------------+------------+
 *            |   opcode   |     n      |     d      |     x      |
 *            +------------+------------+------------+------------+
 *   word 1   +------------+------------+------------+------------+
 *            |     a      |     b      |     m      |    mod     |
 *            +------------+------------+------------+------------+
 *   imm      IMM_N: ceil(n/32) words, word k = bits 32k..32k+31 (LSB first)
 *            IMM1:  one int32 (MULI multiplier, sign-extended to n bits)
 *            IMM6:  int32 A, B, C, D, E, F (QEE coefficients)
 *
 *   n    field width in bits (1..208), or 0 where unused
 *   d    destination bit address in pixel memory (0..207)
 *   a,b  source bit addresses
 *   x    per-opcode small operand: shift count (SHL/SHR/SAR), compare condition
 *        (CMP/CMPI, pp_cond_t), fraction bits dropped (QEE, 0..63), backing-store
 *        block (BSLOAD/BSSTORE, 0..127), flag value (F_SET, 0..1)
 *   m    source width for MUL/MULI (1..208)
 *   mod  bit 0: sources are signed (MUL/MULI); other bits must be 0
 * Unused fields must be zero: a non-zero unused field is a firmware error (it
 * catches streams assembled for another format).
 *
 * Modelled: pixel memory (208 bits), Enable E, flag F, an internal carry, the
 * QEE for the PP's own screen (x, y), the 4096-bit backing store.
 * Not modelled: the real Pixel-Planes 5 opcode set, microcode and word format,
 * which no public source gives (facts §3.4): this ISA is ours, built from the
 * generic facts (bit-serial, Enable register, QEE, 32-bit backing-store blocks). */
#ifndef PP5_PP_ISA_H
#define PP5_PP_ISA_H

#include <stddef.h>
#include <stdint.h>
#include "pp_params.h"
#include "util/status.h"

typedef enum {
    PP_OP_ILLEGAL = 0,
#define PP_OP(NAME, CODE, FMT, DW, AW, BW, IMM, CLASS, COST, TAG, SEM) PP_OP_##NAME = CODE,
#include "pp_isa.def"
#undef PP_OP
    PP_OP_LIMIT = 0x40          /* opcodes are < PP_OP_LIMIT */
} pp_opcode_t;

typedef enum { PP_FMT_1W = 1, PP_FMT_2W = 2 } pp_format_t;
typedef enum { W0 = 0, W1, WN, WM, W32 } pp_width_code_t;
typedef enum { IMM0 = 0, IMM_N, IMM1, IMM6 } pp_imm_code_t;

/* Cycle-accounting classes (renderer per-class counters, benchmark figures). */
typedef enum {
    PP_CLASS_ENABLE, PP_CLASS_FLAG, PP_CLASS_ALU, PP_CLASS_ADD, PP_CLASS_CMP,
    PP_CLASS_MUL, PP_CLASS_QEE, PP_CLASS_BS, PP_CLASS_COUNT
} pp_class_t;

/* CMP/CMPI conditions (field x). */
typedef enum {
    PP_COND_EQ = 0, PP_COND_NE, PP_COND_LTU, PP_COND_GEU, PP_COND_LTS, PP_COND_GES,
    PP_COND_COUNT
} pp_cond_t;

#define PP_QEE_MAX_SHIFT 63u

/* One decoded, validated instruction. */
typedef struct {
    uint8_t op, n, d, x, a, b, m, mod;
    uint32_t imm[7];           /* IMM_N: bits LSB first (n <= 208 -> 7 words); IMM1/IMM6 */
    uint32_t n_words;          /* words this instruction occupied in the stream */
} pp_insn_t;

_Static_assert((PP_MEM_BITS + 31) / 32 <= 7, "pp_insn_t.imm must hold an n-bit immediate");

/* Static description of an opcode (from pp_isa.def). */
typedef struct {
    const char *name;
    uint8_t code;
    uint8_t format;            /* pp_format_t */
    uint8_t d_width, a_width, b_width; /* pp_width_code_t */
    uint8_t imm;               /* pp_imm_code_t */
    uint8_t cls;               /* pp_class_t */
    const char *tag;
    const char *semantics;
    const char *cost_text;     /* the cost expression as written in pp_isa.def */
} pp_op_info_t;

/* Number of legal opcodes and the i-th one in table order (for docs and tests). */
unsigned pp_isa_count(void);
const pp_op_info_t *pp_isa_at(unsigned i);

/* NULL for an illegal opcode. */
const pp_op_info_t *pp_isa_info(unsigned opcode);
const char *pp_class_name(pp_class_t c);
const char *pp_cond_name(pp_cond_t c);

/* Decodes the instruction at words[*pos], checks it completely (legal opcode,
 * enough words, every field inside pp.mem_bits, x/m/mod in range, unused fields
 * zero, MUL/MULI destination disjoint from its sources) and advances *pos.
 * PP5_E_FIRMWARE with a message naming the word index, the instruction and the
 * field on any violation. */
pp5_status_t pp_isa_decode(const uint32_t *words, size_t n_words, size_t *pos,
                           unsigned mem_bits, pp_insn_t *out);

/* Compute cycles of one instruction from the table (backing-store transfer
 * time and stalls are added by renderer.c). */
uint64_t pp_isa_cycles(const pp_insn_t *in, const pp_params_t *P);

/* Width in bits of the d/a/b field of `in` (0 if unused). */
unsigned pp_isa_field_bits(const pp_insn_t *in, unsigned width_code);

/* One-line disassembly ("ADD d=10 a=0 b=20 n=8"). */
void pp_isa_format(const pp_insn_t *in, char *buf, size_t size);

#endif
