/* vr_cost.h: i860 operation counts of the volume-rendering GP program's kernels, one row per straight-line span of a kernel, and the counting that checks them.
 *
 * How the cost is charged.  Every kernel (firmware/gp/vr_*_kernels.h,
 * common/vr_kernels.h, common/vr_shade_fixed.h) is cut into spans: pieces of
 * code that always execute the same operations (a loop body, the taken side
 * of a branch, one libm call).  Each span has a row below.  In production a
 * kernel only counts how often each span ran (VR_SPAN into a vr_spans_t, one
 * integer increment) and the caller converts the counts with these rows at
 * the end of a batch (vr_spans_charge).
 *
 * How the rows are checked.  Next to its code every span also states the
 * operations it performs, statement by statement (VR_SPAN / VR_COUNT with the
 * literal counts), into a vr_count_t that the caller passes; production
 * passes NULL, so the compiler drops those statements when it inlines the
 * kernel.  tests/test_fw_cost.c runs each kernel on real data with counting
 * on and requires, for every row and every column, the operations the
 * kernel's spans stated to equal (times the span ran) x (the row): a kernel
 * edited without its row, or a span whose operations vary with the data,
 * fails there.
 *
 * Counting conventions (the i860 of facts §8; firmware/ARCHITECTURE.md
 * "Cost model notes"): FP add, subtract and compare are fadd; a divide by a
 * power of two is a multiply by a table entry (fmul); int<->float
 * conversions, floorf/ceilf, fabsf and isfinite are one integer op each;
 * integer multiplies and divides by a per-level constant are one integer op
 * each (the i860 has neither: [I] a reciprocal table); an ordering compare is
 * an op plus a branch, a test against zero or equality only the branch
 * (bte/btne); a select or clamp counts both of its compares whatever the
 * data; a load is load_use when the next instruction needs its value and no
 * independent work can fill the delay (gp_cost.h).  Data-cache lookups are
 * not in the rows: the kernels declare their accesses to big blocks with
 * fw_dcache_access (vr_mem_t) and the misses are charged as such. */
#ifndef PP5_VR_COST_H
#define PP5_VR_COST_H

#include <stdint.h>
#include <string.h>
#include "fw_api.h"

typedef struct {
    uint32_t fadd, fmul, fdiv, fsqrt, loads, load_use, stores, int_ops, branches;
} vr_cost_row_t;

/* X(ID, row, what): the rows.  Derivations are in the comments beside each
 * span's code; a row is the sum of its span's VR_SPAN/VR_COUNT statements. */
