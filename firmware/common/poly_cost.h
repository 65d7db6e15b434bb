/* poly_cost.h: i860 operation counts of the polygon GP program's kernels, one row per straight-line span, and the counting that checks them (the scheme of vr_cost.h).
 *
 * Every kernel of firmware/gp/poly_kernels.h is cut into spans whose
 * operations do not depend on the data; each has a row here.  Production
 * counts how often each span ran (POLY_SPAN into a poly_spans_t) and charges
 * rows x counts (poly_spans_charge); beside its code each span also states
 * its operations into a poly_count_t that production leaves NULL.
 * tests/test_fw_poly_cost.c runs the kernels on real scenes and requires,
 * for every row and column, stated operations = runs x row, and every row
 * to have run.
 *
 * Counting conventions: those of vr_cost.h (facts §8), and for the exact
 * integer arithmetic of the set-up: 64-bit products and sums are done in
 * double precision (exact below 2^53), a double product taking 2 issue slots
 * of the multiplier (facts §8: one DP multiply per 2 clocks, [I]) and a
 * double add or compare one adder slot; each word of a PP stream costs its
 * assembly (2 integer ops) and its store (ENC_WORD). */
#ifndef PP5_POLY_COST_H
#define PP5_POLY_COST_H

#include "vr_cost.h"

