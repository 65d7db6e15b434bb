/* reproduce_polygons.c: `pp5 reproduce polygons`: Gouraud and Phong triangles per second at 100-pixel triangles on the emulated machine beside the 1989 design target and the 1991 measurements, and the sweeps over triangle size and GP count showing where the machine turns from GP-bound to renderer-bound.
 *
 * Every figure is counted: GP cycles from the cost rows of
 * firmware/common/poly_cost.h under the i860 model, renderer cycles from the
 * PP instructions the renderers executed, ring time from the messages.
 * Nothing is tuned to the published figures; where they disagree the
 * command prints by how much and which stage (and which parameters) set
 * the emulated figure. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/poly_scene.h"
#include "firmware/host/poly_session.h"
#include "params.h"
#include "cliopt.h"
#include "registry.h"

typedef struct {
    pp5_params_cli_t cli;
    size_t triangles;
    bool quick;
} poly_repro_t;

typedef struct {
    double area;
    poly_shading_t shading;
    unsigned n_gp;                /* 0: the parameter table's */
    unsigned n_renderers;         /* 0: the parameter table's */
} poly_point_t;

static pp5_status_t run_point(const poly_repro_t *o, const poly_point_t *pt, poly_frame_result_t *r,
                              pp5_params_t *used)
{
    pp5_params_t p;
    pp5_status_t st = pp5_params_build(&o->cli, &p);
    if (st != PP5_OK)
        return st;
    if (pt->n_gp)
        p.n_gp = pt->n_gp;
    if (pt->n_renderers)
        p.n_renderers = pt->n_renderers;
    *used = p;
    int W = (int)p.fb_width, H = (int)p.fb_height;
    poly_tri_in_t *tris;
    raster_camera_t cam;
    st = poly_scene_triangles(o->triangles, pt->area, W, H, 1989u, &tris, &cam);
    if (st != PP5_OK)
        return st;
    raster_style_t style;
    raster_style_default(&style, RASTER_GOURAUD);
    poly_options_t opt;
    poly_options_default(&opt);
    opt.shading = pt->shading;
    poly_session_t s;
    st = poly_session_init(&s, &p, tris, o->triangles, W, H, &cam, &style, &opt);
    free(tris);
    if (st == PP5_OK)
        st = poly_session_frame(&s, NULL, r);
    poly_session_free(&s);
    return st;
}

static const char *short_stage(const poly_frame_result_t *r)
{
    int b = 0;
    for (int k = 1; k < POLY_STAGE_COUNT; k++)
        if (r->stage_s[k] > r->stage_s[b])
            b = k;
    static const char *const names[POLY_STAGE_COUNT] = {"GP", "renderer", "ring", "rn-port"};
    return names[b];
}

/* Why the emulated figure is what it is: the bottleneck's own counts. */
static void print_cause(const poly_frame_result_t *r, const pp5_params_t *p)
{
    const char *b = short_stage(r);
    if (strcmp(b, "renderer") == 0) {
        double per_pair = r->pairs_sent ? (double)r->rn_exec_cycles_total / (double)r->pairs_sent : 0;
        printf("    cause: renderer-bound: %.0f renderer cycles per (triangle, region) pair at %.0f MHz "
               "(%.0f %% of them QEE: pp.qee_fill_cycles = %u [U] fill + 1 bit per clock [I] per "
               "expression; %.2f pairs per triangle); the 1991 PP instruction set and timing are not "
               "public (facts §3.4), ours is emu/PP_ISA.md\n",
               per_pair, p->renderer_clock_hz / 1e6,
               r->rn_exec_cycles_total ? 100.0 * (double)r->rn_qee_cycles_total / (double)r->rn_exec_cycles_total : 0,
               p->pp.qee_fill_cycles, r->tris_in ? (double)r->pairs_sent / (double)r->tris_in : 0);
    } else if (strcmp(b, "GP") == 0) {
        double per_tri = r->tris_in ? (double)(r->cycles_transform + r->cycles_sort + r->cycles_encode) /
                                          (double)r->tris_in : 0;
        printf("    cause: GP-bound: %.0f i860 cycles per triangle (transform, clip, set-up, sort, "
               "stream) from the cost rows (firmware/common/poly_cost.h) at %.0f MHz, dual issue %s "
               "(facts §8: compiled code rarely dual-issued); facts §8 sketches 1-2 K cycles\n",
               per_tri, p->gp_clock_hz / 1e6, p->i860_dual_issue ? "on" : "off");
    } else if (strcmp(b, "rn-port") == 0) {
        printf("    cause: bound by the renderers' transmitters: each sends its regions (128 x 128 x 3 "
               "bytes) one at a time over one ring channel (80 MB/s: ring.width_bits x ring.clock_hz, "
               "the split [U] facts §5.2)\n");
    } else {
        printf("    cause: ring-bound: %.3f ms of traffic per channel per frame (%u channels; region "
               "transfers %.1f MB, a fixed cost per frame; commands %.1f MB)\n",
               1e3 * r->stage_s[POLY_STAGE_RING], p->ring_channels,
               r->ring_bytes[RING_CLASS_PIXELS] / 1e6, r->ring_bytes[RING_CLASS_COMMAND] / 1e6);
    }
}

