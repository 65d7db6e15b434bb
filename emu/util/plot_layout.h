/* plot_layout.h: where a chart's parts go, shared by plot.c (axis ranges and
 * ticks from the data) and plot_draw.c (margins from the text, drawing). */
#ifndef PP5_PLOT_LAYOUT_H
#define PP5_PLOT_LAYOUT_H

#include <stdbool.h>
#include <math.h>
#include <stddef.h>
#include "plot.h"

#define PLOT_MIN_W 160
#define PLOT_MIN_H 120
#define PLOT_MAX_SIDE 8192
#define PLOT_MAX_TICKS 64

typedef struct {
    double x0, x1, y0, y1;     /* plot area in device units; y0 is the top edge */
    double xmin, xmax;         /* x axis range */
    double ymin, ymax;         /* y axis range (log10 units when log_y) */
    double xstep, ystep;       /* tick steps */
    double xticks[PLOT_MAX_TICKS], yticks[PLOT_MAX_TICKS];
    int n_xticks, n_yticks;
    double bar_width;          /* data units, for stacked bars */
    bool have_stacked;
    double font_px, legend_x, legend_w;
} plot_layout_t;

/* Ranges and ticks (not the margins): the data's extents rounded out, or the
 * fixed ranges.  Errors: size, no series, bad ranges, log of y <= 0. */
pp5_status_t plot_layout_axes(const plot_t *p, int width, int height, plot_layout_t *L);
/* The shared x values of the stacked series (*first = NULL when none), or an
 * error when two of them differ. */
pp5_status_t plot_stacked_base(const plot_t *p, const plot_series_t **first);
/* A tick value's label, with as many decimals as the step needs. */
void plot_tick_label(double v, double step, bool log_axis, char *buf, size_t size);

/* Device x of a data x.  The axis range spans the centres of the frame's
 * pixel columns x0 .. x1 (device x0 + 0.5 .. x1 + 0.5), where the frame is
 * drawn, so a point at the range's end lies on the frame line. */
static inline double plot_map_x(const plot_layout_t *L, double x)
{
    return L->x0 + 0.5 + (x - L->xmin) / (L->xmax - L->xmin) * (L->x1 - L->x0);
}

/* Device y of a y value already in axis units (log10 units on a log axis). */
static inline double plot_axis_row(const plot_layout_t *L, const plot_t *p, double v)
{
    double f = (v - L->ymin) / (L->ymax - L->ymin);
    return 0.5 + (p->y_down ? L->y0 + f * (L->y1 - L->y0) : L->y1 - f * (L->y1 - L->y0));
}

/* The centre of the device pixel that holds v: where a 1-unit line is crisp. */
static inline double plot_snap(double v)
{
    return floor(v) + 0.5;
}

#endif
