/* pp_isa.c: the opcode table expanded from pp_isa.def, the stream decoder/validator,
 * per-instruction cycle costs and the disassembler. */
#include "pp_isa.h"

#include <stdio.h>
#include <string.h>

static const pp_op_info_t op_table[] = {
#define PP_OP(NAME, CODE, FMT, DW, AW, BW, IMM, CLASS, COST, TAG, SEM) \
    { #NAME, CODE, FMT, DW, AW, BW, IMM, CLASS, TAG, SEM, #COST },
#include "pp_isa.def"
#undef PP_OP
};

#define N_OPS (sizeof op_table / sizeof op_table[0])

/* Row numbers of op_table, and for each opcode its row + 1 (0: illegal): a
 * constant table built by the compiler, so the look-up is one load.  (The
 * executors look up every instruction several times, and a scan of the rows
 * was 4% of the host time of a PP stream.) */
enum {
#define PP_OP(NAME, CODE, FMT, DW, AW, BW, IMM, CLASS, COST, TAG, SEM) ROW_##NAME,
#include "pp_isa.def"
#undef PP_OP
};
static const uint8_t row_of_opcode[256] = {
#define PP_OP(NAME, CODE, FMT, DW, AW, BW, IMM, CLASS, COST, TAG, SEM) [CODE] = ROW_##NAME + 1,
#include "pp_isa.def"
#undef PP_OP
};

const pp_op_info_t *pp_isa_info(unsigned opcode)
{
    if (opcode >= sizeof row_of_opcode || row_of_opcode[opcode] == 0)
        return NULL;
    return &op_table[row_of_opcode[opcode] - 1];
}

unsigned pp_isa_count(void)
{
    return (unsigned)N_OPS;
}

const pp_op_info_t *pp_isa_at(unsigned i)
{
    return i < N_OPS ? &op_table[i] : NULL;
}

const char *pp_class_name(pp_class_t c)
{
    static const char *const names[PP_CLASS_COUNT] = {
        "enable", "flag", "logic", "add", "compare", "multiply", "qee", "backing_store"};
    return (unsigned)c < PP_CLASS_COUNT ? names[c] : "?";
}

const char *pp_cond_name(pp_cond_t c)
{
    static const char *const names[PP_COND_COUNT] = {"EQ", "NE", "LTU", "GEU", "LTS", "GES"};
    return (unsigned)c < PP_COND_COUNT ? names[c] : "?";
}

unsigned pp_isa_field_bits(const pp_insn_t *in, unsigned width_code)
{
    switch (width_code) {
    case W1: return 1;
    case WN: return in->n;
    case WM: return in->m;
    case W32: return PP_BS_BLOCK_BITS;
    default: return 0;
    }
}

static bool uses_width(const pp_op_info_t *op, unsigned code)
{
    return op->d_width == code || op->a_width == code || op->b_width == code;
}

/* The message for a field that check_field rejects (out of line: the decoder
 * runs twice for every instruction a renderer executes, and fields are
 * almost always right). */
static pp5_status_t __attribute__((cold, noinline))
field_error(const pp_op_info_t *op, size_t at, const char *field, unsigned addr,
            unsigned width, unsigned mem_bits)
{
    if (width == 0)
        return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s does not use field %s, "
                        "which must be 0 (is %u)", at, op->name, field, addr);
    return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s field %s = bits [%u, %u) "
                    "exceeds the %u-bit pixel memory", at, op->name, field, addr,
                    addr + width, mem_bits);
}

/* Checks one field: unused fields must be zero, used ones must fit the memory. */
static inline pp5_status_t check_field(const pp_op_info_t *op, size_t at, const char *field,
                                       unsigned addr, unsigned width, unsigned mem_bits)
{
    if (width == 0 ? addr == 0 : addr + width <= mem_bits)
        return PP5_OK;
    return field_error(op, at, field, addr, width, mem_bits);
}

static bool overlaps(unsigned lo1, unsigned len1, unsigned lo2, unsigned len2)
{
    return lo1 < lo2 + len2 && lo2 < lo1 + len1;
}

