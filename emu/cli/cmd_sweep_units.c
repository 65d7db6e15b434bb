/* cmd_sweep_units.c: `pp5 sweep`'s grid points as work units
 * (emu/util/workunit.h): the unit of point pt is one frame on the machine of
 * that point (its own machine, setup and mip-map build, since all of them
 * depend on the point's parameters); the volume is loaded and resampled once
 * per process and shared by all its points.  On rank 0, after the last
 * point: the CSV and JSON report in grid order, the terminal lines and the
 * plot, made from the units' rows, so they are the same for any number of
 * ranks. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "emu/cli/cmd_sweep.h"
#include "json.h"

typedef struct {
    const sweep_t *sw;
    const render_job_t *job;
} sweep_units_t;

/* The canonical key of point pt: every axis as KEY=VALUE, in axis order. */
static pp5_status_t point_key(const sweep_t *sw, int pt, char *key, size_t cap)
{
    int idx[SWEEP_MAX_KEYS], rem = pt;
    for (int a = sw->n_axes - 1; a >= 0; a--) {
        idx[a] = rem % sw->axes[a].n;
        rem /= sw->axes[a].n;
    }
    size_t len = 0;
    for (int a = 0; a < sw->n_axes; a++) {
        int n = snprintf(key + len, cap - len, "%s%s=%s", a ? " " : "", sw->axes[a].key,
                         sw->axes[a].values[idx[a]]);
        if (n < 0 || (size_t)n >= cap - len)
            return pp5_fail(PP5_E_CONFIG, "sweep: point %d's parameters are too long", pt);
        len += (size_t)n;
    }
    return PP5_OK;
}

/* Everything the points share, one setting per line: with the keys it makes
 * the batch's plan hash, which a resumed run and a merge check. */
static void sweep_plan(const sweep_t *sw, char *plan, size_t cap)
{
    int n = snprintf(plan, cap, "volume=%s%s\nsize=%dx%d\nmode=%s\nlighting=%s\npreset=%s\naxes=",
                     sw->dataset ? "dataset:" : "phantom:", sw->dataset ? sw->dataset : sw->phantom,
                     sw->w, sw->h, render_mode_name(sw->mode), shade_case_name(sw->lighting),
                     sw->preset);
    for (int a = 0; a < sw->n_axes && n > 0 && (size_t)n < cap; a++)
        n += snprintf(plan + n, cap - (size_t)n, "%s%s", a ? "," : "", sw->axes[a].key);
}

static void point_json(FILE *f, const sweep_t *sw, const int *idx, pp5_status_t rst,
                       const fw_frame_result_t *r)
{
    json_writer_t j;
    json_init(&j, f, false);
    json_begin_object(&j);
    json_key(&j, "params");
    json_begin_object(&j);
    for (int a = 0; a < sw->n_axes; a++)
        json_kv_string(&j, sw->axes[a].key, sw->axes[a].values[idx[a]]);
    json_end_object(&j);
    if (rst == PP5_OK) {
        json_kv_double(&j, "frame_time_s", r->frame_time_s);
        json_key(&j, "phases_s");
        json_begin_object(&j);
        for (int k = 0; k < FW_PHASE_COUNT; k++)
            json_kv_double(&j, fw_phase_key((fw_phase_t)k), r->phase_s[k]);
        json_end_object(&j);
        json_kv_uint(&j, "rays", r->rays);
        json_kv_uint(&j, "samples", r->samples);
        json_kv_uint(&j, "ring_bytes", r->ring_bytes_total);
        json_kv_uint(&j, "ring_data_bytes", r->ring_bytes[RING_CLASS_DATA]);
        json_kv_uint(&j, "ring_pixel_bytes", r->ring_bytes[RING_CLASS_PIXELS]);
        json_kv_double(&j, "ring_util", r->ring_util_total);
        json_kv_double(&j, "gp_util_mean", r->gp_util_mean);
        json_kv_double(&j, "gp_util_max", r->gp_util_max);
        json_kv_double(&j, "gp_imbalance", r->gp_imbalance);
        json_kv_double(&j, "renderer_util_mean", r->rn_util_mean);
        json_kv_uint(&j, "gp_dcache_hits", r->dcache_hits);
        json_kv_uint(&j, "gp_dcache_misses", r->dcache_misses);
        json_kv_string(&j, "bottleneck", r->bottleneck);
    }
    json_end_object(&j);
}

