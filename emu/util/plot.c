/* plot.c: the chart model of plot.h (series, styles, ranges, reference
 * lines, categories) and its axes: ranges rounded to "nice" tick steps.
 * Text, margins and drawing are in plot_draw.c (cairo); both that and
 * plot_data_to_pixel use the one layout, so annotations and tests agree with
 * what is drawn. */
#include "plot.h"
#include "plot_layout.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* A fixed palette of distinguishable colours, chosen by hand. */
static const uint8_t palette[10][3] = {
    {40, 90, 200},  {235, 120, 20}, {40, 160, 60},  {210, 40, 40},  {140, 90, 190},
    {130, 80, 60},  {220, 100, 180}, {110, 110, 110}, {170, 170, 30}, {30, 180, 200},
};

void plot_init(plot_t *p, const char *title, const char *xlabel, const char *ylabel)
{
    memset(p, 0, sizeof *p);
    snprintf(p->title, sizeof p->title, "%s", title ? title : "");
    snprintf(p->xlabel, sizeof p->xlabel, "%s", xlabel ? xlabel : "");
    snprintf(p->ylabel, sizeof p->ylabel, "%s", ylabel ? ylabel : "");
    p->stack_style = PLOT_STACK_BARS;
    p->legend = true;
}

void plot_free(plot_t *p)
{
    for (int i = 0; i < p->n_series; i++) {
        free(p->series[i].xs);
        free(p->series[i].ys);
        p->series[i].xs = p->series[i].ys = NULL;
    }
    p->n_series = 0;
}

static pp5_status_t add(plot_t *p, const char *name, const double *xs, const double *ys, int n,
                        bool stacked)
{
    if (p->n_series >= PLOT_MAX_SERIES)
        return pp5_fail(PP5_E_RANGE, "plot: more than %d series", PLOT_MAX_SERIES);
    if (n < 1 || n > PLOT_MAX_POINTS || !xs || !ys)
        return pp5_fail(PP5_E_RANGE, "plot: series '%s' has %d points (need 1..%d)",
                        name ? name : "", n, PLOT_MAX_POINTS);
    for (int i = 0; i < n; i++) {
        if (!isfinite(xs[i]) || !isfinite(ys[i]))
            return pp5_fail(PP5_E_RANGE, "plot: series '%s' point %d is not finite",
                            name ? name : "", i);
        if (stacked && ys[i] < 0)
            return pp5_fail(PP5_E_RANGE, "plot: stacked series '%s' point %d is negative (%g)",
                            name ? name : "", i, ys[i]);
    }
    plot_series_t *s = &p->series[p->n_series];
    memset(s, 0, sizeof *s);
    s->xs = malloc((size_t)n * sizeof(double));
    s->ys = malloc((size_t)n * sizeof(double));
    if (!s->xs || !s->ys) {
        free(s->xs);
        free(s->ys);
        s->xs = s->ys = NULL;
        return pp5_fail(PP5_E_NOMEM, "plot: cannot copy %d points", n);
    }
    memcpy(s->xs, xs, (size_t)n * sizeof(double));
    memcpy(s->ys, ys, (size_t)n * sizeof(double));
    snprintf(s->name, sizeof s->name, "%s", name ? name : "");
    s->n = n;
    s->stacked = stacked;
    s->style = PLOT_LINE;
    memcpy(s->rgb, palette[p->n_series % 10], 3);
    s->thickness_px = 2;
    p->n_series++;
    return PP5_OK;
}

pp5_status_t plot_add_series(plot_t *p, const char *name, const double *xs, const double *ys,
                             int n)
{
    return add(p, name, xs, ys, n, false);
}

pp5_status_t plot_add_stacked(plot_t *p, const char *name, const double *xs, const double *ys,
                              int n)
{
    return add(p, name, xs, ys, n, true);
}

void plot_set_style(plot_t *p, int index, plot_line_style_t style)
{
    if (index >= 0 && index < p->n_series)
        p->series[index].style = style;
}

void plot_set_color(plot_t *p, int index, uint8_t r, uint8_t g, uint8_t b)
{
    if (index >= 0 && index < p->n_series) {
        p->series[index].rgb[0] = r;
        p->series[index].rgb[1] = g;
        p->series[index].rgb[2] = b;
    }
}

