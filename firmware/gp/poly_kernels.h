/* poly_kernels.h: the polygon GP program's per-vertex, per-triangle and per-region kernels (transform, light, clip, project and snap, set-up, binning, the PP stream of a triangle in a region), counted by spans of common/poly_cost.h.
 *
 * The GP program (poly_gp.c, poly_frame.c) and tests/test_fw_poly_cost.c
 * both call these: production passes span counters (poly_spans_t) and no
 * operation count (cnt = NULL); the test passes both and checks every row.
 * The stages follow render/mesh/mesh_raster.c (its image is the reference):
 * the same near-plane clip, viewport, edge functions with the top-left rule
 * and depth range, in the GP's single precision and the fixed point of
 * common/poly_config.h.  Counting conventions: common/poly_cost.h. */
#ifndef PP5_POLY_KERNELS_H
#define PP5_POLY_KERNELS_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "common/poly_config.h"
#include "common/poly_cost.h"
#include "pp_encode.h"

/* A vertex in clip space with its attributes (Gouraud: the intensities
 * seen from the front and from behind; Phong: the unit camera normal). */
typedef struct {
    float clip[4];
    float attr[4];
} poly_vert_t;

#define POLY_CLIP_MAX 10    /* a triangle clipped by 6 planes has at most 9 corners */

/* A triangle ready for the renderers: snapped screen corners, orientation,
 * the edges it owns (top-left rule), the regions of its box, and planes of
 * its attributes over the screen (value at corner 0, d/dx, d/dy; pixels). */
typedef struct {
    int32_t X[3], Y[3];          /* 1/16 pixel */
    int32_t s;                   /* +1 or -1: the sign that makes the edges positive inside */
    int32_t own[3];              /* edge k (opposite corner k) owns its pixels */
    int32_t back;                /* seen from behind */
    int32_t rx0, ry0, rx1, ry1;  /* regions of the box, inclusive */
    uint32_t flat_rgb;           /* flat: the lit colour; Phong per pixel: the side's colour (R | G << 8 | B << 16) */
    float x0, y0;                /* corner 0 in pixels */
    float plane[4][3];           /* z (scaled to 24 bits), then colour or normal channels */
} poly_tri_t;

/* ---- vertices ---- */

/* Clip-space position and (Gouraud, Phong) the camera normal and its light. */
static inline void poly_vertex(const poly_config_t *c, const float p[3], const float n[3],
                               poly_vert_t *v, poly_spans_t *sp, poly_count_t *cnt)
{
    const float *m = c->clip_from_world;
    for (int i = 0; i < 4; i++)
        v->clip[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3];
    /* the position (3 loads) and the 16 matrix entries; 4 rows of 3
     * multiply-adds and the translation; 4 stores; the shading test */
    POLY_SPAN(sp, cnt, VERTEX, .loads = 3 + 16, .fmul = 12, .fadd = 12, .stores = 4, .branches = 1);
    if (c->shading == POLY_FLAT)
        return;
    const float *V = c->view;
    float w[3];
    for (int i = 0; i < 3; i++)
        w[i] = V[4 * i] * n[0] + V[4 * i + 1] * n[1] + V[4 * i + 2] * n[2];
    float l2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2], l = sqrtf(l2);
    /* the normal (3 loads), the view's 3x3 (9 loads), 9 mul 6 add; the
     * squared length (3 mul 2 add), its root, the l > 0 test */
    POLY_SPAN(sp, cnt, NORMAL, .loads = 3 + 9, .fmul = 9 + 3, .fadd = 6 + 2 + 1, .fsqrt = 1,
              .branches = 1);
    if (l > 0) {
        float inv = 1.0f / l;
        w[0] *= inv, w[1] *= inv, w[2] *= inv;
        POLY_SPAN(sp, cnt, NORMAL_SCALE, .fdiv = 1, .fmul = 3);
    }
    if (c->shading == POLY_PHONG) {
        v->attr[0] = w[0], v->attr[1] = w[1], v->attr[2] = w[2];
        POLY_SPAN(sp, cnt, NORMAL_STORE, .stores = 3, .branches = 1);
        return;
    }
    float d = w[0] * c->light[0] + w[1] * c->light[1] + w[2] * c->light[2];
    float nd = -d;
    v->attr[0] = c->ambient + c->diffuse * (d > 0 ? d : 0);
    v->attr[1] = c->ambient + c->diffuse * (nd > 0 ? nd : 0);
    /* the shading test; L (3 loads), ambient, diffuse; the dot (3 mul 2
     * add); its negation; two clamps (both compares); 2 mul 2 add; 2 stores */
    POLY_SPAN(sp, cnt, LIGHT, .branches = 1 + 2, .loads = 3 + 2, .fmul = 3 + 2, .fadd = 2 + 1 + 2 + 2,
              .stores = 2);
}

/* Flat: the face's intensities (front, behind) from its world corners,
 * as mesh_raster: cross product of two edges, camera space, normalised. */
