/* reproduce_demip.c: `pp5 reproduce demip`: Díaz & Vázquez, "Depth-Enhanced
 * Maximum Intensity Projection" (Volume Graphics 2010; seed 002), Table 1
 * (§4) as cost ratios beside ours, on CThead and the MR subject: MIP, DEMIP,
 * DEMIP with the colour sphere, MIDA and compositing, full resolution and
 * gaze-directed, with a comparison image per volume, the eps sweep and the
 * max-against-box pyramid difference of gaze-directed MIP. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cliopt.h"
#include "plot.h"
#include "registry.h"
#include "render/quality.h"
#include "render/renderer_native.h"
#include "render/scene.h"
#include "reproduce_demip.h"

/* Table 1 of seed 002 (§4): GTX 280, 512x512 viewport, one sample per voxel,
 * frames per second. */
enum { COL_MIP, COL_DEMIP, COL_MIDA, COL_DVR };
static const struct {
    const char *model, *size;
    double fps[4];
} paper_table1[5] = {
    {"Jaw", "512^2 x 40", {64.7, 53.8, 48.1, 49.8}},
    {"Aneurysm", "512^2 x 120", {76.2, 54.5, 43.9, 45.8}},
    {"Abdomen", "512^2 x 171", {59.4, 51.8, 50.1, 53.4}},
    {"Head", "512^2 x 485", {28.9, 25.8, 17.3, 17.6}},
    {"Body", "512^2 x 512", {28.1, 24.1, 26.6, 27.1}},
};

/* Cost ratios (time / time = fps / fps) the paper's table implies. */
typedef enum { RATIO_DEMIP_MIP, RATIO_DVR_DEMIP, RATIO_MIDA_DEMIP, RATIO_COUNT } ratio_t;
static const char *const ratio_names[RATIO_COUNT] = {"DEMIP/MIP", "DVR/DEMIP", "MIDA/DEMIP"};

static double paper_ratio(int row, ratio_t r)
{
    const double *f = paper_table1[row].fps;
    switch (r) {
    case RATIO_DEMIP_MIP: return f[COL_MIP] / f[COL_DEMIP];
    case RATIO_DVR_DEMIP: return f[COL_DEMIP] / f[COL_DVR];
    default: return f[COL_DEMIP] / f[COL_MIDA];
    }
}

static void paper_ratio_range(ratio_t r, double *lo, double *hi, double *mean)
{
    *lo = INFINITY, *hi = -INFINITY, *mean = 0.0;
    for (int i = 0; i < 5; i++) {
        double x = paper_ratio(i, r);
        *lo = fmin(*lo, x), *hi = fmax(*hi, x), *mean += x / 5.0;
    }
}

static void print_paper_table(void)
{
    printf("Table 1 of Diaz & Vazquez 2010 (seed 002 §4): GTX 280, 512x512 viewport, one\n"
           "sample per voxel, frames/s, and the cost ratios (time over time) it implies:\n");
    printf("  %-9s %-12s %6s %6s %6s %6s   %9s %9s %10s\n", "model", "size", "MIP", "DEMIP",
           "MIDA", "DVR", ratio_names[0], ratio_names[1], ratio_names[2]);
    for (int i = 0; i < 5; i++) {
        const double *f = paper_table1[i].fps;
        printf("  %-9s %-12s %6.1f %6.1f %6.1f %6.1f   %9.2f %9.2f %10.2f\n",
               paper_table1[i].model, paper_table1[i].size, f[0], f[1], f[2], f[3],
               paper_ratio(i, 0), paper_ratio(i, 1), paper_ratio(i, 2));
    }
    double lo, hi, mean;
    printf("  %-41s", "range (mean)");
    for (int r = 0; r < RATIO_COUNT; r++) {
        paper_ratio_range((ratio_t)r, &lo, &hi, &mean);
        printf(" %.2f-%.2f (%.2f)", lo, hi, mean);
    }
    printf("\nThe paper's volumes are not public; ours are CThead and the MR subject\n"
           "(../shared/data/volumes), so only the ratios carry over, not the frame rates.\n");
}

/* ---- the five panels ---- */

