/* renderer_native.c: one frame of the gaze-directed renderer (see the header
 * for the phases and why the output is thread-count independent). */
#include "renderer_native.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "blend_bricks.h"
#include "blend_trace.h"
#include "mip2d_row.h"
#include "parallel.h"

/* Host wall time for the timing report only; never feeds into the image. */
static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void render_settings_defaults(render_settings_t *s)
{
    memset(s, 0, sizeof *s);
    s->width = 512;
    s->height = 512;
    s->mode = RENDER_MODE_GAZE;
    s->gaze_x = 255.5;
    s->gaze_y = 255.5;
    view_defaults(&s->view);
    gaze_display_defaults(&s->display);
    s->threads = 0;
    s->progressive = false;
    s->progressive_growth = 2.0;
    blend_settings_defaults(&s->blend);
}

const char *render_mode_name(render_mode_t m)
{
    return m == RENDER_MODE_FULL ? "full" : "gaze";
}

pp5_status_t native_renderer_init(native_renderer_t *r, const volume_t *v, const classify_tf_t *tf,
                           const shade_params_t *shade, int threads)
{
    return native_renderer_init_format(r, v, tf, shade, MIP3D_F32, threads);
}

pp5_status_t native_renderer_init_format(native_renderer_t *r, const volume_t *v,
                                         const classify_tf_t *tf, const shade_params_t *shade,
                                         mip3d_format_t format, int threads)
{
    memset(r, 0, sizeof *r);
    r->tf = *tf;
    r->shade = *shade;
    r->threads = threads > 0 ? threads : parallel_default_threads();
    double t0 = now_ms();
    pp5_status_t st = mip3d_build_format(&r->mip, v, &r->tf, &r->shade, format, r->threads);
    if (st != PP5_OK)
        return st;
    double t1 = now_ms();
    st = octree_build(&r->octree, &r->mip, r->threads);
    if (st != PP5_OK) {
        mip3d_free(&r->mip);
        return st;
    }
    r->ms_build_mip = t1 - t0;
    r->ms_build_octree = now_ms() - t1;
    return PP5_OK;
}

pp5_status_t native_renderer_build_scalar(native_renderer_t *r, const volume_t *v,
                                          scalar_pyramid_kind_t kind)
{
    scalar_pyramid_free(&r->scalar);
    r->have_scalar = false;
    double t0 = now_ms();
    pp5_status_t st = scalar_pyramid_build(&r->scalar, v, kind, r->threads);
    if (st != PP5_OK)
        return st;
    const scalar_level_t *a = &r->scalar.level[0];
    const mip3d_level_t *b = &r->mip.level[0];
    if (a->nx != b->nx || a->ny != b->ny || a->nz != b->nz) {
        scalar_pyramid_free(&r->scalar);
        return pp5_fail(PP5_E_RANGE, "render: the value pyramid's volume is not the renderer's");
    }
    r->ms_build_scalar = now_ms() - t0;
    r->have_scalar = true;
    return PP5_OK;
}

void native_renderer_free(native_renderer_t *r)
{
    mip3d_free(&r->mip);
    octree_free(&r->octree);
    scalar_pyramid_free(&r->scalar);
    mip2d_free(&r->mip2d);
    gaze_level_tables_free(&r->tables);
    for (int l = 0; l < MIP2D_MAX_LEVELS; l++)
        blend_bins_free(&r->bins[l]);
    free(r->level_best);
    free(r->level_now);
    memset(r, 0, sizeof *r);
}

const float *native_renderer_levels(const native_renderer_t *r)
{
    return r->level_best;
}

/* Same view (camera, size, display, mode) as the previous frame? */
static bool same_view(const render_settings_t *a, const render_settings_t *b)
{
    return a->width == b->width && a->height == b->height && a->mode == b->mode &&
           a->level_tables == b->level_tables && memcmp(&a->view, &b->view, sizeof a->view) == 0 &&
           memcmp(&a->display, &b->display, sizeof a->display) == 0 &&
           memcmp(&a->blend, &b->blend, sizeof a->blend) == 0;
}

#define MARK_MAX_BANDS 1024