static inline void poly_face_light(const poly_config_t *c, const float p[3][3], float out[2],
                                   poly_spans_t *sp, poly_count_t *cnt)
{
    float u[3], w[3], fn[3], q[3];
    for (int k = 0; k < 3; k++)
        u[k] = p[1][k] - p[0][k], w[k] = p[2][k] - p[0][k];
    fn[0] = u[1] * w[2] - u[2] * w[1];
    fn[1] = u[2] * w[0] - u[0] * w[2];
    fn[2] = u[0] * w[1] - u[1] * w[0];
    const float *V = c->view;
    for (int i = 0; i < 3; i++)
        q[i] = V[4 * i] * fn[0] + V[4 * i + 1] * fn[1] + V[4 * i + 2] * fn[2];
    float l = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    /* 6 subtracts; the cross product (6 mul 3 sub); the view's 3x3 (9
     * loads, 9 mul 6 add); the length (3 mul 2 add, root); l > 0 */
    POLY_SPAN(sp, cnt, FACE_NORMAL, .fadd = 6 + 3 + 6 + 2 + 1, .fmul = 6 + 9 + 3, .loads = 9,
              .fsqrt = 1, .branches = 1);
    if (l > 0) {
        float inv = 1.0f / l;
        q[0] *= inv, q[1] *= inv, q[2] *= inv;
        POLY_SPAN(sp, cnt, NORMAL_SCALE, .fdiv = 1, .fmul = 3);
    }
    float d = q[0] * c->light[0] + q[1] * c->light[1] + q[2] * c->light[2], nd = -d;
    out[0] = c->ambient + c->diffuse * (d > 0 ? d : 0);
    out[1] = c->ambient + c->diffuse * (nd > 0 ? nd : 0);
    /* as LIGHT without the shading test */
    POLY_SPAN(sp, cnt, FACE_LIGHT, .branches = 2, .loads = 3 + 2, .fmul = 3 + 2, .fadd = 2 + 1 + 2 + 2,
              .stores = 2);
}

/* ---- clipping: near (z + w >= 0 and w > 0, as mesh_raster), far (z <= w),
 * and the guard band |x|, |y| <= POLY_GUARD w ---- */

static const int POLY_PLANE_AXIS[6] = {2, 2, 0, 0, 1, 1};
static const float POLY_PLANE_SIGN[6] = {1, -1, -1, 1, -1, 1};
static const float POLY_PLANE_W[6] = {1, 1, POLY_GUARD, POLY_GUARD, POLY_GUARD, POLY_GUARD};

/* Signed distance to plane k (inside >= 0): sign x coordinate + g w. */
static inline float poly_plane_dist(const poly_vert_t *v, int k)
{
    return POLY_PLANE_SIGN[k] * v->clip[POLY_PLANE_AXIS[k]] + POLY_PLANE_W[k] * v->clip[3];
}

/* Bit k set: outside plane k (bit 0 also when w <= 0). */
static inline unsigned poly_outcode(const poly_vert_t *v, poly_spans_t *sp, poly_count_t *cnt)
{
    unsigned oc = 0;
    for (int k = 0; k < 6; k++)
        oc |= (poly_plane_dist(v, k) < 0 ? 1u : 0u) << k;
    oc |= v->clip[3] > 0 ? 0u : 1u;
    /* 6 distances (3 table loads, 2 mul 1 add each); 7 compares; 7 ors */
    POLY_SPAN(sp, cnt, OUTCODE, .loads = 18, .fmul = 12, .fadd = 6 + 7, .branches = 7, .int_ops = 7);
    return oc;
}

static inline void poly_lerp(const poly_vert_t *a, const poly_vert_t *b, float t, poly_vert_t *o)
{
    for (int k = 0; k < 4; k++) {
        o->clip[k] = a->clip[k] + t * (b->clip[k] - a->clip[k]);
        o->attr[k] = a->attr[k] + t * (b->attr[k] - a->attr[k]);
    }
}

/* Sutherland-Hodgman of polygon in[n] against plane k into out; returns
 * the corners out has.  The cut is mesh_raster's clip_near for every plane. */
static inline int poly_clip_plane(const poly_vert_t *in, int n, int k, poly_vert_t *out,
                                  poly_spans_t *sp, poly_count_t *cnt)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        const poly_vert_t *a = &in[i], *b = &in[(i + 1) % n];
        float da = poly_plane_dist(a, k), db = poly_plane_dist(b, k);
        bool ina = da >= 0 && a->clip[3] > 0, inb = db >= 0 && b->clip[3] > 0;
        /* two distances (6 loads, 4 mul 2 add); 4 compares; the loop (2
         * int ops, 1 branch); ina, inb both tested against each other */
        POLY_SPAN(sp, cnt, CLIP_EDGE, .loads = 6, .fmul = 4, .fadd = 2 + 4, .branches = 4 + 1 + 2,
                  .int_ops = 2 + 1);
        if (ina) {
            out[m++] = *a;
            POLY_SPAN(sp, cnt, CLIP_KEEP, .loads = 8, .stores = 8, .int_ops = 1);
        }
        if (ina != inb && da != db) {
            float t = da / (da - db);
            /* da != db; the parameter; its two bounds */
            POLY_SPAN(sp, cnt, CLIP_CUT, .fadd = 1 + 1 + 2, .fdiv = 1, .branches = 1 + 2);
            if (t > 0 && t < 1) {
                poly_lerp(a, b, t, &out[m++]);
                POLY_SPAN(sp, cnt, CLIP_LERP, .loads = 16, .fadd = 16, .fmul = 8, .stores = 8,
                          .int_ops = 1);
            }
        }
    }
    return m;
}

