/* vr_cast_kernels.h: the ray caster's kernels (TraceRay of render/raycast.c on fetched units, octree skipping, level blending, opacity correction), counted by spans of common/vr_cost.h.
 *
 * The GP program (vr_cast.c) and tests/test_fw_cost.c both call these.
 * Production passes span counters (vr_spans_t) and no operation count
 * (cnt = NULL: the VR_COUNT statements fold away); the test passes both and
 * checks each row.  Accesses to the big blocks (fetched units, octree bit
 * grids, texel rows and parked rays) are declared to the data cache through
 * the vr_mem_t; the tables inside the state (u8_to_f, alpha_lut) are left as
 * hits.  Paper: seed 004 §4 last paragraph, §5 (octree), §6. */
#ifndef PP5_VR_CAST_KERNELS_H
#define PP5_VR_CAST_KERNELS_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "vr_gp_internal.h"

/* Where kernels declare their data-cache accesses (production and tests
 * alike: the outcome is charged).  NULL: none declared. */
typedef struct {
    gp_t *gp;
    fw_ops_t *ops;
} vr_mem_t;

static inline void vr_mem_access(const vr_mem_t *m, const void *block, size_t offset, size_t bytes,
                                 int is_store)
{
    if (m)
        fw_dcache_access(m->gp, m->ops, block, offset, bytes, is_store);
}

/* The per-pass constants of the rays of one 2D level (raycast_trace's
 * set-up, which depends on the level and the frame only: computed once per
 * pass, as firmware would). */
typedef struct {
    bool perspective;
    float step, offset, base, growth, top, level3d;
} vr_ray_consts_t;

static inline void vr_ray_consts(const vr_state_t *s, int level2d, vr_ray_consts_t *k)
{
    const vr_config_t *c = &s->cfg;
    k->perspective = s->fr.projection != 0;
    k->step = c->sample_step > 0.0f ? c->sample_step : 1.0f;
    k->offset = log2f(k->step);
    k->base = k->step * (float)(1 << level2d);
    k->growth = 1.0f + k->base / s->fr.eye_distance;
    k->top = (float)(c->levels - 1);
    float level3d = log2f(k->base) - k->offset;
    k->level3d = level3d < 0.0f ? 0.0f : (level3d > k->top ? k->top : level3d);
}

/* octree_empty_node (render/octree.c) on the bit grids: -1 when the leaf
 * cell of p is occupied, else the height h of the largest empty node and its
 * bounds.  Spans: OCT_LEAF (the caller's), OCT_UP per step up, OCT_TOP when
 * the steps reach the top of the pyramid, SKIP (the bounds; the caller's
 * SKIP_EXIT finds where the ray leaves them). */
