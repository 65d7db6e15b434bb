/* qee.c: the Quadratic Expression Evaluator (definition and overflow rule in qee.h). */
#include "qee.h"

#include <string.h>

#include "pp_simd.h"

bool qee_origin_ok(int x0, int y0)
{
    const int lim = QEE_COORD_MAX - 127;    /* no abs(): abs(INT_MIN) overflows */
    return x0 >= -lim && x0 <= lim && y0 >= -lim && y0 <= lim;
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

/* The entry points of one kernel copy (qee_kernels.inc defines one table per copy). */
typedef struct {
    void (*lanes_to_planes)(const int64_t *values, unsigned bits, uint64_t *planes);
    void (*lanes_start)(uint64_t *dst, const uint64_t *row, unsigned shl, const uint64_t *col,
                        const int64_t *K, unsigned bits);
    void (*lanes_add)(uint64_t *dst, const uint64_t *add, unsigned bits);
    void (*chains_step)(uint64_t *acc, uint64_t *D, int64_t K, unsigned bits);
} qee_kernels_t;

#define PP_SIMD_KERNELS "qee_kernels.inc"
#include "pp_simd_copies.inc"

/* The copy for `level` (a level the host has, see pp_kernel_level.h). */
static const qee_kernels_t *qee_kernels_of(pp_kernel_level_t level)
{
#if PP_HAVE_X86_COPIES
    if (level == PP_KERNELS_AVX512)
        return &qee_kernels_avx512;
    if (level == PP_KERNELS_AVX2)
        return &qee_kernels_avx2;
#else
    (void)level;
#endif
    return &qee_kernels_base;
}

/* Q at (x0 + i, y) for the 128 columns i, by differences along the row: exact,
 * as every value fits an int64 (qee.h), so arithmetic mod 2^64 gives it. */
static void row_values(const qee_coeffs_t *q, int x0, int y, int64_t *v)
{
    uint64_t value = (uint64_t)qee_value(q, x0, y);
    /* Q(x + 1, y) - Q(x, y) = A (2x + 1) + B y + D, which grows by 2A per column. */
    uint64_t diff = (uint64_t)((int64_t)q->A * (2 * (int64_t)x0 + 1) + (int64_t)q->B * y + q->D);
    for (unsigned i = 0; i < 128; i++) {
        v[i] = (int64_t)value;
        value += diff;
        diff += 2 * (uint64_t)(int64_t)q->A;
    }
}

/* Eight interleaved chains: chain c computes rows c, c+8, c+16, ... so one step
 * of all chains yields rows 8t..8t+7, i.e. 16 consecutive plane words.  Going
 * down 8 rows adds D = Q(x, y+8) - Q(x, y) = 8Bx + C(16y + 64) + 8E, and D
 * grows by 128C per step.  Everything is exact integer arithmetic done mod
 * 2^bits, so the low `bits` bits of Q are exact. */
void qee_eval_steps(const qee_coeffs_t *q, int x0, int y0, unsigned bits, uint64_t *scratch,
                    qee_step_fn emit, void *ctx, pp_kernel_level_t kernels)
{
    const qee_kernels_t *k = qee_kernels_of(kernels);
    uint64_t *acc = scratch;                       /* bits x 16 */
    uint64_t *D = acc + QEE_LANES * bits;          /* bits x 16 */
    uint64_t *row0 = D + QEE_LANES * bits;         /* bits x 2: Q of row y0 */
    uint64_t *col = row0 + 2 * bits;               /* bits x 2: B x */
    int64_t v[128], K[QEE_CHAINS];
    row_values(q, x0, y0, v);
    k->lanes_to_planes(v, bits, row0);
    /* Without the xy term B x is zero: no planes to build or add (host speed;
     * the same bits). */
    if (q->B != 0) {
        uint64_t bx = (uint64_t)q->B * (uint64_t)(int64_t)x0;    /* exact mod 2^64 */
        for (unsigned i = 0; i < 128; i++, bx += (uint64_t)(int64_t)q->B)
            v[i] = (int64_t)bx;
        k->lanes_to_planes(v, bits, col);
    }
    const uint64_t *bx_planes = q->B != 0 ? col : NULL;
    /* Chain c starts at row y0 + c: Q(x, y0 + c) = Q(x, y0) + c B x + C(2 y0 c + c^2) + E c. */
    for (unsigned c = 0; c < QEE_CHAINS; c++)
        K[c] = (int64_t)q->C * (2 * (int64_t)y0 * c + (int64_t)c * c) + (int64_t)q->E * c;
    k->lanes_start(acc, row0, 0, bx_planes, K, bits);
    /* D of chain c at its first row y = y0 + c: 8 B x (B x shifted by 3 planes)
     * + C(16y + 64) + 8E. */
    for (unsigned c = 0; c < QEE_CHAINS; c++)
        K[c] = (int64_t)q->C * (16 * ((int64_t)y0 + c) + 64) + 8 * (int64_t)q->E;
    k->lanes_start(D, bx_planes, 3, NULL, K, bits);
    /* Without the y^2 term D stays the same: only acc moves (host speed;
     * the same bits as stepping D by zero). */
    int64_t dD = 128 * (int64_t)q->C;
    for (unsigned t = 0; t < 128 / QEE_CHAINS; t++) {
        emit(ctx, t, acc);
        if (t + 1 < 128 / QEE_CHAINS && dD != 0)
            k->chains_step(acc, D, dD, bits);
        else if (t + 1 < 128 / QEE_CHAINS)
            k->lanes_add(acc, D, bits);
    }
}

int64_t qee_row_linear_start(const qee_coeffs_t *q, int x0, int y0, unsigned bits,
                             uint64_t *step0, pp_kernel_level_t kernels)
{
    const qee_kernels_t *k = qee_kernels_of(kernels);
    uint64_t row0[2 * QEE_MAX_BITS];
    int64_t v[128], K[QEE_CHAINS];
    row_values(q, x0, y0, v);
    k->lanes_to_planes(v, bits, row0);
    /* Chain c (row y0 + c) is row y0 plus E c. */
    for (unsigned c = 0; c < QEE_CHAINS; c++)
        K[c] = (int64_t)q->E * c;
    k->lanes_start(step0, row0, 0, NULL, K, bits);
    return 8 * (int64_t)q->E;
}
