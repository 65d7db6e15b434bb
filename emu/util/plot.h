/* plot.h: charts (line plots, stacked bars/areas) with titles, axis labels
 * with units, ticks, reference lines and a legend, drawn with cairo in
 * anti-aliased vector graphics and fontconfig's DejaVu Sans, written as PNG,
 * SVG or PDF as the output name says.
 *
 * Used for the paper's figure 5 (target and quantized resolution against
 * distance from the gaze point), sweeps of frame time stacked by phase, and
 * gaze-trace replays.
 *
 *   plot_t p;
 *   plot_init(&p, "Frame time", "GPs", "frame time (ms)");
 *   plot_add_series(&p, "full", xs, ys, n);
 *   plot_add_series(&p, "gaze", xs, ys2, n);
 *   plot_write(&p, "sweep.pdf", 800, 500);      (or .png, .svg)
 *   plot_free(&p);
 *
 * Stacked charts: every plot_add_stacked series is drawn on top of the
 * previous stacked ones; all stacked series must share the same x values.
 * Line series and stacked series may be mixed (lines are drawn on top).
 * Sizes are in pixels for PNG and in points (1/72 inch) for SVG and PDF; the
 * layout is the same in all three.  plot_render gives the same pixels for
 * the same plot on one machine (cairo's rasteriser is deterministic); PDF
 * and SVG files carry no pixels, and a PDF names its creation date, so
 * determinism tests compare the plotted data (plot_data_to_pixel, rendered
 * pixels), not file bytes. */
#ifndef PP5_PLOT_H
#define PP5_PLOT_H

#include <stdbool.h>
#include <stdint.h>
#include "png_io.h"
#include "status.h"

#define PLOT_MAX_SERIES 16
#define PLOT_MAX_POINTS 1000000
#define PLOT_MAX_CATEGORIES 64
#define PLOT_MAX_REFS 8

typedef enum { PLOT_FORMAT_PNG, PLOT_FORMAT_SVG, PLOT_FORMAT_PDF } plot_format_t;

typedef enum {
    PLOT_LINE,      /* straight segments between points (default for plot_add_series) */
    PLOT_STEPS,     /* horizontal then vertical: a step function, y[i] held until x[i+1] */
    PLOT_POINTS,    /* small squares at the points only */
    PLOT_LINE_POINTS /* line and squares */
} plot_line_style_t;

typedef enum {
    PLOT_STACK_BARS, /* one bar per x value, width 0.7 of the smallest x spacing (default) */
    PLOT_STACK_AREA  /* filled bands between consecutive stacked series */
} plot_stack_style_t;

typedef struct {
    char name[64];
    double *xs, *ys;          /* owned copies, n points */
    int n;
    bool stacked;
    plot_line_style_t style;
    uint8_t rgb[3];
    int thickness_px;         /* line width in pixels (default 2) */
} plot_series_t;

typedef struct {
    char title[128], xlabel[96], ylabel[96];
    plot_series_t series[PLOT_MAX_SERIES];
    int n_series;
    plot_stack_style_t stack_style;
    bool fixed_x, fixed_y;    /* set by plot_set_xrange / plot_set_yrange */
    double xmin, xmax, ymin, ymax;
    bool log_y;               /* logarithmic y axis (all y values must be > 0) */
    bool legend;              /* default true when more than one series */
    bool y_down;              /* y grows downwards (image/gaze pixel coordinates) */
    /* Optional text labels under x = 0, 1, ..., n-1 (bar charts of named cases). */
    char categories[PLOT_MAX_CATEGORIES][32];
    int n_categories;
    /* Dashed reference lines (plot_add_xref / plot_add_yref). */
    struct {
        bool vertical;
        double at;
        char label[48];
    } refs[PLOT_MAX_REFS];
    int n_refs;
} plot_t;

/* Initialises an empty plot; NULL texts mean none. Never fails. */
void plot_init(plot_t *p, const char *title, const char *xlabel, const char *ylabel);
void plot_free(plot_t *p);

/* Adds a line series (copied).  Errors: too many series, n < 1 or > PLOT_MAX_POINTS,
 * non-finite values. */
pp5_status_t plot_add_series(plot_t *p, const char *name, const double *xs, const double *ys,
                             int n);
/* Adds a stacked series (its values are heights above the previous stacked series). */
pp5_status_t plot_add_stacked(plot_t *p, const char *name, const double *xs, const double *ys,
                              int n);
/* Style and colour of series `index` (0 = first added).  Colours default to a
 * fixed palette; out-of-range indices are ignored. */
void plot_set_style(plot_t *p, int index, plot_line_style_t style);
void plot_set_color(plot_t *p, int index, uint8_t r, uint8_t g, uint8_t b);
void plot_set_stack_style(plot_t *p, plot_stack_style_t style);
/* Fixed axis ranges (otherwise: data range, y from 0 when all y >= 0, padded to
 * round tick values). */
void plot_set_xrange(plot_t *p, double xmin, double xmax);
void plot_set_yrange(plot_t *p, double ymin, double ymax);
void plot_set_log_y(plot_t *p, bool log_y);
void plot_set_legend(plot_t *p, bool on);
/* Smallest y at the top, as in image and gaze-trace pixel coordinates. */
void plot_set_y_down(plot_t *p, bool y_down);
/* A dashed gray reference line at x = at (xref, vertical) or y = at (yref),
 * labelled near its top/right end, e.g. the 12 and 20 degree limits of the
 * sweet spot.  Lines outside the axis ranges are not drawn; they do not
 * widen the automatic ranges.  Errors: more than PLOT_MAX_REFS, non-finite. */
pp5_status_t plot_add_xref(plot_t *p, double at, const char *label);
pp5_status_t plot_add_yref(plot_t *p, double at, const char *label);
/* Text labels for x = 0..n-1 instead of numeric x ticks. */
pp5_status_t plot_set_categories(plot_t *p, const char *const *labels, int n);

/* Draws the chart into a new RGB image (caller frees with image8_free).
 * Errors: size outside 160x120..8192x8192, no series, log axis with y <= 0,
 * stacked series with different x values. */
pp5_status_t plot_render(const plot_t *p, int width, int height, image8_t *img);
/* The format that `path` names: .png, .svg or .pdf (any case); otherwise
 * PP5_E_CONFIG with a message naming the path. */
pp5_status_t plot_format_from_name(const char *path, plot_format_t *fmt);
/* Writes the chart to `path` in the format its name says.  The file appears
 * whole or not at all (written beside it, then renamed). */
pp5_status_t plot_write(const plot_t *p, const char *path, int width, int height);

/* Labels on an 8-bit image (gray or RGB) in the charts' text, a monospaced
 * face about 6*scale pixels per character and 10*scale pixels high; (x, y)
 * is the label's top-left corner, and what falls outside the image is
 * clipped.  plot_text_width gives the label's advance in pixels. */
void plot_draw_text(image8_t *img, int x, int y, const char *text, int scale, const uint8_t rgb[3]);
int plot_text_width(const char *text, int scale);

/* Every user of cairo's text calls this first: cairo's and fontconfig's
 * font caches are then released at exit. */
void plot_text_setup(void);

/* Where data point (x, y) lands in a width x height rendering: pixel column and
 * row (row 0 at the top), as the renderer computes them.  For tests and for
 * callers that annotate a chart.  False if the plot cannot be laid out. */
bool plot_data_to_pixel(const plot_t *p, int width, int height, double x, double y,
                        double *px, double *py);

#endif