#define VR_COST_ROWS(X) \
    /* ---- ray casting (firmware/gp/vr_cast_kernels.h, common/vr_kernels.h) ---- */ \
    X(RAY, (.fadd = 11, .fmul = 11, .loads = 13, .branches = 1), \
      "a camera ray, parallel projection") \
    X(RAY_PERSPECTIVE, (.fadd = 14, .fmul = 11, .fdiv = 3, .fsqrt = 1, .loads = 13, .branches = 1), \
      "a camera ray, perspective projection") \
    X(CLIP_AXIS, (.fadd = 6, .fdiv = 2, .loads = 1, .branches = 4), \
      "box clip: an axis the ray crosses") \
    X(CLIP_FLAT, (.fadd = 3, .loads = 1, .branches = 3), \
      "box clip: an axis the ray runs parallel to") \
    X(CLIP_END, (.fadd = 2, .branches = 2), \
      "box clip: the entry clamped, entry against exit") \
    X(RAY_MISS, (.stores = 3, .branches = 1), \
      "a new ray that misses the volume: black texel") \
    X(RAY_START, (.fmul = 6, .loads = 3, .branches = 2), \
      "a ray that meets the volume: voxel-space origin and direction") \
    X(RAY_NEAR, (.fadd = 1, .branches = 1), \
      "perspective: the ray starts no nearer than 1e-3") \
    X(RAY_RESUME, (.fadd = 1, .fmul = 1, .loads = 6, .int_ops = 1, .branches = 1), \
      "a ray resumed in the next depth segment: its parked state") \
    X(RAY_PARK, (.stores = 6), \
      "a ray parked at the end of a depth segment") \
    X(RAY_END, (.stores = 3), \
      "a finished ray: its colour into the texel") \
    X(SAMPLE, (.fadd = 5, .fmul = 3, .branches = 4), \
      "one step of the ray loop (sampled or skipped): tests, position") \
    X(SAMPLE_PERSPECTIVE, (.fadd = 3, .fmul = 1, .branches = 2), \
      "perspective: the step's spacing and 3D level (its log2 is a LIBM)") \
    X(OCT_LEAF, (.fadd = 13, .fmul = 3, .loads = 7, .load_use = 1, .int_ops = 23, .branches = 10), \
      "octree: the leaf cell of the position and its bit") \
    X(OCT_UP, (.loads = 4, .load_use = 1, .int_ops = 14, .branches = 2), \
      "octree: one step up the OR pyramid") \
    X(OCT_TOP, (.int_ops = 2, .branches = 1), \
      "octree: the steps reached the top of the pyramid") \
    X(SKIP, (.fadd = 12, .fmul = 6, .loads = 1, .int_ops = 21, .branches = 6), \
      "an empty node: its height and bounds") \
    X(SKIP_EXIT, (.fadd = 10, .int_ops = 6, .branches = 16), \
      "an empty node: where the ray leaves it, against the ray's end") \
    X(SKIP_DIVIDE, (.fadd = 1, .fdiv = 1), \
      "the exit parameter of an axis bounded inside the volume") \
    X(SKIP_PARALLEL, (.fadd = 3, .fmul = 1, .fdiv = 1, .int_ops = 5, .branches = 2), \
      "parallel: the sample index after the skip") \
    X(SKIP_PERSPECTIVE, (.fadd = 3, .fdiv = 1, .int_ops = 3, .branches = 3), \
      "perspective: where the ray's 3D level changes (its exp2 is a LIBM)") \
    X(SKIP_STEP, (.fadd = 2, .fmul = 1, .branches = 2), \
      "perspective: one sample position skipped") \
    X(POINT, (.fadd = 5, .int_ops = 4, .branches = 5), \
      "a sampled position: 3D level split, blend test, opacity test") \
    X(STEP, (.fadd = 1, .fmul = 1, .int_ops = 2, .branches = 1), \
      "parallel: the next sample position") \
    X(STEP_PERSPECTIVE, (.fmul = 1, .branches = 1), \
      "perspective: the next sample position") \
    X(TRILERP, (.fadd = 65, .fmul = 31, .loads = 18, .load_use = 8, .int_ops = 91, .branches = 20), \
      "trilinear lookup of 4 components: coordinates, clamps, the 8 corners' units, 7 lerps x 4") \
    X(CORNER, (.loads = 5, .load_use = 1, .int_ops = 11), \
      "a corner in a fetched unit: its word and 4 byte-to-float lookups") \
    X(LEVEL_BLEND, (.fadd = 8, .fmul = 4), \
      "blend of the two 3D levels' lookups") \
    X(CORRECT, (.fadd = 1, .fmul = 3, .fdiv = 1, .branches = 1), \
      "opacity correction: a >= 1 test, colour rescaled") \
    X(CORRECT_LUT, (.fadd = 3, .fmul = 2, .loads = 2, .load_use = 1, .int_ops = 7, .branches = 3), \
      "opacity correction by the table of the 2D level") \
    X(CORRECT_POW, (.fadd = 2, .int_ops = 1, .branches = 2), \
      "opacity correction by powf (perspective, deep levels; the powf is a LIBM)") \
    X(COMPOSITE, (.fadd = 7, .fmul = 4, .branches = 2), \
      "front-to-back compositing and the early-termination test") \
    X(LIBM, (.fadd = 20, .fmul = 20, .fdiv = 2, .loads = 4, .int_ops = 3, .branches = 3), \
      "[I] one libm-style transcendental (atan, exp, exp2, log2, pow): range reduction and a polynomial") \
    X(SHADE_WORD, (.loads = 2, .load_use = 1, .stores = 1, .int_ops = 3, .branches = 1), \
      "GP split: one word of a fetched unit shaded in place") \
    X(SHADE_VOXEL, (.int_ops = 47, .branches = 10), \
      "GP split: specular shading of one voxel, fixed point (vr_shade_fixed.h)") \
    X(SHADE_TOP, (.int_ops = 3, .branches = 1), \
      "GP split: one bit of the exponent above its top bit") \
    X(SHADE_SQUARE, (.int_ops = 6, .branches = 2), \
      "GP split: one squaring of the specular power") \
    X(SHADE_MULTIPLY, (.int_ops = 3), \
      "GP split: one multiply of the specular power (a set exponent bit)") \
    X(SHADE_DIFFUSE, (.int_ops = 55, .branches = 9), \
      "GP split, moving object: the per-frame diffuse term") \
    /* ---- blends: MIP, DEMIP, MIDA (firmware/gp/vr_blend_kernels.h) ---- */ \
    X(BLEND_START, (.fmul = 6, .loads = 3, .branches = 1), \
      "a blend ray that meets the volume: voxel-space origin and direction") \
    X(BLEND_SAMPLE, (.fadd = 4, .fmul = 3, .branches = 3), \
      "one position of a blend ray (sampled or skipped): tests, position") \
    X(BLEND_STEP_PERSPECTIVE, (.fmul = 1, .int_ops = 1, .branches = 1), \
      "perspective: a blend ray's next position and sample index") \
    X(VALUE_POINT, (.fadd = 4, .int_ops = 4, .branches = 4), \
      "a value sample: 3D level split, blend test") \
    X(VALUE_TRILERP, (.fadd = 23, .fmul = 10, .loads = 18, .load_use = 8, .int_ops = 91, .branches = 20), \
      "trilinear lookup of a value: coordinates, clamps, the 8 corners' units, 7 lerps") \
    X(VALUE_CORNER, (.loads = 1, .int_ops = 1), \
      "a value corner in a fetched unit: its float") \
    X(VALUE_LEVEL_BLEND, (.fadd = 2, .fmul = 1), \
      "blend of the two 3D levels' values") \
    X(MATERIAL, (.fadd = 3, .fmul = 1, .branches = 2), \
      "the window ramp: material of a value") \
    X(MIP_SAMPLE, (.fadd = 2, .branches = 2), \
      "ray 1: the running maximum and the saturation test") \
    X(MIP_END, (.int_ops = 1, .branches = 2), \
      "ray 1 done: the mode and k_max tests") \
    X(RAY2_START, (.fadd = 1, .loads = 1, .branches = 1), \
      "ray 2: its threshold m_max - eps, the reading test") \
    X(RAY2_TEST, (.fadd = 1, .branches = 2), \
      "ray 2 or the occluder test: is a sample of the maximum's material") \
    X(GAP_TEST, (.int_ops = 1, .branches = 1), \
      "reading B: the occluder test's position against k_max") \
    X(DEMIP_POINT, (.fadd = 3, .fmul = 3, .branches = 1), \
      "DEMIP colour: ray 2's point in object space") \
    X(DEPTH_AXIS, (.fadd = 5, .fmul = 4, .loads = 5, .branches = 3), \
      "exact depth, parallel: the view-axis depth normalised") \
    X(DEPTH_EYE, (.fadd = 8, .fmul = 4, .fsqrt = 1, .loads = 5, .branches = 3), \
      "exact depth, perspective: the distance from the eye normalised") \
    X(DEPTH_ENTRY, (.fadd = 10, .fmul = 8, .loads = 5, .branches = 2), \
      "the paper's depth: the entry's view-axis depth plus the ray length") \
    X(DEMIP_GREY, (.branches = 2), \
      "DEMIP colour: does eq. (1) apply (reading, occluder)") \
    X(EQ1, (.fadd = 5, .fmul = 3, .loads = 1, .branches = 2), \
      "eq. (1): MIP (1 - dw) + 2 dw (1 - depth), clamped") \
    X(NO_SPHERE, (.fadd = 1, .loads = 1, .branches = 1), \
      "no colour sphere: the grey to three channels") \
    X(SPHERE, (.fadd = 21, .fmul = 16, .fdiv = 1, .fsqrt = 1, .loads = 13, .branches = 4), \
      "the colour sphere at ray 2's point and eq. (2)") \
    X(MIDA_OPACITY, (.branches = 2), \
      "MIDA: the opacity's short cuts (spacing 1, material 0)") \
    X(MIDA_RAMP, (.fadd = 1, .branches = 1), \
      "MIDA: the opacity of a material below 1 test") \
    X(MIDA_POW, (.fadd = 2), \
      "MIDA: 1 - (1 - m)^spacing (its powf is a LIBM)") \
    X(MIDA_SAMPLE, (.fadd = 8, .fmul = 4, .branches = 3), \
      "MIDA: the rise of the maximum, the accumulation, early termination") \
    /* ---- object slabs (firmware/gp/vr_slab_kernels.h) ---- */ \
    X(SEGMENT, (.fadd = 2, .loads = 3, .int_ops = 4, .branches = 1), \
      "a needed texel's ray through the slab: its pixel position") \
    X(SEGMENT_START, (.fadd = 5, .fmul = 8, .fdiv = 1, .loads = 3, .int_ops = 17, .branches = 7), \
      "a segment: voxel-space ray, sample count, both searches' set-up, the end") \
    X(SEGMENT_PROBE, (.fadd = 3, .fmul = 2, .int_ops = 10, .branches = 5), \
      "a segment: one probe of the binary search for its first or last sample") \
    X(SEGMENT_HIT, (.fadd = 1, .fmul = 1, .loads = 2, .int_ops = 1), \
      "a segment with samples: the ray set at its first one") \
    X(SEGMENT_KEEP, (.branches = 4), \
      "a segment cast: does it add colour or opacity") \
    X(SEGMENT_OUT, (.loads = 1, .stores = 5), \
      "a segment kept: its partial colour stored") \
    X(MERGE, (.loads = 1, .int_ops = 2, .branches = 2), \
      "a partial colour received: its texel code checked") \
    X(MERGE_ADD, (.fadd = 5, .fmul = 4, .loads = 8, .load_use = 1, .stores = 4, .int_ops = 2), \
      "a partial colour composited behind the texel's accumulator") \
    X(NEED_COUNT, (.loads = 1, .int_ops = 7, .branches = 1), \
      "a need set received: one bit counted") \
    X(NEED_LEVEL, (.loads = 4, .int_ops = 2, .branches = 1), \
      "a need set unpacked: one 2D level's geometry") \
    X(NEED_TEST, (.loads = 1, .int_ops = 6, .branches = 2), \
      "a need set unpacked: one bit tested") \
    X(NEED_REF, (.stores = 4, .int_ops = 5), \
      "a need set unpacked: one texel's reference") \
    X(NEED_ROW, (.loads = 5, .int_ops = 8, .branches = 2), \
      "our need set packed: one texel row") \
    X(NEED_FLAG, (.loads = 1, .int_ops = 1, .branches = 2), \
      "our need set packed: one texel's flag") \
    X(NEED_SET, (.loads = 1, .stores = 1, .int_ops = 5), \
      "our need set packed: one bit set") \
    /* ---- 2DLevel, marks, RenderPixel (firmware/gp/vr_image_kernels.h, common/vr_kernels.h) ---- */ \
    X(LEVEL_PIXEL, (.fadd = 1, .loads = 1, .load_use = 1, .stores = 1, .int_ops = 2, .branches = 4), \
      "2DLevel of a pixel: the mode tests, the finest level kept") \
    X(LEVEL, (.fadd = 3, .fmul = 2, .fdiv = 1, .fsqrt = 1, .int_ops = 2), \
      "2DLevel exact: the pixel's distance from the gaze") \
    X(GAZE_LEVEL, (.fadd = 2, .int_ops = 1, .branches = 2), \
      "the acuity model: radius inside the sweet spot or past the periphery") \
    X(LEVEL_ANNULUS, (.fadd = 4, .fmul = 2, .fdiv = 3, .branches = 4), \
      "the acuity model in the annulus (atan and log2 are LIBMs)") \
    X(LEVEL_FALLOFF, (.fadd = 2, .fmul = 3, .fdiv = 1), \
      "the acuity model's Gaussian falloff (its exp is a LIBM)") \
    X(LEVEL_TABLE, (.fadd = 2, .loads = 1, .load_use = 1, .int_ops = 11, .branches = 7), \
      "2DLevel by the paper's two tables (seed 004 §4)") \
    X(LEVEL_TABLE_NEAR, (.loads = 1, .load_use = 1, .int_ops = 3), \
      "2DLevel by tables: the distance from the 2D table") \
    X(LEVEL_TABLE_FAR, (.fadd = 2, .fmul = 3, .fsqrt = 1, .int_ops = 3), \
      "2DLevel by tables: an offset beyond the 2D table") \
    X(LEVEL_TABLE_SCALED, (.fadd = 1, .fdiv = 1, .int_ops = 2), \
      "2DLevel by tables: the distance rescaled (progressive growth)") \
    X(MARK, (.fadd = 1, .loads = 1, .load_use = 1, .int_ops = 7, .branches = 4), \
      "texel marking of a pixel: its level, the second-level test") \
    X(MARK_LEVEL, (.loads = 4, .int_ops = 10, .branches = 1), \
      "texel marking: one 2D level of the pixel") \
    X(MARK_ROW, (.int_ops = 5, .branches = 3), \
      "texel marking: one texel row tried") \
    X(MARK_STORE, (.stores = 1, .int_ops = 4, .branches = 1), \
      "texel marking: a flag set in an own row") \
    X(MARK_RIGHT, (.stores = 1), \
      "texel marking: the right neighbour of a pixel between texels") \
    X(PIXEL, (.fadd = 11, .fmul = 3, .loads = 1, .load_use = 1, .stores = 3, .int_ops = 13, .branches = 10), \
      "RenderPixel: level, blend test, three bytes") \
    X(BILERP, (.fadd = 20, .fmul = 11, .loads = 16, .int_ops = 20, .branches = 4), \
      "RenderPixel: bilinear lookup of one 2D level, 3 channels") \
    X(PIXEL_BLEND, (.fadd = 6, .fmul = 3), \
      "RenderPixel: the blend of the two levels") \
    /* ---- once per sequence (firmware/gp/vr_setup_kernels.h, common/vr_kernels.h) ---- */ \
    X(TABLE_DIST, (.fadd = 2, .fmul = 3, .fsqrt = 1, .stores = 1, .int_ops = 8, .branches = 1), \
      "2DLevel tables: one entry of the distance table") \
    X(TABLE_LEVEL, (.fmul = 1, .stores = 1, .int_ops = 3, .branches = 1), \
      "2DLevel tables: one entry of the level table (+ the acuity model)") \
    X(ALPHA_ENTRY, (.fadd = 2, .fmul = 1, .stores = 1, .int_ops = 4, .branches = 1), \
      "one entry of the opacity-correction tables (its pow is a LIBM)") \
    X(VOXEL, (.fadd = 3, .fmul = 3, .fsqrt = 1, .loads = 1, .int_ops = 25, .branches = 11), \
      "level-0 voxel: neighbours, |gradient|, its value, the opacity test") \
    X(GRADIENT_AXIS, (.fadd = 1, .fmul = 1, .fdiv = 1, .loads = 2, .load_use = 1, .int_ops = 11), \
      "one central difference of the gradient") \
    X(ZERO, (.stores = 1), \
      "a transparent voxel: one zero component") \
    X(SURFACE, (.fadd = 1, .fmul = 6, .fdiv = 3, .stores = 4, .branches = 3), \
      "an opaque voxel: normal, opacity-weighted shaded colour") \
    X(SURFACE_NORMAL, (.fmul = 3, .stores = 4), \
      "specular/moving: the opacity-weighted normal") \
    X(DIFFUSE, (.fadd = 3, .fmul = 3, .branches = 1), \
      "diffuse shading: the normal's length test") \
    X(DIFFUSE_LIT, (.fadd = 4, .fmul = 4, .int_ops = 1, .branches = 2), \
      "diffuse shading of a surface voxel") \
    X(DIFFUSE_UNLIT, (.fadd = 1), \
      "diffuse shading where the normal is zero") \
    X(CLASSIFY, (.fadd = 2, .fdiv = 3, .int_ops = 1, .branches = 2), \
      "classification: the contour loop's entry, normalised colour, opacity") \
    X(CONTOUR, (.fadd = 3, .loads = 1, .load_use = 1, .int_ops = 3, .branches = 3), \
      "classification: one contour of the transfer function") \
    X(CONTOUR_RAMP, (.fadd = 2, .fmul = 2, .fdiv = 1, .loads = 2, .load_use = 2, .branches = 1), \
      "classification: a contour's ramp (non-zero gradient)") \
    X(CONTOUR_FLAT, (.fadd = 1, .loads = 1, .branches = 1), \
      "classification: a contour at zero gradient") \
    X(CONTOUR_HIT, (.fadd = 5, .fmul = 4, .loads = 3), \
      "classification: a contour that gives opacity") \
    X(FILTER_LOOP, (.int_ops = 2, .branches = 1), \
      "box filter: one child coordinate tried") \
    X(FILTER_CHILD, (.int_ops = 7), \
      "box filter: a child's address") \
    X(FILTER_ADD, (.fadd = 1, .loads = 1), \
      "box filter: one component of a child added") \
    X(FILTER_COMPONENT, (.fmul = 1, .stores = 1), \
      "box filter: one component of the output voxel") \
    X(VALUE_VOXEL, (.loads = 1, .stores = 1, .int_ops = 7, .branches = 1), \
      "blend: a level-0 value from the slab") \
    X(REDUCE_MAX, (.fadd = 1, .loads = 1, .branches = 1), \
      "blend, max pyramid: one child against the maximum") \
    X(REDUCE_OUT, (.stores = 1), \
      "blend, max pyramid: the output voxel") \
    X(VALUE_WORD, (.fadd = 1, .loads = 1, .stores = 1, .branches = 1), \
      "blend: a value's backing-store word and its cold test") \
    X(QUANTISE, (.fadd = 12, .fmul = 4, .loads = 4, .stores = 1, .int_ops = 10, .branches = 9), \
      "quantise a voxel's colour and opacity to block A") \
    X(QUANTISE_NORMAL, (.fadd = 3, .fmul = 6, .fdiv = 3, .fsqrt = 1, .loads = 3, .stores = 1, .int_ops = 18, .branches = 7), \
      "specular/moving: renormalise and pack the normal into block N")