enum { PANEL_MIP, PANEL_DEMIP, PANEL_SPHERE, PANEL_MIDA, PANEL_DVR, PANELS };
static const char *const panel_names[PANELS] = {"MIP", "DEMIP", "DEMIP + sphere", "MIDA",
                                                "compositing"};

typedef struct {
    double ms[2];                 /* median frame time: [0] full, [1] gaze */
    render_stats_t stats[2];
    image8_t image[2];
} panel_run_t;

typedef struct {
    int size;
    int machine_size;             /* the emulated machine's image side; 0: not run */
    const char *datasets;
    const pp5_reproduce_opts_t *o;
    const char *out_dir;
} demip_opts_t;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of `reps` frames; the last frame's image and stats are kept. */
static pp5_status_t timed_frames(native_renderer_t *r, const render_settings_t *s, int reps,
                                 double *ms, render_stats_t *stats, image8_t *img)
{
    double t[16];
    reps = reps < 1 ? 1 : (reps > 16 ? 16 : reps);
    for (int i = 0; i < reps; i++) {
        image8_free(img);
        pp5_status_t st = native_renderer_frame(r, s, img, stats);
        if (st != PP5_OK)
            return st;
        t[i] = stats->ms_total;
    }
    qsort(t, (size_t)reps, sizeof t[0], cmp_double);
    *ms = t[reps / 2];
    return PP5_OK;
}

static void panel_settings(const render_settings_t *base, int panel, render_settings_t *s)
{
    *s = *base;
    s->blend.mode = panel == PANEL_MIP ? BLEND_MIP
                    : panel == PANEL_MIDA ? BLEND_MIDA
                    : panel == PANEL_DVR ? BLEND_COMPOSITE : BLEND_DEMIP;
    if (panel == PANEL_DEMIP)
        s->blend.sphere_weight = 0.0f;    /* the paper's DEMIP column: no sphere */
}

static void progress(const char *what, const char *tag)
{
    if (isatty(2))
        fprintf(stderr, "\r  %s: %-40s", tag, what);
}

/* All full-resolution frames, then all gaze-directed ones, each pass after
 * one untimed frame: a change of mode reallocates the 2D mip map, and the
 * first frame after that pays for fresh pages. */
static pp5_status_t run_panels(native_renderer_t *r, const render_settings_t *base, int reps,
                               const char *tag, panel_run_t runs[PANELS])
{
    for (int m = 0; m < 2; m++) {
        render_settings_t s = *base;
        s.mode = m ? RENDER_MODE_GAZE : RENDER_MODE_FULL;
        image8_t warm = {0};
        render_stats_t ws;
        pp5_status_t st = native_renderer_frame(r, &s, &warm, &ws);
        image8_free(&warm);
        for (int p = 0; st == PP5_OK && p < PANELS; p++) {
            panel_settings(base, p, &s);
            s.mode = m ? RENDER_MODE_GAZE : RENDER_MODE_FULL;
            char what[64];
            snprintf(what, sizeof what, "%s, %s", panel_names[p], m ? "gaze" : "full");
            progress(what, tag);
            st = timed_frames(r, &s, reps, &runs[p].ms[m], &runs[p].stats[m], &runs[p].image[m]);
        }
        if (st != PP5_OK)
            return st;
    }
    if (isatty(2))
        fprintf(stderr, "\r%70s\r", "");
    return PP5_OK;
}

/* Images side by side, each labelled in its top left corner. */
static pp5_status_t write_strip(const char *path, const image8_t *const *imgs,
                                const char *const *labels, int n)
{
    image8_t out;
    int w = imgs[0]->width, h = imgs[0]->height;
    pp5_status_t st = image8_alloc(&out, w * n, h, 3);
    if (st != PP5_OK)
        return st;
    const uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0};
    int scale = h >= 256 ? 2 : 1;
    for (int i = 0; i < n; i++) {
        for (int y = 0; y < h; y++)
            memcpy(out.pixels + ((size_t)y * w * n + (size_t)i * w) * 3,
                   imgs[i]->pixels + (size_t)y * w * 3, (size_t)w * 3);
        plot_draw_text(&out, i * w + 4 + 1, 4 + 1, labels[i], scale, black);
        plot_draw_text(&out, i * w + 4, 4, labels[i], scale, white);
    }
    st = png_write(path, &out);
    image8_free(&out);
    return st;
}