static inline int vr_oct_empty_node(const vr_state_t *s, int n, bool exact, const float p[3],
                                    float lo[3], float hi[3], const vr_mem_t *mem, vr_spans_t *sp,
                                    vr_count_t *cnt)
{
    if (n >= s->cfg.levels)
        n = s->cfg.levels - 1;
    const octgrid_t *g = exact ? &s->exact[n] : &s->grid[n];
    const bits_t *b0 = &g->occ[0];
    int c[3], dims[3] = {b0->nx, b0->ny, b0->nz};
    for (int a = 0; a < 3; a++) {
        float q = vr_level_coord(p[a], n);
        float f = floorf(q);
        c[a] = f < 0.0f ? 0 : (f >= (float)dims[a] ? dims[a] - 1 : (int)f);
    }
    size_t w0 = ((size_t)c[2] * b0->ny + c[1]) * b0->wpr + (c[0] >> 6);
    vr_mem_access(mem, b0->w, w0 * 8, 8, 0);
    /* n against the levels (compare); the grid (select, address); its dims
     * (3 loads) and 2^-n (1 load); per axis the level coordinate (add,
     * multiply, subtract), floor, the clamp (2 compares, a conversion of the
     * dim, the conversion of f); the word: wpr and w loads, index (2
     * multiplies, 2 adds, a shift), its load (the shift needs it at once),
     * bit (mask, shift, and), the test */
    VR_COUNT(cnt, OCT_LEAF, .int_ops = 1 + 2 + 3 * 3 + 5 + 3, .branches = 1 + 1 + 3 * 2 + 1,
             .loads = 3 + 1 + 2 + 1, .load_use = 1, .fadd = 3 * 4, .fmul = 3);
    if ((b0->w[w0] >> (c[0] & 63)) & 1u)
        return -1;
    int h = 0;
    VR_COUNT(cnt, SKIP, .loads = 1);      /* the pyramid's height */
    for (;;) {
        int up = h + 1;
        if (up >= g->heights) {
            VR_SPAN(sp, cnt, OCT_TOP, .int_ops = 2, .branches = 1);   /* the loop's last test */
            break;
        }
        const bits_t *b = &g->occ[up];
        int x = c[0] >> up, y = c[1] >> up, z = c[2] >> up;
        size_t w = ((size_t)z * b->ny + y) * b->wpr + (x >> 6);
        vr_mem_access(mem, b->w, w * 8, 8, 0);
        /* the loop test (h + 1, compare); the grid's address; 3 shifts; ny,
         * wpr and w loads; index as above (5), the word (used at once), bit
         * (3), the test (h = up is a move in its delay slot) */
        VR_SPAN(sp, cnt, OCT_UP, .int_ops = 2 + 1 + 3 + 5 + 3, .branches = 1 + 1, .loads = 3 + 1,
                .load_use = 1);
        if ((b->w[w] >> (x & 63)) & 1u)
            break;
        h = up;
    }
    float scale = (float)(1 << n);
    for (int a = 0; a < 3; a++) {
        int first = (c[a] >> h) << h;
        int last = first + (1 << h);
        lo[a] = first == 0 ? -INFINITY : ((float)first + 0.5f) * scale - 0.5f;
        hi[a] = last >= dims[a] ? INFINITY : ((float)last + 0.5f) * scale - 0.5f;
    }
    /* scale (shift, conversion), 1 << h; per axis first (2 shifts), last
     * (add), lo (zero test, conversion, add, multiply, subtract), hi
     * (compare, conversion, add, multiply, subtract) */
    VR_SPAN(sp, cnt, SKIP, .int_ops = 2 + 1 + 3 * (2 + 1 + 1 + 2), .branches = 3 * 2, .fadd = 3 * 4,
            .fmul = 3 * 2);
    return h;
}

/* The four bytes of word `word` of a held unit as floats: a CORNER span. */
static inline void vr_corner_word(const vr_state_t *s, const uint32_t *b, size_t word, float *out,
                                  vr_spans_t *sp, vr_count_t *cnt)
{
    uint32_t w = b[word];
    out[0] = s->u8_to_f[w & 255u];
    out[1] = s->u8_to_f[(w >> 8) & 255u];
    out[2] = s->u8_to_f[(w >> 16) & 255u];
    out[3] = s->u8_to_f[w >> 24];
    /* the word's address (shift), its load (the masks need it at once), 3
     * shifts and 3 masks, 4 table indices (shifts) and loads */
    VR_SPAN(sp, cnt, CORNER, .int_ops = 1 + 6 + 4, .loads = 1 + 4, .load_use = 1);
}

/* A corner of a trilinear lookup in unit `id` at word `word` of it: the four
 * bytes as floats (0 when the unit is empty and so never fetched).  Its
 * unit lookup is TRILERP's; a held unit's word is a CORNER span. */
static inline void vr_corner(const vr_state_t *s, int id, size_t word, float *out,
                             const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    const uint32_t *b = s->cache[id];
    /* the pointer (shift, load: the test needs it at once), the test */
    VR_COUNT(cnt, TRILERP, .int_ops = 1, .loads = 1, .load_use = 1, .branches = 1);
    if (!b) {
        out[0] = out[1] = out[2] = out[3] = 0.0f;
        return;
    }
    vr_mem_access(mem, b, word * 4, 4, 0);
    vr_corner_word(s, b, word, out, sp, cnt);
}