/* The triangle's polygon after clipping (n corners, 0 when nothing is left). */
static inline int poly_clip(const poly_vert_t tri[3], poly_vert_t out[POLY_CLIP_MAX],
                            poly_spans_t *sp, poly_count_t *cnt)
{
    unsigned o0 = poly_outcode(&tri[0], sp, cnt), o1 = poly_outcode(&tri[1], sp, cnt),
             o2 = poly_outcode(&tri[2], sp, cnt);
    /* the union and the intersection; their tests */
    POLY_SPAN(sp, cnt, CLIP_TEST, .int_ops = 4, .branches = 2);
    if (o0 & o1 & o2)
        return 0;
    for (int i = 0; i < 3; i++)
        out[i] = tri[i];
    if (!(o0 | o1 | o2))
        return 3;
    poly_vert_t tmp[POLY_CLIP_MAX];
    int n = 3;
    for (int k = 0; k < 6 && n >= 3; k++) {
        /* the loop; the plane's bit and its test */
        POLY_SPAN(sp, cnt, CLIP_PLANE, .int_ops = 1 + 2, .branches = 1 + 1);
        if (!((o0 | o1 | o2) & (1u << k)))
            continue;
        n = poly_clip_plane(out, n, k, tmp, sp, cnt);
        for (int i = 0; i < n; i++) {
            out[i] = tmp[i];
            POLY_SPAN(sp, cnt, CLIP_COPY_VERT, .loads = 8, .stores = 8, .int_ops = 1, .branches = 1);
        }
    }
    return n >= 3 ? n : 0;
}

/* ---- projection and snapping ---- */

typedef struct {
    float x, y, z;               /* pixels, z/w */
    int32_t X, Y;                /* snapped, 1/16 pixel */
} poly_screen_t;

static inline void poly_project(const poly_config_t *c, const poly_vert_t *v, poly_screen_t *o,
                                poly_spans_t *sp, poly_count_t *cnt)
{
    float iw = 1.0f / v->clip[3], hw = 0.5f * (float)c->width, hh = 0.5f * (float)c->height;
    o->x = (v->clip[0] * iw + 1.0f) * hw;
    o->y = (1.0f - v->clip[1] * iw) * hh;
    o->z = v->clip[2] * iw;
    o->X = (int32_t)lrintf(o->x * (float)POLY_SUB);
    o->Y = (int32_t)lrintf(o->y * (float)POLY_SUB);
    /* 4 loads; 1/w; the half sizes (2 conversions, 2 mul: per frame, kept
     * in registers, not counted); x, y (2 mul 1 add each); z; the snaps (1
     * mul, 1 conversion each); 5 stores */
    POLY_SPAN(sp, cnt, PROJECT, .loads = 4, .fdiv = 1, .fmul = 2 + 2 + 1 + 2, .fadd = 2, .int_ops = 2,
              .stores = 5);
}

/* ---- triangle set-up ---- */

static inline int32_t poly_min3(int32_t a, int32_t b, int32_t c)
{
    int32_t m = a < b ? a : b;
    return m < c ? m : c;
}
static inline int32_t poly_max3(int32_t a, int32_t b, int32_t c)
{
    int32_t m = a > b ? a : b;
    return m > c ? m : c;
}

/* floor(a / 2^k) for any sign (an arithmetic shift). */
static inline int32_t poly_floor_shift(int32_t a, int k)
{
    return (int32_t)((a - (a < 0 ? (1 << k) - 1 : 0)) / (1 << k));
}

/* A plane through three values at the triangle's snapped corners. */
static inline void poly_plane(const float v[3], float ex1, float ey1, float ex2, float ey2,
                              float inv, float out[3], poly_spans_t *sp, poly_count_t *cnt)
{
    float d1 = v[1] - v[0], d2 = v[2] - v[0];
    out[0] = v[0];
    out[1] = (d1 * ey2 - d2 * ey1) * inv;
    out[2] = (d2 * ex1 - d1 * ex2) * inv;
    /* 3 loads; 2 subtracts; each gradient 2 mul, a subtract, 1 mul; 3 stores */
    POLY_SPAN(sp, cnt, PLANE_SETUP, .loads = 3, .fadd = 2 + 2, .fmul = 6, .stores = 3);
}