void plot_set_stack_style(plot_t *p, plot_stack_style_t style) { p->stack_style = style; }
void plot_set_log_y(plot_t *p, bool log_y) { p->log_y = log_y; }
void plot_set_legend(plot_t *p, bool on) { p->legend = on; }
void plot_set_y_down(plot_t *p, bool y_down) { p->y_down = y_down; }

void plot_set_xrange(plot_t *p, double xmin, double xmax)
{
    p->fixed_x = true;
    p->xmin = xmin;
    p->xmax = xmax;
}

void plot_set_yrange(plot_t *p, double ymin, double ymax)
{
    p->fixed_y = true;
    p->ymin = ymin;
    p->ymax = ymax;
}

pp5_status_t plot_set_categories(plot_t *p, const char *const *labels, int n)
{
    if (n < 0 || n > PLOT_MAX_CATEGORIES)
        return pp5_fail(PP5_E_RANGE, "plot: %d categories (max %d)", n, PLOT_MAX_CATEGORIES);
    for (int i = 0; i < n; i++)
        snprintf(p->categories[i], sizeof p->categories[i], "%s", labels[i] ? labels[i] : "");
    p->n_categories = n;
    return PP5_OK;
}

static pp5_status_t add_ref(plot_t *p, bool vertical, double at, const char *label)
{
    if (p->n_refs >= PLOT_MAX_REFS)
        return pp5_fail(PP5_E_RANGE, "plot: more than %d reference lines", PLOT_MAX_REFS);
    if (!isfinite(at))
        return pp5_fail(PP5_E_RANGE, "plot: reference line position is not finite");
    p->refs[p->n_refs].vertical = vertical;
    p->refs[p->n_refs].at = at;
    snprintf(p->refs[p->n_refs].label, sizeof p->refs[p->n_refs].label, "%s", label ? label : "");
    p->n_refs++;
    return PP5_OK;
}

pp5_status_t plot_add_xref(plot_t *p, double at, const char *label)
{
    return add_ref(p, true, at, label);
}

pp5_status_t plot_add_yref(plot_t *p, double at, const char *label)
{
    return add_ref(p, false, at, label);
}

/* 1, 2 or 5 times a power of ten, at least `raw`. */
static double nice_step(double raw)
{
    if (!(raw > 0))
        return 1.0;
    double mag = pow(10.0, floor(log10(raw)));
    double f = raw / mag;
    double nice = f <= 1.0 ? 1.0 : f <= 2.0 ? 2.0 : f <= 5.0 ? 5.0 : 10.0;
    return nice * mag;
}

/* Ticks at multiples of step within [lo, hi] (with a little tolerance). */
static int make_ticks(double lo, double hi, double step, double *ticks)
{
    int n = 0;
    double eps = step * 1e-9;
    for (double k = ceil((lo - eps) / step); n < PLOT_MAX_TICKS; k++) {
        double t = k * step;
        if (t > hi + eps)
            break;
        ticks[n++] = fabs(t) < eps ? 0.0 : t;
    }
    return n;
}

/* Label for a tick value, with as many decimals as the step needs. */
void plot_tick_label(double v, double step, bool log_axis, char *buf, size_t size)
{
    if (log_axis) {
        snprintf(buf, size, "%g", pow(10.0, v));
        return;
    }
    double a = fabs(v);
    if (a != 0 && (a >= 1e6 || a < 1e-4)) {
        snprintf(buf, size, "%.3g", v);
        return;
    }
    int decimals = step >= 1 ? 0 : (int)ceil(-log10(step) - 1e-9);
    if (decimals > 6)
        decimals = 6;
    snprintf(buf, size, "%.*f", decimals, v);
}

/* The shared x values of the stacked series, or an error if they differ. */
pp5_status_t plot_stacked_base(const plot_t *p, const plot_series_t **first)
{
    *first = NULL;
    for (int i = 0; i < p->n_series; i++) {
        const plot_series_t *s = &p->series[i];
        if (!s->stacked)
            continue;
        if (!*first) {
            *first = s;
            continue;
        }
        if (s->n != (*first)->n || memcmp(s->xs, (*first)->xs, (size_t)s->n * sizeof(double)))
            return pp5_fail(PP5_E_RANGE, "plot: stacked series '%s' and '%s' have different x "
                            "values", (*first)->name, s->name);
    }
    return PP5_OK;
}

