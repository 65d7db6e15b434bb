/* vr_cast.c: per pass, the gaze-directed rays: TraceRay (render/raycast.c) on fetched bricks, with octree skipping, level blending and opacity correction, charged from counted kernel executions.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"

/* Kernel executions of a pass, converted to operations with vr_cost.h rows. */
typedef struct {
    uint64_t samples, skipped, trilerp, blend, oct_leaf, oct_up, skips, composites;
} cast_counts_t;

/* octree_empty_node (render/octree.c) on bit grids. */
static inline int oct_empty_node(const vr_state_t *s, int n, bool exact, const float p[3],
                                 float lo[3], float hi[3], uint32_t *ups)
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
    if (vr_bits_get(b0, c[0], c[1], c[2]))
        return -1;
    int h = 0;
    while (h + 1 < g->heights) {
        (*ups)++;
        if (vr_bits_get(&g->occ[h + 1], c[0] >> (h + 1), c[1] >> (h + 1), c[2] >> (h + 1)))
            break;
        h++;
    }
    float scale = (float)(1 << n);
    for (int a = 0; a < 3; a++) {
        int first = (c[a] >> h) << h;
        int last = first + (1 << h);
        lo[a] = first == 0 ? -INFINITY : ((float)first + 0.5f) * scale - 0.5f;
        hi[a] = last >= dims[a] ? INFINITY : ((float)last + 0.5f) * scale - 0.5f;
    }
    return h;
}

static inline void fetch4(const vr_state_t *s, int n, int x, int y, int z, float *out)
{
    const vr_unit_geom_t *u = &s->unit[n];
    int ix = x / u->ux, iy = y / u->uy, iz = z / u->uz;
    const uint32_t *b = s->cache[s->unit_base[n] + (iz * u->ugy + iy) * u->ugx + ix];
    if (!b) {
        out[0] = out[1] = out[2] = out[3] = 0.0f;
        return;
    }
    uint32_t w = b[((z - iz * u->uz) * u->uy + (y - iy * u->uy)) * u->ux + (x - ix * u->ux)];
    out[0] = s->u8_to_f[w & 255u];
    out[1] = s->u8_to_f[(w >> 8) & 255u];
    out[2] = s->u8_to_f[(w >> 16) & 255u];
    out[3] = s->u8_to_f[w >> 24];
}

/* mip3d_trilerp for 4 components (render/mip3d.h). */
static inline void trilerp(const vr_state_t *s, int n, float x, float y, float z, float *out)
{
    const vr_level_geom_t *L = &s->geom[n];
    float fx = floorf(x), fy = floorf(y), fz = floorf(z);
    float wx = x - fx, wy = y - fy, wz = z - fz;
    int x0 = (int)fx, y0 = (int)fy, z0 = (int)fz;
    int x1 = x0 + 1, y1 = y0 + 1, z1 = z0 + 1;
    x0 = x0 < 0 ? 0 : (x0 >= L->nx ? L->nx - 1 : x0);
    x1 = x1 < 0 ? 0 : (x1 >= L->nx ? L->nx - 1 : x1);
    y0 = y0 < 0 ? 0 : (y0 >= L->ny ? L->ny - 1 : y0);
    y1 = y1 < 0 ? 0 : (y1 >= L->ny ? L->ny - 1 : y1);
    z0 = z0 < 0 ? 0 : (z0 >= L->nz ? L->nz - 1 : z0);
    z1 = z1 < 0 ? 0 : (z1 >= L->nz ? L->nz - 1 : z1);
    float c000[4], c100[4], c010[4], c110[4], c001[4], c101[4], c011[4], c111[4];
    fetch4(s, n, x0, y0, z0, c000);
    fetch4(s, n, x1, y0, z0, c100);
    fetch4(s, n, x0, y1, z0, c010);
    fetch4(s, n, x1, y1, z0, c110);
    fetch4(s, n, x0, y0, z1, c001);
    fetch4(s, n, x1, y0, z1, c101);
    fetch4(s, n, x0, y1, z1, c011);
    fetch4(s, n, x1, y1, z1, c111);
    for (int k = 0; k < 4; k++) {
        float a = c000[k] + wx * (c100[k] - c000[k]);
        float b = c010[k] + wx * (c110[k] - c010[k]);
        float c = c001[k] + wx * (c101[k] - c001[k]);
        float d = c011[k] + wx * (c111[k] - c011[k]);
        float e = a + wy * (b - a);
        float f = c + wy * (d - c);
        out[k] = e + wz * (f - e);
    }
}