enum {
#define VR_COST_ROW_ID(ID, ROW, WHAT) VR_ROW_##ID,
    VR_COST_ROWS(VR_COST_ROW_ID)
#undef VR_COST_ROW_ID
    VR_ROW_COUNT
};

/* The rows by name (VR_COST_TRILERP, ...) and as a table. */
#define VR_COST_ROW_CONST(ID, ROW, WHAT) static const vr_cost_row_t VR_COST_##ID = {VR_UNPAREN ROW};
#define VR_UNPAREN(...) __VA_ARGS__
VR_COST_ROWS(VR_COST_ROW_CONST)
#undef VR_COST_ROW_CONST

typedef struct {
    const char *name, *what;
    vr_cost_row_t row;
} vr_cost_entry_t;

static inline const vr_cost_entry_t *vr_cost_table(void)
{
    static const vr_cost_entry_t table[VR_ROW_COUNT] = {
#define VR_COST_ROW_ENTRY(ID, ROW, WHAT) {#ID, WHAT, {VR_UNPAREN ROW}},
        VR_COST_ROWS(VR_COST_ROW_ENTRY)
#undef VR_COST_ROW_ENTRY
    };
    return table;
}

static inline void vr_cost_add(fw_ops_t *o, const vr_cost_row_t *r, uint64_t times)
{
    o->fadd += r->fadd * times;
    o->fmul += r->fmul * times;
    o->fdiv += r->fdiv * times;
    o->fsqrt += r->fsqrt * times;
    o->loads += r->loads * times;
    o->load_use += r->load_use * times;
    o->stores += r->stores * times;
    o->int_ops += r->int_ops * times;
    o->branches += r->branches * times;
}

