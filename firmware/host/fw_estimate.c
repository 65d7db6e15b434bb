/* fw_estimate.c: the host's estimate of each band unit's GP work, so that a single frame's bands are balanced by samples, not rays (fw_plan_t FW_PLAN_SAMPLES).
 *
 * A band unit's work is its rays (the acuity model on a 4x4-subsampled grid,
 * as for FW_PLAN_RAYS) times what each ray costs: its setup, and the samples
 * it draws before the octree skips or early termination stops it.  The
 * samples come from a march through the volume's opacity on a coarse grid,
 * at the ray's own sample spacing; cycles per ray, sample and pixel come from
 * the firmware's cost rows (firmware/common/vr_cost.h) under this machine's
 * i860 cost model.  Host work, sent with the frame parameters, not charged to
 * the machine (firmware/ARCHITECTURE.md "Balanced single frames"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/common/vr_cost.h"
#include "fw_internal.h"
#include "gp_cost.h"
#include "render/classify.h"

/* Coarse cells are at most COARSE_SIDE per axis. */
#define COARSE_SIDE 128
#define PYRAMID_HEIGHTS 8

/* The mean of the volume over cell (i, j, k) of f^3 voxels. */
static float cell_mean(const volume_t *v, int f, int i, int j, int k)
{
    double sum = 0;
    int n = 0;
    for (int z = k * f; z < (k + 1) * f && z < v->nz; z++)
        for (int y = j * f; y < (j + 1) * f && y < v->ny; y++)
            for (int x = i * f; x < (i + 1) * f && x < v->nx; x++, n++)
                sum += volume_at(v, x, y, z);
    return n ? (float)(sum / n) : 0.0f;
}

/* The coarse occupancy pyramid: level 0 marks cells with opacity in them
 * or a neighbour (trilinear reads reach one voxel across), level k the OR of
 * level k-1's 2x2x2 blocks, as the octree's OR pyramid. */
static uint8_t *pyramid_at(const fw_session_t *s, int k, int x, int y, int z)
{
    int nx = (s->coarse_nx + (1 << k) - 1) >> k, ny = (s->coarse_ny + (1 << k) - 1) >> k;
    return s->coarse_occ[k] + ((size_t)z * ny + y) * nx + x;
}

static pp5_status_t build_pyramid(fw_session_t *s)
{
    int nx = s->coarse_nx, ny = s->coarse_ny, nz = s->coarse_nz;
    for (int k = 0; k < PYRAMID_HEIGHTS; k++) {
        int kx = (nx + (1 << k) - 1) >> k, ky = (ny + (1 << k) - 1) >> k, kz = (nz + (1 << k) - 1) >> k;
        s->coarse_occ[k] = calloc((size_t)kx * ky * kz, 1);
        if (!s->coarse_occ[k])
            return pp5_fail(PP5_E_NOMEM, "machine renderer: out of memory for the band estimate");
    }
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++) {
                if (!(s->coarse_alpha[((size_t)z * ny + y) * nx + x] > 0.0f))
                    continue;
                for (int dz = -1; dz <= 1; dz++)
                    for (int dy = -1; dy <= 1; dy++)
                        for (int dx = -1; dx <= 1; dx++) {
                            int X = x + dx, Y = y + dy, Z = z + dz;
                            if (X >= 0 && Y >= 0 && Z >= 0 && X < nx && Y < ny && Z < nz)
                                *pyramid_at(s, 0, X, Y, Z) = 1;
                        }
            }
    for (int k = 1; k < PYRAMID_HEIGHTS; k++) {
        int px = (nx + (1 << (k - 1)) - 1) >> (k - 1), py = (ny + (1 << (k - 1)) - 1) >> (k - 1),
            pz = (nz + (1 << (k - 1)) - 1) >> (k - 1);
        for (int z = 0; z < pz; z++)
            for (int y = 0; y < py; y++)
                for (int x = 0; x < px; x++)
                    if (*pyramid_at(s, k - 1, x, y, z))
                        *pyramid_at(s, k, x >> 1, y >> 1, z >> 1) = 1;
    }
    return PP5_OK;
}

/* The largest empty node of the pyramid around coarse cell c: its height
 * (0: the cell alone), or -1 when the cell is occupied.  Outside the grid
 * everything is empty. */
static int empty_height(const fw_session_t *s, const int c[3])
{
    if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= s->coarse_nx || c[1] >= s->coarse_ny ||
        c[2] >= s->coarse_nz)
        return PYRAMID_HEIGHTS - 1;
    for (int k = 0; k < PYRAMID_HEIGHTS; k++)
        if (*pyramid_at(s, k, c[0] >> k, c[1] >> k, c[2] >> k))
            return k - 1;
    return PYRAMID_HEIGHTS - 1;
}

/* A blend's stand-in for the opacity of coarse cell (i, j, k) (the march
 * below stops where the opacity reaches early termination): 0 where every
 * voxel is cold (the rays skip it), 1 where the mean's material is 1 (ray 1
 * stops at a saturated sample; MIDA, which needs its maximum at the
 * threshold too, in practice there as well), else a trace: the rays do not
 * terminate by opacity (firmware/ARCHITECTURE.md "Blends"). */
