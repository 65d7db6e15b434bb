/* cmd_sweep.c: `pp5 sweep`: work-division studies: the machine renderer over a grid of machine parameters and firmware settings, a CSV row per point and a stacked-by-phase plot of frame time. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "outfile.h"
#include "emu/cli/cmd_sweep.h"
#include "firmware/host/fw_session.h"
#include "plot.h"
#include "registry.h"
#include "render/scene.h"

static void sweep_usage(FILE *out)
{
    fprintf(out,
            "usage: pp5 sweep [--set KEY=V1,V2,...]... [--out FILE.csv] [--plot FILE.png]\n"
            "                 [--phantom NAME | --dataset mrbrain] [--size WxH] [--mode gaze|full]\n"
            "                 [--lighting diffuse|specular] [--preset NAME] [--report FILE.json]\n"
            "                 [--resume] [--shard K/N] [--accounting FILE.json]\n"
            "       mpirun -n N pp5 sweep ...   (the same outputs, the points shared among N ranks)\n\n"
            "Runs one frame of the gaze-directed renderer on the emulated machine for every\n"
            "point of a grid of parameters and writes a CSV (frame time, its critical-path\n"
            "phases, rays, samples, ring bytes, utilisation, GP imbalance and the GPs'\n"
            "data-cache line lookups) and a PNG of frame time against the grid, stacked by\n"
            "phase, so you see where the machine saturates and how the work divisions\n"
            "compare.  The console shows each point's data-cache hit rate (D-cache).\n\n"
            "  --set KEY=V1,V2,...  a machine parameter (see `pp5 machine`: gp.count,\n"
            "                       renderer.count, ring.channels, ring.clock_hz, gp.clock_hz,\n"
            "                       renderer.clock_hz, ...) or a firmware setting: division=\n"
            "                       image-bands,resident,object-slabs; split=pp,gp (where the\n"
            "                       viewpoint-dependent shading runs); plan=rays,samples (how\n"
            "                       bands are balanced); level_tables=0,1 (2DLevel exact or by\n"
            "                       the paper's tables).  Several --set make a grid\n"
            "                       (default: --set gp.count=1,2,4,8,16,32)\n"
            "  --out FILE.csv       (default sweep.csv)\n"
            "  --plot FILE.png      (default sweep.png)\n"
            "  --phantom NAME       volume (default shepp-logan at 128x128x109)\n"
            "  --dataset mrbrain    the MR subject, resampled to 128x128x109\n"
            "  --size WxH           image size (default 210x210, the paper's Table I)\n"
            "  --mode gaze|full     (default gaze, gaze at the image centre)\n"
            "  --lighting L         specular (default; ks 0.4: the PPs shade every frame) or diffuse\n"
            "  --preset NAME        machine preset (default, gaze1990-literal)\n"
            "  --report FILE.json   every point's parameters and results (or error) as JSON\n"
            "  --resume             keep the points already done in FILE.csv.units (the unit\n"
            "                       log a killed or failed run leaves) and run the rest; points\n"
            "                       that failed run again\n"
            "  --shard K/N          run only the points whose unit id mod N is K, into the part\n"
            "                       file --out (a unit log; no CSV, plot or report): `pp5 merge`\n"
            "                       combines the N parts into the CSV of the whole grid\n"
            "  --accounting FILE    JSON of what the run cost: ranks, units per rank, host\n"
            "                       seconds per unit, parallel efficiency (a summary always goes\n"
            "                       to stderr; host times never enter the CSV or report)\n"
            "  --help               this text\n\n"
            "Each point is a work unit with a stable id (a hash of its parameters).  Under an\n"
            "MPI launcher, rank 0 hands the points out one at a time and writes the outputs in\n"
            "grid order: they are byte-identical to the plain run for any number of ranks.  A\n"
            "point that fails (e.g. GP memory too small) is a row with its error; the others\n"
            "still run, and the exit code is 8 (units failed).\n\n"
            "Examples:\n"
            "  pp5 sweep --set division=image-bands,resident,object-slabs --out d.csv --plot d.png\n"
            "  mpirun -n 2 pp5 sweep --set gp.count=4,8,16,32 --set ring.channels=1,8 --out s.csv\n"
            "  pp5 sweep --set gp.count=4,8,16,32 --shard 1/2 --out s.part1   (then pp5 merge)\n");
}

/* KEY=V1,V2,... with every value checked now, not half-way through the grid. */
static pp5_status_t parse_axis(const char *arg, sweep_axis_t *ax)
{
    const char *eq = strchr(arg, '=');
    if (!eq || eq == arg || (size_t)(eq - arg) >= sizeof ax->key)
        return pp5_fail(PP5_E_CONFIG, "--set: expected KEY=V1,V2,..., got '%s'", arg);
    memset(ax, 0, sizeof *ax);
    memcpy(ax->key, arg, (size_t)(eq - arg));
    for (const char *p = eq + 1; *p;) {
        const char *c = strchr(p, ',');
        size_t len = c ? (size_t)(c - p) : strlen(p);
        if (len == 0 || len >= sizeof ax->values[0] || ax->n >= SWEEP_MAX_VALUES)
            return pp5_fail(PP5_E_CONFIG, "--set %s: bad value list", ax->key);
        memcpy(ax->values[ax->n], p, len);
        for (int k = 0; k < ax->n; k++)
            if (strcmp(ax->values[k], ax->values[ax->n]) == 0)
                return pp5_fail(PP5_E_CONFIG, "--set %s: value %s is given twice", ax->key,
                                ax->values[k]);
        ax->n++;
        p += len + (c ? 1 : 0);
    }
    if (ax->n == 0)
        return pp5_fail(PP5_E_CONFIG, "--set %s: no values", ax->key);
    pp5_params_t probe;
    pp5_params_default(&probe);
    fw_options_t fo;
    fw_options_default(&fo);
    for (int i = 0; i < ax->n; i++) {
        char kv[128];
        snprintf(kv, sizeof kv, "%s=%s", ax->key, ax->values[i]);
        bool taken = false;
        pp5_status_t st = fw_options_set(&fo, kv, &taken);
        if (st == PP5_OK && !taken)
            st = pp5_params_set(&probe, ax->key, ax->values[i]);
        if (st != PP5_OK)
            return st;
    }
    return PP5_OK;
}

