/* gaze2d.c: the retinal-acuity 2DLevel model and the partially populated 2D
 * mip map (see gaze2d.h for the model and the paper sections). */
#include "gaze2d.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEG (M_PI / 180.0)

void gaze_display_defaults(gaze_display_t *d)
{
    /* Gaze paper §6: 19" monitor viewed from 20", 37-degree image line,
     * full resolution inside 12 degrees (4.2"), 1 ray per 16 pixels outside
     * 20 degrees (7"), level 0 out to "roughly 5 inches in diameter". */
    d->monitor_diag_in = 19.0;
    d->monitor_aspect = 4.0 / 3.0;
    d->view_distance_in = 20.0;
    d->image_subtense_deg = 37.0;
    d->full_res_diameter_deg = 12.0;
    d->periphery_diameter_deg = 20.0;
    d->periphery_rays_per_px = 1.0 / 16.0;
    d->span1_diameter_in = 5.0;
    d->sigma_deg = 0.0;
}

pp5_status_t gaze_model_init(gaze_model_t *g, const gaze_display_t *d, int width, int height)
{
    memset(g, 0, sizeof *g);
    if (width < 1 || height < 1)
        return pp5_fail(PP5_E_RANGE, "gaze: image size %dx%d", width, height);
    if (!(d->view_distance_in > 0.0) || !(d->monitor_diag_in > 0.0) ||
        !(d->monitor_aspect > 0.0) || !(d->image_subtense_deg >= 0.0) ||
        !(d->image_subtense_deg < 170.0))
        return pp5_fail(PP5_E_CONFIG, "gaze: display geometry must be positive and finite");
    if (!(d->full_res_diameter_deg > 0.0) ||
        !(d->periphery_diameter_deg > d->full_res_diameter_deg) ||
        !(d->periphery_diameter_deg < 170.0))
        return pp5_fail(PP5_E_CONFIG, "gaze: need 0 < full-resolution diameter (%g) < "
                        "periphery diameter (%g) < 170 degrees",
                        d->full_res_diameter_deg, d->periphery_diameter_deg);
    if (!(d->periphery_rays_per_px > 0.0) || !(d->periphery_rays_per_px < 0.25 + 1e-12) ||
        d->periphery_rays_per_px < 1.0 / 65536.0)
        return pp5_fail(PP5_E_CONFIG, "gaze: periphery rays per pixel %g must lie in "
                        "[1/65536, 1/4]", d->periphery_rays_per_px);
    g->display = *d;
    g->width = width;
    g->height = height;
    double mon_w = d->monitor_diag_in * d->monitor_aspect / sqrt(1.0 + d->monitor_aspect *
                                                               d->monitor_aspect);
    double mon_h = mon_w / d->monitor_aspect;
    double image_w = d->image_subtense_deg > 0.0
                         ? 2.0 * d->view_distance_in * tan(0.5 * d->image_subtense_deg * DEG)
                         : mon_w;
    g->inches_per_px = image_w / (double)width;
    g->fits_monitor = image_w <= mon_w + 1e-9 && g->inches_per_px * height <= mon_h + 1e-9;
    g->e_full_deg = 0.5 * d->full_res_diameter_deg;
    g->e_edge_deg = 0.5 * d->periphery_diameter_deg;
    g->rho_min = d->periphery_rays_per_px;
    g->max_level = (int)ceil(log2(1.0 / g->rho_min) / 2.0 - 1e-9);
    if (g->max_level >= MIP2D_MAX_LEVELS)
        return pp5_fail(PP5_E_CONFIG, "gaze: periphery too coarse");
    if (d->sigma_deg > 0.0) {
        g->sigma_deg = d->sigma_deg;
    } else {
        double e5 = atan(0.5 * d->span1_diameter_in / d->view_distance_in) / DEG;
        double ratio = (1.0 - g->rho_min) / (0.25 - g->rho_min);
        if (e5 > g->e_full_deg && e5 < g->e_edge_deg && ratio > 1.0)
            g->sigma_deg = (e5 - g->e_full_deg) / sqrt(2.0 * log(ratio));
        else    /* a user geometry the 5" span does not fit: edge at 3 sigma */
            g->sigma_deg = (g->e_edge_deg - g->e_full_deg) / 3.0;
    }
    g->level_edge = (float)(0.5 * log2(1.0 / g->rho_min));
    g->r_zero_px = gaze_radius_px(g, g->e_full_deg) * (1.0 - 1e-9);
    g->r_max_px = gaze_radius_px(g, g->e_edge_deg) * (1.0 + 1e-9);
    return PP5_OK;
}

