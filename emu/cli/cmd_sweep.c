/* cmd_sweep.c: `pp5 sweep`: work-division studies: the machine renderer over a grid of parameters, CSV and a stacked-by-phase plot of frame time. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "firmware/host/fw_session.h"
#include "plot.h"
#include "registry.h"
#include "render/scene.h"

#define SWEEP_MAX_KEYS 4
#define SWEEP_MAX_VALUES 32
#define SWEEP_MAX_POINTS 256

typedef struct {
    char key[64];
    char values[SWEEP_MAX_VALUES][32];
    int n;
} sweep_axis_t;

static void sweep_usage(FILE *out)
{
    fprintf(out,
            "usage: pp5 sweep [--set KEY=V1,V2,...]... [--out FILE.csv] [--plot FILE.png]\n"
            "                 [--phantom NAME | --dataset mrbrain] [--size WxH] [--mode gaze|full]\n"
            "                 [--lighting diffuse|specular] [--preset NAME]\n\n"
            "Runs one frame of the gaze-directed renderer on the emulated machine for every\n"
            "point of a grid of parameters and writes a CSV (frame time, its critical-path\n"
            "phases, rays, samples, ring bytes and utilisation) and a PNG of frame time against\n"
            "the grid, stacked by phase, so you see where the machine saturates.\n\n"
            "  --set KEY=V1,V2,...  a machine parameter (see `pp5 machine`: gp.count,\n"
            "                       renderer.count, ring.channels, ring.clock_hz, gp.clock_hz,\n"
            "                       renderer.clock_hz, ...) or split=pp,gp (where the\n"
            "                       viewpoint-dependent shading runs); several --set make a grid\n"
            "                       (default: --set gp.count=1,2,4,8,16,32)\n"
            "  --out FILE.csv       (default sweep.csv)\n"
            "  --plot FILE.png      (default sweep.png)\n"
            "  --phantom NAME       volume (default shepp-logan at 128x128x109)\n"
            "  --dataset mrbrain    the MR subject, resampled to 128x128x109\n"
            "  --size WxH           image size (default 210x210, the paper's Table I)\n"
            "  --mode gaze|full     (default gaze, gaze at the image centre)\n"
            "  --lighting L         specular (default; ks 0.4: the PPs shade every frame) or diffuse\n"
            "  --preset NAME        machine preset (default, gaze1990-literal)\n"
            "  --help               this text\n");
}

static pp5_status_t parse_axis(const char *arg, sweep_axis_t *ax)
{
    const char *eq = strchr(arg, '=');
    if (!eq || eq == arg || (size_t)(eq - arg) >= sizeof ax->key)
        return pp5_fail(PP5_E_CONFIG, "--set: expected KEY=V1,V2,..., got '%s'", arg);
    memset(ax, 0, sizeof *ax);
    memcpy(ax->key, arg, (size_t)(eq - arg));
    const char *p = eq + 1;
    while (*p) {
        const char *c = strchr(p, ',');
        size_t len = c ? (size_t)(c - p) : strlen(p);
        if (len == 0 || len >= sizeof ax->values[0] || ax->n >= SWEEP_MAX_VALUES)
            return pp5_fail(PP5_E_CONFIG, "--set %s: bad value list", ax->key);
        memcpy(ax->values[ax->n], p, len);
        ax->values[ax->n][len] = 0;
        ax->n++;
        p += len + (c ? 1 : 0);
    }
    if (ax->n == 0)
        return pp5_fail(PP5_E_CONFIG, "--set %s: no values", ax->key);
    if (strcmp(ax->key, "split") == 0) {
        for (int i = 0; i < ax->n; i++)
            if (strcmp(ax->values[i], "pp") != 0 && strcmp(ax->values[i], "gp") != 0)
                return pp5_fail(PP5_E_CONFIG, "--set split: values are pp and gp");
        return PP5_OK;
    }
    pp5_params_t probe;
    pp5_params_default(&probe);
    for (int i = 0; i < ax->n; i++) {
        pp5_status_t st = pp5_params_set(&probe, ax->key, ax->values[i]);
        if (st != PP5_OK)
            return st;
    }
    return PP5_OK;
}

static int cmd_sweep(int argc, char **argv)
{
    static const struct option opts[] = {
        {"set", required_argument, NULL, 's'},   {"out", required_argument, NULL, 'o'},
        {"plot", required_argument, NULL, 'p'},  {"phantom", required_argument, NULL, 'P'},
        {"dataset", required_argument, NULL, 'd'}, {"size", required_argument, NULL, 'z'},
        {"mode", required_argument, NULL, 'm'},  {"lighting", required_argument, NULL, 'l'},
        {"preset", required_argument, NULL, 'r'}, {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0}};
    sweep_axis_t axes[SWEEP_MAX_KEYS];
    int n_axes = 0;
    const char *out_csv = "sweep.csv", *out_png = "sweep.png", *phantom = "shepp-logan";
    const char *dataset = NULL, *preset = "default";
    int w = 210, h = 210;
    render_mode_t mode = RENDER_MODE_GAZE;
    shade_case_t lighting = SHADE_SPECULAR_FIXED_LIGHT;
    pp5_status_t st = PP5_OK;
    optind = 1;
    int c;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 's':
            if (n_axes >= SWEEP_MAX_KEYS)
                st = pp5_fail(PP5_E_CONFIG, "at most %d --set axes", SWEEP_MAX_KEYS);
            else
                st = parse_axis(optarg, &axes[n_axes++]);
            break;
        case 'o': out_csv = optarg; break;
        case 'p': out_png = optarg; break;
        case 'P': phantom = optarg; dataset = NULL; break;
        case 'd': dataset = optarg; break;
        case 'z': st = cliopt_size2("--size", optarg, 8, 1280, &w, &h); break;
        case 'm':
            if (strcmp(optarg, "gaze") == 0) mode = RENDER_MODE_GAZE;
            else if (strcmp(optarg, "full") == 0) mode = RENDER_MODE_FULL;
            else st = pp5_fail(PP5_E_CONFIG, "--mode: gaze or full");
            break;
        case 'l':
            if (strcmp(optarg, "specular") == 0) lighting = SHADE_SPECULAR_FIXED_LIGHT;
            else if (strcmp(optarg, "diffuse") == 0) lighting = SHADE_DIFFUSE_FIXED_LIGHT;
            else st = pp5_fail(PP5_E_CONFIG, "--lighting: specular or diffuse");
            break;
        case 'r': preset = optarg; break;
        case 'h': sweep_usage(stdout); return 0;
        default: sweep_usage(stderr); return 2;
        }
    }
    if (st != PP5_OK)
        return cliopt_report("sweep", st);
    if (optind < argc) {
        fprintf(stderr, "pp5 sweep: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    if (n_axes == 0 && (st = parse_axis("gp.count=1,2,4,8,16,32", &axes[n_axes++])) != PP5_OK)
        return cliopt_report("sweep", st);
    int points = 1;
    for (int a = 0; a < n_axes; a++)
        points *= axes[a].n;
    if (points > SWEEP_MAX_POINTS)
        return cliopt_report("sweep", pp5_fail(PP5_E_CONFIG, "grid of %d points (max %d)", points,
                                               SWEEP_MAX_POINTS));
    /* Volume */
    scene_t sc;
    st = scene_load(dataset ? dataset : phantom, dataset != NULL, &sc);
    if (st != PP5_OK)
        return cliopt_report("sweep", st);
    volume_t vol;
    st = volume_resample(&sc.volume, 128, 128, 109, &vol);
    if (st != PP5_OK) {
        scene_free(&sc);
        return cliopt_report("sweep", st);
    }
    for (int a = 0; a < 3; a++)
        vol.spacing[a] = sc.volume.spacing[a] * (a == 0 ? sc.volume.nx / 128.0
                                                 : a == 1 ? sc.volume.ny / 128.0
                                                          : sc.volume.nz / 109.0);
    printf("sweep: %s resampled to 128x128x109, %dx%d %s image, lighting %s, preset %s, %d points\n",
           sc.volume.source, w, h, render_mode_name(mode), shade_case_name(lighting), preset, points);
    FILE *csv = fopen(out_csv, "w");
    if (!csv) {
        volume_free(&vol);
        scene_free(&sc);
        return cliopt_report("sweep", pp5_fail(PP5_E_IO, "cannot write %s", out_csv));
    }
    for (int a = 0; a < n_axes; a++)
        fprintf(csv, "%s,", axes[a].key);
    fprintf(csv, "frame_time_s");
    for (int k = 0; k < FW_PHASE_COUNT; k++)
        fprintf(csv, ",%s", fw_phase_key((fw_phase_t)k));
    fprintf(csv, ",rays,samples,ring_data_bytes,ring_pixel_bytes,ring_util,gp_util_mean,"
                 "renderer_util_mean,bottleneck\n");
    double *xs = calloc((size_t)points, sizeof *xs);
    double *ph = calloc((size_t)points * FW_PHASE_COUNT, sizeof *ph);
    char (*labels)[64] = calloc((size_t)points, sizeof *labels);
    if (!xs || !ph || !labels) {
        st = pp5_fail(PP5_E_NOMEM, "sweep: out of memory");
    }
    for (int pt = 0; st == PP5_OK && pt < points; pt++) {
        pp5_params_t p;
        pp5_params_default(&p);
        st = pp5_params_preset(&p, preset);
        int split = VR_SPLIT_PP, rem = pt;
        labels[pt][0] = 0;
        int idx[SWEEP_MAX_KEYS];
        for (int a = n_axes - 1; a >= 0; a--) {
            idx[a] = rem % axes[a].n;
            rem /= axes[a].n;
        }
        for (int a = 0; st == PP5_OK && a < n_axes; a++) {
            const char *v = axes[a].values[idx[a]];
            if (strcmp(axes[a].key, "split") == 0)
                split = strcmp(v, "gp") == 0 ? VR_SPLIT_GP : VR_SPLIT_PP;
            else
                st = pp5_params_set(&p, axes[a].key, v);
            /* label by the axes that vary */
            size_t l = strlen(labels[pt]);
            if (axes[a].n > 1 || n_axes == 1)
                snprintf(labels[pt] + l, sizeof labels[pt] - l, "%s%s", l ? "," : "", v);
        }
        if (st == PP5_OK)
            st = pp5_params_validate(&p);
        if (st != PP5_OK)
            break;
        render_settings_t rs;
        render_settings_defaults(&rs);
        rs.width = (int)w;
        rs.height = (int)h;
        rs.mode = mode;
        rs.view.rot_x_deg = sc.rot_x_deg;
        rs.view.rot_y_deg = sc.rot_y_deg;
        rs.view.rot_z_deg = sc.rot_z_deg;
        shade_params_t sh;
        shade_defaults(&sh);
        sh.lighting = lighting;
        if (lighting == SHADE_SPECULAR_FIXED_LIGHT)
            sh.specular = 0.4f;
        fw_options_t o;
        fw_options_default(&o);
        o.split = split;
        fw_session_t s;
        fw_frame_result_t r;
        memset(&r, 0, sizeof r);
        pp5_status_t rst = fw_session_init(&s, &vol, &sc.tf, &sh, &rs, &p, &o);
        if (rst == PP5_OK)
            rst = fw_session_frame(&s, 0.5 * (w - 1), 0.5 * (h - 1), NULL, &r);
        fw_session_free(&s);
        for (int a = 0; a < n_axes; a++)
            fprintf(csv, "%s,", axes[a].values[idx[a]]);
        if (rst != PP5_OK) {
            /* A point that does not fit (memory, backing store) is a result too. */
            fprintf(csv, "nan");
            for (int k = 0; k < FW_PHASE_COUNT; k++)
                fprintf(csv, ",nan");
            fprintf(csv, ",0,0,0,0,0,0,0,\"error: %s\"\n", pp5_error_text());
            printf("  %-24s error: %s\n", labels[pt], pp5_error_text());
            xs[pt] = pt;
            continue;
        }
        fprintf(csv, "%.9g", r.frame_time_s);
        for (int k = 0; k < FW_PHASE_COUNT; k++)
            fprintf(csv, ",%.9g", r.phase_s[k]);
        fprintf(csv, ",%llu,%llu,%llu,%llu,%.6f,%.6f,%.6f,\"%s\"\n", (unsigned long long)r.rays,
                (unsigned long long)r.samples, (unsigned long long)r.ring_bytes[RING_CLASS_DATA],
                (unsigned long long)r.ring_bytes[RING_CLASS_PIXELS], r.ring_util_total,
                r.gp_util_mean, r.rn_util_mean, r.bottleneck);
        printf("  %-24s %9.2f ms  %6.2f f/s  bottleneck: %s\n", labels[pt], r.frame_time_s * 1e3,
               1.0 / r.frame_time_s, r.bottleneck);
        xs[pt] = pt;
        for (int k = 0; k < FW_PHASE_COUNT; k++)
            ph[(size_t)k * points + pt] = r.phase_s[k] * 1e3;
    }
    fclose(csv);
    if (st == PP5_OK) {
        plot_t pl;
        char xl[96] = "";
        for (int a = 0; a < n_axes; a++) {
            size_t l = strlen(xl);
            if ((axes[a].n > 1 || n_axes == 1) && l + strlen(axes[a].key) + 3 < sizeof xl) {
                if (l)
                    strcat(xl, ", ");
                strcat(xl, axes[a].key);
            }
        }
        plot_init(&pl, "Emulated frame time by phase (critical path)", xl, "frame time (ms)");
        const char *cats[SWEEP_MAX_POINTS];
        for (int pt = 0; pt < points; pt++)
            cats[pt] = labels[pt];
        st = plot_set_categories(&pl, cats, points);
        for (int k = 0; st == PP5_OK && k < FW_PHASE_COUNT; k++)
            st = plot_add_stacked(&pl, fw_phase_name((fw_phase_t)k), xs, ph + (size_t)k * points, points);
        if (st == PP5_OK)
            st = plot_write_png(&pl, out_png, 1100, 640);
        plot_free(&pl);
        if (st == PP5_OK)
            printf("wrote %s and %s\n", out_csv, out_png);
    }
    free(xs);
    free(ph);
    free(labels);
    volume_free(&vol);
    scene_free(&sc);
    return st == PP5_OK ? 0 : cliopt_report("sweep", st);
}

PP5_COMMAND(sweep, "work-division study: frame time on the emulated machine over a parameter grid (CSV + plot)",
            cmd_sweep)