#define POLY_COST_ROWS(X) \
    /* ---- per vertex and per triangle (transform, light, clip, project) ---- */ \
    X(TRI, (.loads = 2, .int_ops = 2, .branches = 4), "a triangle: its record, the loop, the flat, clipped and own-colour tests") \
    X(OWN_COLOUR, (.int_ops = 6), "a triangle's own colour unpacked") \
    X(PHONG_COLOUR, (.int_ops = 4), "Phong per pixel: the side's colour packed") \
    X(VERTEX, (.loads = 19, .fmul = 12, .fadd = 12, .stores = 4, .branches = 1), "a corner to clip space") \
    X(NORMAL, (.loads = 12, .fmul = 12, .fadd = 9, .fsqrt = 1, .branches = 1), "a corner's normal to camera space, its length") \
    X(NORMAL_SCALE, (.fdiv = 1, .fmul = 3), "a normal normalised") \
    X(NORMAL_STORE, (.stores = 3, .branches = 1), "Phong: the corner's normal kept") \
    X(LIGHT, (.branches = 3, .loads = 5, .fmul = 5, .fadd = 7, .stores = 2), "Gouraud: the corner's intensities, front and behind") \
    X(FACE_NORMAL, (.fadd = 18, .fmul = 18, .loads = 9, .fsqrt = 1, .branches = 1), "flat: the face normal in camera space, its length") \
    X(FACE_LIGHT, (.branches = 2, .loads = 5, .fmul = 5, .fadd = 7, .stores = 2), "flat: the face's intensities") \
    X(OUTCODE, (.loads = 18, .fmul = 12, .fadd = 13, .branches = 7, .int_ops = 7), "a corner against the 6 clip planes") \
    X(CLIP_TEST, (.int_ops = 4, .branches = 2), "trivial accept and reject") \
    X(CLIP_PLANE, (.int_ops = 3, .branches = 2), "clipping: one plane tried") \
    X(CLIP_EDGE, (.loads = 6, .fmul = 4, .fadd = 6, .branches = 7, .int_ops = 3), "clipping: an edge against the plane") \
    X(CLIP_KEEP, (.loads = 8, .stores = 8, .int_ops = 1), "clipping: an inside corner kept") \
    X(CLIP_CUT, (.fadd = 4, .fdiv = 1, .branches = 3), "clipping: an edge that crosses, its parameter") \
    X(CLIP_LERP, (.loads = 16, .fadd = 16, .fmul = 8, .stores = 8, .int_ops = 1), "clipping: the new corner") \
    X(CLIP_COPY_VERT, (.loads = 8, .stores = 8, .int_ops = 1, .branches = 1), "clipping: a corner copied back") \
    X(PROJECT, (.loads = 4, .fdiv = 1, .fmul = 7, .fadd = 2, .int_ops = 2, .stores = 5), "a corner to the screen, snapped to 1/16 pixel") \
    X(FACE, (.loads = 6, .fadd = 6, .fmul = 2, .branches = 2), "front or back (mesh_raster's area sign), the cull test") \
    X(ATTR_Z, (.loads = 1, .fadd = 2, .fmul = 1, .stores = 1, .branches = 1), "a corner's depth on the 24-bit scale") \
    X(ATTR_COLOUR, (.loads = 4, .fmul = 3, .fadd = 3, .branches = 3, .stores = 3), "Gouraud: a corner's colour, clamped to 255") \
    X(ATTR_NORMAL, (.loads = 3, .fmul = 3, .stores = 3), "Phong: a corner's normal, 2^14 = 1, reversed behind") \
    X(FLAT_COLOUR, (.loads = 4, .fmul = 3, .fadd = 6, .branches = 3, .int_ops = 7, .stores = 1), "flat: the packed colour") \
    X(FAN, (.int_ops = 2, .branches = 2, .loads = 12, .stores = 14), "a fan triangle of the clipped polygon") \
    X(SETUP, (.loads = 6, .stores = 6, .int_ops = 8, .fmul = 4, .fadd = 1, .branches = 1), "set-up: corners, the exact area") \
    X(SETUP_EDGES, (.fadd = 1, .branches = 24, .int_ops = 51, .stores = 4, .loads = 2), "set-up: sign, owned edges, pixel box") \
    X(SETUP_PLANES, (.int_ops = 10, .stores = 6, .fmul = 8, .fadd = 1, .fdiv = 1), "set-up: regions, corner 0, 1/area") \
    X(PLANE_SETUP, (.loads = 3, .fadd = 4, .fmul = 6, .stores = 3), "set-up: one attribute's plane") \
    /* ---- sorting into regions ---- */ \
    X(BIN_COUNT, (.loads = 1, .load_use = 1, .stores = 1, .int_ops = 4, .branches = 1), "sort: a (triangle, region) pair counted") \
    X(BIN_PREFIX, (.loads = 1, .stores = 3, .int_ops = 2, .branches = 1), "sort: a region's start") \
    X(BIN_FILL, (.loads = 2, .load_use = 1, .stores = 2, .int_ops = 5, .branches = 1), "sort: a pair's triangle index stored") \
    X(BIN_TRI, (.loads = 4, .int_ops = 2, .branches = 2), "sort: a triangle's region rows") \
    X(GROW_COPY, (.loads = 1, .stores = 1, .int_ops = 1, .branches = 1), "a word of a full triangle table moved to a larger one") \
    /* ---- a triangle in a region: its PP stream ---- */ \
    X(REGION, (.loads = 3, .int_ops = 6, .branches = 2), "a region's stream: its bin, its origin") \
    X(ENC_TRI, (.loads = 10, .branches = 1), "a triangle in a region") \
    X(ENC_EDGE, (.int_ops = 16, .fmul = 8, .fadd = 11, .branches = 6, .loads = 1), "an edge: exact coefficients, its sign at the region's corners") \
    X(ENC_OUTSIDE, (.branches = 1), "an edge that leaves the region outside") \
    X(ENC_EDGE_TEST, (.branches = 2, .int_ops = 1), "an edge: sent or not") \
    X(ENC_EDGE_EMIT, (.int_ops = 1), "an edge sent: F mod 2^32") \
    X(QEE_PLANE, (.loads = 5, .int_ops = 2, .fadd = 6, .fmul = 8), "a plane at the region's first pixel centre") \
    X(QEE_TRY, (.fmul = 4, .int_ops = 2, .fadd = 2, .branches = 4), "a plane: do its gradients fit 31 bits at this shift") \
    X(QEE_SHIFT_DOWN, (.int_ops = 1, .branches = 1), "a plane: one fraction bit fewer") \
    X(QEE_COEFFS, (.fadd = 7, .branches = 4, .int_ops = 4, .fmul = 10), "a plane's QEE coefficients") \
    X(ENC_Z, (.branches = 2), "the depth test sent") \
    X(ENC_FLAT, (.loads = 1), "flat: the colour sent") \
    X(ENC_CHANNEL, (.int_ops = 1, .branches = 2), "a colour or normal channel sent") \
    X(ENC_PHONG_FLAGS, (.loads = 1, .branches = 1), "Phong: the covered and back bits sent, the colour test") \
    X(ENC_PHONG_COLOUR, (.loads = 1), "Phong per pixel: the triangle's colour sent") \
    X(ENC_WORD, (.int_ops = 2, .stores = 1), "a word of a PP stream assembled and stored") \
    /* ---- gaze-directed frames: the variable-resolution Z-buffer ---- */ \
    X(VRZ_LEVEL_FAR, (.fadd = 2, .branches = 2), "2DLevel: the periphery test (gaze_level's own value past it)") \
    X(VRZ_TILE, (.int_ops = 24, .loads = 4, .branches = 12), "plan: a level tile's texels and the pixels that read them") \
    X(VRZ_TILE_LEVELS, (.int_ops = 6, .fadd = 27, .fmul = 4, .fsqrt = 2, .loads = 3, .branches = 6), "plan: a tile's nearest and farthest 2DLevel, the populated test") \
    X(VRZ_SLOT, (.stores = 4, .int_ops = 3, .branches = 1), "plan: a tile's region slot (or none)") \
    X(VRZ_TRI, (.loads = 6, .int_ops = 8, .branches = 8), "sort: a triangle's snapped box") \
    X(VRZ_LEVEL_BOX, (.int_ops = 28, .loads = 2, .branches = 6), "sort: a triangle's tiles on one level") \
    X(VRZ_BIN_TILE, (.int_ops = 4, .loads = 1, .load_use = 1, .branches = 2), "sort: a tile of the box, its slot looked up") \
    X(ENC_LEVEL, (.loads = 16, .stores = 16, .fadd = 4, .fmul = 2), "a triangle on a coarse level: the record, corner 0") \
    X(ENC_LEVEL_PLANE, (.loads = 2, .fmul = 2, .stores = 2), "a triangle on a coarse level: a plane's gradients") \
    X(ENC_LEVEL_EDGE, (.fmul = 2, .int_ops = 3, .branches = 1), "an edge on a coarse level: floor(F / 2^l)") \
    X(VRZ_BAND_PIXEL, (.int_ops = 4, .fadd = 3, .fmul = 2, .fsqrt = 1, .stores = 1, .branches = 1), "resample: a pixel's distance from the gaze and its 2DLevel stored") \
    X(VRZ_BAND_PIXEL_TABLED, (.int_ops = 3, .stores = 1, .branches = 1), "resample: a pixel's 2DLevel by the tables stored") \
    X(VRZ_EXPECT, (.loads = 3, .int_ops = 6, .branches = 3), "a region's texel rows this GP reads (counted once per region)") \
    X(VRZ_BOX, (.loads = 3, .int_ops = 14, .stores = 6, .branches = 3), "the last GP: a GP's texel box of a region requested") \
    X(VRZ_TEXEL_ROW, (.loads = 2, .int_ops = 6, .branches = 1), "resample: a received texel row's place") \
    X(VRZ_BILERP, (.int_ops = 50, .fmul = 23, .fadd = 20, .loads = 8, .branches = 4), "resample: bilinear lookup in one level") \
    X(VRZ_PIXEL_BLEND, (.fadd = 6, .fmul = 3), "resample: a pixel between two levels") \
    X(VRZ_PIXEL, (.int_ops = 12, .loads = 1, .load_use = 1, .branches = 10, .fadd = 11, .fmul = 3, .stores = 3), "resample: a pixel (RenderPixel)") \
    X(VRZ_SECTION, (.int_ops = 8, .stores = 6, .branches = 2), "resample: a section of the band sent to the frame buffer")