typedef struct {
    native_renderer_t *r;
    const render_settings_t *s;
    raycast_ctx_t ray;
    blend_ctx_t blend;            /* rays of --blend mip|demip|mida */
    int band_rows, bands, band_parity;
    bool band_full[MARK_MAX_BANDS];
    double gaze_scale;            /* eccentricity divisor for progressive growth */
    image8_t *out;
    int rows_total;               /* texel rows over all levels */
    int row_level[MIP2D_MAX_LEVELS + 1]; /* prefix sums of texel rows */
    /* MIP and DEMIP in brick order (blend_bricks.h): the tiles of all
     * levels numbered as one range (the bins are the renderer's). */
    int tile_level[MIP2D_MAX_LEVELS + 1];
    pp5_status_t tile_status[PARALLEL_MAX_THREADS];
    struct {
        raycast_counts_t c;
        char pad[64];             /* keep threads' counters on separate cache lines */
    } counts[PARALLEL_MAX_THREADS];
} frame_job_t;

static void job_levels_row(void *ctx, int y, int thread)
{
    (void)thread;
    frame_job_t *job = ctx;
    native_renderer_t *r = job->r;
    const render_settings_t *s = job->s;
    /* The first frame of a view has no earlier levels: the finest so far
     * is this frame's, written straight into level_best. */
    float *levels = job->r->frame_index == 0 ? r->level_best : r->level_now;
    float *now = levels + (size_t)y * s->width;
    /* Row 2 gaze_y - y has dy of exactly opposite sign when 2 gaze_y is an
     * integer (see gaze_level_row), so the same levels: the lower-numbered
     * row of each such pair computes both, the other item does nothing. */
    int twin = -1;
    double twice = 2.0 * s->gaze_y;
    if (s->mode == RENDER_MODE_GAZE && !s->level_tables && fabs(twice) < 1e9 &&
        twice == floor(twice)) {
        long t = (long)twice - y;
        if (t >= 0 && t < s->height && t != y) {
            if (t < y)
                return;
            twin = (int)t;
        }
    }
    if (s->mode == RENDER_MODE_GAZE && s->level_tables)
        gaze_level_row_tabled(&r->tables, y, s->width, s->gaze_x, s->gaze_y, job->gaze_scale, now);
    else if (s->mode == RENDER_MODE_GAZE)
        gaze_level_row(&r->gaze, y, s->width, s->gaze_x, s->gaze_y, job->gaze_scale, now);
    else
        for (int x = 0; x < s->width; x++)
            now[x] = 0.0f;
    for (int k = 0; k < (twin >= 0 ? 2 : 1); k++) {
        int row = k == 0 ? y : twin;
        float *dst = levels + (size_t)row * s->width;
        float *best = r->level_best + (size_t)row * s->width;
        if (k == 1)
            memcpy(dst, now, (size_t)s->width * sizeof(float));
        if (dst != best)
            for (int x = 0; x < s->width; x++)
                if (dst[x] < best[x])
                    best[x] = dst[x];
    }
}

/* Marks the texels needed by band 2*item + parity. */
static void job_mark_band(void *ctx, int item, int thread)
{
    (void)thread;
    frame_job_t *job = ctx;
    native_renderer_t *r = job->r;
    int band = 2 * item + job->band_parity;
    int y0 = band * job->band_rows, y1 = y0 + job->band_rows;
    if (y1 > job->s->height)
        y1 = job->s->height;
    bool full = true;
    for (int y = y0; y < y1; y++)
        if (!mip2d_mark_row_runs(&r->mip2d, y, r->level_best + (size_t)y * job->s->width,
                            job->s->width))
            full = false;
    job->band_full[band] = full;
}

static void job_cast_row(void *ctx, int item, int thread)
{
    frame_job_t *job = ctx;
    mip2d_t *m = &job->r->mip2d;
    int l = 0;
    while (item >= job->row_level[l + 1])
        l++;
    int j = item - job->row_level[l];
    size_t base = (size_t)j * m->w[l];
    /* Gather the row's uncast, needed texels and trace them in batches. */
    float px[RAYCAST_CHUNK], py[RAYCAST_CHUNK], rgb[RAYCAST_CHUNK][3];
    float guess = 0.0f;           /* threshold guess along the row (ray-order MIP/DEMIP) */
    int idx[RAYCAST_CHUNK], n = 0;
    bool composite = job->s->blend.mode == BLEND_COMPOSITE;
    int cap = composite ? RAYCAST_CHUNK : RAYCAST_BATCH;
    for (int i = 0; i <= m->w[l]; i++) {
        if (i < m->w[l]) {
            if (!m->need[l][base + i] || m->cast[l][base + i])
                continue;
            mip2d_texel_point(l, i, j, &px[n], &py[n]);
            idx[n++] = i;
        }
        if (n == cap || (i == m->w[l] && n > 0)) {
            if (composite)
                raycast_trace_rays(&job->ray, n, px, py, l, rgb, &job->counts[thread].c);
            else
                blend_trace_batch(&job->blend, n, px, py, l, rgb, &guess,
                                  &job->counts[thread].c);
            for (int b = 0; b < n; b++) {
                float *dst = m->rgb[l] + (base + (size_t)idx[b]) * 3;
                dst[0] = rgb[b][0];
                dst[1] = rgb[b][1];
                dst[2] = rgb[b][2];
                m->cast[l][base + (size_t)idx[b]] = 1;
            }
            n = 0;
        }
    }
}