static void print_timings(const panel_run_t runs[PANELS], const char *tf_name)
{
    printf("  %-28s %10s %10s %12s %12s\n", "blend", "full ms", "gaze ms", "full samples",
           "gaze samples");
    for (int p = 0; p < PANELS; p++) {
        char name[64];
        snprintf(name, sizeof name, "%s%s%s%s", panel_names[p], p == PANEL_DVR ? " (" : "",
                 p == PANEL_DVR ? tf_name : "", p == PANEL_DVR ? ")" : "");
        printf("  %-28s %10.1f %10.1f %12llu %12llu\n", name, runs[p].ms[0], runs[p].ms[1],
               (unsigned long long)runs[p].stats[0].samples,
               (unsigned long long)runs[p].stats[1].samples);
    }
}

static double our_ratio(const panel_run_t runs[PANELS], ratio_t r, int m)
{
    double demip = runs[PANEL_DEMIP].ms[m];
    switch (r) {
    case RATIO_DEMIP_MIP: return demip / runs[PANEL_MIP].ms[m];
    case RATIO_DVR_DEMIP: return runs[PANEL_DVR].ms[m] / demip;
    default: return runs[PANEL_MIDA].ms[m] / demip;
    }
}

/* Why a ratio of ours lies above (or below) the paper's range. */
static const char *ratio_cause(ratio_t r, bool above)
{
    if (r == RATIO_DEMIP_MIP)
        return above ? "ray 1 visits bricks from the highest bound down and leaves a ray after "
                       "the few that hold its maximum, while ray 2 must confirm that no brick "
                       "in front of its stop reaches m_max - eps (render/blend_bricks.h)"
                     : "ray 2 mostly ends in the first brick it tries (bricks front to back, "
                       "render/blend_bricks.h), so DEMIP adds little but eq. (1) and (2); the "
                       "paper's shader walks ray 2 sample by sample";
    if (r == RATIO_DVR_DEMIP)
        return above ? "our MIP and DEMIP rays pass every brick below their running maximum and "
                       "stop at saturated material, skipping that compositing cannot do"
                     : "our compositing rays stop at opacity 0.95, usually within a few voxels "
                       "of the skin surface, while MIP and DEMIP must see the whole ray; the "
                       "paper's DVR evaluates Phong shading per sample on the GPU";
    return above ? "MIDA cannot pass a region by its maximum (every non-empty sample changes the "
                   "colour) and stops only when both opacity and maximum reach 0.95, so it draws "
                   "far more samples than DEMIP (table above)"
                 : "MIDA's rays stop once opacity and maximum both reach 0.95, which this volume "
                   "allows early, while DEMIP's ray 1 must see the whole ray unless its material "
                   "saturates";
}

/* A ratio on the machine: each blend at its best division (NAN when the
 * machine did not run). */
static double machine_ratio(const demip_machine_t *mm, ratio_t r, int m)
{
    if (!mm)
        return NAN;
    double t[DEMIP_MPANELS];
    for (int p = 0; p < DEMIP_MPANELS; p++)
        t[p] = demip_machine_ms(mm, demip_machine_best(mm, p, m), p, m);
    switch (r) {
    case RATIO_DEMIP_MIP: return t[DEMIP_MPANEL_DEMIP] / t[DEMIP_MPANEL_MIP];
    case RATIO_DVR_DEMIP: return t[DEMIP_MPANEL_DVR] / t[DEMIP_MPANEL_DEMIP];
    default: return t[DEMIP_MPANEL_MIDA] / t[DEMIP_MPANEL_DEMIP];
    }
}