/* The eight corners when they all lie in one held unit (the usual case):
 * the same operations and the same data-cache lookups, in the same order,
 * as eight vr_corner calls; the lookups are declared in one call (host
 * speed only). */
static inline void vr_corners_one_unit(const vr_state_t *s, const uint32_t *b,
                                       const size_t word[8], float c[8][4], const vr_mem_t *mem,
                                       vr_spans_t *sp, vr_count_t *cnt)
{
    if (mem) {
        size_t offset[8];
        for (int k = 0; k < 8; k++)
            offset[k] = word[k] * 4;
        fw_dcache_access_n(mem->gp, mem->ops, b, offset, 8, 4, 0);
    }
    for (int k = 0; k < 8; k++) {
        /* vr_corner's pointer test */
        VR_COUNT(cnt, TRILERP, .int_ops = 1, .loads = 1, .load_use = 1, .branches = 1);
        vr_corner_word(s, b, word[k], c[k], sp, cnt);
    }
}

static inline int vr_clampi(int v, int n)
{
    return v < 0 ? 0 : (v >= n ? n - 1 : v);
}

/* mip3d_trilerp of 4 components at level-0 position p in 3D level n
 * (render/mip3d.h), from the units in the cache.  Span TRILERP (+ CORNER per
 * corner in a held unit). */
static inline void vr_trilerp(const vr_state_t *s, int n, const float p[3], float *out,
                              const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_level_geom_t *L = &s->geom[n];
    const vr_unit_geom_t *u = &s->unit[n];
    float x = vr_level_coord(p[0], n), y = vr_level_coord(p[1], n), z = vr_level_coord(p[2], n);
    float fx = floorf(x), fy = floorf(y), fz = floorf(z);
    float wx = x - fx, wy = y - fy, wz = z - fz;
    int x0 = (int)fx, y0 = (int)fy, z0 = (int)fz;
    int cx[2] = {vr_clampi(x0, L->nx), vr_clampi(x0 + 1, L->nx)};
    int cy[2] = {vr_clampi(y0, L->ny), vr_clampi(y0 + 1, L->ny)};
    int cz[2] = {vr_clampi(z0, L->nz), vr_clampi(z0 + 1, L->nz)};
    /* 3 level coordinates (add, multiply by 2^-n from a table, subtract);
     * floors, weights, conversions, 3 increments; the level's dims (3 loads)
     * and 6 clamps (2 compares each) */
    VR_SPAN(sp, cnt, TRILERP, .fadd = 3 * 2 + 3, .fmul = 3, .loads = 1 + 3, .int_ops = 3 + 3 + 3 + 6 * 2,
            .branches = 6 * 2);
    /* Each corner coordinate's unit and offset inside it (per axis 2:
     * divide by the unit edge, multiply back, subtract), then the 4 (z, y)
     * rows: unit id base and word offset. */
    int ux[2], lx[2], uy[2], ly[2], uz[2], lz[2];
    for (int k = 0; k < 2; k++) {
        ux[k] = cx[k] / u->ux;
        lx[k] = cx[k] - ux[k] * u->ux;
        uy[k] = cy[k] / u->uy;
        ly[k] = cy[k] - uy[k] * u->uy;
        uz[k] = cz[k] / u->uz;
        lz[k] = cz[k] - uz[k] * u->uz;
    }
    int base = s->unit_base[n];
    float c[8][4];
    const uint32_t *one = NULL;      /* the unit of all eight corners, if they share a held one */
    if (ux[0] == ux[1] && uy[0] == uy[1] && uz[0] == uz[1])
        one = s->cache[base + (uz[0] * u->ugy + uy[0]) * u->ugx + ux[0]];
    if (one) {
        size_t word[8];
        for (int dz = 0; dz < 2; dz++)
            for (int dy = 0; dy < 2; dy++) {
                size_t woff = ((size_t)lz[dz] * u->uy + ly[dy]) * u->ux;
                for (int dx = 0; dx < 2; dx++)
                    word[(dz * 2 + dy) * 2 + dx] = woff + (size_t)lx[dx];
            }
        vr_corners_one_unit(s, one, word, c, mem, sp, cnt);
    } else {
        for (int dz = 0; dz < 2; dz++)
            for (int dy = 0; dy < 2; dy++) {
                int row = base + (uz[dz] * u->ugy + uy[dy]) * u->ugx;
                size_t woff = ((size_t)lz[dz] * u->uy + ly[dy]) * u->ux;
                for (int dx = 0; dx < 2; dx++)
                    vr_corner(s, row + ux[dx], woff + (size_t)lx[dx], c[(dz * 2 + dy) * 2 + dx],
                              mem, sp, cnt);
            }
    }
    /* 6 x (divide, multiply, subtract) with the unit edges loaded (3); the
     * base, ugy, ugx loads; 4 rows x (2 multiplies, 2 adds) for the id and
     * (2 multiplies, 1 add) for the offset; 8 x 2 adds for the corner */
    VR_COUNT(cnt, TRILERP, .int_ops = 6 * 3 + 4 * 4 + 4 * 3 + 8 * 2, .loads = 3 + 3);
    for (int k = 0; k < 4; k++) {
        float a = c[0][k] + wx * (c[1][k] - c[0][k]);
        float b = c[2][k] + wx * (c[3][k] - c[2][k]);
        float cc = c[4][k] + wx * (c[5][k] - c[4][k]);
        float d = c[6][k] + wx * (c[7][k] - c[6][k]);
        float e = a + wy * (b - a);
        float f = cc + wy * (d - cc);
        out[k] = e + wz * (f - e);
    }
    VR_COUNT(cnt, TRILERP, .fadd = 28 * 2, .fmul = 28);   /* 7 lerps x 4 components */
}