static pp5_status_t parse_option(sweep_t *sw, int c, const char *a)
{
    switch (c) {
    case 's':
        if (sw->n_axes >= SWEEP_MAX_KEYS)
            return pp5_fail(PP5_E_CONFIG, "at most %d --set axes", SWEEP_MAX_KEYS);
        return parse_axis(a, &sw->axes[sw->n_axes++]);
    case 'o': sw->out_csv = a; return PP5_OK;
    case 'p': sw->out_png = a; return PP5_OK;
    case 'P': sw->phantom = a; sw->dataset = NULL; return PP5_OK;
    case 'd': sw->dataset = a; return PP5_OK;
    case 'z': return cliopt_size2("--size", a, 8, 1280, &sw->w, &sw->h);
    case 'm':
        if (strcmp(a, "gaze") == 0 || strcmp(a, "full") == 0) {
            sw->mode = strcmp(a, "gaze") == 0 ? RENDER_MODE_GAZE : RENDER_MODE_FULL;
            return PP5_OK;
        }
        return pp5_fail(PP5_E_CONFIG, "--mode: gaze or full, got '%s'", a);
    case 'l':
        if (strcmp(a, "specular") == 0 || strcmp(a, "diffuse") == 0) {
            sw->lighting = strcmp(a, "specular") == 0 ? SHADE_SPECULAR_FIXED_LIGHT
                                                      : SHADE_DIFFUSE_FIXED_LIGHT;
            return PP5_OK;
        }
        return pp5_fail(PP5_E_CONFIG, "--lighting: specular or diffuse, got '%s'", a);
    case 'r': sw->preset = a; return PP5_OK;
    case 'j': sw->report = a; return PP5_OK;
    case 'a': sw->accounting = a; return PP5_OK;
    case 'R': sw->resume = true; return PP5_OK;
    case 'S': return workunit_parse_shard(a, &sw->shard_k, &sw->shard_n);
    default: return PP5_E_CONFIG;
    }
}