static inline void sample3d(const vr_state_t *s, float level3d, const float p[3], float *out,
                            cast_counts_t *cc)
{
    float top = (float)(s->cfg.levels - 1);
    if (level3d < 0.0f)
        level3d = 0.0f;
    if (level3d > top)
        level3d = top;
    int lo = (int)level3d;
    float t = level3d - (float)lo;
    trilerp(s, lo, vr_level_coord(p[0], lo), vr_level_coord(p[1], lo), vr_level_coord(p[2], lo), out);
    cc->trilerp++;
    if (t > 0.0f && lo + 1 < s->cfg.levels) {
        float hi[4];
        int n = lo + 1;
        trilerp(s, n, vr_level_coord(p[0], n), vr_level_coord(p[1], n), vr_level_coord(p[2], n), hi);
        cc->trilerp++;
        cc->blend++;
        for (int k = 0; k < 4; k++)
            out[k] += t * (hi[k] - out[k]);
    }
}

static inline float correct_alpha(const vr_state_t *s, int level2d, bool perspective, float spacing,
                                  float a)
{
    if (a >= 1.0f)
        return 1.0f;
    if (perspective || level2d >= VR_LUT_LEVELS)
        return 1.0f - powf(1.0f - a, spacing);
    float x = a * (float)VR_LUT_SIZE;
    int i = (int)x;
    if (i >= VR_LUT_SIZE)
        i = VR_LUT_SIZE - 1;
    float f = x - (float)i;
    const float *t = s->alpha_lut[level2d];
    return t[i] + f * (t[i + 1] - t[i]);
}

/* TraceRay (raycast_trace) for the samples with ray parameter t < t_stop.
 * A ray stopped at t_stop keeps its accumulated colour in rgb and its
 * opacity and position in *io_a, *io_t, *io_k, and resumes there (resume =
 * true) with exactly the same arithmetic.  Returns true when the ray is done. */