/* The data's extents before the axes round them: x, and y in axis units
 * (log10 units on a log axis). */
typedef struct {
    double xlo, xhi, ylo, yhi;
} extent_t;

/* What must hold before anything is laid out; *base is the first stacked
 * series (NULL when there is none). */
static pp5_status_t layout_check(const plot_t *p, int width, int height,
                                 const plot_series_t **base)
{
    if (width < PLOT_MIN_W || height < PLOT_MIN_H || width > PLOT_MAX_SIDE ||
        height > PLOT_MAX_SIDE)
        return pp5_fail(PP5_E_RANGE, "plot: size %dx%d outside %dx%d..%dx%d", width, height,
                        PLOT_MIN_W, PLOT_MIN_H, PLOT_MAX_SIDE, PLOT_MAX_SIDE);
    if (p->n_series < 1)
        return pp5_fail(PP5_E_RANGE, "plot '%s': no series to draw", p->title);
    pp5_status_t st = plot_stacked_base(p, base);
    if (st != PP5_OK)
        return st;
    if (p->log_y && *base)
        return pp5_fail(PP5_E_RANGE, "plot '%s': stacked series need a linear y axis", p->title);
    return PP5_OK;
}

/* Stacked series: the bar width (0.7 of the smallest x spacing) and the
 * cumulative tops at each shared x widen the extents. */
static void stacked_extents(const plot_t *p, const plot_series_t *base, plot_layout_t *L,
                            extent_t *e)
{
    L->bar_width = 1.0;
    if (base->n > 1) {
        double dmin = INFINITY;
        for (int k = 1; k < base->n; k++)
            if (base->xs[k] != base->xs[k - 1])
                dmin = fmin(dmin, fabs(base->xs[k] - base->xs[k - 1]));
        if (isfinite(dmin))
            L->bar_width = dmin;
    }
    L->bar_width *= 0.7;
    for (int k = 0; k < base->n; k++) {
        double top = 0;
        for (int i = 0; i < p->n_series; i++)
            if (p->series[i].stacked)
                top += p->series[i].ys[k];
        e->ylo = fmin(e->ylo, 0.0);
        e->yhi = fmax(e->yhi, top);
    }
    if (p->stack_style == PLOT_STACK_BARS) {
        e->xlo -= L->bar_width / 2;
        e->xhi += L->bar_width / 2;
    }
}

/* Extents of every series (stacked tops and category slots included). */
static pp5_status_t data_extents(const plot_t *p, const plot_series_t *base, plot_layout_t *L,
                                 extent_t *e)
{
    *e = (extent_t){INFINITY, -INFINITY, INFINITY, -INFINITY};
    for (int i = 0; i < p->n_series; i++) {
        const plot_series_t *s = &p->series[i];
        for (int k = 0; k < s->n; k++) {
            e->xlo = fmin(e->xlo, s->xs[k]);
            e->xhi = fmax(e->xhi, s->xs[k]);
            if (!s->stacked) {
                if (p->log_y && s->ys[k] <= 0)
                    return pp5_fail(PP5_E_RANGE, "plot '%s': log y axis but series '%s' has "
                                    "y = %g", p->title, s->name, s->ys[k]);
                double y = p->log_y ? log10(s->ys[k]) : s->ys[k];
                e->ylo = fmin(e->ylo, y);
                e->yhi = fmax(e->yhi, y);
            }
        }
    }
    if (base)
        stacked_extents(p, base, L, e);
    if (p->n_categories > 0) {
        e->xlo = fmin(e->xlo, -0.5);
        e->xhi = fmax(e->xhi, p->n_categories - 0.5);
    }
    if (!p->log_y && e->ylo > 0)
        e->ylo = 0;   /* quantities from zero unless told otherwise */
    return PP5_OK;
}

/* The x range (fixed, or the data's rounded out to whole tick steps) and its
 * ticks (or one per category); *xstep is the tick step. */
