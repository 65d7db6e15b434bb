/* plot.c: rasterises plot_t charts (line series, stacked bars or areas) with
 * axes, "nice" numeric ticks, titles and a legend into an RGB image.
 *
 * One layout function decides the axis ranges, margins and tick steps; both
 * drawing and plot_data_to_pixel use it, so annotations and tests agree with
 * what is drawn.  Everything is integer/IEEE arithmetic on the inputs only:
 * the same plot always gives the same pixels. */
#include "plot.h"
#include "plot_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PLOT_MIN_W 160
#define PLOT_MIN_H 120
#define PLOT_MAX_SIDE 8192
#define TICK_PX 5
#define MAX_TICKS 64

/* A fixed palette of distinguishable colours, chosen by hand. */
static const uint8_t palette[10][3] = {
    {40, 90, 200},  {235, 120, 20}, {40, 160, 60},  {210, 40, 40},  {140, 90, 190},
    {130, 80, 60},  {220, 100, 180}, {110, 110, 110}, {170, 170, 30}, {30, 180, 200},
};
static const uint8_t black[3] = {0, 0, 0};
static const uint8_t grid_gray[3] = {225, 225, 225};

typedef struct {
    int scale;                 /* font scale */
    int x0, x1, y0, y1;        /* plot area, inclusive pixel bounds; y0 is the top row */
    double xmin, xmax;         /* x axis range */
    double ymin, ymax;         /* y axis range (log10 units when log_y) */
    double xticks[MAX_TICKS], yticks[MAX_TICKS];
    int n_xticks, n_yticks;
    double bar_width;          /* data units, for stacked bars */
    bool have_stacked;
    int legend_x;              /* left edge of the legend column */
} layout_t;

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
    for (double k = ceil((lo - eps) / step); n < MAX_TICKS; k++) {
        double t = k * step;
        if (t > hi + eps)
            break;
        ticks[n++] = fabs(t) < eps ? 0.0 : t;
    }
    return n;
}

/* Label for a tick value, with as many decimals as the step needs. */
static void tick_label(double v, double step, bool log_axis, char *buf, size_t size)
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
static pp5_status_t stacked_base(const plot_t *p, const plot_series_t **first)
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
    pp5_status_t st = stacked_base(p, base);
    if (st != PP5_OK)
        return st;
    if (p->log_y && *base)
        return pp5_fail(PP5_E_RANGE, "plot '%s': stacked series need a linear y axis", p->title);
    return PP5_OK;
}

/* Stacked series: the bar width (0.7 of the smallest x spacing) and the
 * cumulative tops at each shared x widen the extents. */
static void stacked_extents(const plot_t *p, const plot_series_t *base, layout_t *L,
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
static pp5_status_t data_extents(const plot_t *p, const plot_series_t *base, layout_t *L,
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
                                  layout_t *L, double *xstep)
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
        for (int i = 0; i < p->n_categories && i < MAX_TICKS; i++)
            L->xticks[L->n_xticks++] = i;
    } else {
        L->n_xticks = make_ticks(xlo, xhi, *xstep, L->xticks);
    }
    return PP5_OK;
}

/* The y range: fixed, or the data's rounded out to whole tick steps (whole
 * decades on a log axis); *ystep is the tick step. */
static pp5_status_t layout_y_axis(const plot_t *p, extent_t e, layout_t *L, double *ystep)
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

/* Margins from the text around the plot area (title, axis labels, tick
 * labels, legend), then the area itself; fails when nothing is left. */