/* A typical ray, sample, skip and pixel as spans (what the host's planner,
 * firmware/host/fw_estimate.c, weighs a band by; kept here, beside the rows,
 * so that it follows them): an oblique parallel ray that meets the volume; a
 * sampled position with all 8 corners fetched, composited with the table's
 * opacity correction; an octree skip with three bounded axes; a pixel by the
 * tables with two bilinear lookups and its marks. */
static inline void vr_cost_typical(fw_ops_t *ray, fw_ops_t *sample, fw_ops_t *skip, fw_ops_t *pixel)
{
    static const struct {
        int which, row;
        unsigned times;
    } spans[] = {
        {0, VR_ROW_RAY, 1}, {0, VR_ROW_CLIP_AXIS, 3}, {0, VR_ROW_CLIP_END, 1}, {0, VR_ROW_RAY_START, 1},
        {0, VR_ROW_RAY_END, 1},
        {1, VR_ROW_SAMPLE, 1}, {1, VR_ROW_OCT_LEAF, 1}, {1, VR_ROW_POINT, 1}, {1, VR_ROW_TRILERP, 1},
        {1, VR_ROW_CORNER, 8}, {1, VR_ROW_COMPOSITE, 1}, {1, VR_ROW_CORRECT, 1}, {1, VR_ROW_CORRECT_LUT, 1},
        {1, VR_ROW_STEP, 1},
        {2, VR_ROW_SAMPLE, 1}, {2, VR_ROW_OCT_LEAF, 1}, {2, VR_ROW_OCT_UP, 2}, {2, VR_ROW_SKIP, 1},
        {2, VR_ROW_SKIP_EXIT, 1}, {2, VR_ROW_SKIP_DIVIDE, 3}, {2, VR_ROW_SKIP_PARALLEL, 1},
        {3, VR_ROW_LEVEL_PIXEL, 1}, {3, VR_ROW_LEVEL_TABLE, 1}, {3, VR_ROW_LEVEL_TABLE_NEAR, 1},
        {3, VR_ROW_MARK, 1}, {3, VR_ROW_MARK_LEVEL, 1}, {3, VR_ROW_MARK_ROW, 1}, {3, VR_ROW_MARK_STORE, 1},
        {3, VR_ROW_PIXEL, 1}, {3, VR_ROW_BILERP, 2}, {3, VR_ROW_PIXEL_BLEND, 1},
    };
    fw_ops_t *out[4] = {ray, sample, skip, pixel};
    const vr_cost_entry_t *t = vr_cost_table();
    for (int k = 0; k < 4; k++)
        memset(out[k], 0, sizeof *out[k]);
    for (size_t i = 0; i < sizeof spans / sizeof spans[0]; i++)
        vr_cost_add(out[spans[i].which], &t[spans[i].row].row, spans[i].times);
}