/* Set-up of the fan triangle (a, b, d) of a polygon: false when it has no
 * area or covers no pixel centre of the image.  vals[k][i]: attribute k
 * (z first) at corner i; n_vals of them. */
static inline bool poly_setup(const poly_config_t *c, const poly_screen_t *a, const poly_screen_t *b,
                              const poly_screen_t *d, float vals[4][3], int n_vals, poly_tri_t *t,
                              poly_spans_t *sp, poly_count_t *cnt)
{
    const poly_screen_t *v[3] = {a, b, d};
    for (int i = 0; i < 3; i++)
        t->X[i] = v[i]->X, t->Y[i] = v[i]->Y;
    int32_t ex1 = t->X[1] - t->X[0], ey1 = t->Y[1] - t->Y[0];
    int32_t ex2 = t->X[2] - t->X[0], ey2 = t->Y[2] - t->Y[0];
    int64_t area = (int64_t)ex1 * ey2 - (int64_t)ey1 * ex2;
    /* 6 loads, 6 stores; 4 subtracts; the area in double (4 conversions,
     * 2 mul = 4 issue slots, 1 subtract); the zero test */
    POLY_SPAN(sp, cnt, SETUP, .loads = 6, .stores = 6, .int_ops = 4 + 4, .fmul = 4, .fadd = 1,
              .branches = 1);
    if (area == 0)
        return false;
    t->s = area > 0 ? 1 : -1;    /* mesh_raster's s: the sign of edge_fn(v0, v1, v2) */
    for (int k = 0; k < 3; k++) {
        const poly_screen_t *p = v[(k + 1) % 3], *q = v[(k + 2) % 3];
        int32_t nx = -(q->Y - p->Y) * t->s, ny = (q->X - p->X) * t->s;
        t->own[k] = nx > 0 || (nx == 0 && ny > 0);
    }
    int32_t xlo = poly_min3(t->X[0], t->X[1], t->X[2]), xhi = poly_max3(t->X[0], t->X[1], t->X[2]);
    int32_t ylo = poly_min3(t->Y[0], t->Y[1], t->Y[2]), yhi = poly_max3(t->Y[0], t->Y[1], t->Y[2]);
    /* the pixels whose centres 16 x + 8 lie in the box, clamped to the image */
    int32_t px0 = poly_floor_shift(xlo - POLY_SUB / 2 + POLY_SUB - 1, POLY_SUB_BITS);
    int32_t px1 = poly_floor_shift(xhi - POLY_SUB / 2, POLY_SUB_BITS);
    int32_t py0 = poly_floor_shift(ylo - POLY_SUB / 2 + POLY_SUB - 1, POLY_SUB_BITS);
    int32_t py1 = poly_floor_shift(yhi - POLY_SUB / 2, POLY_SUB_BITS);
    px0 = px0 < 0 ? 0 : px0, py0 = py0 < 0 ? 0 : py0;
    px1 = px1 > c->width - 1 ? c->width - 1 : px1;
    py1 = py1 > c->height - 1 ? c->height - 1 : py1;
    /* the orientation compare; per edge 2 subtracts, 2 sign products, 3
     * compares (nx > 0, nx == 0, ny > 0), 1 store; the box (8 compares);
     * 4 pixel bounds (an add and a shift with its sign fix: 4 ops); 4
     * clamps (2 loads); the empty test (2 compares) */
    POLY_SPAN(sp, cnt, SETUP_EDGES, .fadd = 1, .branches = 1 + 3 * 3 + 8 + 4 + 2,
              .int_ops = 3 * (2 + 2 + 3) + 8 + 4 * 4 + 4 + 2, .stores = 1 + 3, .loads = 2);
    if (px0 > px1 || py0 > py1)
        return false;
    t->rx0 = px0 >> 7, t->rx1 = px1 >> 7, t->ry0 = py0 >> 7, t->ry1 = py1 >> 7;
    t->x0 = (float)t->X[0] / POLY_SUB, t->y0 = (float)t->Y[0] / POLY_SUB;
    float fx1 = (float)ex1 / POLY_SUB, fy1 = (float)ey1 / POLY_SUB;
    float fx2 = (float)ex2 / POLY_SUB, fy2 = (float)ey2 / POLY_SUB;
    float inv = 1.0f / (fx1 * fy2 - fy1 * fx2);
    /* 4 region shifts, 4 stores; corner 0 and the edge vectors in pixels (6
     * conversions, 6 mul by 1/16); the area in pixels (2 mul 1 sub), 1/area;
     * 2 stores */
    POLY_SPAN(sp, cnt, SETUP_PLANES, .int_ops = 4 + 6, .stores = 4 + 2, .fmul = 6 + 2, .fadd = 1,
              .fdiv = 1);
    for (int k = 0; k < n_vals; k++)
        poly_plane(vals[k], fx1, fy1, fx2, fy2, inv, t->plane[k], sp, cnt);
    return true;
}

/* ---- a whole input triangle ---- */

/* Transform, light, clip, cull, project and set up one input triangle:
 * the fan triangles of what is left go to out (returns how many, at most
 * POLY_CLIP_MAX - 2). */
