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

/* T = the row planes `src` (2 words per plane) shifted up by `shl` planes
 * (times 2^shl), in the lanes of chain c if bit c of `chains` is set, else 0. */
static void lanes_spread(uint64_t *T, const uint64_t *src, unsigned shl, unsigned chains,
                         unsigned bits)
{
    uint64_t m[QEE_CHAINS];
    for (unsigned c = 0; c < QEE_CHAINS; c++)
        m[c] = (chains >> c) & 1u ? ~(uint64_t)0 : 0;
    for (unsigned k = 0; k < bits; k++) {
        uint64_t s0 = k >= shl ? src[2 * (k - shl)] : 0, s1 = k >= shl ? src[2 * (k - shl) + 1] : 0;
        for (unsigned c = 0; c < QEE_CHAINS; c++) {
            T[QEE_LANES * k + 2 * c] = s0 & m[c];
            T[QEE_LANES * k + 2 * c + 1] = s1 & m[c];
        }
    }
}

/* Chains whose index has bit b set (they add (B x) 2^b when starting at row c). */
static unsigned chains_with_bit(unsigned b)
{
    unsigned m = 0;
    for (unsigned c = 0; c < QEE_CHAINS; c++)
        m |= ((c >> b) & 1u) << c;
    return m;
}

/* T = per-chain constants K[c] (sign-extended) in the lanes of chain c. */
static void lanes_consts(uint64_t *T, const int64_t *K, unsigned bits)
{
    for (unsigned k = 0; k < bits; k++)
        for (unsigned c = 0; c < QEE_CHAINS; c++) {
            uint64_t m = bit_of(K[c], k) ? ~(uint64_t)0 : 0;
            T[QEE_LANES * k + 2 * c] = m;
            T[QEE_LANES * k + 2 * c + 1] = m;
        }
}

/* The entry points of one kernel copy (qee_kernels.inc defines one table per copy). */
typedef struct {
    void (*lanes_add)(uint64_t *dst, const uint64_t *add, unsigned bits);
    void (*lanes_add_row)(uint64_t *dst, const uint64_t *src, unsigned shl,
                          const uint64_t *lane_mask, unsigned bits);
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
    uint64_t *T = D + QEE_LANES * bits;            /* bits x 16: addends */
    uint64_t *row0 = T + QEE_LANES * bits;         /* bits x 2: Q of row y0 */
    uint64_t *col = row0 + 2 * bits;               /* bits x 2: B x */
    int64_t v[128];
    for (unsigned i = 0; i < 128; i++)
        v[i] = qee_value(q, x0 + (int)i, y0);
    lanes_to_planes(v, bits, row0);
    /* Without the xy term B x is zero: no planes to build, no rows to add
     * (host speed; the same bits). */
    if (q->B == 0) {
        memset(col, 0, sizeof *col * 2 * bits);
    } else {
        for (unsigned i = 0; i < 128; i++)
            v[i] = (int64_t)q->B * (x0 + (int)i);
        lanes_to_planes(v, bits, col);
    }
    /* Chain c starts at row y0 + c: Q(x, y0 + c) = Q(x, y0) + c B x + C(2 y0 c + c^2) + E c,
     * with c B x = sum over the bits b of c of (B x) 2^b. */
    lanes_spread(acc, row0, 0, ~0u, bits);
    for (unsigned b = 0; q->B != 0 && (1u << b) < QEE_CHAINS; b++) {
        uint64_t lane_mask[QEE_LANES];
        for (unsigned j = 0; j < QEE_LANES; j++)
            lane_mask[j] = (chains_with_bit(b) >> (j / 2)) & 1u ? ~(uint64_t)0 : 0;
        k->lanes_add_row(acc, col, b, lane_mask, bits);
    }
    int64_t K[QEE_CHAINS];
    for (unsigned c = 0; c < QEE_CHAINS; c++)
        K[c] = (int64_t)q->C * (2 * (int64_t)y0 * c + (int64_t)c * c) + (int64_t)q->E * c;
    lanes_consts(T, K, bits);
    k->lanes_add(acc, T, bits);
    /* D of chain c at its first row y = y0 + c: 8 B x (col shifted by 3 planes)
     * + C(16y + 64) + 8E. */
    lanes_spread(D, col, 3, ~0u, bits);
    for (unsigned c = 0; c < QEE_CHAINS; c++)
        K[c] = (int64_t)q->C * (16 * ((int64_t)y0 + c) + 64) + 8 * (int64_t)q->E;
    lanes_consts(T, K, bits);
    k->lanes_add(D, T, bits);
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
