/* qee.c: the Quadratic Expression Evaluator (definition and overflow rule in qee.h). */
#include "qee.h"

#include <stdlib.h>

bool qee_origin_ok(int x0, int y0)
{
    return abs(x0) <= QEE_COORD_MAX - 127 && abs(y0) <= QEE_COORD_MAX - 127;
}

/* Each term is below 2^31 * 2^26 = 2^57 in magnitude and there are six, so the
 * sum is exact in int64 (qee.h). */
int64_t qee_value(const qee_coeffs_t *q, int x, int y)
{
    int64_t X = x, Y = y;
    return (int64_t)q->A * X * X + (int64_t)q->B * X * Y + (int64_t)q->C * Y * Y +
           (int64_t)q->D * X + (int64_t)q->E * Y + (int64_t)q->F;
}

void qee_serial_start(qee_serial_t *s, const qee_coeffs_t *q, int x, int y)
{
    int64_t X = x, Y = y;
    s->term[0] = (int64_t)q->A * X * X;
    s->term[1] = (int64_t)q->B * X * Y;
    s->term[2] = (int64_t)q->C * Y * Y;
    s->term[3] = (int64_t)q->D * X;
    s->term[4] = (int64_t)q->E * Y;
    s->term[5] = (int64_t)q->F;
    s->carry = 0;
    s->k = 0;
}

/* Bit k of a two's-complement int64 extended to infinite width. */
static unsigned bit_of(int64_t v, unsigned k)
{
    uint64_t u = (uint64_t)v;
    return k < 64 ? (unsigned)(u >> k) & 1u : (unsigned)(u >> 63);
}

unsigned qee_serial_next_bit(qee_serial_t *s)
{
    unsigned sum = s->carry;
    for (int t = 0; t < 6; t++)
        sum += bit_of(s->term[t], s->k);
    s->carry = sum >> 1;
    s->k++;
    return sum & 1u;
}

/* Bit-sliced add of `bits` planes: acc += addend (both 2 words per plane). */
static void row_add(uint64_t *acc, const uint64_t *addend, unsigned bits)
{
    uint64_t c0 = 0, c1 = 0;
    for (unsigned k = 0; k < bits; k++) {
        uint64_t a0 = acc[2 * k], a1 = acc[2 * k + 1];
        uint64_t b0 = addend[2 * k], b1 = addend[2 * k + 1];
        acc[2 * k] = a0 ^ b0 ^ c0;
        acc[2 * k + 1] = a1 ^ b1 ^ c1;
        c0 = (a0 & b0) | (c0 & (a0 ^ b0));
        c1 = (a1 & b1) | (c1 & (a1 ^ b1));
    }
}

/* acc += constant v (sign-extended), in every lane. */
static void row_add_const(uint64_t *acc, int64_t v, unsigned bits)
{
    uint64_t c0 = 0, c1 = 0;
    for (unsigned k = 0; k < bits; k++) {
        uint64_t b = bit_of(v, k) ? ~(uint64_t)0 : 0;
        uint64_t a0 = acc[2 * k], a1 = acc[2 * k + 1];
        acc[2 * k] = a0 ^ b ^ c0;
        acc[2 * k + 1] = a1 ^ b ^ c1;
        c0 = (a0 & b) | (c0 & (a0 ^ b));
        c1 = (a1 & b) | (c1 & (a1 ^ b));
    }
}

/* Planes of 128 int64 lane values. */
static void lanes_to_planes(const int64_t *v, unsigned bits, uint64_t *planes)
{
    for (unsigned k = 0; k < bits; k++) {
        uint64_t w[2] = {0, 0};
        for (unsigned i = 0; i < 128; i++)
            w[i >> 6] |= (uint64_t)bit_of(v[i], k) << (i & 63);
        planes[2 * k] = w[0];
        planes[2 * k + 1] = w[1];
    }
}

/* Row recurrence: Q(x, y+1) - Q(x, y) = B x + C (2y + 1) + E, i.e. a per-column
 * part P(x) = B x plus a per-row constant; both are exact integers, so adding
 * them mod 2^bits keeps the low `bits` bits of Q exact. */
void qee_row_planes(const qee_coeffs_t *q, int x0, int y0, unsigned bits, uint64_t *scratch,
                    qee_row_fn emit, void *ctx)
{
    uint64_t *row = scratch;               /* 2 * bits */
    uint64_t *colpart = scratch + 2 * bits; /* 2 * bits */
    int64_t v[128];
    for (unsigned i = 0; i < 128; i++)
        v[i] = qee_value(q, x0 + (int)i, y0);
    lanes_to_planes(v, bits, row);
    for (unsigned i = 0; i < 128; i++)
        v[i] = (int64_t)q->B * (x0 + (int)i);
    lanes_to_planes(v, bits, colpart);
    emit(ctx, 0, row);
    for (unsigned j = 1; j < 128; j++) {
        int64_t y = (int64_t)y0 + j - 1;
        row_add(row, colpart, bits);
        row_add_const(row, (int64_t)q->C * (2 * y + 1) + q->E, bits);
        emit(ctx, j, row);
    }
}