/* The ratio table, and the causes of any ratio outside the paper's range. */
static void print_ratios(const panel_run_t runs[PANELS], const demip_machine_t *mm)
{
    printf("  %-11s %-18s %12s %12s %14s %14s\n", "cost ratio", "paper (mean)", "native full",
           "native gaze", "machine full", "machine gaze");
    for (int r = 0; r < RATIO_COUNT; r++) {
        double lo, hi, mean;
        paper_ratio_range((ratio_t)r, &lo, &hi, &mean);
        char paper[32];
        snprintf(paper, sizeof paper, "%.2f-%.2f (%.2f)", lo, hi, mean);
        printf("  %-11s %-18s %12.2f %12.2f %14.2f %14.2f\n", ratio_names[r], paper,
               our_ratio(runs, (ratio_t)r, 0), our_ratio(runs, (ratio_t)r, 1),
               machine_ratio(mm, (ratio_t)r, 0), machine_ratio(mm, (ratio_t)r, 1));
    }
    if (mm)
        printf("  machine: emulated frame times at %dx%d, each blend under its best division "
               "(table below).\n", mm->size, mm->size);
    else
        printf("  machine columns: nan, the machine was not run (--machine-size 0).\n");
    printf("  where we differ:\n");
    for (int r = 0; r < RATIO_COUNT; r++) {
        double lo, hi, mean, x = our_ratio(runs, (ratio_t)r, 0);
        paper_ratio_range((ratio_t)r, &lo, &hi, &mean);
        if (x >= lo && x <= hi) {
            printf("   - %s at full resolution (%.2f) lies inside the paper's range.\n",
                   ratio_names[r], x);
            continue;
        }
        const char *cause = ratio_cause((ratio_t)r, x > hi);
        printf("   - %s %.2f at full resolution is %s the paper's %.2f-%.2f: %s.\n",
               ratio_names[r], x, x > hi ? "above" : "below", lo, hi, cause);
    }
    printf("   - times are host wall clock on a CPU (threads as given), not a GPU; the "
           "frame rates themselves are not comparable.\n");
}

/* ---- the eps sweep ---- */

static const float sweep_eps[] = {0.0f, 0.02f, 0.05f, 0.1f, 0.2f, 0.4f};
#define SWEEP_N ((int)(sizeof sweep_eps / sizeof sweep_eps[0]))

/* Fraction of lit pixels whose reading-B colour differs from MIP's: where
 * ray 2 found an occluder of the maximum's material at this eps. */
static double occluder_fraction(const image8_t *mip, const image8_t *b)
{
    size_t lit = 0, diff = 0, n = (size_t)mip->width * mip->height;
    for (size_t i = 0; i < n; i++) {
        const uint8_t *p = mip->pixels + i * 3, *q = b->pixels + i * 3;
        if (p[0] == 0)
            continue;
        lit++;
        diff += p[0] != q[0];
    }
    return lit ? (double)diff / (double)lit : 0.0;
}

static pp5_status_t eps_sweep(native_renderer_t *r, const render_settings_t *base,
                              const image8_t *mip, const char *path, const char *tag)
{
    image8_t imgs[SWEEP_N];
    memset(imgs, 0, sizeof imgs);
    char labels[SWEEP_N][32];
    const image8_t *ptr[SWEEP_N];
    const char *lab[SWEEP_N];
    pp5_status_t st = PP5_OK;
    printf("  eps sweep (DEMIP, no sphere; 'occluded' = share of lit pixels where ray 2 met an\n"
           "  occluder of the maximum's material, i.e. where reading B differs from MIP):\n");
    for (int i = 0; st == PP5_OK && i < SWEEP_N; i++) {
        render_settings_t s = *base;
        s.mode = RENDER_MODE_FULL;
        s.blend.mode = BLEND_DEMIP;
        s.blend.sphere_weight = 0.0f;
        s.blend.tolerance = sweep_eps[i];
        s.blend.reading = DEMIP_READING_B;
        render_stats_t stats;
        image8_t b = {0};
        progress("eps sweep", tag);
        st = native_renderer_frame(r, &s, &b, &stats);
        if (st == PP5_OK) {
            double occ = occluder_fraction(mip, &b);
            s.blend.reading = DEMIP_READING_A;
            st = native_renderer_frame(r, &s, &imgs[i], &stats);
            printf("    eps %.2f: occluded %5.1f%%, %llu samples\n", sweep_eps[i], 100.0 * occ,
                   (unsigned long long)stats.samples);
        }
        image8_free(&b);
        snprintf(labels[i], sizeof labels[i], "eps %.2f", sweep_eps[i]);
        ptr[i] = &imgs[i];
        lab[i] = labels[i];
    }
    if (isatty(2))
        fprintf(stderr, "\r%70s\r", "");
    if (st == PP5_OK)
        st = write_strip(path, ptr, lab, SWEEP_N);
    for (int i = 0; i < SWEEP_N; i++)
        image8_free(&imgs[i]);
    return st;
}