/* A text written by fn into memory, without its final newline. */
static char *text_of(void (*fn)(FILE *, const sweep_t *, const int *, pp5_status_t,
                                const fw_frame_result_t *),
                     const sweep_t *sw, const int *idx, pp5_status_t rst,
                     const fw_frame_result_t *r)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f)
        return NULL;
    fn(f, sw, idx, rst, r);
    if (fclose(f) != 0) {
        free(buf);
        return NULL;
    }
    if (len > 0 && buf[len - 1] == '\n')
        buf[len - 1] = '\0';
    return buf;
}

static pp5_status_t sweep_unit(void *ctx, size_t index, const workunit_t *unit,
                               workunit_output_t *out)
{
    (void)unit;
    const sweep_units_t *su = ctx;
    int idx[SWEEP_MAX_KEYS];
    char label[64];
    pp5_params_t p;
    fw_options_t o;
    fw_frame_result_t r;
    memset(&r, 0, sizeof r);
    pp5_status_t st = sweep_point_config(su->sw, (int)index, idx, &p, &o, label, sizeof label);
    if (st == PP5_OK)
        st = sweep_run_point(su->sw, su->job, &p, &o, &r);
    /* The error text first: the row quotes it. */
    out->row = text_of(sweep_csv_row, su->sw, idx, st, &r);
    out->json = text_of(point_json, su->sw, idx, st, &r);
    out->frames = st == PP5_OK;
    return st;
}

/* The figures of a result row that the terminal line and the plot show. */
typedef struct {
    double frame_s, phase_s[FW_PHASE_COUNT], ring_bytes, imbalance, dcache_hit_rate;
    char bottleneck[96];
} row_figures_t;

/* The figures of a CSV row (sweep_csv_row's columns after the axes: the
 * frame time, its phases, then these, then the bottleneck). */
enum {
    COL_RAYS = 1 + FW_PHASE_COUNT, COL_SAMPLES, COL_RING_BYTES, COL_RING_DATA, COL_RING_PIXELS,
    COL_RING_UTIL, COL_GP_MEAN, COL_GP_MAX, COL_IMBALANCE, COL_RN_MEAN, COL_DC_HITS,
    COL_DC_MISSES, N_NUMERIC
};

static bool parse_row(const char *row, int n_axes, row_figures_t *f)
{
    const char *p = row;
    for (int a = 0; a < n_axes && p; a++)
        p = (p = strchr(p, ',')) ? p + 1 : NULL;
    double v[N_NUMERIC];
    for (int k = 0; k < N_NUMERIC && p; k++) {
        char *end;
        v[k] = strtod(p, &end);
        p = *end == ',' ? end + 1 : NULL;
    }
    if (!p)
        return false;
    f->frame_s = v[0];
    memcpy(f->phase_s, v + 1, sizeof f->phase_s);
    f->ring_bytes = v[COL_RING_BYTES];
    f->imbalance = v[COL_IMBALANCE];
    double lookups = v[COL_DC_HITS] + v[COL_DC_MISSES];
    f->dcache_hit_rate = lookups > 0 ? v[COL_DC_HITS] / lookups : 0.0;
    snprintf(f->bottleneck, sizeof f->bottleneck, "%s", p[0] == '"' ? p + 1 : p);
    size_t n = strlen(f->bottleneck);
    if (n > 0 && f->bottleneck[n - 1] == '"')
        f->bottleneck[n - 1] = '\0';
    return true;
}

/* Rank 0: the terminal lines and the plot, in grid order. */
static pp5_status_t sweep_report_points(const sweep_t *sw, const workunit_run_t *run)
{
    double *xs = calloc((size_t)sw->points, sizeof *xs);
    double *ph = calloc((size_t)sw->points * FW_PHASE_COUNT, sizeof *ph);
    char (*labels)[64] = calloc((size_t)sw->points, sizeof *labels);
    pp5_status_t st = xs && ph && labels ? PP5_OK : pp5_fail(PP5_E_NOMEM, "sweep: out of memory");
    for (int pt = 0; st == PP5_OK && pt < sw->points; pt++) {
        int idx[SWEEP_MAX_KEYS];
        pp5_params_t p;
        fw_options_t o;
        sweep_point_config(sw, pt, idx, &p, &o, labels[pt], sizeof labels[pt]);
        const workunit_result_t *r = &run->results[pt];
        row_figures_t f;
        xs[pt] = pt;
        if (r->failed || !parse_row(r->row, sw->n_axes, &f)) {
            printf("  %-24s error: %s\n", labels[pt], r->error);
            continue;
        }
        printf("  %-24s %9.2f ms  %6.2f f/s  ring %7.2f MB  GP max/mean %.2f  D-cache %5.1f %%  "
               "bottleneck: %s\n", labels[pt], f.frame_s * 1e3, 1.0 / f.frame_s,
               f.ring_bytes / 1e6, f.imbalance, 100.0 * f.dcache_hit_rate, f.bottleneck);
        for (int k = 0; k < FW_PHASE_COUNT; k++)
            ph[(size_t)k * sw->points + pt] = f.phase_s[k] * 1e3;
    }
    if (st == PP5_OK)
        st = sweep_write_plot(sw, xs, ph, labels);
    free(xs);
    free(ph);
    free(labels);
    return st;
}