enum {
#define POLY_COST_ROW_ID(ID, ROW, WHAT) POLY_ROW_##ID,
    POLY_COST_ROWS(POLY_COST_ROW_ID)
#undef POLY_COST_ROW_ID
    POLY_ROW_COUNT
};

static inline const vr_cost_entry_t *poly_cost_table(void)
{
    static const vr_cost_entry_t table[POLY_ROW_COUNT] = {
#define POLY_COST_ROW_ENTRY(ID, ROW, WHAT) {#ID, WHAT, {VR_UNPAREN ROW}},
        POLY_COST_ROWS(POLY_COST_ROW_ENTRY)
#undef POLY_COST_ROW_ENTRY
    };
    return table;
}

typedef struct {
    uint64_t n[POLY_ROW_COUNT];
} poly_spans_t;

typedef struct {
    fw_ops_t row[POLY_ROW_COUNT];
} poly_count_t;

/* Production's operation count: none (a typed NULL for the macros). */
#define POLY_NO_COUNT ((poly_count_t *)NULL)

/* A span of row ID ran once (and states its operations). */
#define POLY_SPAN(sp, cnt, ID, ...) POLY_SPANS(sp, cnt, ID, 1, __VA_ARGS__)
/* ... `times` times. */
#define POLY_SPANS(sp, cnt, ID, times, ...)                                               \
    do {                                                                                  \
        uint64_t poly_times_ = (times);                                                   \
        if (sp)                                                                           \
            (sp)->n[POLY_ROW_##ID] += poly_times_;                                        \
        if (cnt)                                                                          \
            vr_cost_add(&(cnt)->row[POLY_ROW_##ID], &(const vr_cost_row_t){__VA_ARGS__},  \
                        poly_times_);                                                     \
    } while (0)

/* Adds rows x span counts to *o and clears the counts. */
static inline void poly_spans_charge(fw_ops_t *o, poly_spans_t *sp)
{
    const vr_cost_entry_t *t = poly_cost_table();
    for (int i = 0; i < POLY_ROW_COUNT; i++)
        if (sp->n[i])
            vr_cost_add(o, &t[i].row, sp->n[i]);
    memset(sp, 0, sizeof *sp);
}

#endif