static pp5_status_t layout_margins(const plot_t *p, int width, int height, double xstep,
                                   double ystep, layout_t *L)
{
    L->scale = (width >= 640 && height >= 400) ? 2 : 1;
    int ch = 7 * L->scale;
    int ylab_w = 0;
    char buf[64];
    for (int i = 0; i < L->n_yticks; i++) {
        tick_label(L->yticks[i], ystep, p->log_y, buf, sizeof buf);
        int w = plot_text_width(buf, L->scale);
        if (w > ylab_w)
            ylab_w = w;
    }
    int legend_w = 0;
    bool legend = p->legend && p->n_series > 1;
    if (legend) {
        for (int i = 0; i < p->n_series; i++) {
            int w = plot_text_width(p->series[i].name, L->scale);
            if (w > legend_w)
                legend_w = w;
        }
        legend_w += 4 * ch + 8;  /* swatch, gap, padding */
    }
    int last_xlab_half = 0;
    if (L->n_xticks > 0 && p->n_categories == 0) {
        tick_label(L->xticks[L->n_xticks - 1], xstep, false, buf, sizeof buf);
        last_xlab_half = plot_text_width(buf, L->scale) / 2;
    }
    int top = 10 + (p->title[0] ? ch + 10 : 0);
    int left = 8 + (p->ylabel[0] ? ch + 8 : 0) + ylab_w + 4 + TICK_PX;
    int bottom = TICK_PX + 4 + ch + (p->xlabel[0] ? 8 + ch : 0) + 10;
    int right = legend ? legend_w + 16 : 12 + last_xlab_half;
    L->x0 = left;
    L->x1 = width - 1 - right;
    L->y0 = top;
    L->y1 = height - 1 - bottom;
    L->legend_x = L->x1 + 12;
    if (L->x1 - L->x0 < 40 || L->y1 - L->y0 < 30)
        return pp5_fail(PP5_E_RANGE, "plot '%s': %dx%d leaves no room for the chart (labels or "
                        "legend too long)", p->title, width, height);
    return PP5_OK;
}

/* The one layout that drawing and plot_data_to_pixel share. */
static pp5_status_t compute_layout(const plot_t *p, int width, int height, layout_t *L)
{
    memset(L, 0, sizeof *L);
    const plot_series_t *base = NULL;
    extent_t e;
    double xstep = 0, ystep = 0;
    pp5_status_t st = layout_check(p, width, height, &base);
    if (st == PP5_OK) {
        L->have_stacked = base != NULL;
        st = data_extents(p, base, L, &e);
    }
    if (st == PP5_OK)
        st = layout_x_axis(p, base, e, L, &xstep);
    if (st == PP5_OK)
        st = layout_y_axis(p, e, L, &ystep);
    if (st == PP5_OK)
        st = layout_margins(p, width, height, xstep, ystep, L);
    return st;
}

static double map_x(const layout_t *L, double x)
{
    return L->x0 + (x - L->xmin) / (L->xmax - L->xmin) * (L->x1 - L->x0);
}

/* Row of a y value already in axis units (log10 units on a log axis). */
static double axis_row(const layout_t *L, const plot_t *p, double v)
{
    double f = (v - L->ymin) / (L->ymax - L->ymin);
    return p->y_down ? L->y0 + f * (L->y1 - L->y0) : L->y1 - f * (L->y1 - L->y0);
}

static double map_y(const layout_t *L, const plot_t *p, double y)
{
    return axis_row(L, p, p->log_y ? log10(y) : y);
}

bool plot_data_to_pixel(const plot_t *p, int width, int height, double x, double y, double *px,
                        double *py)
{
    layout_t L;
    if (compute_layout(p, width, height, &L) != PP5_OK)
        return false;
    if (p->log_y && !(y > 0))
        return false;
    *px = map_x(&L, x);
    *py = map_y(&L, p, y);
    return true;
}

/* Nearest pixel; far-off positions (data outside a fixed axis range) are
 * clamped so the conversion to int is always defined. */
static int round_px(double v)
{
    if (!(v > -1e6))
        return -1000000;
    if (v > 1e6)
        return 1000000;
    return (int)floor(v + 0.5);
}

static void fill_rect(image8_t *img, int xa, int ya, int xb, int yb, const uint8_t rgb[3])
{
    if (xa > xb) { int t = xa; xa = xb; xb = t; }
    if (ya > yb) { int t = ya; ya = yb; yb = t; }
    for (int y = ya; y <= yb; y++)
        for (int x = xa; x <= xb; x++)
            plot_put_pixel(img, x, y, rgb);
}

/* Square brush of `t` pixels at (x, y), kept inside the plot area. */
static void stamp(image8_t *img, const layout_t *L, int x, int y, int t, const uint8_t rgb[3])
{
    for (int dy = -(t / 2); dy <= (t - 1) / 2; dy++)
        for (int dx = -(t / 2); dx <= (t - 1) / 2; dx++) {
            int px = x + dx, py = y + dy;
            if (px >= L->x0 && px <= L->x1 && py >= L->y0 && py <= L->y1)
                plot_put_pixel(img, px, py, rgb);
        }
}