static float blend_cell_alpha(const fw_session_t *s, const volume_t *v, int f, int i, int j,
                              int k, float mean)
{
    const vr_config_t *c = &s->cfg;
    float hi = -INFINITY;
    for (int z = k * f; z < (k + 1) * f && z < v->nz; z++)
        for (int y = j * f; y < (j + 1) * f && y < v->ny; y++)
            for (int x = i * f; x < (i + 1) * f && x < v->nx; x++)
                hi = fmaxf(hi, volume_at(v, x, y, z));
    if (!(hi > c->cold_below))
        return 0.0f;
    float m = (mean - c->window_lo) * c->window_inv_width;
    if (m >= 1.0f)
        return 1.0f;
    return 1e-6f;
}

pp5_status_t fw_estimate_init(fw_session_t *s, const render_job_t *job)
{
    const volume_t *v = job->volume;
    int side = v->nx > v->ny ? (v->nx > v->nz ? v->nx : v->nz) : (v->ny > v->nz ? v->ny : v->nz);
    int f = (side + COARSE_SIDE - 1) / COARSE_SIDE;
    int nx = (v->nx + f - 1) / f, ny = (v->ny + f - 1) / f, nz = (v->nz + f - 1) / f;
    size_t n = (size_t)nx * ny * nz;
    float *mean = malloc(n * sizeof *mean);
    s->coarse_alpha = malloc(n * sizeof *s->coarse_alpha);
    if (!mean || !s->coarse_alpha) {
        free(mean);
        return pp5_fail(PP5_E_NOMEM, "machine renderer: out of memory for the band estimate");
    }
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++)
                mean[((size_t)k * ny + j) * nx + i] = cell_mean(v, f, i, j, k);
    /* Opacity per level-0 voxel length from the transfer function, with the
     * coarse central-difference gradient per level-0 voxel (a blend: its
     * stand-in, blend_cell_alpha). */
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                int c[3] = {i, j, k}, d[3] = {nx, ny, nz};
                double g2 = 0;
                for (int a = 0; a < 3; a++) {
                    int lo[3] = {i, j, k}, hi[3] = {i, j, k};
                    lo[a] = c[a] > 0 ? c[a] - 1 : c[a];
                    hi[a] = c[a] + 1 < d[a] ? c[a] + 1 : c[a];
                    if (hi[a] == lo[a])
                        continue;
                    double dv = mean[((size_t)hi[2] * ny + hi[1]) * nx + hi[0]] -
                                mean[((size_t)lo[2] * ny + lo[1]) * nx + lo[0]];
                    double gr = dv / ((hi[a] - lo[a]) * f) * s->dims.inv_spacing[a];
                    g2 += gr * gr;
                }
                float rgb[3];
                size_t idx = ((size_t)k * ny + j) * nx + i;
                s->coarse_alpha[idx] =
                    s->cfg.blend != VR_BLEND_COMPOSITE
                        ? blend_cell_alpha(s, v, f, i, j, k, mean[idx])
                        : classify_voxel(&job->tf, mean[idx], (float)sqrt(g2), rgb);
            }
    free(mean);
    s->coarse_nx = nx;
    s->coarse_ny = ny;
    s->coarse_nz = nz;
    s->coarse_f = f;
    pp5_status_t st = build_pyramid(s);
    if (st != PP5_OK)
        return st;
    gp_cost_t cost;
    gp_cost_init(&cost, &s->params);
    /* A typical ray, sample, skip (the leaf lookup, two steps up the
     * pyramid, the exit) and pixel, as the firmware's spans (vr_cost.h). */
    fw_ops_t ray, sample, skip, pixel;
    vr_cost_typical(&ray, &sample, &skip, &pixel);
    s->cycles_ray = (double)gp_cost_cycles(&cost, &ray);
    s->cycles_sample = (double)gp_cost_cycles(&cost, &sample);
    s->cycles_skip = (double)gp_cost_cycles(&cost, &skip);
    s->cycles_pixel = (double)gp_cost_cycles(&cost, &pixel);
    return PP5_OK;
}

/* Samples and octree skips of the level-m ray through image point (px, py):
 * a march at the ray's sample spacing that draws a sample in occupied
 * coarse cells and jumps over the largest empty node otherwise (as the
 * octree traversal does), until early termination. */