static pp5_status_t layout_x_axis(const plot_t *p, const plot_series_t *base, extent_t e,
                                  plot_layout_t *L, double *xstep)
{
    double xlo = e.xlo, xhi = e.xhi;
    if (p->fixed_x) {
        if (!(p->xmax > p->xmin) || !isfinite(p->xmin) || !isfinite(p->xmax))
            return pp5_fail(PP5_E_RANGE, "plot '%s': x range %g..%g is empty", p->title, p->xmin,
                            p->xmax);
        xlo = p->xmin;
        xhi = p->xmax;
    } else if (xhi <= xlo) {
        double pad = xlo != 0 ? fabs(xlo) * 0.1 : 1.0;
        xlo -= pad;
        xhi += pad;
    }
    *xstep = nice_step((xhi - xlo) / 6.0);
    if (!p->fixed_x && p->n_categories == 0 && !(base && p->stack_style == PLOT_STACK_BARS)) {
        xlo = floor(xlo / *xstep + 1e-9) * *xstep;
        xhi = ceil(xhi / *xstep - 1e-9) * *xstep;
    }
    L->xmin = xlo;
    L->xmax = xhi;
    if (p->n_categories > 0) {
        L->n_xticks = 0;
        for (int i = 0; i < p->n_categories && i < PLOT_MAX_TICKS; i++)
            L->xticks[L->n_xticks++] = i;
    } else {
        L->n_xticks = make_ticks(xlo, xhi, *xstep, L->xticks);
    }
    return PP5_OK;
}

/* The y range: fixed, or the data's rounded out to whole tick steps (whole
 * decades on a log axis); *ystep is the tick step. */
static pp5_status_t layout_y_axis(const plot_t *p, extent_t e, plot_layout_t *L, double *ystep)
{
    double ylo = e.ylo, yhi = e.yhi;
    if (p->fixed_y) {
        double a = p->ymin, b = p->ymax;
        if (p->log_y) {
            if (!(a > 0) || !(b > 0))
                return pp5_fail(PP5_E_RANGE, "plot '%s': log y range must be positive", p->title);
            a = log10(a);
            b = log10(b);
        }
        if (!(b > a) || !isfinite(a) || !isfinite(b))
            return pp5_fail(PP5_E_RANGE, "plot '%s': y range %g..%g is empty", p->title, p->ymin,
                            p->ymax);
        ylo = a;
        yhi = b;
        *ystep = p->log_y ? fmax(1.0, ceil((b - a) / 8.0)) : nice_step((b - a) / 6.0);
    } else {
        if (yhi <= ylo) {
            double pad = ylo != 0 ? fabs(ylo) * 0.1 : 1.0;
            ylo -= p->log_y ? 0.5 : pad;
            yhi += p->log_y ? 0.5 : pad;
        }
        if (p->log_y) {
            ylo = floor(ylo);
            yhi = ceil(yhi);
            *ystep = fmax(1.0, ceil((yhi - ylo) / 8.0));
        } else {
            *ystep = nice_step((yhi - ylo) / 6.0);
            ylo = floor(ylo / *ystep + 1e-9) * *ystep;
            yhi = ceil(yhi / *ystep - 1e-9) * *ystep;
        }
    }
    L->ymin = ylo;
    L->ymax = yhi;
    L->n_yticks = make_ticks(ylo, yhi, *ystep, L->yticks);
    return PP5_OK;
}


pp5_status_t plot_layout_axes(const plot_t *p, int width, int height, plot_layout_t *L)
{
    memset(L, 0, sizeof *L);
    const plot_series_t *base = NULL;
    extent_t e;
    pp5_status_t st = layout_check(p, width, height, &base);
    if (st == PP5_OK) {
        L->have_stacked = base != NULL;
        st = data_extents(p, base, L, &e);
    }
    if (st == PP5_OK)
        st = layout_x_axis(p, base, e, L, &L->xstep);
    if (st == PP5_OK)
        st = layout_y_axis(p, e, L, &L->ystep);
    return st;
}

pp5_status_t plot_format_from_name(const char *path, plot_format_t *fmt)
{
    static const struct {
        const char *suffix;
        plot_format_t fmt;
    } known[] = {{".png", PLOT_FORMAT_PNG}, {".svg", PLOT_FORMAT_SVG}, {".pdf", PLOT_FORMAT_PDF}};
    size_t n = strlen(path);
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++) {
        size_t k = strlen(known[i].suffix);
        if (n > k && strcasecmp(path + n - k, known[i].suffix) == 0) {
            *fmt = known[i].fmt;
            return PP5_OK;
        }
    }
    return pp5_fail(PP5_E_CONFIG, "%s: a plot's name must end in .png, .svg or .pdf (the format "
                    "follows the name)", path);
}