/* Production: how often each span ran. */
typedef struct {
    uint64_t n[VR_ROW_COUNT];
} vr_spans_t;

/* Tests: the operations each span stated, per row. */
typedef struct {
    fw_ops_t row[VR_ROW_COUNT];
} vr_count_t;

/* A span of row ID starts (and states its first operations). */
#define VR_SPAN(sp, cnt, ID, ...)                                                     \
    do {                                                                              \
        if (sp)                                                                       \
            (sp)->n[VR_ROW_##ID]++;                                                   \
        if (cnt)                                                                      \
            vr_cost_add(&(cnt)->row[VR_ROW_##ID], &(const vr_cost_row_t){__VA_ARGS__}, 1); \
    } while (0)
/* More operations of the current span of row ID. */
#define VR_COUNT(cnt, ID, ...)                                                        \
    do {                                                                              \
        if (cnt)                                                                      \
            vr_cost_add(&(cnt)->row[VR_ROW_##ID], &(const vr_cost_row_t){__VA_ARGS__}, 1); \
    } while (0)

/* Adds rows x span counts to *o. */
static inline void vr_spans_charge(fw_ops_t *o, const vr_spans_t *sp)
{
    const vr_cost_entry_t *t = vr_cost_table();
    for (int i = 0; i < VR_ROW_COUNT; i++)
        if (sp->n[i])
            vr_cost_add(o, &t[i].row, sp->n[i]);
}

#endif
