/* mesh_render_vrz.c: the variable-resolution Z-buffer (gaze paper §7, seed
 * 004): a depth and attributes per texel of the 2D mip map, triangles
 * sampled at the populated texels only, scanlines cut into the runs of
 * populated texels of each level, then the volume renderer's resampling
 * (mesh_render.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_render.h"
#include "render/mip2d_row.h"

/* A run of populated texels [i0, i1) in one row of one level. */
typedef struct {
    int32_t i0, i1;
} run_t;

typedef struct {
    int w, h, shift;
    double *depth;
    float *attr;
    int32_t *row_start;     /* h + 1: runs of row j are runs[row_start[j] .. row_start[j+1]) */
    run_t *runs;
    long n_runs;
} vlevel_t;

typedef struct {
    int levels, na;
    vlevel_t lv[MIP2D_MAX_LEVELS];
    uint64_t fragments;
} vrz_t;

static void vrz_free(vrz_t *v)
{
    for (int l = 0; l < v->levels; l++) {
        free(v->lv[l].depth), free(v->lv[l].attr);
        free(v->lv[l].row_start), free(v->lv[l].runs);
    }
}

/* The runs of populated (needed) texels of level l of m. */
static pp5_status_t build_runs(const mip2d_t *m, int l, vlevel_t *lv, uint64_t *populated)
{
    const uint8_t *need = m->need[l];
    int w = m->w[l], h = m->h[l];
    long n = 0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            n += need[(size_t)j * w + i] && (i == 0 || !need[(size_t)j * w + i - 1]);
    lv->row_start = malloc(sizeof *lv->row_start * (size_t)(h + 1));
    lv->runs = malloc(sizeof *lv->runs * (size_t)(n + 1));
    if (!lv->row_start || !lv->runs)
        return pp5_fail(PP5_E_NOMEM, "render: out of memory for level %d's runs", l);
    long k = 0;
    for (int j = 0; j < h; j++) {
        lv->row_start[j] = (int32_t)k;
        for (int i = 0; i < w;) {
            if (!need[(size_t)j * w + i]) {
                i++;
                continue;
            }
            int i0 = i;
            while (i < w && need[(size_t)j * w + i])
                i++;
            lv->runs[k].i0 = i0, lv->runs[k].i1 = i;
            k++;
            *populated += (uint64_t)(i - i0);
        }
    }
    lv->row_start[h] = (int32_t)k;
    lv->n_runs = k;
    return PP5_OK;
}

static void sample(vrz_t *v, vlevel_t *lv, const tri_setup_t *t, int i, int j, double px, double py)
{
    double b[3];
    if (!tri_cover(t, px, py, b))
        return;
    v->fragments++;
    double d = tri_depth(t, b);
    size_t k = (size_t)j * (size_t)lv->w + (size_t)i;
    if (!(d < lv->depth[k]) || d < -1 || d > 1)
        return;
    lv->depth[k] = d;
    double a[TRI_MAX_ATTRS];
    tri_attrs(t, b, a);
    for (int q = 0; q < v->na; q++)
        lv->attr[k * (size_t)v->na + (size_t)q] = (float)a[q];
}

/* Level l's texel (i, j) sits at image point (i 2^l + 0.5, j 2^l + 0.5)
 * (gaze2d.h); the triangle's bounding box picks the rows, and in each row
 * only the runs of populated texels inside the box are scan-converted. */
static void vrz_sink(void *ctx, const tri_setup_t *t)
{
    vrz_t *v = ctx;
    for (int l = 0; l < v->levels; l++) {
        vlevel_t *lv = &v->lv[l];
        if (lv->n_runs == 0)
            continue;
        double s = (double)(1 << lv->shift);
        int i0 = (int)fmax(0, ceil((t->xmin - 0.5) / s)), i1 = (int)fmin(lv->w - 1, floor((t->xmax - 0.5) / s));
        int j0 = (int)fmax(0, ceil((t->ymin - 0.5) / s)), j1 = (int)fmin(lv->h - 1, floor((t->ymax - 0.5) / s));
        for (int j = j0; j <= j1; j++) {
            double py = j * s + 0.5;
            for (int32_t r = lv->row_start[j]; r < lv->row_start[j + 1]; r++) {
                int a = lv->runs[r].i0 > i0 ? lv->runs[r].i0 : i0;
                int b = lv->runs[r].i1 - 1 < i1 ? lv->runs[r].i1 - 1 : i1;
                for (int i = a; i <= b; i++)
                    sample(v, lv, t, i, j, i * s + 0.5, py);
            }
        }
    }
}