static inline int poly_triangle(const poly_config_t *c, const poly_tri_in_t *in,
                                poly_tri_t out[POLY_CLIP_MAX - 2], poly_spans_t *sp, poly_count_t *cnt)
{
    poly_vert_t v[3], poly[POLY_CLIP_MAX];
    float flat[2] = {0, 0};
    for (int i = 0; i < 3; i++)
        poly_vertex(c, in->p[i], in->n[i], &v[i], sp, cnt);
    if (c->shading == POLY_FLAT)
        poly_face_light(c, in->p, flat, sp, cnt);
    int n = poly_clip(v, poly, sp, cnt);
    /* the record's address; the loop; the flat test; the clipped test; the
     * own-colour word and its test */
    POLY_SPAN(sp, cnt, TRI, .loads = 1 + 1, .int_ops = 2, .branches = 1 + 1 + 1 + 1);
    if (n < 3)
        return 0;
    poly_screen_t sv[POLY_CLIP_MAX];
    for (int i = 0; i < n; i++)
        poly_project(c, &poly[i], &sv[i], sp, cnt);
    float area = (sv[1].x - sv[0].x) * (sv[2].y - sv[0].y) - (sv[1].y - sv[0].y) * (sv[2].x - sv[0].x);
    bool front = area < 0;
    /* mesh_raster's draw_face: counter-clockwise with y up is the front
     * (6 loads, 5 adds 2 mul, the compare); the cull test */
    POLY_SPAN(sp, cnt, FACE, .loads = 6, .fadd = 5 + 1, .fmul = 2, .branches = 1 + 1);
    if (c->cull_back && !front)
        return 0;
    float vals[POLY_CLIP_MAX][4];
    const int32_t *rgb = front ? c->front_rgb : c->back_rgb;
    int32_t own[3];
    if (in->rgb & POLY_RGB_OWN) {
        for (int k = 0; k < 3; k++)
            own[k] = (int32_t)((in->rgb >> (8 * k)) & 0xffu);
        rgb = own;
        /* 3 shifts and masks, kept in registers */
        POLY_SPAN(sp, cnt, OWN_COLOUR, .int_ops = 6);
    }
    for (int i = 0; i < n; i++) {
        vals[i][0] = (float)POLY_Z_LO + (sv[i].z + 1.0f) * (float)POLY_Z_SCALE;
        /* z loaded, 2 adds 1 mul, stored; the shading test */
        POLY_SPAN(sp, cnt, ATTR_Z, .loads = 1, .fadd = 2, .fmul = 1, .stores = 1, .branches = 1);
        if (c->shading == POLY_GOURAUD) {
            float l = poly[i].attr[front ? 0 : 1];
            for (int k = 0; k < 3; k++) {
                float cc = (float)rgb[k] * l;
                vals[i][1 + k] = cc > 255.0f ? 255.0f : cc;
            }
            /* the intensity and 3 channel values (4 loads, 3 mul), 3 clamps
             * (compares), 3 stores */
            POLY_SPAN(sp, cnt, ATTR_COLOUR, .loads = 4, .fmul = 3, .fadd = 3, .branches = 3, .stores = 3);
        } else if (c->shading == POLY_PHONG) {
            float sgn = front ? (float)POLY_N_ONE : -(float)POLY_N_ONE;
            for (int k = 0; k < 3; k++)
                vals[i][1 + k] = poly[i].attr[k] * sgn;
            POLY_SPAN(sp, cnt, ATTR_NORMAL, .loads = 3, .fmul = 3, .stores = 3);
        }
    }
    uint32_t flat_rgb = 0;
    if (c->shading == POLY_PHONG && c->colour_per_pixel) {
        flat_rgb = (uint32_t)rgb[0] | (uint32_t)rgb[1] << 8 | (uint32_t)rgb[2] << 16;
        /* the packing (2 shifts, 2 ors) */
        POLY_SPAN(sp, cnt, PHONG_COLOUR, .int_ops = 4);
    }
    if (c->shading == POLY_FLAT) {
        float l = flat[front ? 0 : 1];
        l = l < 0 ? 0 : l;
        for (int k = 0; k < 3; k++) {
            float cc = (float)rgb[k] * l;
            uint32_t q = cc >= 255.0f ? 255u : (uint32_t)(cc + 0.5f);
            flat_rgb |= q << (8 * k);
        }
        /* the intensity (1 load, clamped: 1 compare), 3 channels (load,
         * mul, the 255 compare, + 0.5, conversion), the packing (shifts and
         * ors: 4), the store */
        POLY_SPAN(sp, cnt, FLAT_COLOUR, .loads = 1 + 3, .fmul = 3, .fadd = 3 + 3, .branches = 3,
                  .int_ops = 3 + 4, .stores = 1);
    }
    int n_vals = c->shading == POLY_FLAT ? 1 : 4, m = 0;
    for (int i = 1; i + 1 < n; i++) {
        float tv[4][3];
        for (int k = 0; k < 4; k++) {
            tv[k][0] = vals[0][k], tv[k][1] = vals[i][k], tv[k][2] = vals[i + 1][k];
        }
        poly_tri_t *t = &out[m];
        t->back = !front;
        t->flat_rgb = flat_rgb;
        /* the loop; 12 values gathered; back and colour stored; the set-up's
         * result tested */
        POLY_SPAN(sp, cnt, FAN, .int_ops = 2, .branches = 2, .loads = 12, .stores = 12 + 2);
        if (poly_setup(c, &sv[0], &sv[i], &sv[i + 1], tv, n_vals, t, sp, cnt))
            m++;
    }
    return m;
}

