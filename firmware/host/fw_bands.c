/* fw_bands.c: which image rows each GP owns in a frame: equal bands, bands of equal estimated work, and the estimate's correction from the previous frame.
 *
 * Host work, not charged to the machine (firmware/ARCHITECTURE.md "Which GP
 * casts which rays"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fw_internal.h"

void fw_bands_equal(int height, int n_gp, int levels2d, int32_t *band_y0)
{
    /* Equal bands whose starts are multiples of 2^(levels2d-1) (so every
     * band's texel rows start on a texel boundary of every 2D level). */
    int unit = 1 << (levels2d - 1);
    int units = (height + unit - 1) / unit;
    /* Fewer units than GPs: one unit each, the empty bands last (a GP's
     * boundary rows always come from the next GP). */
    for (int g = 0; g <= n_gp; g++) {
        int u = units >= n_gp ? (int)(((long long)units * g) / n_gp) : (g < units ? g : units);
        int y = u * unit;
        band_y0[g] = y > height ? height : y;
    }
    band_y0[n_gp] = height;
}

/* Estimated rays of one band unit (2^(levels2d-1) rows): the acuity model
 * (gaze2d.h) on a 4x4-subsampled grid, plus a per-row share for the
 * resampling every pixel needs. */
static double unit_rays(const fw_session_t *s, int u, double gx, double gy)
{
    int unit = 1 << (s->cfg.levels2d - 1), width = s->rs.width;
    bool gaze = s->rs.mode == RENDER_MODE_GAZE;
    double y = u * unit + 0.5 * unit, sum = 0;
    for (int x = 2; x < width; x += 4) {
        float level = 0.0f;
        if (gaze) {
            double dx = x - gx, dy = y - gy;
            level = gaze_level(&s->gaze, sqrt(dx * dx + dy * dy));
        }
        sum += pow(0.25, level);
    }
    return sum * 4.0 * unit + 0.02 * width * unit;
}

/* Cuts the units into n_gp bands of equal summed weight, leaving at least
 * one unit for every remaining band. */
static void cut_bands(const double *w, int units, int unit, int height, int n_gp, int32_t *band_y0)
{
    double total = 0, acc = 0;
    for (int u = 0; u < units; u++)
        total += w[u];
    int g = 1;
    band_y0[0] = 0;
    for (int u = 0; u < units && g < n_gp; u++) {
        acc += w[u];
        if (acc >= total * g / n_gp || units - (u + 1) <= n_gp - g) {
            int y = (u + 1) * unit;
            band_y0[g++] = y > height ? height : y;
        }
    }
    for (; g <= n_gp; g++)
        band_y0[g] = height;
    band_y0[n_gp] = height;
}

void fw_bands_plan(fw_session_t *s, double gx, double gy, int32_t *band_y0)
{
    int n_gp = (int)s->m.n_gp, levels2d = s->cfg.levels2d, height = s->rs.height;
    int unit = 1 << (levels2d - 1);
    int units = s->n_units;
    double *w = calloc((size_t)units, sizeof *w);
    if (!w || units < n_gp) {
        free(w);
        fw_bands_equal(height, n_gp, levels2d, band_y0);
        return;
    }
    camera_t cam;
    if (s->opts.plan == FW_PLAN_SAMPLES)
        camera_setup(&cam, &s->rs.view, &s->dims, s->rs.width, s->rs.height);
    for (int u = 0; u < units; u++) {
        w[u] = s->opts.plan == FW_PLAN_SAMPLES ? fw_estimate_unit(s, &cam, u, gx, gy)
                                               : unit_rays(s, u, gx, gy);
        s->unit_weight[u] = w[u];
        /* Rays plan: the measured cost per estimated ray of the rows' GP in
         * the previous frame (samples per ray vary with the data).  The
         * samples plan already estimates that from the data for this gaze;
         * the previous frame's factors belong to rows under another gaze. */
        if (s->opts.plan == FW_PLAN_RAYS && s->frames > 0 && s->unit_factor[u] > 0)
            w[u] *= s->unit_factor[u];
    }
    cut_bands(w, units, unit, height, n_gp, band_y0);
    free(w);
}

void fw_bands_learn(fw_session_t *s, const stats_t *frame)
{
    int unit = 1 << (s->cfg.levels2d - 1);
    double fsum = 0;
    int fn = 0;
    for (unsigned g = 0; g < s->m.n_gp; g++) {
        int u0 = s->last_bands[g] / unit, u1 = (s->last_bands[g + 1] + unit - 1) / unit;
        if (u1 <= u0)
            continue;
        double wsum = 0;
        for (int u = u0; u < u1 && u < s->n_units; u++)
            wsum += s->unit_weight[u];
        const char *phases[] = {"cycles_prep", "cycles_cast", "cycles_resample", "cycles_receive",
                                "cycles_shade"};
        double cost = 0;
        for (size_t k = 0; k < sizeof phases / sizeof phases[0]; k++)
            cost += stats_valuef(frame, "gp.%u.prog.%s", g, phases[k]);
        double fct = wsum > 0 && cost > 0 ? cost / wsum : 0;
        for (int u = u0; u < u1 && u < s->n_units; u++)
            s->unit_factor[u] = fct;
        if (fct > 0) {
            fsum += fct;
            fn++;
        }
    }
    for (int u = 0; u < s->n_units && fn > 0; u++)
        s->unit_factor[u] = s->unit_factor[u] > 0 ? s->unit_factor[u] / (fsum / fn) : 1.0;
}

void fw_slabs_plan(const fw_session_t *s, int32_t *slab_z0)
{
    int n_gp = (int)s->m.n_gp, nz = s->cfg.nz;
    double total = 0, w[VR_MAX_GPS * 64 + 1];
    int nw = 0;
    /* Weight of each level-0 slice: occupied coarse cells of its coarse
     * slice (or 1 without the estimate), each coarse slice shared by its
     * coarse_f slices. */
    for (int z = 0; z < nz && nw < (int)(sizeof w / sizeof w[0]); z++, nw++) {
        double c = 1.0;
        if (s->coarse_alpha) {
            int k = z / s->coarse_f;
            size_t plane = (size_t)s->coarse_nx * s->coarse_ny, base = (size_t)k * plane;
            c = 0;
            for (size_t i = 0; i < plane; i++)
                c += s->coarse_alpha[base + i] > 0.0f;
            c = c / s->coarse_f + 1e-3;
        }
        w[nw] = c;
        total += c;
    }
    double acc = 0;
    int g = 1;
    slab_z0[0] = 0;
    for (int z = 0; z < nw && g < n_gp; z++) {
        acc += w[z];
        if (acc >= total * g / n_gp)
            slab_z0[g++] = z + 1;
    }
    for (; g <= n_gp; g++)
        slab_z0[g] = nz;
}