static bool trace(const vr_state_t *s, float px, float py, int level2d, float rgb[3],
                  cast_counts_t *cc, bool resume, float t_stop, float *io_a, float *io_t,
                  int32_t *io_k)
{
    const vr_config_t *c = &s->cfg;
    const vr_frame_t *f = &s->fr;
    float o[3], d[3], t0, t1;
    if (!resume)
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
    vr_camera_ray(f, c->width, c->height, px, py, o, d);
    if (!vr_clip_box(o, d, f->box_hi, &t0, &t1))
        return true;
    float ov[3], dv[3];
    for (int k = 0; k < 3; k++) {
        ov[k] = o[k] * c->inv_spacing[k];
        dv[k] = d[k] * c->inv_spacing[k];
    }
    const bool perspective = f->projection != 0;
    const float step = c->sample_step > 0.0f ? c->sample_step : 1.0f;
    const float offset = log2f(step);
    const float base = step * (float)(1 << level2d);
    const float growth = 1.0f + base / f->eye_distance;
    const float top = (float)(c->levels - 1);
    float acc[3] = {0.0f, 0.0f, 0.0f}, acc_a = 0.0f;
    float comp[4];
    long k = 0;
    float t = t0;
    if (perspective && t < 1e-3f)
        t = 1e-3f;
    if (resume) {
        acc[0] = rgb[0];
        acc[1] = rgb[1];
        acc[2] = rgb[2];
        acc_a = *io_a;
        k = *io_k;
        t = perspective ? *io_t : t0 + (float)k * base;
    }
    float spacing = base;
    float level3d = log2f(spacing) - offset;
    level3d = level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
    uint32_t ups = 0;
    while (t <= t1) {
        if (t >= t_stop) {
            /* end of this depth segment: park the ray */
            rgb[0] = acc[0];
            rgb[1] = acc[1];
            rgb[2] = acc[2];
            *io_a = acc_a;
            *io_k = (int32_t)k;
            *io_t = t;
            cc->oct_up += ups;
            return false;
        }
        if (perspective) {
            spacing = t * (growth - 1.0f);
            level3d = log2f(spacing) - offset;
            level3d = level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
        }
        float p[3] = {ov[0] + t * dv[0], ov[1] + t * dv[1], ov[2] + t * dv[2]};
        if (c->use_octree) {
            float lo[3], hi[3];
            int n = (int)level3d;
            cc->oct_leaf++;
            if (oct_empty_node(s, n, level3d == (float)n, p, lo, hi, &ups) >= 0) {
                cc->skips++;
                float t_exit = INFINITY;
                for (int a = 0; a < 3; a++) {
                    float te = INFINITY;
                    if (dv[a] > 0.0f && isfinite(hi[a]))
                        te = (hi[a] - ov[a]) / dv[a];
                    else if (dv[a] < 0.0f && isfinite(lo[a]))
                        te = (lo[a] - ov[a]) / dv[a];
                    if (te < t_exit)
                        t_exit = te;
                }
                if (!(t_exit <= t1))
                    break;
                t_exit -= 1e-3f;
                if (perspective) {
                    float t_level = exp2f((float)(n + 1) + offset) / (growth - 1.0f);
                    if (n + 1 <= (int)top && t_level < t_exit)
                        t_exit = t_level;
                    do {
                        t *= growth;
                        cc->skipped++;
                    } while (t < t_exit && t <= t1);
                } else {
                    long k_new = (long)ceilf((t_exit - t0) / base);
                    if (k_new <= k)
                        k_new = k + 1;
                    cc->skipped += (uint64_t)(k_new - k);
                    k = k_new;
                    t = t0 + (float)k * base;
                }
                continue;
            }
        }
        sample3d(s, level3d, p, comp, cc);
        cc->samples++;
        float col[3] = {comp[0], comp[1], comp[2]};
        float a = comp[3];
        if (a > 0.0f) {
            if (spacing != 1.0f) {
                float ac = correct_alpha(s, level2d, perspective, spacing, a);
                float scale = ac / a;
                col[0] *= scale;
                col[1] *= scale;
                col[2] *= scale;
                a = ac;
            }
            float tt = 1.0f - acc_a;
            acc[0] += tt * col[0];
            acc[1] += tt * col[1];
            acc[2] += tt * col[2];
            acc_a += tt * a;
            cc->composites++;
            if (acc_a >= c->early_termination)
                break;
        }
        if (perspective) {
            t *= growth;
        } else {
            k++;
            t = t0 + (float)k * base;
        }
    }
    cc->oct_up += ups;
    rgb[0] = acc[0];
    rgb[1] = acc[1];
    rgb[2] = acc[2];
    *io_a = acc_a;             /* a finished ray's opacity (object slabs composite it) */
    return true;
}

/* Casts the texels of this pass whose pixel rows (row << level) lie in
 * [py0, py1): new rays, and rays parked at the end of the previous depth
 * segment.  Charged from the counted kernel executions. */
