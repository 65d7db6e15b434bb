/* fw_analysis.c: a finished frame's figures from the machine's named statistics: work, ring traffic, utilisation, and the critical-path split of the frame time.
 *
 * Everything is read from the statistics of the frame (a difference of two
 * snapshots, emu/stats.h): the GP program's published counters and phase
 * times ("gp.G.prog.*", firmware/common/vr_stats.h) and the units' own
 * counters.  The split is described in firmware/ARCHITECTURE.md "Frame
 * report". */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fw_internal.h"

/* A program statistic of GP g in the frame. */
static double prog(const stats_t *f, unsigned g, const char *name)
{
    return stats_valuef(f, "gp.%u.prog.%s", g, name);
}

pp5_status_t fw_frame_check_finished(const fw_session_t *s, const stats_t *f)
{
    char list[256] = "";
    unsigned stuck = 0;
    size_t used = 0;
    for (unsigned g = 0; g < s->m.n_gp; g++) {
        if (!(prog(f, g, "t_done_ps") < prog(f, g, "t_start_ps")))
            continue;
        if (stuck++ < 8 && used + 16 < sizeof list)
            used += (size_t)snprintf(list + used, sizeof list - used, "%s%u", stuck > 1 ? ", " : "", g);
    }
    if (stuck == 0)
        return PP5_OK;
    return pp5_fail(PP5_E_FIRMWARE, "machine renderer: the frame went idle with %u GP(s) unfinished "
                    "(%s%s): a message they waited for was never sent", stuck, list,
                    stuck > 8 ? ", ..." : "");
}

static void gather_work(fw_session_t *s, const stats_t *f, double T, fw_frame_result_t *r)
{
    bool all0 = true;
    double gsum = 0, gmax = 0;
    for (unsigned g = 0; g < s->m.n_gp; g++) {
        fw_gp_frame_t *p = &s->last_gp[g];
        memset(p, 0, sizeof *p);
        p->band_y0 = s->last_bands[g];
        p->band_y1 = s->last_bands[g + 1];
        p->rays = (uint64_t)prog(f, g, "rays");
        p->samples = (uint64_t)prog(f, g, "samples");
        p->bricks_fetched = (uint64_t)prog(f, g, "bricks_fetched");
        p->cycles_prep = (uint64_t)prog(f, g, "cycles_prep");
        p->cycles_pp_stream_build = (uint64_t)prog(f, g, "cycles_pp_stream_build");
        p->cycles_forward = (uint64_t)prog(f, g, "cycles_forward");
        p->cycles_receive = (uint64_t)prog(f, g, "cycles_receive");
        p->cycles_shade = (uint64_t)prog(f, g, "cycles_shade");
        p->cycles_cast = (uint64_t)prog(f, g, "cycles_cast");
        p->cycles_resample = (uint64_t)prog(f, g, "cycles_resample");
        p->busy_s = stats_valuef(f, "gp.%u.busy_s", g);
        p->done_s = ticks_to_s((pp5_tick_t)(prog(f, g, "t_done_ps") - prog(f, g, "t_start_ps")));
        p->mem_peak_bytes = (uint64_t)stats_valuef(f, "gp.%u.mem_peak_bytes", g);
        r->rays += p->rays;
        r->samples += p->samples;
        r->samples_skipped += (uint64_t)prog(f, g, "samples_skipped");
        r->bricks_fetched += p->bricks_fetched;
        r->bytes_fetched += (uint64_t)prog(f, g, "bytes_fetched");
        r->pp_stream_words += (uint64_t)prog(f, g, "pp_stream_words");
        r->dcache_hits += (uint64_t)stats_valuef(f, "gp.%u.frames_dcache_hits", g);
        r->dcache_misses += (uint64_t)stats_valuef(f, "gp.%u.frames_dcache_misses", g);
        r->ray2_samples += (uint64_t)prog(f, g, "demip_ray2_samples");
        r->rays_saturated += (uint64_t)prog(f, g, "mip_rays_saturated");
        r->rays_occluded += (uint64_t)prog(f, g, "demip_rays_occluded");
        r->rays_terminated += (uint64_t)prog(f, g, "mida_rays_terminated");
        if (prog(f, g, "all_level0") == 0)
            all0 = false;
        uint64_t passes = (uint64_t)prog(f, g, "passes");
        r->passes_max = passes > r->passes_max ? passes : r->passes_max;
        double u = T > 0 ? p->busy_s / T : 0;
        gsum += u;
        gmax = u > gmax ? u : gmax;
    }
    r->full_resolution_everywhere = all0;
    r->gp_util_mean = s->m.n_gp ? gsum / s->m.n_gp : 0;
    r->gp_util_max = gmax;
    r->gp_imbalance = r->gp_util_mean > 0 ? gmax / r->gp_util_mean : 1.0;
}