static pp5_status_t vrz_init(vrz_t *v, mip2d_t *m, int na, uint64_t *populated)
{
    memset(v, 0, sizeof *v);
    v->levels = m->levels, v->na = na;
    for (int l = 0; l < m->levels; l++) {
        vlevel_t *lv = &v->lv[l];
        lv->w = m->w[l], lv->h = m->h[l], lv->shift = l;
        size_t n = (size_t)lv->w * (size_t)lv->h;
        lv->depth = malloc(n * sizeof *lv->depth);
        lv->attr = malloc(n * (size_t)na * sizeof *lv->attr);
        if (!lv->depth || !lv->attr)
            return pp5_fail(PP5_E_NOMEM, "render: out of memory for level %d", l);
        for (size_t i = 0; i < n; i++)
            lv->depth[i] = INFINITY;
        pp5_status_t st = build_runs(m, l, lv, populated);
        if (st != PP5_OK)
            return st;
    }
    return PP5_OK;
}

/* Shades every populated texel into the mip map's colours (0..1, the 8-bit
 * value the full-resolution renderer would write, so level 0 resamples to
 * the same bytes). */
static void vrz_resolve(const vrz_t *v, const mesh_render_opts_t *o, mip2d_t *m, uint64_t *shaded)
{
    for (int l = 0; l < v->levels; l++) {
        const vlevel_t *lv = &v->lv[l];
        for (int j = 0; j < lv->h; j++)
            for (int32_t r = lv->row_start[j]; r < lv->row_start[j + 1]; r++)
                for (int i = lv->runs[r].i0; i < lv->runs[r].i1; i++) {
                    size_t k = (size_t)j * (size_t)lv->w + (size_t)i;
                    uint8_t rgb[3];
                    if (lv->depth[k] == INFINITY) {
                        memcpy(rgb, o->background, 3);
                    } else {
                        mesh_render_shade(o, lv->attr + k * (size_t)v->na, rgb);
                        (*shaded)++;
                    }
                    for (int q = 0; q < 3; q++)
                        m->rgb[l][3 * k + (size_t)q] = (float)rgb[q] / 255.0f;
                    m->cast[l][k] = 1;
                }
    }
}

pp5_status_t mesh_render_vrz(const mesh_soup_t *soup, const raster_camera_t *cam,
                             const mesh_render_opts_t *o, const gaze_model_t *g, double gaze_x,
                             double gaze_y, image8_t *img, mesh_render_stats_t *st)
{
    double t0 = mesh_render_now_ms(), c0 = mesh_render_cpu_ms();
    memset(st, 0, sizeof *st);
    int width = g->width, height = g->height, nlev = g->max_level + 1;
    if (nlev > MIP2D_MAX_LEVELS)
        nlev = MIP2D_MAX_LEVELS;
    mip2d_t m;
    pp5_status_t s = mip2d_init(&m, width, height, nlev);
    if (s != PP5_OK)
        return s;
    float *levels = malloc(sizeof *levels * (size_t)width * (size_t)height);
    vrz_t v;
    memset(&v, 0, sizeof v);
    if (!levels)
        s = pp5_fail(PP5_E_NOMEM, "render: out of memory for %dx%d levels", width, height);
    for (int y = 0; y < height && s == PP5_OK; y++) {
        float *row = levels + (size_t)y * (size_t)width;
        gaze_level_row(g, y, width, gaze_x, gaze_y, 1.0, row);
        mip2d_mark_row_runs(&m, y, row, width);
    }
    if (s == PP5_OK)
        s = vrz_init(&v, &m, mesh_render_attrs(o->shading), &st->samples);
    if (s == PP5_OK)
        s = image8_alloc(img, width, height, 3);
    if (s == PP5_OK) {
        double c_tri = mesh_render_cpu_ms();
        mesh_render_triangles(soup, cam, o, width, height, vrz_sink, &v, st);
        st->cpu_ms_triangles = mesh_render_cpu_ms() - c_tri;
        vrz_resolve(&v, o, &m, &st->pixels_shaded);
        for (int y = 0; y < height; y++)
            mip2d_render_row(&m, y, levels + (size_t)y * (size_t)width, width,
                             img->pixels + 3 * (size_t)y * (size_t)width);
        st->fragments = v.fragments;
    }
    vrz_free(&v);
    free(levels);
    mip2d_free(&m);
    st->ms = mesh_render_now_ms() - t0;
    st->cpu_ms = mesh_render_cpu_ms() - c0;
    return s;
}