static unsigned x_limit(unsigned code)
{
    switch (code) {
    case PP_OP_F_SET: return 1;
    case PP_OP_CMP: case PP_OP_CMPI: return PP_COND_COUNT - 1;
    case PP_OP_SHL: case PP_OP_SHR: case PP_OP_SAR: return 255;
    case PP_OP_QEE: return PP_QEE_MAX_SHIFT;
    case PP_OP_BSLOAD: case PP_OP_BSSTORE: return PP_BS_BLOCKS - 1;
    default: return 0;
    }
}

pp5_status_t pp_isa_decode(const uint32_t *words, size_t n_words, size_t *pos,
                           unsigned mem_bits, pp_insn_t *out)
{
    size_t at = *pos;
    if (mem_bits > PP_MEM_BITS)          /* the storage is PP_MEM_BITS planes */
        mem_bits = PP_MEM_BITS;
    if (at >= n_words)
        return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: read past the end", at);
    uint32_t w0 = words[at];
    memset(out, 0, sizeof *out);
    out->op = (uint8_t)(w0 >> 24);
    out->n = (uint8_t)(w0 >> 16);
    out->d = (uint8_t)(w0 >> 8);
    out->x = (uint8_t)w0;
    const pp_op_info_t *op = pp_isa_info(out->op);
    if (!op)
        return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: illegal opcode 0x%02x (word 0x%08x)",
                        at, out->op, (unsigned)w0);
    /* n first: it sizes the immediate (and the imm[] copy below). */
    if (uses_width(op, WN)) {
        if (out->n < 1 || out->n > mem_bits)
            return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s width n = %u outside 1..%u",
                            at, op->name, out->n, mem_bits);
    } else if (out->n != 0) {
        return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s does not use n, which must be 0 "
                        "(is %u)", at, op->name, out->n);
    }
    size_t need = op->format == PP_FMT_2W ? 2 : 1;
    size_t n_imm = 0;
    switch (op->imm) {
    case IMM_N: n_imm = (out->n + 31u) / 32u; break;
    case IMM1: n_imm = 1; break;
    case IMM6: n_imm = 6; break;
    default: break;
    }
    if (n_words - at < need + n_imm)
        return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s needs %zu words, only %zu left",
                        at, op->name, need + n_imm, n_words - at);
    if (need == 2) {
        uint32_t w1 = words[at + 1];
        out->a = (uint8_t)(w1 >> 24);
        out->b = (uint8_t)(w1 >> 16);
        out->m = (uint8_t)(w1 >> 8);
        out->mod = (uint8_t)w1;
    }
    for (size_t i = 0; i < n_imm; i++)
        out->imm[i] = words[at + need + i];
    out->n_words = (uint32_t)(need + n_imm);

    /* m: in range where used, zero where not. */
    if (uses_width(op, WM)) {
        if (out->m < 1 || out->m > mem_bits)
            return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s source width m = %u outside "
                            "1..%u", at, op->name, out->m, mem_bits);
        if (out->mod > 1)
            return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s mod = %u (only bit 0, signed, "
                            "is defined)", at, op->name, out->mod);
    } else if (out->m != 0 || out->mod != 0) {
        return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s does not use m/mod, which must be "
                        "0 (are %u/%u)", at, op->name, out->m, out->mod);
    }
    if (out->x > x_limit(out->op))
        return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s x = %u outside 0..%u", at,
                        op->name, out->x, x_limit(out->op));
    pp5_status_t st;
    if ((st = check_field(op, at, "d", out->d, pp_isa_field_bits(out, op->d_width), mem_bits)) ||
        (st = check_field(op, at, "a", out->a, pp_isa_field_bits(out, op->a_width), mem_bits)) ||
        (st = check_field(op, at, "b", out->b, pp_isa_field_bits(out, op->b_width), mem_bits)))
        return st;
    /* Shift-add multiply re-reads its sources while it accumulates into d. */
    if (op->code == PP_OP_MUL || op->code == PP_OP_MULI) {
        if (overlaps(out->d, out->n, out->a, out->m) ||
            (op->code == PP_OP_MUL && overlaps(out->d, out->n, out->b, out->m)))
            return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: %s destination d = [%u, %u) "
                            "overlaps a source field", at, op->name, out->d, out->d + out->n);
    }
    *pos = at + out->n_words;
    return PP5_OK;
}