static void gather_ring_and_renderers(const fw_session_t *s, const stats_t *f, double T,
                                      fw_frame_result_t *r)
{
    double bw = pp5_params_ring_aggregate_bytes_per_s(&s->params);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        r->ring_bytes[k] = (uint64_t)stats_valuef(f, "ring.by_class.%s.bytes_sent", stats_class_name(k));
        r->ring_bytes_total += r->ring_bytes[k];
        r->ring_util[k] = T > 0 ? (double)r->ring_bytes[k] / (bw * T) : 0.0;
        r->ring_util_total += r->ring_util[k];
    }
    double rsum = 0, rmax = 0;
    for (unsigned j = 0; j < s->m.n_rn; j++) {
        double u = T > 0 ? stats_valuef(f, "renderer.%u.busy_s", j) / T : 0;
        rsum += u;
        rmax = u > rmax ? u : rmax;
        uint64_t ex = (uint64_t)stats_valuef(f, "renderer.%u.exec_cycles", j);
        r->rn_exec_cycles_max = ex > r->rn_exec_cycles_max ? ex : r->rn_exec_cycles_max;
    }
    r->rn_util_mean = s->m.n_rn ? rsum / s->m.n_rn : 0;
    r->rn_util_max = rmax;
}

/* The GP that sent its last section last, and the GP whose work the path
 * runs through: if the critical GP waited for its neighbour's boundary rows,
 * the neighbour's casting is on the path. */
static void critical_gps(const fw_session_t *s, const stats_t *f, int *crit, int *path)
{
    double crit_done = -1;
    *crit = 0;
    for (unsigned g = 0; g < s->m.n_gp; g++) {
        double done = prog(f, g, "t_done_ps");
        if (done >= crit_done) {
            crit_done = done;
            *crit = (int)g;
        }
    }
    *path = *crit;
    unsigned c = (unsigned)*crit;
    if (c + 1 < s->m.n_gp && s->last_gp[c + 1].rays > 0 &&
        prog(f, c, "t_boundary_ps") > prog(f, c, "t_cast_done_ps") &&
        prog(f, c + 1, "t_cast_done_ps") > prog(f, c, "t_cast_done_ps"))
        *path = (int)c + 1;
}

/* GP compute (prep, stream build, cast, resample) of GP g, in seconds. */
static double gp_compute_s(const fw_session_t *s, unsigned g)
{
    const fw_gp_frame_t *p = &s->last_gp[g];
    return (double)(p->cycles_prep + p->cycles_pp_stream_build + p->cycles_cast + p->cycles_resample) /
           s->params.gp_clock_hz;
}

/* The part of the critical path's GP compute that the mean GP did not need:
 * lost to an uneven division, not to the speed of casting. */