/* A 3D level between the mip map's levels, clamped to them: the level
 * below (*lo) and the weight of the one above (the caller charges the
 * clamp, the conversion and t in its POINT span). */
static inline float vr_level_split(const vr_state_t *s, float level3d, int *lo)
{
    float top = (float)(s->cfg.levels - 1);
    if (level3d < 0.0f)
        level3d = 0.0f;
    if (level3d > top)
        level3d = top;
    *lo = (int)level3d;
    return level3d - (float)*lo;
}

/* The sample at p between 3D levels (raycast.c's sample): one or two
 * trilinear lookups.  Spans POINT (+ TRILERP, LEVEL_BLEND). */
static inline void vr_sample3d(const vr_state_t *s, float level3d, const float p[3], float *out,
                               const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    int lo;
    float t = vr_level_split(s, level3d, &lo);
    /* the clamp (2 compares), the conversions, t; the blend test (compare, lo
     * + 1 against the levels) */
    VR_SPAN(sp, cnt, POINT, .fadd = 2 + 1 + 1, .branches = 2 + 2, .int_ops = 2 + 2);
    vr_trilerp(s, lo, p, out, mem, sp, cnt);
    if (t > 0.0f && lo + 1 < s->cfg.levels) {
        float hi[4];
        vr_trilerp(s, lo + 1, p, hi, mem, sp, cnt);
        for (int k = 0; k < 4; k++)
            out[k] += t * (hi[k] - out[k]);
        VR_SPAN(sp, cnt, LEVEL_BLEND, .fadd = 4 * 2, .fmul = 4);
    }
}

/* Opacity correction (raycast.c correct_alpha): the 2D level's table, or
 * powf for perspective and levels past the tables.  Spans: CORRECT_LUT or
 * CORRECT_POW (+ LIBM) when a < 1 (the a >= 1 test is CORRECT's). */