/* The needed, not yet cast texels of one tile, traced in brick order. */
static void job_cast_tile(void *ctx, int item, int thread)
{
    frame_job_t *job = ctx;
    mip2d_t *m = &job->r->mip2d;
    int l = 0;
    while (item >= job->tile_level[l + 1])
        l++;
    const blend_bins_t *b = &job->r->bins[l];
    int tile = item - job->tile_level[l];
    int x0 = tile % b->tiles_x * BLEND_TILE, y0 = tile / b->tiles_x * BLEND_TILE;
    static _Thread_local int ti[BLEND_TILE * BLEND_TILE], tj[BLEND_TILE * BLEND_TILE];
    static _Thread_local float rgb[BLEND_TILE * BLEND_TILE][3];
    int n = 0;
    for (int j = y0; j < y0 + BLEND_TILE && j < m->h[l]; j++)
        for (int i = x0; i < x0 + BLEND_TILE && i < m->w[l]; i++) {
            size_t at = (size_t)j * m->w[l] + i;
            if (m->need[l][at] && !m->cast[l][at]) {
                ti[n] = i;
                tj[n++] = j;
            }
        }
    if (n == 0)
        return;
    pp5_status_t st = blend_trace_tile(&job->blend, b, tile, n, ti, tj, rgb,
                                       &job->counts[thread].c);
    if (st != PP5_OK) {
        job->tile_status[thread] = st;
        return;
    }
    for (int k = 0; k < n; k++) {
        size_t at = (size_t)tj[k] * m->w[l] + ti[k];
        memcpy(m->rgb[l] + at * 3, rgb[k], sizeof rgb[k]);
        m->cast[l][at] = 1;
    }
}

/* Bins every level's bricks to the tiles that have texels to cast. */
static pp5_status_t frame_bin_bricks(frame_job_t *job, int threads)
{
    const mip2d_t *m = &job->r->mip2d;
    job->tile_level[0] = 0;
    pp5_status_t st = PP5_OK;
    for (int l = 0; l < m->levels; l++) {
        int tx = (m->w[l] + BLEND_TILE - 1) / BLEND_TILE, ty = (m->h[l] + BLEND_TILE - 1) / BLEND_TILE;
        uint8_t *active = calloc((size_t)tx * ty, 1);
        if (!active)
            return pp5_fail(PP5_E_NOMEM, "render: out of memory");
        for (int j = 0; j < m->h[l]; j++)
            for (int i = 0; i < m->w[l]; i++) {
                size_t at = (size_t)j * m->w[l] + i;
                if (m->need[l][at] && !m->cast[l][at])
                    active[(j / BLEND_TILE) * tx + i / BLEND_TILE] = 1;
            }
        if (st == PP5_OK)
            st = blend_bins_build(&job->r->bins[l], &job->blend, l, m->w[l], m->h[l], active,
                                  threads);
        free(active);
        job->tile_level[l + 1] = job->tile_level[l] + tx * ty;
    }
    for (int l = m->levels + 1; l <= MIP2D_MAX_LEVELS; l++)
        job->tile_level[l] = job->tile_level[m->levels];
    return st;
}

static void job_reconstruct_row(void *ctx, int y, int thread)
{
    (void)thread;
    frame_job_t *job = ctx;
    const native_renderer_t *r = job->r;
    int w = job->s->width;
    uint8_t *row = job->out->pixels + (size_t)y * w * 3;
    mip2d_render_row(&r->mip2d, y, r->level_best + (size_t)y * w, w, row);
}

/* The frame's settings are usable (size, gaze, view, blend and its value
 * pyramid), before anything of the renderer is changed. */