/* One published figure beside ours. */
static void beside(const char *what, double ours, double published, const char *source,
                   const poly_frame_result_t *r, const pp5_params_t *p)
{
    double ratio = ours / published;
    printf("  %-34s %6.2f M/s   published %4.2f M/s  %-44s ratio %.2f\n", what, ours / 1e6,
           published / 1e6, source, ratio);
    if (ratio < 0.8 || ratio > 1.25) {
        printf("    disagreement: the emulated machine is %.2fx the published figure\n", ratio);
        print_cause(r, p);
    }
}

static int headline(const poly_repro_t *o)
{
    poly_frame_result_t g, ph;
    pp5_params_t p;
    poly_point_t pg = {100, POLY_GOURAUD, 0, 0}, pp = {100, POLY_PHONG, 0, 0};
    pp5_status_t st = run_point(o, &pg, &g, &p);
    if (st == PP5_OK)
        st = run_point(o, &pp, &ph, &p);
    if (st != PP5_OK)
        return cliopt_report("reproduce polygons", st);
    printf("Polygon throughput, %zu independent 100-pixel triangles per frame (random place, rotation "
           "and depth; z-buffered), %u GPs, %u renderers, %ux%u screen, frames pipelined "
           "(triangles / the busiest stage):\n", o->triangles, p.n_gp, p.n_renderers, p.fb_width,
           p.fb_height);
    printf("  %-34s %9s   %-14s\n", "", "emulated", "");
    beside("Gouraud, z-buffered", g.tris_per_s_pipelined, 1.6e6,
           "measured Apr 1991 [S] S3 (facts §7.1)", &g, &p);
    beside("Phong, z-buffered", ph.tris_per_s_pipelined, 1.0e6,
           "design target 1989 [C] S1 (facts §7.1)", &ph, &p);
    beside("Phong, z-buffered", ph.tris_per_s_pipelined, 1.0e6,
           "measured Apr 1991 \"1+M\" [S] S3 (facts §7.1)", &ph, &p);
    printf("  one frame alone (no overlap of GP and renderer work): Gouraud %.3f ms = %.2f M/s, "
           "Phong %.3f ms = %.2f M/s; bottleneck %s / %s\n", 1e3 * g.frame_time_s,
           g.tris_per_s_frame / 1e6, 1e3 * ph.frame_time_s, ph.tris_per_s_frame / 1e6,
           short_stage(&g), short_stage(&ph));
    printf("  the configuration of the 1991 measurement is not known (facts open question 8): "
           "the sweep below shows the figure over GP counts\n");
    return 0;
}

static void sweep_row(const char *label, const poly_frame_result_t *r)
{
    printf("  %-10s %8.3f %10.3f %10.3f %10.3f %10.3f   %-8s %6.2f\n", label,
           r->tris_per_s_pipelined / 1e6, 1e3 * r->stage_s[POLY_STAGE_GP],
           1e3 * r->stage_s[POLY_STAGE_RENDERER], 1e3 * r->stage_s[POLY_STAGE_RING],
           1e3 * r->stage_s[POLY_STAGE_RN_PORT], short_stage(r),
           r->tris_in ? (double)r->pairs_sent / (double)r->tris_in : 0);
}

/* The next stage after the GPs: where GP time / k would meet it. */
static double other_stage(const poly_frame_result_t *r)
{
    double m = 0;
    for (int k = 1; k < POLY_STAGE_COUNT; k++)
        m = r->stage_s[k] > m ? r->stage_s[k] : m;
    return m;
}

/* Fewer renderers at the most GPs: where the machine becomes renderer-bound. */
static int renderer_sweep(const poly_repro_t *o)
{
    static const unsigned rns[] = {2, 4, 8, 16};
    poly_frame_result_t r;
    pp5_params_t p;
    printf("\nSweep over renderer count (Gouraud, 100-pixel triangles, 32 GPs):\n");
    printf("  %-10s %8s %10s %10s %10s %10s   %-8s %6s\n", "renderers", "M tri/s", "GP ms", "rend. ms",
           "ring ms", "port ms", "bound", "pairs");
    for (size_t i = 0; i < sizeof rns / sizeof rns[0]; i++) {
        poly_point_t pt = {100, POLY_GOURAUD, 32, rns[i]};
        char label[16];
        snprintf(label, sizeof label, "%u", rns[i]);
        if (run_point(o, &pt, &r, &p) != PP5_OK) {
            printf("  %-10s not run: %s\n", label, pp5_error_text());
            continue;
        }
        sweep_row(label, &r);
    }
    return 0;
}

