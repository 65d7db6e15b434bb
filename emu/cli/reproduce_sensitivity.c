/* reproduce_sensitivity.c: the sensitivity block of `pp5 reproduce projections`: the frame time of the best division as each unverified or inferred machine parameter moves over the plausible range written beside it in the parameter table. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "params.h"
#include "progress.h"
#include "render/parallel.h"
#include "reproduce_projections.h"

typedef struct {
    const param_info_t *row;
    double lo_s, hi_s;         /* steady frame time at the range's low and high end */
    bool ok;
    char error[2][512];        /* why the low / high run failed (each written by its own run) */
} sens_t;

static bool uncertain(const param_info_t *row)
{
    return params_has_range(row) &&
           (strstr(row->citation, "[U]") != NULL || strstr(row->citation, "[I]") != NULL);
}

static int by_swing(const void *a, const void *b)
{
    const sens_t *x = a, *y = b;
    double dx = x->ok ? x->hi_s - x->lo_s : 0, dy = y->ok ? y->hi_s - y->lo_s : 0;
    dx = dx < 0 ? -dx : dx;
    dy = dy < 0 ? -dy : dy;
    return (dx < dy) - (dx > dy);
}

/* The steady frame with one parameter at `value`. */
static pp5_status_t frame_at(const proj_workload_t *w, fw_division_t d, int size,
                             const param_info_t *row, double value, double *s)
{
    char text[64];
    snprintf(text, sizeof text, "%.17g", value);
    proj_set_t set = {row->name, text};
    pp5_params_t p;
    pp5_status_t st = proj_machine("default", &set, 1, &p);
    proj_row_t r;
    if (st == PP5_OK)
        st = proj_run(w, 1, d, &p, size, &r);
    *s = st == PP5_OK ? r.steady_s : 0;
    return st;
}

/* Every varied parameter at once at the end of its range that gave the
 * faster (k = 0) or the slower (k = 1) frame alone. */
static pp5_status_t corner_frames(const proj_workload_t *w, fw_division_t d, int size,
                                  const sens_t *v, size_t n, double out[2])
{
    proj_set_t *sets = calloc(n ? n : 1, sizeof *sets);
    char (*text)[32] = calloc(n ? n : 1, sizeof *text);
    pp5_status_t st = sets && text ? PP5_OK : pp5_fail(PP5_E_NOMEM, "out of memory");
    for (int k = 0; k < 2 && st == PP5_OK; k++) {
        size_t m = 0;
        for (size_t i = 0; i < n; i++) {
            if (!v[i].ok)
                continue;
            bool low_is_slower = v[i].lo_s > v[i].hi_s;
            double value = (k == 1) == low_is_slower ? v[i].row->plausible_lo : v[i].row->plausible_hi;
            snprintf(text[m], sizeof text[m], "%.17g", value);
            sets[m] = (proj_set_t){v[i].row->name, text[m]};
            m++;
        }
        pp5_params_t p;
        proj_row_t r;
        st = proj_machine("default", sets, (int)m, &p);
        if (st == PP5_OK)
            st = proj_run(w, 1, d, &p, size, &r);
        out[k] = st == PP5_OK ? r.steady_s : 0;
    }
    free(sets);
    free(text);
    return st;
}

/* The runs of the block: item 0 the defaults, then each parameter's low
 * and high end (items 2i + 1, 2i + 2). */
typedef struct {
    const proj_workload_t *w;
    fw_division_t d;
    int size;
    sens_t *v;
    double base_s;
    pp5_status_t base_st;
    char base_error[512];
    proj_runs_t runs;
} sens_runs_t;

static void sens_run(void *ctx, int item, int thread)
{
    (void)thread;
    sens_runs_t *t = ctx;
    if (item == 0) {
        pp5_params_t p;
        proj_row_t r;
        t->base_st = proj_machine("default", NULL, 0, &p);
        if (t->base_st == PP5_OK)
            t->base_st = proj_run(t->w, 1, t->d, &p, t->size, &r);
        t->base_s = t->base_st == PP5_OK ? r.steady_s : 0;
        if (t->base_st != PP5_OK)
            snprintf(t->base_error, sizeof t->base_error, "%s", pp5_error_text());
        proj_runs_step(&t->runs, "defaults");
        return;
    }
    sens_t *v = &t->v[(item - 1) / 2];
    bool high = (item - 1) % 2 == 1;
    double *s = high ? &v->hi_s : &v->lo_s;
    if (frame_at(t->w, t->d, t->size, v->row, high ? v->row->plausible_hi : v->row->plausible_lo,
                 s) != PP5_OK) {
        *s = NAN;
        snprintf(v->error[high], sizeof v->error[high], "%s", pp5_error_text());
    }
    proj_runs_step(&t->runs, v->row->name);
}

