/* pp_ref.c: the bit-serial reference executor: per PP, per bit, as the hardware would. */
#include "pp_ref.h"

#include <stdlib.h>
#include <string.h>

#include "qee.h"

pp5_status_t pp_ref_init(pp_ref_t *r, const unsigned *indices, unsigned count)
{
    r->count = 0;
    r->pe = calloc(count ? count : 1, sizeof *r->pe);
    if (!r->pe)
        return pp5_fail(PP5_E_NOMEM, "cannot allocate %u reference PPs", count);
    for (unsigned i = 0; i < count; i++) {
        if (indices[i] >= PP_COUNT) {
            free(r->pe);
            r->pe = NULL;
            return pp5_fail(PP5_E_RANGE, "reference PP index %u >= %u", indices[i], PP_COUNT);
        }
        r->pe[i].index = indices[i];
        r->pe[i].e = 1;
    }
    r->count = count;
    return PP5_OK;
}

void pp_ref_free(pp_ref_t *r)
{
    free(r->pe);
    r->pe = NULL;
    r->count = 0;
}

/* Bit i of the n-bit immediate. */
static unsigned imm_bit(const pp_insn_t *in, unsigned i)
{
    return (in->imm[i >> 5] >> (i & 31)) & 1u;
}

/* One full adder: returns the sum bit, updates *carry. */
static unsigned full_add(unsigned a, unsigned b, unsigned *carry)
{
    unsigned s = a ^ b ^ *carry;
    *carry = (a & b) | (*carry & (a ^ b));
    return s;
}

/* Bit i of the m-bit field at src extended (sign or zero) to any width. */
static unsigned ext_bit(const pp_ref_pe_t *p, unsigned src, unsigned m, bool sgn, unsigned i)
{
    if (i < m)
        return p->mem[src + i];
    return sgn ? p->mem[src + m - 1] : 0;
}

static void write_bit(pp_ref_pe_t *p, unsigned addr, unsigned v)
{
    if (p->e)
        p->mem[addr] = (uint8_t)v;
}

static void ref_logic(pp_ref_pe_t *p, const pp_insn_t *in)
{
    const unsigned n = in->n, k = in->x;
    for (unsigned step = 0; step < n; step++) {
        unsigned i = in->op == PP_OP_SHL ? n - 1 - step : step;
        unsigned r;
        switch (in->op) {
        case PP_OP_COPY: r = p->mem[in->a + i]; break;
        case PP_OP_NOT: r = !p->mem[in->a + i]; break;
        case PP_OP_AND: r = p->mem[in->a + i] & p->mem[in->b + i]; break;
        case PP_OP_OR: r = p->mem[in->a + i] | p->mem[in->b + i]; break;
        case PP_OP_XOR: r = p->mem[in->a + i] ^ p->mem[in->b + i]; break;
        case PP_OP_SETI: r = imm_bit(in, i); break;
        case PP_OP_SEL: r = p->f ? p->mem[in->a + i] : p->mem[in->b + i]; break;
        case PP_OP_SHL: r = i >= k ? p->mem[in->a + i - k] : 0; break;
        case PP_OP_SHR: r = i + k < n ? p->mem[in->a + i + k] : 0; break;
        default: r = p->mem[in->a + (i + k < n ? i + k : n - 1)]; break;   /* SAR */
        }
        write_bit(p, in->d + i, r);
    }
}

static void ref_add(pp_ref_pe_t *p, const pp_insn_t *in)
{
    const bool sub = in->op == PP_OP_SUB;
    unsigned carry = sub;               /* a - b = a + ~b + 1 */
    for (unsigned i = 0; i < in->n; i++) {
        unsigned a = p->mem[in->a + i];
        unsigned b = in->op == PP_OP_ADDI ? imm_bit(in, i) : p->mem[in->b + i];
        if (sub)
            b ^= 1u;
        write_bit(p, in->d + i, full_add(a, b, &carry));
    }
    if (p->e)
        p->f = (uint8_t)(sub ? !carry : carry);
}

static void ref_cmp(pp_ref_pe_t *p, const pp_insn_t *in)
{
    const unsigned n = in->n, cond = in->x;
    const bool sgn = cond == PP_COND_LTS || cond == PP_COND_GES;
    unsigned carry = 1, diff = 0;       /* serial a - b: carry 0 at the end = borrow */
    for (unsigned i = 0; i < n; i++) {
        unsigned a = p->mem[in->a + i];
        unsigned b = in->op == PP_OP_CMPI ? imm_bit(in, i) : p->mem[in->b + i];
        diff |= a ^ b;
        if (sgn && i == n - 1) {        /* the sign bit weighs -2^(n-1) */
            a ^= 1u;
            b ^= 1u;
        }
        (void)full_add(a, b ^ 1u, &carry);
    }
    unsigned borrow = !carry, r;
    switch (cond) {
    case PP_COND_EQ: r = !diff; break;
    case PP_COND_NE: r = diff; break;
    case PP_COND_LTU: case PP_COND_LTS: r = borrow; break;
    default: r = !borrow; break;
    }
    if (p->e)
        p->f = (uint8_t)r;
}