static double imbalance_s(const fw_session_t *s, unsigned path, unsigned crit)
{
    double sum = 0;
    unsigned n = 0;
    for (unsigned g = 0; g < s->m.n_gp; g++)
        if (s->last_gp[g].band_y1 > s->last_gp[g].band_y0) {
            sum += gp_compute_s(s, g);
            n++;
        }
    const fw_gp_frame_t *pp = &s->last_gp[path], *pc = &s->last_gp[crit];
    double on_path = (double)(pp->cycles_prep + pp->cycles_pp_stream_build + pp->cycles_cast +
                              pc->cycles_resample) / s->params.gp_clock_hz;
    double excess = n ? on_path - sum / n : 0;
    return excess > 0 ? excess : 0;
}

static void split_phases(fw_session_t *s, const stats_t *f, pp5_tick_t t0, double T,
                         fw_frame_result_t *r)
{
    int crit, path;
    critical_gps(s, f, &crit, &path);
    r->critical_gp = crit;
    r->critical_path_gp = path;
    unsigned p = (unsigned)path, c = (unsigned)crit;
    double ts = ticks_to_s((pp5_tick_t)prog(f, p, "t_start_ps") - t0);
    double tc = ticks_to_s((pp5_tick_t)prog(f, p, "t_cast_done_ps") - t0);
    double tb = ticks_to_s((pp5_tick_t)prog(f, c, "t_boundary_ps") - t0);
    double te = ticks_to_s((pp5_tick_t)prog(f, c, "t_done_ps") - t0);
    double wait = prog(f, p, "wait_ps") * 1e-12, cast = prog(f, p, "cast_ps") * 1e-12;
    /* prep: before the first requests, plus the footprints of later passes */
    double prep = (tc - ts) - wait - cast;
    const fw_gp_frame_t *gp = &s->last_gp[p];
    double recv = (double)(gp->cycles_receive + gp->cycles_forward + gp->cycles_shade) /
                  s->params.gp_clock_hz;
    recv = recv > wait ? wait : recv;
    double exec_max_s = (double)r->rn_exec_cycles_max / s->params.renderer_clock_hz;
    double pp = exec_max_s < wait - recv ? exec_max_s : wait - recv;
    pp = pp < 0 ? 0 : pp;
    double resample = te - tb;
    /* The imbalance comes out of the path's own compute: cast first. */
    double imb = imbalance_s(s, p, c), left = imb;
    double *from[3] = {&cast, &prep, &resample};
    for (int k = 0; k < 3 && left > 0; k++) {
        double take = *from[k] < left ? *from[k] : left;
        *from[k] -= take;
        left -= take;
    }
    r->phase_s[FW_PHASE_HOST_START] = ts;
    r->phase_s[FW_PHASE_GP_PREP] = prep;
    r->phase_s[FW_PHASE_GP_RECEIVE] = recv;
    r->phase_s[FW_PHASE_PP_SHADE] = pp;
    r->phase_s[FW_PHASE_RING_FETCH] = wait - recv - pp;
    r->phase_s[FW_PHASE_GP_CAST] = cast;
    r->phase_s[FW_PHASE_GP_IMBALANCE] = imb - left;
    r->phase_s[FW_PHASE_GP_EXCHANGE] = tb - tc;
    r->phase_s[FW_PHASE_GP_RESAMPLE] = resample;
    r->phase_s[FW_PHASE_FB_TRANSFER] = T - te;
}

void fw_frame_analyse(fw_session_t *s, const stats_t *f, pp5_tick_t t0, pp5_tick_t t1,
                      fw_frame_result_t *r)
{
    double T = ticks_to_s(t1 - t0);
    r->frame_time_s = T;
    gather_work(s, f, T, r);
    gather_ring_and_renderers(s, f, T, r);
    split_phases(s, f, t0, T, r);
    int best = 0;
    for (int k = 1; k < FW_PHASE_COUNT; k++)
        if (r->phase_s[k] > r->phase_s[best])
            best = k;
    r->bottleneck = fw_phase_name((fw_phase_t)best);
    r->ok = true;
}