static inline float vr_correct_alpha(const vr_state_t *s, int level2d, bool perspective,
                                     float spacing, float a, vr_spans_t *sp, vr_count_t *cnt)
{
    if (a >= 1.0f)
        return 1.0f;
    if (perspective || level2d >= VR_LUT_LEVELS) {
        VR_SPAN(sp, cnt, CORRECT_POW, .branches = 2, .int_ops = 1, .fadd = 2);
        vr_libm(sp, cnt);
        return 1.0f - powf(1.0f - a, spacing);
    }
    float x = a * (float)VR_LUT_SIZE;
    int i = (int)x;
    if (i >= VR_LUT_SIZE)
        i = VR_LUT_SIZE - 1;
    float f = x - (float)i;
    const float *t = s->alpha_lut[level2d];
    /* the two tests (projection, level: compare); x (multiply), i
     * (conversion, compare), f (conversion, subtract); the level's table
     * (multiply, add) and t[i] (shift, load), t[i + 1] (load, used at once),
     * the lerp */
    VR_SPAN(sp, cnt, CORRECT_LUT, .branches = 2 + 1, .int_ops = 1 + 2 + 1 + 2 + 1, .fmul = 1 + 1,
            .fadd = 1 + 2, .loads = 2, .load_use = 1);
    return t[i] + f * (t[i + 1] - t[i]);
}

/* Where a ray's colour and parked state live: texel idx of 2D level m. */
typedef struct {
    int m;
    size_t idx;
} vr_ray_slot_t;

/* A ray being traced (raycast_trace's locals). */
typedef struct {
    float ov[3], dv[3];           /* origin and direction in voxel space */
    float t0, t1, t;              /* clipped range, current ray parameter */
    float spacing, level3d;
    float acc[3], acc_a;          /* colour and opacity so far */
    long k;                       /* sample index (parallel) */
} vr_ray_t;

/* The ray of pixel (px, py) clipped to the volume and, when resumed, its
 * parked state.  Returns false when it misses the volume (a new ray's texel
 * is then black). */
static inline bool vr_ray_begin(const vr_state_t *s, const vr_ray_consts_t *rc, float px, float py,
                                vr_ray_slot_t slot, bool resume, vr_ray_t *r, const vr_mem_t *mem,
                                vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_config_t *c = &s->cfg;
    const vr_frame_t *f = &s->fr;
    float *rgb = s->texel[slot.m] + slot.idx * 3;
    float o[3], d[3];
    vr_camera_ray(f, c->width, c->height, px, py, o, d, sp, cnt);
    if (!vr_clip_box(o, d, f->box_hi, &r->t0, &r->t1, sp, cnt)) {
        if (!resume) {
            rgb[0] = rgb[1] = rgb[2] = 0.0f;
            vr_mem_access(mem, s->texel[slot.m], slot.idx * 12, 12, 1);
            VR_SPAN(sp, cnt, RAY_MISS, .branches = 1, .stores = 3);
        }
        return false;
    }
    for (int k = 0; k < 3; k++) {
        r->ov[k] = o[k] * c->inv_spacing[k];
        r->dv[k] = d[k] * c->inv_spacing[k];
    }
    r->acc[0] = r->acc[1] = r->acc[2] = 0.0f;
    r->acc_a = 0.0f;
    r->k = 0;
    r->t = r->t0;
    /* voxel-space origin and direction (3 loads, 6 multiplies); the
     * projection and resume tests */
    VR_SPAN(sp, cnt, RAY_START, .loads = 3, .fmul = 6, .branches = 2);
    if (rc->perspective) {
        if (r->t < 1e-3f)
            r->t = 1e-3f;
        VR_SPAN(sp, cnt, RAY_NEAR, .fadd = 1, .branches = 1);
    }
    if (resume) {
        r->acc[0] = rgb[0];
        r->acc[1] = rgb[1];
        r->acc[2] = rgb[2];
        r->acc_a = s->ray_a[slot.m][slot.idx];
        r->k = s->ray_k[slot.m][slot.idx];
        /* A parked ray's t is t0 + k base (parallel) or the product of its
         * steps (perspective), exactly as stored. */
        r->t = rc->perspective ? s->ray_t[slot.m][slot.idx] : r->t0 + (float)r->k * rc->base;
        vr_mem_access(mem, s->texel[slot.m], slot.idx * 12, 12, 0);
        vr_mem_access(mem, s->ray_a[slot.m], slot.idx * 4, 4, 0);
        vr_mem_access(mem, s->ray_k[slot.m], slot.idx * 4, 4, 0);
        vr_mem_access(mem, s->ray_t[slot.m], slot.idx * 4, 4, 0);
        /* colour (3), opacity, index and t loads (t is loaded in both
         * projections and one of the two values kept: both counted, with the
         * conversion, multiply and add of t0 + k base) */
        VR_SPAN(sp, cnt, RAY_RESUME, .loads = 3 + 3, .int_ops = 1, .fmul = 1, .fadd = 1, .branches = 1);
    }
    r->spacing = rc->base;
    r->level3d = rc->level3d;
    return true;
}