void vr_cast_texels(gp_t *gp, vr_state_t *s, int py0, int py1)
{
    uint64_t c0 = fw_cycles(gp), t0 = fw_time_ps(gp);
    cast_counts_t cc;
    memset(&cc, 0, sizeof cc);
    uint64_t rays = 0, calls = 0;
    float px0, px1, tseg[2];
    vr_plan_pass_range(s, s->pass, &px0, &px1);
    vr_plan_seg_range(s, s->pass, &tseg[0], &tseg[1]);
    for (int m = 0; m < s->levels2d; m++) {
        for (int j = s->jlo[m]; j <= s->jhi[m]; j++) {
            if ((j << m) < py0 || (j << m) >= py1)
                continue;
            size_t row = (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *nd = s->need[m] + row;
            uint8_t *cf = s->castf[m] + row, *rsx = s->ray_state[m] + row;
            float *tx = s->texel[m] + row * 3;
            for (int i = 0; i < s->tw[m]; i++) {
                float px = (float)(i << m) + 0.5f;
                if (!nd[i] || cf[i] || rsx[i] == 2 || px < px0 || px >= px1)
                    continue;
                bool resume = rsx[i] == 1;
                if (!resume)
                    rays++;
                calls++;
                bool done = trace(s, px, (float)(j << m) + 0.5f, m, tx + 3 * i, &cc, resume, tseg[1],
                                  s->ray_a[m] + row + i, s->ray_t[m] + row + i, s->ray_k[m] + row + i);
                if (done) {
                    rsx[i] = 2;
                    cf[i] = 1;
                } else {
                    rsx[i] = 1;
                }
            }
        }
    }
    fw_ops_t ops = {0};
    vr_cost_add(&ops, &VR_COST_RAY, calls);
    vr_cost_add(&ops, &VR_COST_SAMPLE, cc.samples + cc.skips);
    vr_cost_add(&ops, &VR_COST_TRILERP, cc.trilerp);
    vr_cost_add(&ops, &VR_COST_LEVEL_BLEND, cc.blend);
    vr_cost_add(&ops, &VR_COST_OCT_LEAF, cc.oct_leaf);
    vr_cost_add(&ops, &VR_COST_OCT_UP, cc.oct_up);
    vr_cost_add(&ops, &VR_COST_SKIP, cc.skips);
    vr_cost_add(&ops, &VR_COST_COMPOSITE, cc.composites);
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_CAST, fw_cycles(gp) - c0);
    vr_stat_add(gp, s, VR_STAT_RAYS, rays);
    vr_stat_add(gp, s, VR_STAT_SAMPLES, cc.samples);
    vr_stat_add(gp, s, VR_STAT_SKIPPED, cc.skipped);
    vr_stat_add(gp, s, VR_STAT_SKIPS, cc.skips);
    vr_stat_add(gp, s, VR_STAT_CAST_PS, fw_time_ps(gp) - t0);
}

/* After the last pass: our first texel row of each level goes to the GP
 * above, which needs it for its last pixel rows. */
fw_status_t vr_cast_send_boundary(gp_t *gp, vr_state_t *s)
{
    size_t floats = 0;
    for (int m = 0; m < s->levels2d; m++)
        floats += (size_t)s->tw[m] * 3;
    float *buf = fw_alloc(gp, floats * sizeof(float));
    if (!buf)
        return FW_ERROR;
    size_t off = 0;
    for (int m = 0; m < s->levels2d; m++) {
        memcpy(buf + off, s->texel[m], (size_t)s->tw[m] * 3 * sizeof(float));
        off += (size_t)s->tw[m] * 3;
    }
    fw_ops_t o2 = {0};
    o2.loads = o2.stores = floats;
    fw_charge(gp, &o2);
    fw_status_t rc = vr_send_gp(gp, (unsigned)(s->g - 1), VR_MSG_BOUNDARY, (uint32_t)s->frame, 0,
                                buf, floats * sizeof(float));
    fw_free(gp, buf);
    return rc;
}

/* ---- object slabs: ray segments ---- */

/* The level-0 slice of sample k of a parallel ray, with the same float
 * expressions as trace's sample position. */
static inline long sample_slice(float t0, float base, long k, float oz, float dz)
{
    float t = t0 + (float)k * base;
    return (long)floorf(oz + t * dz + 0.5f);
}

/* Samples [k_lo, k_hi) of the parallel level-m ray through (px, py) that lie
 * in slices [zlo, zhi): the sample slices are monotone in k, so two binary
 * searches find the ends.  False when no sample of the ray is in the slab. */