/* ---- cycle costs (the cost column of pp_isa.def) ---- */

#define PASS(k) ((uint64_t)(k) * P->cycles_per_bit + P->alu_overhead_cycles)

/* Shift-add: clear d (one pass), then one conditional add of the shifted
 * multiplicand per multiplier bit j, touching d bits j..n-1. */
static uint64_t mul_passes(const pp_params_t *P, unsigned n, unsigned passes)
{
    uint64_t c = PASS(n);
    for (unsigned j = 0; j < passes && j < n; j++)
        c += PASS(n - j);
    return c;
}

static uint64_t pp_cost_mul(const pp_insn_t *in, const pp_params_t *P)
{
    /* A signed multiplier is sign-extended to n bits, so every bit below n counts. */
    unsigned passes = in->mod & 1u ? in->n : (in->m < in->n ? in->m : in->n);
    return mul_passes(P, in->n, passes);
}

static uint64_t pp_cost_muli(const pp_insn_t *in, const pp_params_t *P)
{
    /* The controller skips zero bits of the (sign-extended) constant. */
    uint32_t imm = in->imm[0];
    uint64_t c = PASS(in->n);
    for (unsigned j = 0; j < in->n; j++) {
        unsigned bit = j < 32 ? (imm >> j) & 1u : imm >> 31;
        if (bit)
            c += PASS(in->n - j);
    }
    return c;
}

static uint64_t pp_cost_qee(const pp_insn_t *in, const pp_params_t *P)
{
    /* The tree delivers the sum LSB first, so the x fraction bits stream past
     * before the n kept bits (facts §3.3 [I]); fill and rate are [U] rows. */
    uint64_t bits = (uint64_t)in->x + in->n;
    return P->qee_fill_cycles + (bits + P->qee_bits_per_cycle - 1) / P->qee_bits_per_cycle;
}

uint64_t pp_isa_cycles(const pp_insn_t *in, const pp_params_t *P)
{
    switch (in->op) {
#define PP_OP(NAME, CODE, FMT, DW, AW, BW, IMM, CLASS, COST, TAG, SEM) \
    case CODE: return (uint64_t)(COST);
#include "pp_isa.def"
#undef PP_OP
    default: return 0;
    }
}

void pp_isa_format(const pp_insn_t *in, char *buf, size_t size)
{
    const pp_op_info_t *op = pp_isa_info(in->op);
    if (!op) {
        snprintf(buf, size, "ILLEGAL(0x%02x)", in->op);
        return;
    }
    int len = snprintf(buf, size, "%s", op->name);
    char tail[160] = "";
    size_t t = 0;
#define ADDF(...) t += (size_t)snprintf(tail + t, sizeof tail - t, __VA_ARGS__)
    if (op->d_width) ADDF(" d=%u", in->d);
    if (op->a_width) ADDF(" a=%u", in->a);
    if (op->b_width) ADDF(" b=%u", in->b);
    if (uses_width(op, WN)) ADDF(" n=%u", in->n);
    if (uses_width(op, WM)) ADDF(" m=%u%s", in->m, in->mod ? " signed" : "");
    if (in->op == PP_OP_CMP || in->op == PP_OP_CMPI) ADDF(" %s", pp_cond_name(in->x));
    else if (x_limit(in->op)) ADDF(" x=%u", in->x);
    if (op->imm == IMM_N) ADDF(" imm=0x%x%s", in->imm[0], in->n > 32 ? "..." : "");
    if (op->imm == IMM1) ADDF(" imm=%d", (int32_t)in->imm[0]);
    if (op->imm == IMM6)
        ADDF(" A=%d B=%d C=%d D=%d E=%d F=%d", (int32_t)in->imm[0], (int32_t)in->imm[1],
             (int32_t)in->imm[2], (int32_t)in->imm[3], (int32_t)in->imm[4], (int32_t)in->imm[5]);
#undef ADDF
    if (len >= 0 && (size_t)len < size)
        snprintf(buf + len, size - (size_t)len, "%s", tail);
}