/* ---- gaze-directed MIP: max against box pyramid ---- */

/* Over the reference's lit pixels: mean signed grey difference test - ref
 * and the share of pixels darker than the reference by more than 8 levels. */
static void darkening(const image8_t *test, const image8_t *ref, double *mean, double *darker)
{
    size_t lit = 0, dark = 0, n = (size_t)ref->width * ref->height;
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        int a = test->pixels[i * 3], b = ref->pixels[i * 3];
        if (b == 0)
            continue;
        lit++;
        sum += a - b;
        dark += a < b - 8;
    }
    *mean = lit ? sum / (double)lit : 0.0;
    *darker = lit ? (double)dark / (double)lit : 0.0;
}

static pp5_status_t gaze_mip(native_renderer_t *r, const volume_t *v, const render_settings_t *base,
                             scalar_pyramid_kind_t kind, image8_t *img, render_stats_t *stats)
{
    pp5_status_t st = native_renderer_build_scalar(r, v, kind);
    render_settings_t s = *base;
    s.mode = RENDER_MODE_GAZE;
    s.blend.mode = BLEND_MIP;
    s.blend.pyramid = kind;
    if (st == PP5_OK)
        st = native_renderer_frame(r, &s, img, stats);
    return st;
}

static pp5_status_t pyramid_compare(native_renderer_t *r, const volume_t *v,
                                    const render_settings_t *base, const image8_t *full_mip,
                                    const char *path)
{
    const scalar_pyramid_kind_t kinds[2] = {SCALAR_PYRAMID_MAX, SCALAR_PYRAMID_BOX};
    image8_t g[2] = {{0}, {0}};
    pp5_status_t st = PP5_OK;
    printf("  gaze-directed MIP against full-resolution MIP, by the pyramid coarse rays read:\n"
           "  %-8s %9s %11s %17s %16s %12s\n", "pyramid", "PSNR dB", "AW-PSNR dB",
           "mean grey change", "darker by >8 %", "3D samples");
    for (int k = 0; st == PP5_OK && k < 2; k++) {
        render_stats_t stats;
        st = gaze_mip(r, v, base, kinds[k], &g[k], &stats);
        quality_t q;
        if (st == PP5_OK)
            st = quality_compare(&g[k], full_mip, &r->gaze, base->gaze_x, base->gaze_y, &q);
        if (st != PP5_OK)
            break;
        double mean, darker;
        darkening(&g[k], full_mip, &mean, &darker);
        printf("  %-8s %9.2f %11.2f %+17.2f %16.2f %12llu\n", scalar_pyramid_kind_name(kinds[k]),
               q.psnr_db, q.aw_psnr_db, mean, 100.0 * darker, (unsigned long long)stats.samples);
    }
    if (st == PP5_OK) {
        const image8_t *imgs[3] = {full_mip, &g[0], &g[1]};
        const char *labels[3] = {"MIP full", "MIP gaze, max", "MIP gaze, box"};
        st = write_strip(path, imgs, labels, 3);
    }
    image8_free(&g[0]);
    image8_free(&g[1]);
    /* Leave the renderer as the other measurements expect it. */
    if (st == PP5_OK)
        st = native_renderer_build_scalar(r, v, SCALAR_PYRAMID_MAX);
    return st;
}

/* ---- one volume ---- */

static void base_settings(const scene_t *sc, const demip_opts_t *d, render_settings_t *s)
{
    render_settings_defaults(s);
    s->width = s->height = d->size;
    s->gaze_x = s->gaze_y = 0.5 * (d->size - 1);
    s->threads = d->o->threads;
    s->view.rot_x_deg = sc->rot_x_deg;
    s->view.rot_y_deg = sc->rot_y_deg;
    s->view.rot_z_deg = sc->rot_z_deg;
    blend_settings_fill(&s->blend, sc->window_centre, sc->window_width,
                        (const float[3]){sc->rot_x_deg, sc->rot_y_deg, sc->rot_z_deg});
}