/* Liang-Barsky: clips the segment to the plot area; false if nothing is left. */
static bool clip_segment(const layout_t *L, double *xa, double *ya, double *xb, double *yb)
{
    double t0 = 0, t1 = 1, dx = *xb - *xa, dy = *yb - *ya;
    double pv[4] = {-dx, dx, -dy, dy};
    double qv[4] = {*xa - L->x0, L->x1 - *xa, *ya - L->y0, L->y1 - *ya};
    for (int i = 0; i < 4; i++) {
        if (pv[i] == 0) {
            if (qv[i] < 0)
                return false;
            continue;
        }
        double r = qv[i] / pv[i];
        if (pv[i] < 0) {
            if (r > t1)
                return false;
            if (r > t0)
                t0 = r;
        } else {
            if (r < t0)
                return false;
            if (r < t1)
                t1 = r;
        }
    }
    double nxa = *xa + t0 * dx, nya = *ya + t0 * dy;
    *xb = *xa + t1 * dx;
    *yb = *ya + t1 * dy;
    *xa = nxa;
    *ya = nya;
    return true;
}

static void draw_segment(image8_t *img, const layout_t *L, double fxa, double fya, double fxb,
                         double fyb, int t, const uint8_t rgb[3])
{
    if (!clip_segment(L, &fxa, &fya, &fxb, &fyb))
        return;
    int xa = round_px(fxa), ya = round_px(fya), xb = round_px(fxb), yb = round_px(fyb);
    int dx = abs(xb - xa), sx = xa < xb ? 1 : -1;
    int dy = -abs(yb - ya), sy = ya < yb ? 1 : -1;
    int err = dx + dy;
    for (;;) {
        stamp(img, L, xa, ya, t, rgb);
        if (xa == xb && ya == yb)
            break;
        int e2 = 2 * err;
        if (e2 >= dy) {
            err += dy;
            xa += sx;
        }
        if (e2 <= dx) {
            err += dx;
            ya += sy;
        }
    }
}

static void draw_line_series(image8_t *img, const layout_t *L, const plot_t *p,
                             const plot_series_t *s)
{
    int t = s->thickness_px > 0 ? s->thickness_px : 1;
    bool lines = s->style != PLOT_POINTS;
    bool points = s->style == PLOT_POINTS || s->style == PLOT_LINE_POINTS;
    for (int k = 0; lines && k + 1 < s->n; k++) {
        double xa = map_x(L, s->xs[k]), ya = map_y(L, p, s->ys[k]);
        double xb = map_x(L, s->xs[k + 1]), yb = map_y(L, p, s->ys[k + 1]);
        if (s->style == PLOT_STEPS) {
            draw_segment(img, L, xa, ya, xb, ya, t, s->rgb);
            draw_segment(img, L, xb, ya, xb, yb, t, s->rgb);
        } else {
            draw_segment(img, L, xa, ya, xb, yb, t, s->rgb);
        }
    }
    if (points || s->n == 1)
        for (int k = 0; k < s->n; k++)
            stamp(img, L, round_px(map_x(L, s->xs[k])), round_px(map_y(L, p, s->ys[k])),
                  2 * t + 3, s->rgb);
}