int proj_sensitivity(const proj_workload_t *w, fw_division_t d, int size, bool quick, int threads)
{
    size_t n = 0, cap = params_count();
    sens_t *v = calloc(cap, sizeof *v);
    if (!v)
        return 1;
    for (size_t i = 0; i < cap; i++)
        if (uncertain(params_info(i)))
            v[n++].row = params_info(i);
    if (quick && n > 3)
        n = 3;
    sens_runs_t t = {.w = w, .d = d, .size = size, .v = v};
    proj_runs_begin(&t.runs, "sensitivity", (int)(2 * n + 1));
    pp5_status_t pst = parallel_for(threads, (int)(2 * n + 1), sens_run, &t);
    proj_runs_end(&t.runs);
    if (pst != PP5_OK || t.base_st != PP5_OK) {
        printf("\nSensitivity: not run (%s).\n", pst != PP5_OK ? pp5_error_text() : t.base_error);
        free(v);
        return 1;
    }
    double lo = t.base_s, hi = t.base_s;
    for (size_t i = 0; i < n; i++) {
        v[i].ok = !isnan(v[i].lo_s) && !isnan(v[i].hi_s);
        if (v[i].ok) {
            double a = v[i].lo_s < v[i].hi_s ? v[i].lo_s : v[i].hi_s;
            double b = v[i].lo_s < v[i].hi_s ? v[i].hi_s : v[i].lo_s;
            lo = a < lo ? a : lo;
            hi = b > hi ? b : hi;
        }
    }
    proj_row_t base = {.steady_s = t.base_s};
    double corner[2] = {0, 0};   /* every parameter at its faster / slower end together */
    bool corner_ok = corner_frames(w, d, size, v, n, corner) == PP5_OK;
    qsort(v, n, sizeof *v, by_swing);
    printf("\nSensitivity of the headline (%s, workload B, specular): each [U]/[I] parameter of the\n"
           "table alone at the low and the high end of its plausible range (pp5 machine shows the\n"
           "ranges and why), the others at their defaults.  %zu parameters.\n"
           "Steady frame: %.1f ms at the defaults; %.1f .. %.1f ms over the ranges = %.1f .. %.1f "
           "frames/s.\nThe parameters that move it most:\n", fw_division_name(d), n,
           base.steady_s * 1e3, lo * 1e3, hi * 1e3, hi > 0 ? 1.0 / hi : 0, lo > 0 ? 1.0 / lo : 0);
    printf("| parameter | range | ms at low | ms at high | swing |\n|---|---|---|---|---|\n");
    for (size_t i = 0; i < n && i < 8; i++) {
        if (!v[i].ok) {
            printf("| %s | %g .. %g | error: %s | | |\n", v[i].row->name, v[i].row->plausible_lo,
                   v[i].row->plausible_hi, v[i].error[isnan(v[i].lo_s) ? 0 : 1]);
            continue;
        }
        printf("| %s | %g .. %g %s | %.1f | %.1f | %+.1f ms |\n", v[i].row->name,
               v[i].row->plausible_lo, v[i].row->plausible_hi, v[i].row->unit, v[i].lo_s * 1e3,
               v[i].hi_s * 1e3, (v[i].hi_s - v[i].lo_s) * 1e3);
    }
    if (corner_ok)
        printf("All of them together at the ends that speed or slow the frame: %.1f .. %.1f ms = "
               "%.1f .. %.1f frames/s.\n", corner[0] * 1e3, corner[1] * 1e3,
               corner[1] > 0 ? 1.0 / corner[1] : 0, corner[0] > 0 ? 1.0 / corner[0] : 0);
    else
        printf("All of them together: not run (%s).\n", pp5_error_text());
    free(v);
    return 0;
}