static bool segment_samples(const vr_state_t *s, float px, float py, int m, long zlo, long zhi,
                            long *k_lo, long *k_hi, float *t_end, uint64_t *probes)
{
    const vr_config_t *c = &s->cfg;
    float o[3], d[3], t0, t1;
    vr_camera_ray(&s->fr, c->width, c->height, px, py, o, d);
    if (!vr_clip_box(o, d, s->fr.box_hi, &t0, &t1))
        return false;
    float oz = o[2] * c->inv_spacing[2], dz = d[2] * c->inv_spacing[2];
    float base = (c->sample_step > 0.0f ? c->sample_step : 1.0f) * (float)(1 << m);
    long kmax = (long)floorf((t1 - t0) / base) + 1;         /* samples with t <= t1 */
    while (kmax > 0 && t0 + (float)(kmax - 1) * base > t1)
        kmax--;
    bool up = dz >= 0.0f;
    /* first k whose slice is >= lim (up) or < lim (down) */
    long bound[2];
    long lims[2] = {up ? zlo : zhi, up ? zhi : zlo};
    for (int e = 0; e < 2; e++) {
        long lo = 0, hi = kmax;
        while (lo < hi) {
            long mid = lo + (hi - lo) / 2;
            long z = sample_slice(t0, base, mid, oz, dz);
            bool past = up ? z >= lims[e] : z < lims[e];
            (*probes)++;
            if (past)
                hi = mid;
            else
                lo = mid + 1;
        }
        bound[e] = lo;
    }
    *k_lo = bound[0];
    *k_hi = bound[1];
    *t_end = *k_hi >= kmax ? INFINITY : t0 + (float)*k_hi * base;
    return *k_lo < *k_hi;
}

size_t vr_cast_slab_segments(gp_t *gp, vr_state_t *s, const vr_texel_list_t *tl, long zlo,
                             long zhi, vr_partial_t *out)
{
    uint64_t c0 = fw_cycles(gp), t0 = fw_time_ps(gp), calls = 0, probes = 0;
    cast_counts_t cc;
    memset(&cc, 0, sizeof cc);
    size_t n_out = 0;
    for (size_t i = 0; i < tl->n; i++) {
        const vr_texel_ref_t *r = &tl->t[i];
        float px = (float)(r->i << r->m) + 0.5f, py = (float)(r->j << r->m) + 0.5f;
        long k_lo, k_hi;
        float t_end;
        if (!segment_samples(s, px, py, r->m, zlo, zhi, &k_lo, &k_hi, &t_end, &probes))
            continue;
        float rgb[3] = {0.0f, 0.0f, 0.0f}, a = 0.0f, t_park = 0.0f;
        int32_t k = (int32_t)k_lo;
        calls++;
        trace(s, px, py, r->m, rgb, &cc, true, t_end, &a, &t_park, &k);
        if (a > 0.0f || rgb[0] > 0.0f || rgb[1] > 0.0f || rgb[2] > 0.0f)
            out[n_out++] = (vr_partial_t){r->code, {rgb[0], rgb[1], rgb[2], a}};
    }
    fw_ops_t ops = {0};
    vr_cost_add(&ops, &VR_COST_RAY, calls + (uint64_t)tl->n);
    vr_cost_add(&ops, &VR_COST_SEGMENT_PROBE, probes);
    vr_cost_add(&ops, &VR_COST_SAMPLE, cc.samples + cc.skips);
    vr_cost_add(&ops, &VR_COST_TRILERP, cc.trilerp);
    vr_cost_add(&ops, &VR_COST_LEVEL_BLEND, cc.blend);
    vr_cost_add(&ops, &VR_COST_OCT_LEAF, cc.oct_leaf);
    vr_cost_add(&ops, &VR_COST_OCT_UP, cc.oct_up);
    vr_cost_add(&ops, &VR_COST_SKIP, cc.skips);
    vr_cost_add(&ops, &VR_COST_COMPOSITE, cc.composites);
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_CAST, fw_cycles(gp) - c0);
    vr_stat_add(gp, s, VR_STAT_SAMPLES, cc.samples);
    vr_stat_add(gp, s, VR_STAT_SKIPPED, cc.skipped);
    vr_stat_add(gp, s, VR_STAT_SKIPS, cc.skips);
    vr_stat_add(gp, s, VR_STAT_CAST_PS, fw_time_ps(gp) - t0);
    return n_out;
}