static void draw_stacked(image8_t *img, const layout_t *L, const plot_t *p)
{
    const plot_series_t *base = NULL;
    stacked_base(p, &base);
    if (!base)
        return;
    if (p->stack_style == PLOT_STACK_BARS) {
        for (int k = 0; k < base->n; k++) {
            double bottom = 0;
            int xa = round_px(map_x(L, base->xs[k] - L->bar_width / 2));
            int xb = round_px(map_x(L, base->xs[k] + L->bar_width / 2));
            xa = xa < L->x0 ? L->x0 : xa;
            xb = xb > L->x1 ? L->x1 : xb;
            if (xa > xb)
                continue;   /* bar outside a fixed x range */
            for (int i = 0; i < p->n_series; i++) {
                const plot_series_t *s = &p->series[i];
                if (!s->stacked)
                    continue;
                double top = bottom + s->ys[k];
                int ya = round_px(map_y(L, p, top)), yb = round_px(map_y(L, p, bottom));
                if (ya > yb) { int t = ya; ya = yb; yb = t; }   /* y_down */
                ya = ya < L->y0 ? L->y0 : ya;
                yb = yb > L->y1 ? L->y1 : yb;
                if (ya <= yb && s->ys[k] > 0)
                    fill_rect(img, xa, ya, xb, yb, s->rgb);
                bottom = top;
            }
        }
        return;
    }
    /* Areas: for each pixel column, interpolate the cumulative curves. */
    int ca = round_px(map_x(L, base->xs[0])), cb = round_px(map_x(L, base->xs[base->n - 1]));
    if (ca < L->x0) ca = L->x0;
    if (cb > L->x1) cb = L->x1;
    for (int col = ca; col <= cb; col++) {
        double x = L->xmin + (col - L->x0) / (double)(L->x1 - L->x0) * (L->xmax - L->xmin);
        int k = 0;
        while (k + 2 < base->n && base->xs[k + 1] < x)
            k++;
        double span = base->n > 1 ? base->xs[k + 1] - base->xs[k] : 0;
        double w = span > 0 ? (x - base->xs[k]) / span : 0;
        if (w < 0) w = 0;
        if (w > 1) w = 1;
        double bottom = 0;
        for (int i = 0; i < p->n_series; i++) {
            const plot_series_t *s = &p->series[i];
            if (!s->stacked)
                continue;
            double v = base->n > 1 ? s->ys[k] * (1 - w) + s->ys[k + 1] * w : s->ys[0];
            double top = bottom + v;
            int ya = round_px(map_y(L, p, top)), yb = round_px(map_y(L, p, bottom));
            if (ya > yb) { int t = ya; ya = yb; yb = t; }   /* y_down */
            ya = ya < L->y0 ? L->y0 : ya;
            yb = yb > L->y1 ? L->y1 : yb;
            for (int y = ya; y <= yb && v > 0; y++)
                plot_put_pixel(img, col, y, s->rgb);
            bottom = top;
        }
    }
}

/* Dashed (4 on, 3 off) gray lines with their labels, over the data. */
static void draw_refs(image8_t *img, const layout_t *L, const plot_t *p)
{
    static const uint8_t ref_gray[3] = {90, 90, 90};
    int s = L->scale;
    for (int i = 0; i < p->n_refs; i++) {
        if (p->refs[i].vertical) {
            double fx = map_x(L, p->refs[i].at);
            if (fx < L->x0 || fx > L->x1)
                continue;
            int x = round_px(fx);
            for (int y = L->y0 + 1; y < L->y1; y++)
                if ((y - L->y0) % 7 < 4)
                    plot_put_pixel(img, x, y, ref_gray);
            plot_draw_text(img, x + 3, L->y0 + 3, p->refs[i].label, s, ref_gray);
        } else {
            if (p->log_y && !(p->refs[i].at > 0))
                continue;
            double fy = map_y(L, p, p->refs[i].at);
            if (fy < L->y0 || fy > L->y1)
                continue;
            int y = round_px(fy);
            for (int x = L->x0 + 1; x < L->x1; x++)
                if ((x - L->x0) % 7 < 4)
                    plot_put_pixel(img, x, y, ref_gray);
            plot_draw_text(img, L->x1 - 3 - plot_text_width(p->refs[i].label, s),
                           y - 7 * s - 3, p->refs[i].label, s, ref_gray);
        }
    }
}

