/* vr_cost.h: i860 operation counts of one execution of each inner kernel of the volume-rendering GP program.
 *
 * The ray caster counts kernel executions in local integers (no per-sample
 * call overhead) and converts them with these rows at the end of each ray
 * batch.  Each row is the count of operations the C kernel in
 * firmware/gp/vr_gp.c performs (read off the code, statement by statement);
 * tests/test_fw_pp.c (fw_trilerp_cost_row_counts_real_operations) re-counts the
 * trilinear kernel's floating-point operations with the counting
 * helpers of fw_api.h on real data and requires equality.  Rows are
 * {fadd, fmul, fdiv, fsqrt, loads, stores, int_ops, branches}. */
#ifndef PP5_VR_COST_H
#define PP5_VR_COST_H

#include <stdint.h>
#include "fw_api.h"

typedef struct {
    uint32_t fadd, fmul, fdiv, fsqrt, loads, stores, int_ops, branches;
} vr_cost_row_t;

/* Trilinear lookup of 4 components from 8 byte-packed voxels of bricks:
 * level coordinates (6 fadd, 3 fmul: (p+0.5)*2^-n - 0.5), floor and
 * weights (3 floor as int ops, 3 fadd), clamps (12 int ops, 12 branches),
 * brick/offset for the 2 x 3 axis indices (12 int div/mod as int ops, 6 mul),
 * 8 brick pointer loads + 8 word loads, 32 LUT loads, 7 lerps x 4
 * components = 28 x (2 fadd + 1 fmul). */
static const vr_cost_row_t VR_COST_TRILERP = {6 + 3 + 56, 3 + 28, 0, 0, 8 + 8 + 32, 0,
                                              3 + 12 + 12 + 6 + 8, 12};
/* Object slabs: one probe of the binary search for a ray's first or last
 * sample in the slab: t = t0 + k * base and z at it (2 fadd, 2 fmul, 1
 * int->float), round and floor, compare, halve the interval. */
static const vr_cost_row_t VR_COST_SEGMENT_PROBE = {2 + 1, 2, 0, 0, 0, 0, 2 + 4, 2};
/* Object slabs: compositing one partial colour into a texel, front to back:
 * load it (5 words) and the accumulator (4), 1 - a (1 fadd), 4 x (1 fmul +
 * 1 fadd), store the accumulator. */
static const vr_cost_row_t VR_COST_MERGE = {1 + 4, 4, 0, 0, 9, 4, 3, 2};
/* Blend of two levels: 4 x (2 fadd + 1 fmul), 1 compare. */
static const vr_cost_row_t VR_COST_LEVEL_BLEND = {8 + 1, 4, 0, 0, 0, 0, 2, 1};
/* One sample's bookkeeping: position (3 fadd + 3 fmul), loop test, step
 * (1 fadd + 1 fmul + 1 int), 3DLevel compare. */
static const vr_cost_row_t VR_COST_SAMPLE = {3 + 2, 3 + 1, 0, 0, 0, 0, 2, 3};
/* Octree leaf lookup: 3 level coords (3 fadd, 3 fmul), 3 floor+clamp,
 * index (4 int), bit load and test. */
static const vr_cost_row_t VR_COST_OCT_LEAF = {3, 3, 0, 0, 1, 0, 3 + 6 + 4 + 2, 4};
/* One step up the OR pyramid: 3 shifts, index, load, test. */
static const vr_cost_row_t VR_COST_OCT_UP = {0, 0, 0, 0, 1, 0, 3 + 4 + 2, 2};
/* Skip: node bounds (6 x (1 fadd + 1 fmul)), exit t per axis (3 fdiv, 3
 * fadd), min, ceil, sample index update. */
static const vr_cost_row_t VR_COST_SKIP = {6 + 3 + 4, 6 + 1, 3, 0, 0, 0, 8, 8};
/* Opacity correction (LUT: 2 loads, 3 fadd/fmul, 1 fdiv for scale, 3 fmul)
 * and front-to-back compositing (1 fadd + 3 x (1 fadd + 1 fmul) + 1 fadd +
 * 1 fmul) and the termination compare. */
static const vr_cost_row_t VR_COST_COMPOSITE = {2 + 1 + 8 + 1, 1 + 3 + 4, 1, 0, 2, 0, 3, 3};
/* Ray setup: camera ray (6 fadd/fmul + 9 fmadd), clip (6 fdiv, 12 fadd),
 * voxel-space origin/direction (6 fmul), half vector unused (stride 4). */
