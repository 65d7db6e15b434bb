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

/* The two words of a 128-PP row as one vector (SSE2 on x86-64, pairs elsewhere). */
typedef uint64_t v2_t __attribute__((vector_size(16), aligned(8), may_alias));
#define LD2(p) (*(const v2_t *)(const void *)(p))
#define ST2(p, v) (*(v2_t *)(void *)(p) = (v))

/* Per row: acc += addend (bit-sliced, `bits` planes of 2 words), then
 * acc += constant v (sign-extended) in every lane.  One pass, two carries. */
static void row_step(uint64_t *acc, const uint64_t *addend, int64_t v, unsigned bits)
{
    v2_t c1 = {0, 0}, c2 = {0, 0};
    for (unsigned k = 0; k < bits; k++) {
        v2_t a = LD2(acc + 2 * k), b = LD2(addend + 2 * k);
        v2_t x = a ^ b;
        v2_t s = x ^ c1;
        c1 = (a & b) | (c1 & x);
        uint64_t kb = bit_of(v, k) ? ~(uint64_t)0 : 0;
        v2_t K = {kb, kb};
        v2_t y = s ^ K;
        ST2(acc + 2 * k, y ^ c2);
        c2 = (s & K) | (c2 & y);
    }
}

/* In-place transpose of a 64x64 bit matrix (bit c of word r <-> bit r of word c)
 * by swapping ever smaller blocks: 6 stages x 32 word pairs. */
static void transpose64(uint64_t a[64])
{
    uint64_t m = 0x00000000FFFFFFFFull;
    for (unsigned j = 32; j != 0; j >>= 1, m ^= m << j) {
        for (unsigned k = 0; k < 64; k = ((k | j) + 1) & ~j) {
            uint64_t t = ((a[k] >> j) ^ a[k | j]) & m;
            a[k] ^= t << j;
            a[k | j] ^= t;
        }
    }
}

/* Planes (2 words each) of 128 int64 lane values; planes 64 and up repeat the
 * sign plane (two's complement extended to `bits`). */
static void lanes_to_planes(const int64_t *v, unsigned bits, uint64_t *planes)
{
    for (unsigned h = 0; h < 2; h++) {
        uint64_t t[64];
        for (unsigned i = 0; i < 64; i++)
            t[i] = (uint64_t)v[64 * h + i];
        transpose64(t);
        for (unsigned k = 0; k < bits; k++)
            planes[2 * k + h] = t[k < 64 ? k : 63];
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
        row_step(row, colpart, (int64_t)q->C * (2 * y + 1) + q->E, bits);
        emit(ctx, j, row);
    }
}