static void draw_axes(image8_t *img, const layout_t *L, const plot_t *p)
{
    int s = L->scale, ch = 7 * s;
    char buf[64];
    double ystep = L->n_yticks > 1 ? L->yticks[1] - L->yticks[0] : 1.0;
    double xstep = L->n_xticks > 1 ? L->xticks[1] - L->xticks[0] : 1.0;
    /* Frame. */
    for (int x = L->x0; x <= L->x1; x++) {
        plot_put_pixel(img, x, L->y0, black);
        plot_put_pixel(img, x, L->y1, black);
    }
    for (int y = L->y0; y <= L->y1; y++) {
        plot_put_pixel(img, L->x0, y, black);
        plot_put_pixel(img, L->x1, y, black);
    }
    for (int i = 0; i < L->n_yticks; i++) {
        int y = round_px(axis_row(L, p, L->yticks[i]));
        for (int d = 1; d <= TICK_PX; d++)
            plot_put_pixel(img, L->x0 - d, y, black);
        tick_label(L->yticks[i], ystep, p->log_y, buf, sizeof buf);
        plot_draw_text(img, L->x0 - TICK_PX - 4 - plot_text_width(buf, s), y - ch / 2, buf, s,
                       black);
    }
    for (int i = 0; i < L->n_xticks; i++) {
        int x = round_px(map_x(L, L->xticks[i]));
        for (int d = 1; d <= TICK_PX; d++)
            plot_put_pixel(img, x, L->y1 + d, black);
        if (p->n_categories > 0)
            snprintf(buf, sizeof buf, "%s", p->categories[i]);
        else
            tick_label(L->xticks[i], xstep, false, buf, sizeof buf);
        plot_draw_text(img, x - plot_text_width(buf, s) / 2, L->y1 + TICK_PX + 4, buf, s, black);
    }
    /* Titles. */
    int mid_x = (L->x0 + L->x1) / 2;
    if (p->title[0])
        plot_draw_text(img, mid_x - plot_text_width(p->title, s) / 2, 10, p->title, s, black);
    if (p->xlabel[0])
        plot_draw_text(img, mid_x - plot_text_width(p->xlabel, s) / 2,
                       L->y1 + TICK_PX + 4 + ch + 8, p->xlabel, s, black);
    if (p->ylabel[0]) {
        int mid_y = (L->y0 + L->y1) / 2;
        plot_draw_text_up(img, 8, mid_y - plot_text_width(p->ylabel, s) / 2, p->ylabel, s, black);
    }
}

static void draw_legend(image8_t *img, const layout_t *L, const plot_t *p)
{
    if (!p->legend || p->n_series < 2)
        return;
    int s = L->scale, ch = 7 * s, row_h = ch + 6 * s;
    int y = L->y0 + 4;
    /* Stacked series listed top band first, as they appear in the bars. */
    for (int pass = 0; pass < 2; pass++) {
        for (int j = 0; j < p->n_series; j++) {
            int i = pass == 0 ? j : p->n_series - 1 - j;
            const plot_series_t *se = &p->series[i];
            if ((pass == 0) == se->stacked)
                continue;
            int sx = L->legend_x;
            if (se->stacked)
                fill_rect(img, sx, y, sx + 3 * ch, y + ch - 1, se->rgb);
            else
                fill_rect(img, sx, y + ch / 2 - 1, sx + 3 * ch, y + ch / 2, se->rgb);
            plot_draw_text(img, sx + 3 * ch + 6, y, se->name, s, black);
            y += row_h;
        }
    }
}

pp5_status_t plot_render(const plot_t *p, int width, int height, image8_t *img)
{
    layout_t L;
    pp5_status_t st = compute_layout(p, width, height, &L);
    if (st != PP5_OK)
        return st;
    st = image8_alloc(img, width, height, 3);
    if (st != PP5_OK)
        return st;
    memset(img->pixels, 255, (size_t)width * height * 3);
    /* Grid lines under the data. */
    for (int i = 0; i < L.n_yticks; i++) {
        int y = round_px(axis_row(&L, p, L.yticks[i]));
        for (int x = L.x0 + 1; x < L.x1; x++)
            plot_put_pixel(img, x, y, grid_gray);
    }
    if (p->n_categories == 0)
        for (int i = 0; i < L.n_xticks; i++) {
            int x = round_px(map_x(&L, L.xticks[i]));
            for (int y = L.y0 + 1; y < L.y1; y++)
                plot_put_pixel(img, x, y, grid_gray);
        }
    draw_stacked(img, &L, p);
    for (int i = 0; i < p->n_series; i++)
        if (!p->series[i].stacked)
            draw_line_series(img, &L, p, &p->series[i]);
    draw_refs(img, &L, p);
    draw_axes(img, &L, p);
    draw_legend(img, &L, p);
    return PP5_OK;
}

pp5_status_t plot_write_png(const plot_t *p, const char *path, int width, int height)
{
    image8_t img;
    pp5_status_t st = plot_render(p, width, height, &img);
    if (st != PP5_OK)
        return st;
    st = png_write(path, &img);
    image8_free(&img);
    return st;
}