/* The ray's end (done) or its parking at the end of a depth segment. */
static inline void vr_ray_store(const vr_state_t *s, vr_ray_slot_t slot, const vr_ray_t *r, bool park,
                                const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    float *rgb = s->texel[slot.m] + slot.idx * 3;
    rgb[0] = r->acc[0];
    rgb[1] = r->acc[1];
    rgb[2] = r->acc[2];
    vr_mem_access(mem, s->texel[slot.m], slot.idx * 12, 12, 1);
    if (!park) {
        VR_SPAN(sp, cnt, RAY_END, .stores = 3);
        return;
    }
    s->ray_a[slot.m][slot.idx] = r->acc_a;
    s->ray_k[slot.m][slot.idx] = (int32_t)r->k;
    s->ray_t[slot.m][slot.idx] = r->t;
    vr_mem_access(mem, s->ray_a[slot.m], slot.idx * 4, 4, 1);
    vr_mem_access(mem, s->ray_k[slot.m], slot.idx * 4, 4, 1);
    vr_mem_access(mem, s->ray_t[slot.m], slot.idx * 4, 4, 1);
    VR_SPAN(sp, cnt, RAY_PARK, .stores = 6);
}

/* An empty octree node at 3D level n with bounds lo..hi: the ray jumps to
 * where it leaves the node.  Returns false when the ray leaves the volume
 * there (the ray is done). */
static inline bool vr_ray_skip(const vr_ray_consts_t *rc, int n, const float lo[3], const float hi[3],
                               vr_ray_t *r, vr_spans_t *sp, vr_count_t *cnt, uint64_t *skipped)
{
    float t_exit = INFINITY;
    for (int a = 0; a < 3; a++) {
        float te = INFINITY;
        if (r->dv[a] > 0.0f && isfinite(hi[a])) {
            te = (hi[a] - r->ov[a]) / r->dv[a];
            VR_SPAN(sp, cnt, SKIP_DIVIDE, .fadd = 1, .fdiv = 1);
        } else if (r->dv[a] < 0.0f && isfinite(lo[a])) {
            te = (lo[a] - r->ov[a]) / r->dv[a];
            VR_SPAN(sp, cnt, SKIP_DIVIDE, .fadd = 1, .fdiv = 1);
        }
        if (te < t_exit)
            t_exit = te;
    }
    /* per axis the two direction tests with their isfinite (all counted)
     * and the minimum; the test against t1 */
    VR_SPAN(sp, cnt, SKIP_EXIT, .fadd = 3 * 3 + 1, .int_ops = 3 * 2, .branches = 3 * 5 + 1);
    if (!(t_exit <= r->t1))
        return false;
    t_exit -= 1e-3f;
    if (rc->perspective) {
        float t_level = exp2f((float)(n + 1) + rc->offset) / (rc->growth - 1.0f);
        if (n + 1 <= (int)rc->top && t_level < t_exit)
            t_exit = t_level;
        vr_libm(sp, cnt);
        /* t_exit - 1e-3; n + 1 (add, conversion) + offset; the divide; the
         * two tests (compare each; (int)top is the pass's); the loop back */
        VR_SPAN(sp, cnt, SKIP_PERSPECTIVE, .fadd = 1 + 1 + 1, .int_ops = 2 + 1, .fdiv = 1, .branches = 2 + 1);
        do {
            r->t *= rc->growth;
            (*skipped)++;
            VR_SPAN(sp, cnt, SKIP_STEP, .fmul = 1, .fadd = 2, .branches = 2);
        } while (r->t < t_exit && r->t <= r->t1);
    } else {
        long k_new = (long)ceilf((t_exit - r->t0) / rc->base);
        if (k_new <= r->k)
            k_new = r->k + 1;
        *skipped += (uint64_t)(k_new - r->k);
        r->k = k_new;
        r->t = r->t0 + (float)r->k * rc->base;
        /* t_exit - 1e-3; (t_exit - t0) / base, ceil, conversion; the compare
         * with k (and k + 1); t (conversion, multiply, add); the loop back */
        VR_SPAN(sp, cnt, SKIP_PARALLEL, .fadd = 1 + 1 + 1, .fdiv = 1, .int_ops = 2 + 2 + 1, .fmul = 1,
                .branches = 1 + 1);
    }
    return true;
}