static const vr_cost_row_t VR_COST_RAY = {4 + 9 + 12 + 3, 2 + 9 + 6, 6, 0, 12, 3, 10, 12};
/* RenderPixel: two bilinear lookups (3 x (2 fadd + 1 fmul) + weights) and
 * the level blend, float->u8 conversion x 3. */
static const vr_cost_row_t VR_COST_PIXEL = {2 * (6 + 2) + 6, 2 * (3 + 2) + 3 + 3, 0, 0, 2 * 12, 3,
                                            2 * 8 + 9, 2 * 4 + 6};
/* 2DLevel of one pixel without transcendentals: dx, dy, dx^2 + dy^2, sqrt,
 * 2 compares. */
static const vr_cost_row_t VR_COST_LEVEL = {3, 2, 0, 1, 0, 1, 2, 3};
/* 2DLevel by the paper's tables (vr_level_tabled): two offsets and their
 * absolute values (4 int, 2 branches), the 2D index (2 int) and its load,
 * the 1D index compare and its load. */
static const vr_cost_row_t VR_COST_LEVEL_TABLE = {0, 0, 0, 0, 2, 1, 6 + 1, 3};
/* One entry of the 2D distance table at setup: dx^2 + dy^2 (2 fmul, 1 fadd),
 * sqrt, scale and round (1 fmul, 1 fadd, 1 int), store. */
static const vr_cost_row_t VR_COST_TABLE_DIST = {2, 3, 0, 1, 0, 1, 3, 1};
/* The transcendental branch of 2DLevel (atan, exp, log2 by libm-style
 * polynomial evaluation): [I] ~20 fadd + 20 fmul + 2 fdiv each. */
static const vr_cost_row_t VR_COST_LEVEL_TRANS = {60, 60, 6, 0, 12, 0, 10, 10};
/* Texel marking per pixel: 2 shifts, 2 masks, up to 4 flag stores. */
static const vr_cost_row_t VR_COST_MARK = {0, 0, 0, 0, 0, 4, 8, 4};
/* Level-0 voxel of the mip-map build: 3 central differences (6 loads, 3 fadd,
 * 3 fdiv, 3 fmul), |g| (3 fmul, 2 fadd, 1 fsqrt), one contour (~8 flops,
 * 1 fdiv) per contour counted separately, normal (3 fdiv), diffuse
 * (3 fmul + 3 fadd), 4..7 products and stores. */
static const vr_cost_row_t VR_COST_VOXEL = {3 + 2 + 3 + 2, 3 + 3 + 3 + 7, 3 + 3, 1, 6, 8, 20, 8};
static const vr_cost_row_t VR_COST_CONTOUR = {5, 4, 1, 0, 5, 0, 2, 3};
/* Box-filter output voxel: 8 children x stride loads and adds, stride fmul. */
static const vr_cost_row_t VR_COST_FILTER_COMPONENT = {8, 1, 0, 0, 8, 1, 9, 9};
/* Quantise one voxel to blocks A (+N): 4 (7) clamps/rounds, a normal
 * renormalisation (3 fmul, 2 fadd, 1 fsqrt, 3 fdiv), packing. */
static const vr_cost_row_t VR_COST_QUANTISE = {4 + 2, 4 + 6, 3, 1, 7, 2, 20, 10};
/* GP-side fixed-point shading of one voxel (the GP split): 3 integer
 * multiplies + adds, abs, (bits of e) x 2 multiplies, 2 multiplies, 3
 * saturating adds; about 40 integer ops and 10 branches at exponent 20. */
static const vr_cost_row_t VR_COST_SHADE_VOXEL = {0, 0, 0, 0, 2, 1, 40, 10};
/* Unpacking one received word into the brick cache. */
static const vr_cost_row_t VR_COST_UNPACK_WORD = {0, 0, 0, 0, 1, 1, 1, 0};

static inline void vr_cost_add(fw_ops_t *o, const vr_cost_row_t *r, uint64_t times)
{
    o->fadd += r->fadd * times;
    o->fmul += r->fmul * times;
    o->fdiv += r->fdiv * times;
    o->fsqrt += r->fsqrt * times;
    o->loads += r->loads * times;
    o->stores += r->stores * times;
    o->int_ops += r->int_ops * times;
    o->branches += r->branches * times;
}

#endif