static pp5_status_t frame_check_settings(const native_renderer_t *r, const render_settings_t *s)
{
    if (s->width < 1 || s->height < 1 || s->width > 16384 || s->height > 16384)
        return pp5_fail(PP5_E_RANGE, "render: image size %dx%d outside 1..16384",
                        s->width, s->height);
    if (!isfinite(s->gaze_x) || !isfinite(s->gaze_y))
        return pp5_fail(PP5_E_RANGE, "render: gaze point must be finite");
    if (!(s->view.sample_step > 0.0f) || !(s->view.sample_step <= 64.0f) ||
        !(s->view.zoom > 0.0f) || !isfinite(s->view.zoom) ||
        !(s->view.early_termination > 0.0f) || !(s->view.early_termination <= 1.0f))
        return pp5_fail(PP5_E_RANGE, "render: sample step (0, 64], zoom > 0 and early "
                        "termination (0, 1] required");
    pp5_status_t st = blend_settings_check(&s->blend);
    if (st != PP5_OK)
        return st;
    if (s->blend.mode != BLEND_COMPOSITE && (!r->have_scalar || r->scalar.kind != s->blend.pyramid))
        return pp5_fail(PP5_E_CONFIG, "render: --blend %s needs the %s value pyramid "
                        "(native_renderer_build_scalar)", blend_mode_name(s->blend.mode),
                        scalar_pyramid_kind_name(s->blend.pyramid));
    return PP5_OK;
}

/* The 2D mip map and level maps for this frame: kept (with every ray cast
 * so far) for a progressive frame of the same view, else cleared or made
 * anew; then the level tables and the view remembered. */
static pp5_status_t frame_prepare_buffers(native_renderer_t *r, const render_settings_t *s,
                                          const gaze_model_t *gm)
{
    bool keep = s->progressive && r->have_view && same_view(s, &r->last);
    int levels_wanted = s->mode == RENDER_MODE_GAZE ? gm->max_level + 1 : 1;
    pp5_status_t st;
    if (!keep && r->level_best && r->level_now && r->mip2d.width == s->width &&
        r->mip2d.height == s->height && r->mip2d.levels == levels_wanted) {
        /* A new view of the same size: reuse the buffers (fresh allocations
         * cost a page fault per 4 KiB on first touch, several ms a frame at
         * 1024x1024) and forget every cast ray.  Colours of uncast texels
         * are never read (each needed texel is cast first), so the image is
         * the same as with zeroed buffers. */
        mip2d_clear(&r->mip2d);
        r->frame_index = 0;
    } else if (!keep) {
        mip2d_free(&r->mip2d);
        free(r->level_best);
        free(r->level_now);
        r->level_best = r->level_now = NULL;
        r->have_view = false;
        st = mip2d_init(&r->mip2d, s->width, s->height, levels_wanted);
        if (st != PP5_OK)
            return st;
        size_t n = (size_t)s->width * (size_t)s->height;
        r->level_best = malloc(n * sizeof(float));
        r->level_now = malloc(n * sizeof(float));
        if (!r->level_best || !r->level_now)
            return pp5_fail(PP5_E_NOMEM, "render: cannot allocate level maps");
        r->frame_index = 0;
    } else {
        r->frame_index++;
    }
    if (s->level_tables && (r->tables.w != s->width || r->tables.h != s->height ||
                            memcmp(&r->tables_display, &s->display, sizeof s->display) != 0)) {
        r->tables_display = s->display;
        gaze_level_tables_free(&r->tables);
        if ((st = gaze_level_tables_init(&r->tables, gm, s->width, s->height)) != PP5_OK)
            return st;
    }
    r->gaze = *gm;
    r->last = *s;
    r->have_view = true;
    return PP5_OK;
}

/* Phase 1: 2DLevel per pixel, then the texels it needs, marked in bands of
 * rows; *full tells whether every band needs full resolution everywhere. */
static pp5_status_t frame_mark_texels(frame_job_t *job, int threads, bool *full)
{
    native_renderer_t *r = job->r;
    const render_settings_t *s = job->s;
    pp5_status_t st = parallel_for(threads, s->height, job_levels_row, job);
    mip2d_clear_need(&r->mip2d);
    /* Marking in bands of rows: a band writes texel rows up to and including
     * the first row of the next band, so even bands run in parallel, then odd
     * ones (flags are only ever set, so the result is order-independent). */
    job->band_rows = 16 << (r->mip2d.levels - 1);
    job->bands = (s->height + job->band_rows - 1) / job->band_rows;
    /* Heights are at most 16384 and bands at least 16 rows. */
    PP5_ASSERT(job->bands <= MARK_MAX_BANDS, "too many marking bands");
    if (st == PP5_OK) {
        job->band_parity = 0;
        st = parallel_for(threads, (job->bands + 1) / 2, job_mark_band, job);
    }
    if (st == PP5_OK) {
        job->band_parity = 1;
        st = parallel_for(threads, job->bands / 2, job_mark_band, job);
    }
    *full = true;
    for (int b = 0; b < job->bands; b++)
        *full = *full && job->band_full[b];
    return st;
}