/* Rank 0 of a whole-grid run: every output, then the log goes (or stays,
 * when points failed, for --resume). */
static pp5_status_t sweep_outputs(const sweep_t *sw, const workunit_list_t *l,
                                  const workunit_run_t *run, const char *header,
                                  const char *log_path)
{
    pp5_status_t st = workunit_write_csv(sw->out_csv, header, run);
    if (st == PP5_OK && sw->report)
        st = workunit_write_json(sw->report, "sweep", l, run);
    if (st == PP5_OK)
        st = sweep_report_points(sw, run);
    if (st != PP5_OK)
        return st;
    printf("wrote %s%s%s and %s\n", sw->out_csv, sw->report ? ", " : "",
           sw->report ? sw->report : "", sw->out_png);
    if (run->failed)
        printf("%zu of %d points failed (see their rows); the unit log %s stays: --resume runs "
               "them again\n", run->failed, sw->points, log_path);
    else
        remove(log_path);
    return PP5_OK;
}

static pp5_status_t sweep_list(const sweep_t *sw, workunit_list_t *l)
{
    workunit_list_init(l);
    pp5_status_t st = PP5_OK;
    for (int pt = 0; st == PP5_OK && pt < sw->points; pt++) {
        char key[SWEEP_MAX_KEYS * 100];
        if ((st = point_key(sw, pt, key, sizeof key)) == PP5_OK)
            st = workunit_list_add(l, key);
    }
    return st;
}

int sweep_run_units(const sweep_t *sw, const render_job_t *job)
{
    char plan[1024], log_path[1100], *header = NULL;
    size_t header_len = 0;
    FILE *hf = open_memstream(&header, &header_len);
    if (!hf)
        return cliopt_report("sweep", pp5_fail(PP5_E_NOMEM, "out of memory"));
    sweep_csv_header(hf, sw);
    fclose(hf);
    if (header_len > 0 && header[header_len - 1] == '\n')
        header[header_len - 1] = '\0';
    sweep_plan(sw, plan, sizeof plan);
    bool shard = sw->shard_n > 1;
    snprintf(log_path, sizeof log_path, shard ? "%s" : "%s.units", sw->out_csv);
    workunit_opts_t wo = {.command = "sweep", .plan = plan, .csv_header = header,
                          .log_path = log_path, .resume = sw->resume, .shard_k = sw->shard_k,
                          .shard_n = sw->shard_n, .accounting_path = sw->accounting};
    workunit_list_t l;
    workunit_run_t run = {0};
    sweep_units_t su = {sw, job};
    pp5_status_t st = sweep_list(sw, &l);
    if (st == PP5_OK)
        st = workunit_run(&l, &wo, sweep_unit, &su, &run);
    int rc = 0;
    if (!run.root && run.results)
        rc = st == PP5_OK ? 0 : 1;          /* an MPI rank that only computed: rank 0 reports */
    else if (!run.root)
        rc = cliopt_report("sweep", st);    /* failed before the run */
    else if (st == PP5_OK && shard)
        printf("wrote the part %s: shard %u/%u, %zu of the %d points (combine the parts with "
               "pp5 merge)\n", log_path, sw->shard_k, sw->shard_n, run.in_shard, sw->points);
    else if (st == PP5_OK)
        st = sweep_outputs(sw, &l, &run, header, log_path);
    if (run.root && st != PP5_OK)
        rc = cliopt_report("sweep", st);
    else if (run.root && run.failed)
        rc = WORKUNIT_EXIT_UNITS_FAILED;
    workunit_run_free(&run);
    workunit_list_free(&l);
    free(header);
    return rc;
}