double gaze_eccentricity_deg(const gaze_model_t *g, double r_px)
{
    return atan(r_px * g->inches_per_px / g->display.view_distance_in) / DEG;
}

double gaze_radius_px(const gaze_model_t *g, double e_deg)
{
    return tan(e_deg * DEG) * g->display.view_distance_in / g->inches_per_px;
}

double gaze_target_rays_per_px(const gaze_model_t *g, double e_deg)
{
    if (e_deg <= g->e_full_deg)
        return 1.0;
    if (e_deg >= g->e_edge_deg)
        return g->rho_min;
    double x = (e_deg - g->e_full_deg) / g->sigma_deg;
    return g->rho_min + (1.0 - g->rho_min) * exp(-0.5 * x * x);
}

float gaze_level(const gaze_model_t *g, double r_px)
{
    if (r_px <= g->r_zero_px)
        return 0.0f;
    if (r_px >= g->r_max_px)
        return g->level_edge;
    double rho = gaze_target_rays_per_px(g, gaze_eccentricity_deg(g, r_px));
    double level = 0.5 * log2(1.0 / rho);
    if (level < 0.0)
        level = 0.0;
    if (level > g->max_level)
        level = g->max_level;
    return (float)level;
}

pp5_status_t gaze_level_tables_init(gaze_level_tables_t *t, const gaze_model_t *g, int w, int h)
{
    memset(t, 0, sizeof *t);
    if (w < 1 || h < 1 || w > 8192 || h > 8192)
        return pp5_fail(PP5_E_RANGE, "2DLevel tables: offsets %dx%d outside 1..8192", w, h);
    /* The 1D table reaches the periphery radius; past it every level is the
     * periphery level. */
    double far = g->r_max_px < sqrt((double)w * w + (double)h * h) ? g->r_max_px
                                                                  : sqrt((double)w * w + (double)h * h);
    t->n = (int)ceil(far * GAZE_TABLE_STEPS) + 2;
    t->w = w;
    t->h = h;
    t->dist = malloc((size_t)w * (size_t)h * sizeof *t->dist);
    t->level = malloc((size_t)t->n * sizeof *t->level);
    if (!t->dist || !t->level) {
        gaze_level_tables_free(t);
        return pp5_fail(PP5_E_NOMEM, "2DLevel tables: out of memory for %dx%d", w, h);
    }
    for (int dy = 0; dy < h; dy++)
        for (int dx = 0; dx < w; dx++)
            t->dist[(size_t)dy * w + dx] =
                (uint16_t)floor(sqrt((double)dx * dx + (double)dy * dy) * GAZE_TABLE_STEPS + 0.5);
    for (int k = 0; k < t->n; k++)
        t->level[k] = gaze_level(g, (double)k / GAZE_TABLE_STEPS);
    t->level_far = gaze_level(g, INFINITY);
    return PP5_OK;
}

void gaze_level_tables_free(gaze_level_tables_t *t)
{
    free(t->dist);
    free(t->level);
    memset(t, 0, sizeof *t);
}

void gaze_level_row_tabled(const gaze_level_tables_t *t, int y, int width, double gaze_x,
                           double gaze_y, double scale, float *levels)
{
    int gx = (int)floor(gaze_x + 0.5), gy = (int)floor(gaze_y + 0.5);
    for (int x = 0; x < width; x++)
        levels[x] = gaze_level_tabled(t, x - gx, y - gy, scale);
}

void mip2d_free(mip2d_t *m)
{
    for (int i = 0; i < MIP2D_MAX_LEVELS; i++) {
        free(m->rgb[i]);
        free(m->cast[i]);
        free(m->need[i]);
    }
    memset(m, 0, sizeof *m);
}