/* Shift-add: clear d, then for each multiplier bit j that is 1, add the
 * multiplicand into d[j..n).  A disabled PP does nothing at all. */
static void ref_mul(pp_ref_pe_t *p, const pp_insn_t *in)
{
    if (!p->e)
        return;
    const unsigned n = in->n, m = in->m;
    const bool sgn = in->mod & 1u;
    for (unsigned i = 0; i < n; i++)
        p->mem[in->d + i] = 0;
    for (unsigned j = 0; j < n; j++) {
        unsigned bj;
        if (in->op == PP_OP_MULI)
            bj = j < 32 ? (in->imm[0] >> j) & 1u : in->imm[0] >> 31;
        else
            bj = ext_bit(p, in->b, m, sgn, j);
        if (!bj)
            continue;
        unsigned carry = 0;
        for (unsigned i = j; i < n; i++) {
            unsigned a = ext_bit(p, in->a, m, sgn, i - j);
            p->mem[in->d + i] = (uint8_t)full_add(p->mem[in->d + i], a, &carry);
        }
    }
}

static void ref_qee(pp_ref_pe_t *p, const pp_insn_t *in, int x0, int y0)
{
    qee_coeffs_t c = {(int32_t)in->imm[0], (int32_t)in->imm[1], (int32_t)in->imm[2],
                      (int32_t)in->imm[3], (int32_t)in->imm[4], (int32_t)in->imm[5]};
    int x = x0 + (int)(p->index % PP_ARRAY_DIM), y = y0 + (int)(p->index / PP_ARRAY_DIM);
    qee_serial_t s;
    qee_serial_start(&s, &c, x, y);
    for (unsigned k = 0; k < in->x + in->n; k++) {
        unsigned bit = qee_serial_next_bit(&s);   /* fraction bits stream past */
        if (k >= in->x)
            write_bit(p, in->d + k - in->x, bit);
    }
}

static void ref_bs(pp_ref_pe_t *p, const pp_insn_t *in)
{
    if (!p->e)
        return;
    if (in->op == PP_OP_BSLOAD) {
        for (unsigned k = 0; k < PP_BS_BLOCK_BITS; k++)
            p->mem[in->d + k] = (uint8_t)((p->bs[in->x] >> k) & 1u);
    } else if (in->op == PP_OP_BSSTORE) {
        uint32_t v = 0;
        for (unsigned k = 0; k < PP_BS_BLOCK_BITS; k++)
            v |= (uint32_t)p->mem[in->a + k] << k;
        p->bs[in->x] = v;
    }
}

static void ref_pe(pp_ref_pe_t *p, const pp_insn_t *in, int x0, int y0)
{
    switch (in->op) {
    case PP_OP_EN_ALL: p->e = 1; break;
    case PP_OP_EN_FLAG: p->e = p->f; break;
    case PP_OP_EN_AND: p->e &= p->f; break;
    case PP_OP_EN_ANDN: p->e &= (uint8_t)!p->f; break;
    case PP_OP_EN_OR: p->e |= p->f; break;
    case PP_OP_EN_NOT: p->e = (uint8_t)!p->e; break;
    case PP_OP_F_SET: if (p->e) p->f = in->x & 1u; break;
    case PP_OP_F_NOT: if (p->e) p->f = (uint8_t)!p->f; break;
    case PP_OP_F_LD: if (p->e) p->f = p->mem[in->a]; break;
    case PP_OP_F_ST: write_bit(p, in->d, p->f); break;
    case PP_OP_ADD: case PP_OP_SUB: case PP_OP_ADDI: ref_add(p, in); break;
    case PP_OP_CMP: case PP_OP_CMPI: ref_cmp(p, in); break;
    case PP_OP_MUL: case PP_OP_MULI: ref_mul(p, in); break;
    case PP_OP_QEE: ref_qee(p, in, x0, y0); break;
    case PP_OP_BSLOAD: case PP_OP_BSSTORE: case PP_OP_BSWAIT: ref_bs(p, in); break;
    default: ref_logic(p, in); break;
    }
}

void pp_ref_exec(pp_ref_t *r, const pp_insn_t *in, int x0, int y0)
{
    for (unsigned i = 0; i < r->count; i++)
        ref_pe(&r->pe[i], in, x0, y0);
}