/* Phase 2: cast every needed, not yet cast texel once, the texel rows of
 * all levels numbered as one range (row_level: its prefix sums). */
static pp5_status_t frame_cast_texels(frame_job_t *job, int threads, pp5_status_t st)
{
    const mip2d_t *m = &job->r->mip2d;
    job->row_level[0] = 0;
    for (int l = 0; l < m->levels; l++)
        job->row_level[l + 1] = job->row_level[l] + m->h[l];
    for (int l = m->levels + 1; l <= MIP2D_MAX_LEVELS; l++)
        job->row_level[l] = job->row_level[m->levels];
    if (st != PP5_OK)
        return st;
    if (job->s->blend.mode != BLEND_COMPOSITE && blend_bricks_apply(&job->blend)) {
        st = frame_bin_bricks(job, threads);
        if (st == PP5_OK)
            st = parallel_for(threads, job->tile_level[m->levels], job_cast_tile, job);
        for (int t = 0; st == PP5_OK && t < PARALLEL_MAX_THREADS; t++)
            st = job->tile_status[t];
        return st;
    }
    return parallel_for(threads, job->row_level[m->levels], job_cast_row, job);
}

/* The threads' ray and sample counters summed into the frame's statistics
 * (in thread order: integer sums, the same for any thread count). */
static void frame_sum_counts(const frame_job_t *job, render_stats_t *stats)
{
    for (int t = 0; t < PARALLEL_MAX_THREADS; t++) {
        stats->rays += job->counts[t].c.rays;
        stats->samples += job->counts[t].c.samples;
        stats->samples_skipped += job->counts[t].c.samples_skipped;
        stats->samples_retraced += job->counts[t].c.samples_retraced;
    }
}

pp5_status_t native_renderer_frame(native_renderer_t *r, const render_settings_t *s, image8_t *out,
                            render_stats_t *stats)
{
    memset(stats, 0, sizeof *stats);
    pp5_status_t st = frame_check_settings(r, s);
    if (st != PP5_OK)
        return st;
    double t_start = now_ms();
    int threads = s->threads > 0 ? s->threads : r->threads;
    gaze_model_t gm;
    st = gaze_model_init(&gm, &s->display, s->width, s->height);
    if (st != PP5_OK)
        return st;
    st = frame_prepare_buffers(r, s, &gm);
    if (st != PP5_OK)
        return st;
    st = image8_alloc(out, s->width, s->height, 3);
    if (st != PP5_OK)
        return st;

    frame_job_t *job = calloc(1, sizeof *job);
    if (!job)
        return pp5_fail(PP5_E_NOMEM, "render: out of memory");
    job->r = r;
    job->s = s;
    job->out = out;
    job->gaze_scale = s->progressive ? pow(s->progressive_growth > 1.0 ? s->progressive_growth
                                                                        : 1.0,
                                           r->frame_index)
                                     : 1.0;
    camera_t cam;
    camera_setup(&cam, &s->view, &r->mip, s->width, s->height);
    raycast_ctx_init(&job->ray, &r->mip, &r->octree, &cam, &r->shade, &s->view);
    if (s->blend.mode != BLEND_COMPOSITE)
        blend_ctx_init(&job->blend, &r->scalar, &cam, &s->view, &s->blend);

    double t1 = now_ms();
    bool full;
    st = frame_mark_texels(job, threads, &full);
    double t2 = now_ms();
    st = frame_cast_texels(job, threads, st);
    /* Phase 3: RenderPixel for every pixel. */
    double t3 = now_ms();
    if (st == PP5_OK)
        st = parallel_for(threads, s->height, job_reconstruct_row, job);
    /* The colour sphere's legend (seed 002 figure 1), drawn over the image. */
    if (st == PP5_OK && s->blend.mode == BLEND_DEMIP && s->blend.sphere_weight > 0.0f &&
        s->blend.legend)
        colour_sphere_draw_legend(&job->blend.frame.sphere, cam.right, cam.down, cam.forward,
                                  out);
    double t4 = now_ms();
    frame_sum_counts(job, stats);
    free(job);
    stats->ms_levels = t2 - t1;
    stats->ms_cast = t3 - t2;
    stats->ms_reconstruct = t4 - t3;
    stats->ms_total = t4 - t_start;
    stats->frame_index = r->frame_index;
    stats->full_resolution_everywhere = full;
    if (st != PP5_OK)
        image8_free(out);
    return st;
}