pp5_status_t mip2d_init(mip2d_t *m, int width, int height, int levels)
{
    memset(m, 0, sizeof *m);
    if (width < 1 || height < 1 || levels < 1 || levels > MIP2D_MAX_LEVELS)
        return pp5_fail(PP5_E_RANGE, "mip2d: %dx%d with %d levels", width, height, levels);
    m->levels = levels;
    m->width = width;
    m->height = height;
    for (int l = 0; l < levels; l++) {
        /* Enough texels for floor(x / 2^l) + 1 at the last pixel. */
        int w = ((width - 1) >> l) + 2, h = ((height - 1) >> l) + 2;
        size_t n = (size_t)w * (size_t)h;
        m->w[l] = w;
        m->h[l] = h;
        /* One float more than the texels: RenderPixel's fast path loads a
         * texel's three channels as four (mip2d_row.c). */
        m->rgb[l] = calloc(n * 3 + 1, sizeof(float));
        m->cast[l] = calloc(n, 1);
        m->need[l] = calloc(n, 1);
        if (!m->rgb[l] || !m->cast[l] || !m->need[l]) {
            mip2d_free(m);
            return pp5_fail(PP5_E_NOMEM, "mip2d: cannot allocate level %d", l);
        }
    }
    return PP5_OK;
}

void mip2d_clear(mip2d_t *m)
{
    for (int l = 0; l < m->levels; l++)
        memset(m->cast[l], 0, (size_t)m->w[l] * (size_t)m->h[l]);
}

void mip2d_clear_need(mip2d_t *m)
{
    for (int l = 0; l < m->levels; l++)
        memset(m->need[l], 0, (size_t)m->w[l] * (size_t)m->h[l]);
}

static void mark_level(mip2d_t *m, int l, int x, int y)
{
    int i = x >> l, j = y >> l;
    bool fx = (x & ((1 << l) - 1)) != 0, fy = (y & ((1 << l) - 1)) != 0;
    uint8_t *need = m->need[l];
    int w = m->w[l];
    need[(size_t)j * w + i] = 1;
    if (fx)
        need[(size_t)j * w + i + 1] = 1;
    if (fy)
        need[(size_t)(j + 1) * w + i] = 1;
    if (fx && fy)
        need[(size_t)(j + 1) * w + i + 1] = 1;
}

void mip2d_mark_pixel(mip2d_t *m, int x, int y, float level)
{
    int lo = (int)level;
    if (lo >= m->levels)
        lo = m->levels - 1;
    mark_level(m, lo, x, y);
    if (level > (float)lo && lo + 1 < m->levels)
        mark_level(m, lo + 1, x, y);
}

bool mip2d_mark_row(mip2d_t *m, int y, const float *levels, int width)
{
    bool full = true;
    for (int x = 0; x < width; x++) {
        float level = levels[x];
        if (level == 0.0f) {
            /* Level 0 lands exactly on its own texel. */
            m->need[0][(size_t)y * m->w[0] + x] = 1;
            continue;
        }
        full = false;
        mip2d_mark_pixel(m, x, y, level);
    }
    return full;
}

static void bilerp(const mip2d_t *m, int l, int x, int y, float rgb[3])
{
    int i = x >> l, j = y >> l;
    float s = (float)(1 << l);
    float u = (float)(x - (i << l)) / s, v = (float)(y - (j << l)) / s;
    int w = m->w[l];
    const float *c00 = m->rgb[l] + ((size_t)j * w + i) * 3;
    /* Zero-weight corners may be unpopulated: read them only when needed. */
    const float *c10 = u > 0.0f ? c00 + 3 : c00;
    const float *c01 = v > 0.0f ? c00 + (size_t)w * 3 : c00;
    const float *c11 = (u > 0.0f && v > 0.0f) ? c00 + ((size_t)w + 1) * 3 : (u > 0.0f ? c10 : c01);
    for (int k = 0; k < 3; k++) {
        float a = c00[k] + u * (c10[k] - c00[k]);
        float b = c01[k] + u * (c11[k] - c01[k]);
        rgb[k] = a + v * (b - a);
    }
}

void mip2d_pixel(const mip2d_t *m, int x, int y, float level, float rgb[3])
{
    int lo = (int)level;
    if (lo >= m->levels)
        lo = m->levels - 1;
    bilerp(m, lo, x, y, rgb);
    float t = level - (float)lo;
    if (t > 0.0f && lo + 1 < m->levels) {
        float hi[3];
        bilerp(m, lo + 1, x, y, hi);
        for (int k = 0; k < 3; k++)
            rgb[k] += t * (hi[k] - rgb[k]);
    }
}

uint64_t mip2d_count_cast(const mip2d_t *m)
{
    uint64_t n = 0;
    for (int l = 0; l < m->levels; l++) {
        size_t count = (size_t)m->w[l] * (size_t)m->h[l];
        for (size_t i = 0; i < count; i++)
            n += m->cast[l][i];
    }
    return n;
}