static void ray_work(const fw_session_t *s, const camera_t *cam, float px, float py, int m,
                     double *samples, double *skips)
{
    float o[3], d[3];
    camera_ray(cam, px, py, o, d);
    double step = s->rs.view.sample_step * (double)(1 << m), t0 = 0, t1 = INFINITY;
    for (int a = 0; a < 3; a++) {
        if (fabs(d[a]) < 1e-12) {
            if (o[a] < 0 || o[a] > cam->box_hi[a])
                return;
            continue;
        }
        double ta = (0 - o[a]) / d[a], tb = (cam->box_hi[a] - o[a]) / d[a];
        t0 = fmax(t0, fmin(ta, tb));
        t1 = fmin(t1, fmax(ta, tb));
    }
    double acc = 0, len = step * cam->inv_spacing[0];
    int guard = 0;
    for (double t = t0; t <= t1 && acc < s->rs.view.early_termination && guard < 100000; guard++) {
        int c[3];
        double cf[3];
        for (int a = 0; a < 3; a++) {
            cf[a] = (o[a] + t * d[a]) * cam->inv_spacing[a] / s->coarse_f;
            c[a] = (int)floor(cf[a]);
        }
        int h = empty_height(s, c);
        if (h < 0) {
            /* On the box's faces floor() can give the cell just outside the
             * grid: its neighbour is the one the ray samples. */
            int dims[3] = {s->coarse_nx, s->coarse_ny, s->coarse_nz}, q[3];
            for (int a = 0; a < 3; a++)
                q[a] = c[a] < 0 ? 0 : (c[a] >= dims[a] ? dims[a] - 1 : c[a]);
            float alpha = s->coarse_alpha[((size_t)q[2] * s->coarse_ny + q[1]) * s->coarse_nx + q[0]];
            *samples += 1;
            acc += (1 - acc) * (1 - pow(1 - fmin(alpha, 1.0), len));
            t += step;
            continue;
        }
        /* Jump to the node's exit along the ray (object units). */
        *skips += 1;
        double size = (double)(1 << h), t_exit = INFINITY;
        for (int a = 0; a < 3; a++) {
            double lo = floor(cf[a] / size) * size, hi = lo + size;
            double v = d[a] * cam->inv_spacing[a] / s->coarse_f;
            if (v > 1e-12)
                t_exit = fmin(t_exit, t + (hi - cf[a]) / v);
            else if (v < -1e-12)
                t_exit = fmin(t_exit, t + (lo - cf[a]) / v);
        }
        double k = ceil((t_exit - t) / step);
        t += (k < 1 ? 1 : k) * step;
    }
}

/* Columns of the 4x4-subsampled estimate grid (fw_estimate_unit). */
static int estimate_columns(const fw_session_t *s)
{
    return s->rs.width > 2 ? (s->rs.width - 2 + 3) / 4 : 0;
}

void fw_estimate_forget(fw_session_t *s)
{
    if (s->work_known)
        memset(s->work_known, 0, s->work_entries);
}

/* ray_work of column `col` of band unit u at 2D level l, from the memo when
 * this view already marched it (no memo when the host lacks the memory). */
static void unit_ray_work(fw_session_t *s, const camera_t *cam, int u, int col, int l, float px,
                          float py, double *samples, double *skips)
{
    if (!s->work_known) {
        size_t n = (size_t)s->n_units * (size_t)estimate_columns(s) * (size_t)s->cfg.levels2d;
        s->work_memo = malloc(2 * n * sizeof *s->work_memo);
        s->work_known = calloc(n, 1);
        if (!s->work_memo || !s->work_known) {
            free(s->work_memo);
            free(s->work_known);
            s->work_memo = NULL, s->work_known = NULL;
            ray_work(s, cam, px, py, l, samples, skips);
            return;
        }
        s->work_entries = n;
    }
    size_t e = ((size_t)u * (size_t)estimate_columns(s) + (size_t)col) * (size_t)s->cfg.levels2d +
               (size_t)l;
    if (!s->work_known[e]) {
        double a = 0, b = 0;
        ray_work(s, cam, px, py, l, &a, &b);
        s->work_memo[2 * e] = a, s->work_memo[2 * e + 1] = b;
        s->work_known[e] = 1;
    }
    *samples += s->work_memo[2 * e];
    *skips += s->work_memo[2 * e + 1];
}

double fw_estimate_unit(fw_session_t *s, const camera_t *cam, int u, double gx, double gy)
{
    int unit = 1 << (s->cfg.levels2d - 1), width = s->rs.width;
    bool gaze = s->rs.mode == RENDER_MODE_GAZE;
    double y = u * unit + 0.5 * unit, work = 0;
    for (int x = 2, col = 0; x < width; x += 4, col++) {
        float level = 0.0f;
        if (gaze) {
            double dx = x - gx, dy = y - gy;
            level = gaze_level(&s->gaze, sqrt(dx * dx + dy * dy));
        }
        /* This column of 4 pixels over the unit's rows: a pixel at a
         * fractional level needs the texels of both levels around it. */
        int m = (int)level;
        for (int l = m; l <= m + 1 && l < s->cfg.levels2d; l++) {
            if (l > m && !(level > (float)m))
                break;
            double rays = 4.0 * unit * pow(0.25, l), samples = 0, skips = 0;
            unit_ray_work(s, cam, u, col, l, (float)x + 0.5f, (float)y, &samples, &skips);
            work += rays * (s->cycles_ray + s->cycles_sample * samples + s->cycles_skip * skips);
        }
    }
    return work + s->cycles_pixel * width * unit;
}