static pp5_status_t demip_measure(native_renderer_t *r, const scene_t *sc, const demip_opts_t *d,
                                  const char *tag)
{
    render_settings_t base;
    base_settings(sc, d, &base);
    panel_run_t runs[PANELS];
    memset(runs, 0, sizeof runs);
    pp5_status_t st = run_panels(r, &base, d->o->repeats, tag, runs);
    static demip_machine_t mm;
    if (st == PP5_OK && d->machine_size > 0)
        st = demip_machine_measure(sc, &base, d->machine_size, r, tag, &mm);
    char path[1200];
    if (st == PP5_OK) {
        print_timings(runs, sc->tf.name);
        print_ratios(runs, d->machine_size > 0 ? &mm : NULL);
        if (d->machine_size > 0)
            demip_machine_print(&mm);
        const image8_t *imgs[PANELS];
        for (int p = 0; p < PANELS; p++)
            imgs[p] = &runs[p].image[0];
        snprintf(path, sizeof path, "%s/demip_%s.png", d->out_dir, tag);
        st = write_strip(path, imgs, panel_names, PANELS);
        if (st == PP5_OK)
            printf("  image: %s (full resolution: %s, %s, %s, %s, %s)\n", path, panel_names[0],
                   panel_names[1], panel_names[2], panel_names[3], panel_names[4]);
    }
    if (st == PP5_OK) {
        snprintf(path, sizeof path, "%s/demip_%s_eps.png", d->out_dir, tag);
        st = eps_sweep(r, &base, &runs[PANEL_MIP].image[0], path, tag);
        if (st == PP5_OK)
            printf("  image: %s (DEMIP, reading A, eps %.2f .. %.2f)\n", path, sweep_eps[0],
                   sweep_eps[SWEEP_N - 1]);
    }
    if (st == PP5_OK) {
        snprintf(path, sizeof path, "%s/demip_%s_pyramid.png", d->out_dir, tag);
        st = pyramid_compare(r, &sc->volume, &base, &runs[PANEL_MIP].image[0], path);
        if (st == PP5_OK)
            printf("  image: %s\n", path);
    }
    for (int p = 0; p < PANELS; p++)
        for (int m = 0; m < 2; m++)
            image8_free(&runs[p].image[m]);
    return st;
}

static int demip_dataset(const char *dataset, const demip_opts_t *d, bool *phantom_done)
{
    scene_t sc;
    pp5_status_t st = scene_load(dataset, true, &sc);
    if (st != PP5_OK)
        return cliopt_report("reproduce", st);
    if (sc.fell_back && *phantom_done) {
        printf("\n%s: %s (the phantom's figures are above)\n", dataset, sc.note);
        scene_free(&sc);
        return 0;
    }
    *phantom_done = *phantom_done || sc.fell_back;
    const char *tag = sc.fell_back ? "phantom" : dataset;
    printf("\n%s: %s, %dx%dx%d, spacing %g:%g:%g\n", sc.fell_back ? "FALLBACK" : dataset,
           sc.volume.source, sc.volume.nx, sc.volume.ny, sc.volume.nz, sc.volume.spacing[0],
           sc.volume.spacing[1], sc.volume.spacing[2]);
    if (sc.fell_back)
        printf("  NOTE: %s; the figures below are the phantom's, not the data's.\n", sc.note);
    if (sc.window_width > 0.0f)
        printf("  window C=%g W=%g (material 0 at %g, 1 at %g); compositing: transfer "
               "function %s\n", sc.window_centre, sc.window_width,
               sc.window_centre - 0.5 * sc.window_width, sc.window_centre + 0.5 * sc.window_width,
               sc.tf.name);
    else
        printf("  window: the volume's value range %g..%g; compositing: transfer function %s\n",
               sc.volume.min_value, sc.volume.max_value, sc.tf.name);
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    st = native_renderer_init(&r, &sc.volume, &sc.tf, &sh, d->o->threads);
    if (st == PP5_OK)
        st = native_renderer_build_scalar(&r, &sc.volume, SCALAR_PYRAMID_MAX);
    if (st == PP5_OK) {
        printf("  value pyramid (max) %.1f MB built in %.0f ms; %dx%d, parallel, one sample per "
               "voxel, %d thread%s, median of %d frames\n", r.scalar.bytes / 1e6, r.ms_build_scalar,
               d->size, d->size, r.threads, r.threads == 1 ? "" : "s", d->o->repeats);
        st = demip_measure(&r, &sc, d, tag);
    }
    native_renderer_free(&r);
    scene_free(&sc);
    return st == PP5_OK ? 0 : cliopt_report("reproduce", st);
}