/* ---- sorting into regions (count, prefix sums, fill) ---- */

/* Adds triangle t's regions to the per-region counts. */
static inline void poly_bin_count(const poly_tri_t *t, int regions_x, uint32_t *count, poly_spans_t *sp,
                                  poly_count_t *cnt)
{
    POLY_SPAN(sp, cnt, BIN_TRI, .loads = 4, .int_ops = 2, .branches = 2);
    for (int ry = t->ry0; ry <= t->ry1; ry++)
        for (int rx = t->rx0; rx <= t->rx1; rx++) {
            count[ry * regions_x + rx]++;
            /* the index (mul by a per-frame constant, add), the loop
             * (increment, compare), the count's load (used at once),
             * increment and store */
            POLY_SPAN(sp, cnt, BIN_COUNT, .loads = 1, .load_use = 1, .stores = 1, .int_ops = 4,
                      .branches = 1);
        }
}

/* start[k] = the sum of count[0..k); fill[k] = 0; count[k] = 0 for the
 * next frame.  Returns the number of pairs. */
static inline uint32_t poly_bin_prefix(uint32_t *count, uint32_t *start, uint32_t *fill, int n,
                                       poly_spans_t *sp, poly_count_t *cnt)
{
    uint32_t sum = 0;
    for (int k = 0; k < n; k++) {
        start[k] = sum, fill[k] = 0;
        sum += count[k];
        count[k] = 0;
        /* the loop (increment, compare); the count; 3 stores; the sum */
        POLY_SPAN(sp, cnt, BIN_PREFIX, .loads = 1, .stores = 3, .int_ops = 2, .branches = 1);
    }
    return sum;
}

static inline void poly_bin_fill(const poly_tri_t *t, uint32_t index, int regions_x, const uint32_t *start,
                                 uint32_t *fill, uint32_t *list, poly_spans_t *sp, poly_count_t *cnt)
{
    POLY_SPAN(sp, cnt, BIN_TRI, .loads = 4, .int_ops = 2, .branches = 2);
    for (int ry = t->ry0; ry <= t->ry1; ry++)
        for (int rx = t->rx0; rx <= t->rx1; rx++) {
            int k = ry * regions_x + rx;
            list[start[k] + fill[k]++] = index;
            /* the index, the loop; start and fill (the second used at once),
             * the address, the stores of the entry and of fill */
            POLY_SPAN(sp, cnt, BIN_FILL, .loads = 2, .load_use = 1, .stores = 2, .int_ops = 5,
                      .branches = 1);
        }
}

/* ---- a triangle in a region: its PP instructions ---- */

/* The integer coefficients of a plane over the region at (rx, ry) for the
 * QEE: value * 2^shift + offset at pixel centres, F reduced mod 2^32 (the
 * QEE keeps at most 32 - max_shift bits, which the reduction leaves exact).
 * The shift is the largest <= max_shift whose gradients fit 31 bits. */
typedef struct {
    int32_t D, E, F;
    unsigned shift;
} poly_qee_t;

static inline poly_qee_t poly_plane_qee(const float pl[3], float x0, float y0, int32_t rx, int32_t ry,
                                        double scale, double offset, unsigned max_shift,
                                        poly_spans_t *sp, poly_count_t *cnt)
{
    double v = (double)pl[0] + (double)pl[1] * ((double)rx + 0.5 - x0) +
               (double)pl[2] * ((double)ry + 0.5 - y0);
    double gx = (double)pl[1] * scale, gy = (double)pl[2] * scale;
    /* in double (a product takes 2 issue slots): 5 loads; 2 conversions; 4
     * adds (+0.5 and - corner, x and y), 2 products and 2 adds of the value;
     * the two gradients scaled (2 products) */
    POLY_SPAN(sp, cnt, QEE_PLANE, .loads = 5, .int_ops = 2, .fadd = 4 + 2, .fmul = 4 + 4);
    const double lim = 2147483647.0;
    unsigned s = max_shift;
    double sx, sy;
    for (;;) {
        sx = ldexp(gx, (int)s), sy = ldexp(gy, (int)s);
        bool fits = fabs(sx) <= lim && fabs(sy) <= lim;
        /* two products by the table's 2^s; 2 fabs; 2 compares (both);
         * the fits and s == 0 tests */
        POLY_SPAN(sp, cnt, QEE_TRY, .fmul = 4, .int_ops = 2, .fadd = 2, .branches = 2 + 2);
        if (fits || s == 0)
            break;
        s--;
        POLY_SPAN(sp, cnt, QEE_SHIFT_DOWN, .int_ops = 1, .branches = 1);
    }
    sx = sx > lim ? lim : sx < -lim ? -lim : sx;
    sy = sy > lim ? lim : sy < -lim ? -lim : sy;
    poly_qee_t q;
    q.D = (int32_t)lrint(sx);
    q.E = (int32_t)lrint(sy);
    int64_t fr = (int64_t)llrint(ldexp(v * scale, (int)s) + ldexp(offset, (int)s));
    int64_t f = fr - (int64_t)q.D * rx - (int64_t)q.E * ry;
    q.F = (int32_t)(uint32_t)(uint64_t)f;
    q.shift = s;
    /* 2 clamps (4 compares); D, E (2 conversions); the value scaled and by
     * 2^s, the offset by 2^s (3 products), their sum, its conversion; F: 2
     * products, 2 subtracts, the reduction mod 2^32 */
    POLY_SPAN(sp, cnt, QEE_COEFFS, .fadd = 4 + 1 + 2, .branches = 4, .int_ops = 2 + 1 + 1,
              .fmul = 6 + 4);
    return q;
}