/* 0: go on; 1: help printed; 2: usage error; else a failed status. */
static int parse_args(int argc, char **argv, sweep_t *sw, pp5_status_t *st)
{
    static const struct option opts[] = {
        {"set", required_argument, NULL, 's'},   {"out", required_argument, NULL, 'o'},
        {"plot", required_argument, NULL, 'p'},  {"phantom", required_argument, NULL, 'P'},
        {"dataset", required_argument, NULL, 'd'}, {"size", required_argument, NULL, 'z'},
        {"mode", required_argument, NULL, 'm'},  {"lighting", required_argument, NULL, 'l'},
        {"preset", required_argument, NULL, 'r'}, {"help", no_argument, NULL, 'h'},
        {"report", required_argument, NULL, 'j'}, {"accounting", required_argument, NULL, 'a'},
        {"resume", no_argument, NULL, 'R'},      {"shard", required_argument, NULL, 'S'},
        {NULL, 0, NULL, 0}};
    *sw = (sweep_t){.out_csv = "sweep.csv", .out_png = "sweep.png", .phantom = "shepp-logan",
                    .preset = "default", .w = 210, .h = 210, .mode = RENDER_MODE_GAZE,
                    .lighting = SHADE_SPECULAR_FIXED_LIGHT};
    *st = PP5_OK;
    optind = 1;
    int c;
    while (*st == PP5_OK && (c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        if (c == 'h') {
            sweep_usage(stdout);
            return 1;
        }
        if (c == '?') {
            sweep_usage(stderr);
            return 2;
        }
        *st = parse_option(sw, c, optarg);
    }
    if (*st == PP5_OK && optind < argc)
        *st = pp5_fail(PP5_E_CONFIG, "unexpected argument '%s'", argv[optind]);
    if (*st == PP5_OK && sw->n_axes == 0)
        *st = parse_axis("gp.count=1,2,4,8,16,32", &sw->axes[sw->n_axes++]);
    sw->points = 1;
    for (int a = 0; a < sw->n_axes; a++)
        sw->points *= sw->axes[a].n;
    if (*st == PP5_OK && sw->points > SWEEP_MAX_POINTS)
        *st = pp5_fail(PP5_E_CONFIG, "grid of %d points (max %d)", sw->points, SWEEP_MAX_POINTS);
    return 0;
}

/* The machine and the firmware settings of grid point pt, and its label
 * (the values of the axes that vary). */
pp5_status_t sweep_point_config(const sweep_t *sw, int pt, int *idx, pp5_params_t *p,
                                fw_options_t *o, char *label, size_t label_cap)
{
    pp5_params_default(p);
    fw_options_default(o);
    pp5_status_t st = pp5_params_preset(p, sw->preset);
    label[0] = '\0';
    int rem = pt;
    for (int a = sw->n_axes - 1; a >= 0; a--) {
        idx[a] = rem % sw->axes[a].n;
        rem /= sw->axes[a].n;
    }
    for (int a = 0; st == PP5_OK && a < sw->n_axes; a++) {
        const char *v = sw->axes[a].values[idx[a]];
        char kv[128];
        snprintf(kv, sizeof kv, "%s=%s", sw->axes[a].key, v);
        bool taken = false;
        st = fw_options_set(o, kv, &taken);
        if (st == PP5_OK && !taken)
            st = pp5_params_set(p, sw->axes[a].key, v);
        size_t l = strlen(label);
        if (sw->axes[a].n > 1 || sw->n_axes == 1)
            snprintf(label + l, label_cap - l, "%s%s", l ? "," : "", v);
    }
    return st == PP5_OK ? pp5_params_validate(p) : st;
}

void sweep_csv_header(FILE *csv, const sweep_t *sw)
{
    for (int a = 0; a < sw->n_axes; a++)
        fprintf(csv, "%s,", sw->axes[a].key);
    fprintf(csv, "frame_time_s");
    for (int k = 0; k < FW_PHASE_COUNT; k++)
        fprintf(csv, ",%s", fw_phase_key((fw_phase_t)k));
    fprintf(csv, ",rays,samples,ring_bytes,ring_data_bytes,ring_pixel_bytes,ring_util,gp_util_mean,"
                 "gp_util_max,gp_imbalance,renderer_util_mean,gp_dcache_hits,gp_dcache_misses,"
                 "bottleneck\n");
}

void sweep_csv_row(FILE *csv, const sweep_t *sw, const int *idx, pp5_status_t rst,
                   const fw_frame_result_t *r)
{
    for (int a = 0; a < sw->n_axes; a++)
        fprintf(csv, "%s,", sw->axes[a].values[idx[a]]);
    if (rst != PP5_OK) {
        /* A point that does not fit (memory, backing store) is a result too. */
        fprintf(csv, "nan");
        for (int k = 0; k < FW_PHASE_COUNT; k++)
            fprintf(csv, ",nan");
        fprintf(csv, ",0,0,0,0,0,0,0,0,0,0,0,0,\"error: %s\"\n", pp5_error_text());
        return;
    }
    fprintf(csv, "%.9g", r->frame_time_s);
    for (int k = 0; k < FW_PHASE_COUNT; k++)
        fprintf(csv, ",%.9g", r->phase_s[k]);
    fprintf(csv, ",%llu,%llu,%llu,%llu,%llu,%.6f,%.6f,%.6f,%.6f,%.6f,%llu,%llu,\"%s\"\n",
            (unsigned long long)r->rays, (unsigned long long)r->samples,
            (unsigned long long)r->ring_bytes_total,
            (unsigned long long)r->ring_bytes[RING_CLASS_DATA],
            (unsigned long long)r->ring_bytes[RING_CLASS_PIXELS], r->ring_util_total,
            r->gp_util_mean, r->gp_util_max, r->gp_imbalance, r->rn_util_mean,
            (unsigned long long)r->dcache_hits, (unsigned long long)r->dcache_misses, r->bottleneck);
}

/* One frame of the job on the machine of point pt. */
pp5_status_t sweep_run_point(const sweep_t *sw, const render_job_t *job, const pp5_params_t *p,
                             const fw_options_t *o, fw_frame_result_t *r)
{
    fw_session_t s;
    memset(r, 0, sizeof *r);
    pp5_status_t st = fw_session_init(&s, job, p, o);
    if (st == PP5_OK)
        st = fw_session_frame(&s, 0.5 * (sw->w - 1), 0.5 * (sw->h - 1), NULL, r);
    fw_session_free(&s);
    return st;
}

pp5_status_t sweep_write_plot(const sweep_t *sw, double *xs, double *ph, char (*labels)[64])
{
    plot_t pl;
    char xl[96] = "";
    for (int a = 0; a < sw->n_axes; a++) {
        size_t l = strlen(xl);
        if ((sw->axes[a].n > 1 || sw->n_axes == 1) && l + strlen(sw->axes[a].key) + 3 < sizeof xl)
            snprintf(xl + l, sizeof xl - l, "%s%s", l ? ", " : "", sw->axes[a].key);
    }
    plot_init(&pl, "Emulated frame time by phase (critical path)", xl, "frame time (ms)");
    const char *cats[SWEEP_MAX_POINTS];
    for (int pt = 0; pt < sw->points; pt++)
        cats[pt] = labels[pt];
    pp5_status_t st = plot_set_categories(&pl, cats, sw->points);
    for (int k = 0; st == PP5_OK && k < FW_PHASE_COUNT; k++)
        st = plot_add_stacked(&pl, fw_phase_name((fw_phase_t)k), xs, ph + (size_t)k * sw->points,
                              sw->points);
    if (st == PP5_OK)
        st = plot_write(&pl, sw->out_png, 1100, 640);
    plot_free(&pl);
    return st;
}

static int cmd_sweep(int argc, char **argv)
{
    sweep_t sw;
    pp5_status_t st;
    int rc = parse_args(argc, argv, &sw, &st);
    if (rc)
        return rc == 1 ? 0 : 2;
    /* Bad output paths are reported before any point runs. */
    if (st == PP5_OK)
        st = outpath_check_all("--out", sw.out_csv, "--plot", sw.out_png, "--report", sw.report,
                               "--accounting", sw.accounting, NULL);
    if (st != PP5_OK)
        return cliopt_report("sweep", st);
    scene_t sc;
    if ((st = scene_load(sw.dataset ? sw.dataset : sw.phantom, sw.dataset != NULL, &sc)) != PP5_OK)
        return cliopt_report("sweep", st);
    volume_t vol;
    if ((st = scene_paper_volume(&sc, &vol)) != PP5_OK) {
        scene_free(&sc);
        return cliopt_report("sweep", st);
    }
    render_job_t job = {.volume = &vol, .volume_name = sc.volume.source, .tf = sc.tf, .frames = 1};
    render_settings_defaults(&job.settings);
    job.settings.width = sw.w;
    job.settings.height = sw.h;
    job.settings.mode = sw.mode;
    job.settings.view.rot_x_deg = sc.rot_x_deg;
    job.settings.view.rot_y_deg = sc.rot_y_deg;
    job.settings.view.rot_z_deg = sc.rot_z_deg;
    shade_defaults(&job.shade);
    job.shade.lighting = sw.lighting;
    if (sw.lighting == SHADE_SPECULAR_FIXED_LIGHT)
        job.shade.specular = 0.4f;
    if (workunit_launcher_rank() == 0)
        printf("sweep: %s resampled to 128x128x109, %dx%d %s image, lighting %s, preset %s, %d "
               "points\n", sc.volume.source, sw.w, sw.h, render_mode_name(sw.mode),
               shade_case_name(sw.lighting), sw.preset, sw.points);
    rc = sweep_run_units(&sw, &job);
    volume_free(&vol);
    scene_free(&sc);
    return rc;
}

PP5_COMMAND(sweep, "work-division study: frame time on the emulated machine over a parameter grid (CSV + plot)",
            cmd_sweep)