/* The sample at the ray's position p: looked up, corrected for the
 * spacing and composited.  Returns true when the ray is opaque enough to
 * stop (early termination). */
static inline bool vr_ray_sample(const vr_state_t *s, const vr_ray_consts_t *rc, int level2d,
                                 const float p[3], vr_ray_t *r, const vr_mem_t *mem, vr_spans_t *sp,
                                 vr_count_t *cnt)
{
    float comp[4];
    vr_sample3d(s, r->level3d, p, comp, mem, sp, cnt);
    float col[3] = {comp[0], comp[1], comp[2]};
    float a = comp[3];
    VR_COUNT(cnt, POINT, .fadd = 1, .branches = 1);   /* a > 0 */
    if (!(a > 0.0f))
        return false;
    /* spacing != 1; 1 - acc_a; 3 colour and 1 opacity multiply-adds; the
     * termination test */
    VR_SPAN(sp, cnt, COMPOSITE, .fadd = 1 + 1 + 4 + 1, .fmul = 4, .branches = 1 + 1);
    if (r->spacing != 1.0f) {
        /* a >= 1; ac / a and the colour scaled */
        VR_SPAN(sp, cnt, CORRECT, .fadd = 1, .branches = 1, .fdiv = 1, .fmul = 3);
        float ac = vr_correct_alpha(s, level2d, rc->perspective, r->spacing, a, sp, cnt);
        float scale = ac / a;
        col[0] *= scale;
        col[1] *= scale;
        col[2] *= scale;
        a = ac;
    }
    float tt = 1.0f - r->acc_a;
    r->acc[0] += tt * col[0];
    r->acc[1] += tt * col[1];
    r->acc[2] += tt * col[2];
    r->acc_a += tt * a;
    return r->acc_a >= s->cfg.early_termination;
}

/* The ray's march from its current position: samples with ray parameter
 * t < t_stop, octree skips, early termination.  Returns true when the ray
 * is done, false when it reached t_stop (the caller parks it or, for a slab
 * segment, keeps its partial colour). */