/* Appends the instructions of triangle t in the region whose top-left pixel
 * is (rx, ry): false (nothing appended) when some edge leaves the whole
 * region outside.  Edges that leave it all inside are not sent.  On level
 * l > 0 of the variable-resolution Z-buffer (poly_vrz_kernels.h) (rx, ry) is
 * a texel, t's planes are the level's (poly_tri_on_level) and each edge's F
 * becomes floor(F / 2^l). */
static inline bool poly_encode(const poly_config_t *c, const poly_tri_t *t, int level, int32_t rx,
                               int32_t ry, pp_stream_t *st, poly_spans_t *sp, poly_count_t *cnt)
{
    int64_t F[3];
    int32_t D[3], E[3];
    bool need[3];
    /* the triangle's corners, sign and owned edges (10 loads); the region's
     * first pixel centre in 1/16 pixel is not needed: the corners below are
     * pixel coordinates */
    POLY_SPAN(sp, cnt, ENC_TRI, .loads = 10, .branches = 1);
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        int32_t dX = t->X[j] - t->X[i], dY = t->Y[j] - t->Y[i];
        /* e = s (dX (16 y + 8 - Yi) - dY (16 x + 8 - Xi)) + own - 1 */
        D[k] = -POLY_SUB * dY * t->s;
        E[k] = POLY_SUB * dX * t->s;
        F[k] = (int64_t)t->s * ((int64_t)dX * (POLY_SUB / 2 - t->Y[i]) -
                                (int64_t)dY * (POLY_SUB / 2 - t->X[i])) + t->own[k] - 1;
        if (level > 0) {
            /* exact in double (|F| < 2^41): the product by 2^-l (2 slots),
             * the floor and the conversions */
            F[k] = (int64_t)floor(ldexp((double)F[k], -level));
            POLY_SPAN(sp, cnt, ENC_LEVEL_EDGE, .fmul = 2, .int_ops = 2 + 1, .branches = 1);
        }
        int64_t e00 = (int64_t)D[k] * rx + (int64_t)E[k] * ry + F[k];
        int64_t e10 = e00 + 127 * (int64_t)D[k], e01 = e00 + 127 * (int64_t)E[k];
        int64_t e11 = e10 + 127 * (int64_t)E[k];
        int negative = (e00 < 0) + (e10 < 0) + (e01 < 0) + (e11 < 0);
        need[k] = negative > 0;
        /* dX, dY; D, E (shift, sign: 4 ops); F (2 subtracts, 2 products in
         * double = 4 slots, 1 subtract, the sign, + own - 1); the corner
         * (2 products, 2 adds), 127 D and 127 E (shift and subtract: 4),
         * 3 adds; 4 compares; the count (3 adds); 2 tests */
        POLY_SPAN(sp, cnt, ENC_EDGE, .int_ops = 2 + 4 + 2 + 1 + 4 + 3, .fmul = 4 + 4,
                  .fadd = 1 + 1 + 2 + 3 + 4, .branches = 4 + 2, .loads = 1);
        if (negative == 4) {
            POLY_SPAN(sp, cnt, ENC_OUTSIDE, .branches = 1);
            return false;
        }
    }
    size_t w0 = st->n_words;
    pp_emit_en_all(st);
    for (int k = 0; k < 3; k++) {
        POLY_SPAN(sp, cnt, ENC_EDGE_TEST, .branches = 1 + 1, .int_ops = 1);
        if (!need[k])
            continue;
        pp_emit_qee(st, POLY_PP_T, 1, POLY_EDGE_SHIFT, 0, 0, 0, D[k], E[k],
                    (int32_t)(uint32_t)(uint64_t)F[k]);
        pp_emit_f_ld(st, POLY_PP_T);
        pp_emit_en_andn(st);
        POLY_SPAN(sp, cnt, ENC_EDGE_EMIT, .int_ops = 1);
    }
    poly_qee_t z = poly_plane_qee(t->plane[0], t->x0, t->y0, rx, ry, 1.0, 0.0, 8, sp, cnt);
    pp_emit_qee(st, POLY_PP_ZT, POLY_Z_BITS, z.shift, 0, 0, 0, z.D, z.E, z.F);
    pp_emit_cmp(st, PP_CMP_LTU, POLY_PP_ZT, POLY_PP_Z, POLY_Z_BITS);
    pp_emit_en_and(st);
    pp_emit_copy(st, POLY_PP_Z, POLY_PP_ZT, POLY_Z_BITS);
    /* the shading test */
    POLY_SPAN(sp, cnt, ENC_Z, .branches = 2);
    if (c->shading == POLY_FLAT) {
        pp_emit_seti(st, POLY_PP_R, 24, t->flat_rgb);
        POLY_SPAN(sp, cnt, ENC_FLAT, .loads = 1);
    } else {
        static const unsigned field[2][3] = {{POLY_PP_R, POLY_PP_G, POLY_PP_B},
                                             {POLY_PP_NX, POLY_PP_NY, POLY_PP_NZ}};
        bool phong = c->shading == POLY_PHONG;
        for (int k = 0; k < 3; k++) {
            /* colour: value + 0.5, 8 bits kept (shift <= 24); normal: 2^14 = 1 */
            poly_qee_t q = phong ? poly_plane_qee(t->plane[1 + k], t->x0, t->y0, rx, ry, 1.0, 0.0, 16, sp, cnt)
                                 : poly_plane_qee(t->plane[1 + k], t->x0, t->y0, rx, ry, 1.0, 0.5, 16, sp, cnt);
            pp_emit_qee(st, field[phong][k], phong ? 16 : 8, q.shift, 0, 0, 0, q.D, q.E, q.F);
            POLY_SPAN(sp, cnt, ENC_CHANNEL, .int_ops = 1, .branches = 2);
        }
        if (phong) {
            pp_emit_f_set(st, 1);
            pp_emit_f_st(st, POLY_PP_COVER);
            pp_emit_f_set(st, (unsigned)t->back);
            pp_emit_f_st(st, POLY_PP_BACK);
            /* the back bit's load; the colour test */
            POLY_SPAN(sp, cnt, ENC_PHONG_FLAGS, .loads = 1, .branches = 1);
            if (c->colour_per_pixel) {
                pp_emit_seti(st, POLY_PP_R, 24, t->flat_rgb);
                POLY_SPAN(sp, cnt, ENC_PHONG_COLOUR, .loads = 1);
            }
        }
    }
    /* each word assembled (shift and or of its fields) and stored */
    POLY_SPANS(sp, cnt, ENC_WORD, st->n_words - w0, .int_ops = 2, .stores = 1);
    return true;
}