static void demip_usage(void)
{
    printf("usage: pp5 reproduce demip [--size N] [--datasets A,B] [common options]\n\n"
           "Diaz & Vazquez 2010, Table 1 as cost ratios: MIP, DEMIP, DEMIP with the colour\n"
           "sphere, MIDA and compositing on each dataset, full resolution and gaze-directed,\n"
           "with a comparison image, the eps sweep and the max/box pyramid comparison.\n"
           "  --size N          image side (default 512, the paper's viewport)\n"
           "  --datasets LIST   comma-separated (default cthead,mrbrain; phantom names work)\n"
           "  --machine-size N  the emulated machine's image side (default 256: its frames\n"
           "                    are emulated sample by sample; 0 skips the machine)\n"
           "Images go to --out-dir (default build/reproduce-demip).\n"
           "Example: pp5 reproduce demip --threads 2 --repeats 3 --out-dir demip\n"
           "         pp5 reproduce demip --datasets shepp-logan --size 64 --machine-size 32\n");
}

static pp5_status_t parse_demip_options(const pp5_reproduce_opts_t *o, demip_opts_t *d, bool *help)
{
    static const struct option longopts[] = {
        {"size", required_argument, NULL, 's'},
        {"datasets", required_argument, NULL, 'd'},
        {"machine-size", required_argument, NULL, 'm'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    long l;
    int c;
    optind = 1;
    opterr = 1;
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && (c = getopt_long(o->argc, o->argv, "h", longopts, NULL)) != -1) {
        if (c == 's') {
            st = cliopt_long("--size", optarg, 16, 4096, &l);
            d->size = (int)l;
        } else if (c == 'd') {
            d->datasets = optarg;
        } else if (c == 'm') {
            st = cliopt_long("--machine-size", optarg, 0, 4096, &l);
            d->machine_size = (int)l;
        } else if (c == 'h') {
            *help = true;
        } else {
            st = pp5_fail(PP5_E_CONFIG, "reproduce demip: unknown option (see --help)");
        }
    }
    if (st == PP5_OK && optind < o->argc)
        st = pp5_fail(PP5_E_CONFIG, "reproduce demip: unexpected argument '%s'", o->argv[optind]);
    return st;
}

static int reproduce_demip(const pp5_reproduce_opts_t *o)
{
    demip_opts_t d = {512, 256, "cthead,mrbrain", o, o->out_dir};
    bool help = false;
    pp5_status_t st = parse_demip_options(o, &d, &help);
    if (st != PP5_OK)
        return cliopt_report("reproduce", st);
    if (help) {
        demip_usage();
        return 0;
    }
    if (!d.out_dir) {
        d.out_dir = "build/reproduce-demip";
        if ((access("build", F_OK) != 0 && mkdir("build", 0777) != 0) ||
            (access(d.out_dir, F_OK) != 0 && mkdir(d.out_dir, 0777) != 0))
            return cliopt_report("reproduce", pp5_fail(PP5_E_IO, "%s: cannot create the folder",
                                                       d.out_dir));
    }
    print_paper_table();
    char list[256];
    snprintf(list, sizeof list, "%s", d.datasets);
    bool phantom_done = false;
    int rc = 0;
    for (char *save = NULL, *name = strtok_r(list, ",", &save); rc == 0 && name;
         name = strtok_r(NULL, ",", &save))
        rc = demip_dataset(name, &d, &phantom_done);
    return rc;
}

PP5_REPRODUCE(demip, "Diaz & Vazquez 2010 Table 1: MIP, DEMIP, MIDA, DVR cost ratios",
              reproduce_demip)