static inline bool vr_ray_march(const vr_state_t *s, const vr_ray_consts_t *rc, int level2d,
                                vr_ray_t *r, float t_stop, const vr_mem_t *mem, vr_spans_t *sp,
                                vr_count_t *cnt, uint64_t *skipped)
{
    while (r->t <= r->t1) {
        /* the loop test, the segment test, the projection test, the position,
         * the octree test */
        VR_SPAN(sp, cnt, SAMPLE, .fadd = 2 + 3, .fmul = 3, .branches = 2 + 1 + 1);
        if (r->t >= t_stop)
            return false;
        if (rc->perspective) {
            r->spacing = r->t * (rc->growth - 1.0f);
            float level3d = log2f(r->spacing) - rc->offset;
            r->level3d = level3d < 0.0f ? 0.0f : (level3d > rc->top ? rc->top : level3d);
            vr_libm(sp, cnt);
            VR_SPAN(sp, cnt, SAMPLE_PERSPECTIVE, .fmul = 1, .fadd = 1 + 2, .branches = 2);
        }
        float p[3] = {r->ov[0] + r->t * r->dv[0], r->ov[1] + r->t * r->dv[1],
                      r->ov[2] + r->t * r->dv[2]};
        if (s->cfg.use_octree) {
            float lo[3], hi[3];
            int n = (int)r->level3d;
            /* n (conversion), exact (conversion, compare); the result's test */
            VR_SPAN(sp, cnt, OCT_LEAF, .int_ops = 2 + 1, .fadd = 1, .branches = 1);
            if (vr_oct_empty_node(s, n, r->level3d == (float)n, p, lo, hi, mem, sp, cnt) >= 0) {
                if (!vr_ray_skip(rc, n, lo, hi, r, sp, cnt, skipped))
                    return true;
                continue;
            }
        }
        if (vr_ray_sample(s, rc, level2d, p, r, mem, sp, cnt))
            return true;
        if (rc->perspective) {
            r->t *= rc->growth;
            VR_SPAN(sp, cnt, STEP_PERSPECTIVE, .fmul = 1, .branches = 1);
        } else {
            r->k++;
            r->t = r->t0 + (float)r->k * rc->base;
            VR_SPAN(sp, cnt, STEP, .int_ops = 1 + 1, .fmul = 1, .fadd = 1, .branches = 1);
        }
    }
    return true;
}

/* TraceRay (raycast_trace) for the samples with ray parameter t < t_stop.
 * A ray stopped at t_stop keeps its accumulated colour in its texel and its
 * opacity and position in the level's parked-ray arrays, and resumes there
 * (resume = true) with exactly the same arithmetic.  Returns true when the
 * ray is done.  *skipped counts the sample positions skipped (a statistic).
 * Spans: every row of the ray-casting block of vr_cost.h. */
static inline bool vr_trace(const vr_state_t *s, const vr_ray_consts_t *rc, float px, float py,
                            vr_ray_slot_t slot, bool resume, float t_stop, const vr_mem_t *mem,
                            vr_spans_t *sp, vr_count_t *cnt, uint64_t *skipped)
{
    vr_ray_t r;
    if (!vr_ray_begin(s, rc, px, py, slot, resume, &r, mem, sp, cnt))
        return true;
    bool done = vr_ray_march(s, rc, slot.m, &r, t_stop, mem, sp, cnt, skipped);
    vr_ray_store(s, slot, &r, !done, mem, sp, cnt);   /* parked at the end of a depth segment */
    return done;
}

/* The GP split: the viewpoint-dependent shading of a fetched unit's words
 * (a: its A words, shaded in place; nb: its N words), the integer function
 * of the PP stream (vr_shade_fixed.h).  Spans SHADE_WORD per word and
 * vr_shade_voxel_counted's.  The words are declared to the data cache in
 * chunks of 64, in the order the loop touches them. */
static inline void vr_shade_words(const vr_shade_consts_t *c, uint32_t *a, const uint32_t *nb,
                                  size_t words, const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    for (size_t i0 = 0; i0 < words; i0 += 64) {
        size_t n = words - i0 < 64 ? words - i0 : 64;
        vr_mem_access(mem, a, i0 * 4, n * 4, 0);
        vr_mem_access(mem, nb, i0 * 4, n * 4, 0);
        for (size_t i = i0; i < i0 + n; i++) {
            a[i] = vr_shade_voxel_counted(c, a[i], nb[i], sp, cnt);
            /* the A and N loads (N is used at once), the store; the index
             * shift, increment and test */
            VR_SPAN(sp, cnt, SHADE_WORD, .loads = 2, .load_use = 1, .stores = 1, .int_ops = 3, .branches = 1);
        }
        vr_mem_access(mem, a, i0 * 4, n * 4, 1);
    }
}

#endif
