/* qee.h: the Quadratic Expression Evaluator: every PP's own value of
 * Q(x,y) = A x^2 + B x y + C y^2 + D x + E y + F for its screen pixel (x, y).
 *
 * Definition (ours; the hardware's coefficient format is [U], facts §3.3):
 * coefficients are signed 32-bit integers (fixed point is the firmware's
 * choice: with `shift` fraction bits the stored value is floor(Q / 2^shift));
 * x = region x0 + column, y = region y0 + row; Q is computed exactly (the
 * region origin is limited to |x0|,|y0| <= 8064, so |x|,|y| < 2^13 and
 * |Q| < 2^60 fits an int64).  The PP stores bits shift..shift+n-1 of Q in two's
 * complement: floor(Q / 2^shift) mod 2^n.  Overflow therefore WRAPS to n bits
 * (no saturation), and bits above bit 63 are copies of the sign.
 *
 * Hardware picture [I] (facts §3.3, S17/S18): a tree of one-bit serial adders
 * delivers Q LSB first, one bit per clock, the same to all 16384 PPs; the
 * low `shift` bits stream past and are dropped, so a QEE costs
 * pp.qee_fill_cycles + (shift + n) / pp.qee_bits_per_cycle.
 *
 * Three implementations, which the tests compare: qee_value (direct int64
 * formula), qee_serial_* (per-PP multi-operand serial adder, bit by bit: the
 * reference executor's), qee_eval_steps (bit-sliced row recurrence: the fast
 * array's). */
#ifndef PP5_QEE_H
#define PP5_QEE_H

#include <stdbool.h>
#include <stdint.h>

#include "pp_kernel_level.h"

typedef struct {
    int32_t A, B, C, D, E, F;
} qee_coeffs_t;

/* Largest |origin| for which qee_value is exact (see renderer.h). */
#define QEE_COORD_MAX (8064 + 127)

bool qee_origin_ok(int x0, int y0);
/* Exact Q at (x, y); |x|, |y| <= QEE_COORD_MAX. */
int64_t qee_value(const qee_coeffs_t *q, int x, int y);

/* Bit-serial evaluation for one PP: six operand streams (the terms as
 * two's-complement integers) summed by a serial adder, one bit per step. */
typedef struct {
    int64_t term[6];
    unsigned carry;   /* <= 6: the sum of 6 bits + carry fits 3 bits */
    unsigned k;       /* next bit position */
} qee_serial_t;
void qee_serial_start(qee_serial_t *s, const qee_coeffs_t *q, int x, int y);
unsigned qee_serial_next_bit(qee_serial_t *s);

/* Fast path (bit-sliced, 8 interleaved row chains): for t = 0..15 calls
 * emit(ctx, t, planes) where planes[16 * k + j] is bit k (0 <= k < bits) of Q
 * for the 64 PPs of plane word 16t + j (row 8t + j/2, columns 64(j%2)..+63,
 * PP column c in bit c % 64): the 16 words of the array's planes that hold
 * rows 8t..8t+7.  `scratch` holds QEE_SCRATCH_WORDS(bits) uint64 values;
 * bits <= QEE_MAX_BITS (64 + 208).  `kernels` selects the kernel copy (same results; only a
 * level the host has: see pp_kernel_level.h). */
#define QEE_MAX_BITS (64u + 208u)
#define QEE_CHAINS 8u
#define QEE_LANES (2u * QEE_CHAINS)
#define QEE_SCRATCH_WORDS(bits) ((2u * QEE_LANES + 4u) * (bits))
typedef void (*qee_step_fn)(void *ctx, unsigned step, const uint64_t *planes);
void qee_eval_steps(const qee_coeffs_t *q, int x0, int y0, unsigned bits, uint64_t *scratch,
                    qee_step_fn emit, void *ctx, pp_kernel_level_t kernels);

/* Row-linear QEEs (no xy and no y^2 term, B = C = 0): Q(x, y + 8) = Q(x, y) +
 * 8E, so step t of qee_eval_steps is its step 0 plus 8 E t in every lane,
 * without the steps in between; the fast array evaluates them tile by tile.
 * qee_row_linear_start writes step 0's planes (what qee_eval_steps hands to
 * emit first: QEE_LANES words per plane) and returns 8E. */
static inline bool qee_is_row_linear(const qee_coeffs_t *q)
{
    return q->B == 0 && q->C == 0;
}
int64_t qee_row_linear_start(const qee_coeffs_t *q, int x0, int y0, unsigned bits,
                             uint64_t *step0, pp_kernel_level_t kernels);

#endif