static int sweeps(const poly_repro_t *o)
{
    static const double sizes[] = {10, 30, 100, 300, 1000};
    static const unsigned gps[] = {1, 2, 4, 8, 16, 32};
    pp5_params_t p;
    poly_frame_result_t r;
    const char *head = "  %-10s %8s %10s %10s %10s %10s   %-8s %6s\n";
    printf("\nSweep over triangle size (Gouraud, the parameter table's GP count):\n");
    printf(head, "pixels", "M tri/s", "GP ms", "rend. ms", "ring ms", "port ms", "bound", "pairs");
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        poly_point_t pt = {sizes[i], POLY_GOURAUD, 0, 0};
        char label[16];
        snprintf(label, sizeof label, "%g", sizes[i]);
        if (run_point(o, &pt, &r, &p) != PP5_OK) {
            printf("  %-10s not run: %s\n", label, pp5_error_text());
            continue;
        }
        sweep_row(label, &r);
    }
    for (int sh = POLY_GOURAUD; sh <= POLY_PHONG; sh++) {
        printf("\nSweep over GP count (%s, 100-pixel triangles):\n", poly_shading_name((poly_shading_t)sh));
        printf(head, "GPs", "M tri/s", "GP ms", "rend. ms", "ring ms", "port ms", "bound", "pairs");
        int turn = -1;
        double cross = 0;
        for (size_t i = 0; i < sizeof gps / sizeof gps[0]; i++) {
            if (o->quick && gps[i] > 8)
                break;
            poly_point_t pt = {100, (poly_shading_t)sh, gps[i], 0};
            char label[16];
            snprintf(label, sizeof label, "%u", gps[i]);
            if (run_point(o, &pt, &r, &p) != PP5_OK) {
                /* e.g. one GP's 8 MiB cannot hold a large scene */
                printf("  %-10s not run: %s\n", label, pp5_error_text());
                continue;
            }
            sweep_row(label, &r);
            if (turn < 0 && strcmp(short_stage(&r), "GP") != 0)
                turn = (int)gps[i];
            /* GP time falls as 1 / GPs (the same work dealt wider): the
             * count at which it would equal the next stage */
            cross = gps[i] * r.stage_s[POLY_STAGE_GP] / other_stage(&r);
        }
        if (turn > 0)
            printf("  turn: GP-bound below %d GPs, %s-bound from %d on\n", turn,
                   turn == 1 ? "not GP" : "renderer or ring", turn);
        else
            printf("  turn: GP-bound at every GP count swept; GP time scaled by 1/GPs from the last "
                   "row meets the next stage near %.0f GPs\n", cross);
    }
    return renderer_sweep(o);
}

static int reproduce_polygons(const pp5_reproduce_opts_t *ro)
{
    poly_repro_t o;
    memset(&o, 0, sizeof o);
    o.triangles = 40000;
    static const struct option longs[] = {{"quick", no_argument, NULL, 'q'},
                                          {"triangles", required_argument, NULL, 'n'},
                                          {"set", required_argument, NULL, 's'},
                                          {"help", no_argument, NULL, 'h'},
                                          {NULL, 0, NULL, 0}};
    optind = 1;
    int c;
    while ((c = getopt_long(ro->argc, ro->argv, "", longs, NULL)) != -1) {
        if (c == 'q') {
            o.quick = true;
        } else if (c == 'n') {
            char *end;
            long v = strtol(optarg, &end, 10);
            if (*end || v < 100 || v > 2000000) {
                fprintf(stderr, "reproduce polygons: --triangles %s (allowed 100..2000000)\n", optarg);
                return 2;
            }
            o.triangles = (size_t)v;
        } else if (c == 's') {
            pp5_status_t st = pp5_params_cli_add_set(&o.cli, optarg);
            if (st != PP5_OK)
                return cliopt_report("reproduce polygons", st);
        } else if (c == 'h') {
            printf("usage: pp5 reproduce polygons [--quick] [--triangles N] [--set NAME=VALUE]...\n"
                   "  Gouraud and Phong triangles/s at 100-pixel triangles beside the published\n"
                   "  figures, and sweeps over triangle size and GP count.\n"
                   "  --quick        4,000 triangles, GP counts up to 8 (a few seconds)\n"
                   "  --triangles N  triangles per frame (default 40,000)\n"
                   "  --set K=V      a machine parameter for every run (see pp5 machine)\n"
                   "Example: pp5 reproduce polygons --quick --set pp.qee_fill_cycles=8\n");
            return 0;
        } else {
            return 2;
        }
    }
    if (o.quick && o.triangles == 40000)
        o.triangles = 4000;
    int rc = headline(&o);
    return rc ? rc : sweeps(&o);
}

PP5_REPRODUCE(polygons, "Pixel-Planes 5 polygons: Gouraud and Phong triangles/s beside the 1989 target and 1991 "
              "measurements; sweeps over triangle size and GP count", reproduce_polygons)