/* The words of a stream written outside poly_encode (the region's clear,
 * the Phong stream): each assembled and stored. */
static inline void poly_words(size_t words, poly_spans_t *sp, poly_count_t *cnt)
{
    POLY_SPANS(sp, cnt, ENC_WORD, words, .int_ops = 2, .stores = 1);
}

/* A region's stream begins: its bin and origin; the first GP (clear) also
 * clears depth to the far value and colour to the background (and, Phong,
 * the covered bits). */
static inline void poly_region_start(const poly_config_t *c, bool clear, pp_stream_t *st,
                                     poly_spans_t *sp, poly_count_t *cnt)
{
    /* the bin's start and size and the region number (3 loads); its x, y
     * (a divide and a remainder by the per-frame row length: 2 ops, [I] a
     * reciprocal table) and origin (2 shifts); the encode loop's set-up (2
     * ops); the clear and shading tests */
    POLY_SPAN(sp, cnt, REGION, .loads = 3, .int_ops = 6, .branches = 2);
    if (!clear)
        return;
    size_t w0 = st->n_words;
    pp_emit_en_all(st);
    pp_emit_seti(st, POLY_PP_Z, POLY_Z_BITS, POLY_Z_FAR);
    pp_emit_seti(st, POLY_PP_R, 24, c->background_rgb[0] | c->background_rgb[1] << 8 | c->background_rgb[2] << 16);
    if (c->shading == POLY_PHONG) {
        pp_emit_f_set(st, 0);
        pp_emit_f_st(st, POLY_PP_COVER);
    }
    poly_words(st->n_words - w0, sp, cnt);
}

/* A full triangle table moved to a larger one: `words` 32-bit words. */
static inline void poly_grow_moved(uint64_t words, poly_spans_t *sp, poly_count_t *cnt)
{
    /* per word: load, store, the address increment, the loop test */
    POLY_SPANS(sp, cnt, GROW_COPY, words, .loads = 1, .stores = 1, .int_ops = 1, .branches = 1);
}

#endif
