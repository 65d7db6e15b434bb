/* plot_draw.c: draws a plot_t with cairo (anti-aliased lines, fontconfig
 * text) onto an image, an SVG or a PDF surface; the margins come from the
 * measured text, so long labels never overlap the chart.
 *
 * Text is laid out with hinting off (CAIRO_HINT_METRICS_OFF), so the same plot
 * has the same layout on every surface and at every size the margins allow.
 * Axis lines, ticks, grid and reference lines sit on pixel centres
 * (plot_snap) so that a 1-unit line covers whole pixels in a PNG. */
#include "plot.h"
#include "plot_layout.h"

#include <cairo.h>
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <fontconfig/fontconfig.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define TICK_LEN 5.0
#define FONT_FACE "DejaVu Sans"

static void set_rgb(cairo_t *cr, const uint8_t rgb[3])
{
    cairo_set_source_rgb(cr, rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0);
}

static void set_gray(cairo_t *cr, int v)
{
    cairo_set_source_rgb(cr, v / 255.0, v / 255.0, v / 255.0);
}

/* cairo's font caches and fontconfig's configuration live until exit; they
 * are handed back then, so that LeakSanitizer (make SAN=1 test) sees only
 * pp5's own leaks. */
static void release_fonts(void)
{
    cairo_debug_reset_static_data();
    FcFini();
}

static void register_release(void)
{
    atexit(release_fonts);
}

void plot_text_setup(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, register_release);
}

/* The one font every chart uses, sized for the chart. */
static void use_font(cairo_t *cr, double px)
{
    plot_text_setup();
    cairo_select_font_face(cr, FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, px);
    cairo_font_options_t *fo = cairo_font_options_create();
    cairo_font_options_set_antialias(fo, CAIRO_ANTIALIAS_GRAY);
    cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
    cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
    cairo_set_font_options(cr, fo);
    cairo_font_options_destroy(fo);
}

static double text_w(cairo_t *cr, const char *s)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, s, &e);
    return e.x_advance;
}

/* Text with its left end at x and its middle at height y (align 0), or
 * centred on x (align 1), or ending at x (align 2). */
static void text_at(cairo_t *cr, double x, double y, const char *s, int align)
{
    if (!s[0])
        return;
    cairo_font_extents_t fe;
    cairo_font_extents(cr, &fe);
    double w = text_w(cr, s);
    cairo_move_to(cr, x - (align == 1 ? w / 2 : align == 2 ? w : 0),
                  y + (fe.ascent - fe.descent) / 2);
    cairo_show_text(cr, s);
}

/* Margins from the measured text (title, axis labels, tick labels, legend),
 * then the plot area; fails when nothing is left. */
static pp5_status_t layout_margins(cairo_t *cr, const plot_t *p, int width, int height,
                                   plot_layout_t *L)
{
    double f = fmin(width, height * 1.6) / 64.0;
    L->font_px = f < 9 ? 9 : f > 16 ? 16 : f;
    use_font(cr, L->font_px);
    double ch = L->font_px, ylab_w = 0;
    char buf[64];
    for (int i = 0; i < L->n_yticks; i++) {
        plot_tick_label(L->yticks[i], L->ystep, p->log_y, buf, sizeof buf);
        ylab_w = fmax(ylab_w, text_w(cr, buf));
    }
    bool legend = p->legend && p->n_series > 1;
    L->legend_w = 0;
    for (int i = 0; legend && i < p->n_series; i++)
        L->legend_w = fmax(L->legend_w, text_w(cr, p->series[i].name));
    if (legend)
        L->legend_w += 3 * ch + 6;  /* swatch and gap */
    double last_half = 0;
    if (L->n_xticks > 0 && p->n_categories == 0) {
        plot_tick_label(L->xticks[L->n_xticks - 1], L->xstep, false, buf, sizeof buf);
        last_half = text_w(cr, buf) / 2;
    }
    double top = 10 + (p->title[0] ? 1.6 * ch + 8 : 0);
    double left = 8 + (p->ylabel[0] ? 1.4 * ch + 6 : 0) + ylab_w + 5 + TICK_LEN;
    double bottom = TICK_LEN + 5 + 1.2 * ch + (p->xlabel[0] ? 6 + 1.4 * ch : 0) + 8;
    double right = legend ? L->legend_w + 24 : 12 + last_half;
    L->x0 = floor(left);
    L->x1 = floor(width - 1 - right);
    L->y0 = floor(top);
    L->y1 = floor(height - 1 - bottom);
    L->legend_x = L->x1 + 12;
    if (L->x1 - L->x0 < 40 || L->y1 - L->y0 < 30)
        return pp5_fail(PP5_E_RANGE, "plot '%s': %dx%d leaves no room for the chart (labels or "
                        "legend too long)", p->title, width, height);
    return PP5_OK;
}

/* The whole layout on a scratch context (text metrics need one). */
static pp5_status_t compute_layout(const plot_t *p, int width, int height, plot_layout_t *L)
{
    pp5_status_t st = plot_layout_axes(p, width, height, L);
    if (st != PP5_OK)
        return st;
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
    cairo_t *cr = cairo_create(s);
    st = layout_margins(cr, p, width, height, L);
    cairo_destroy(cr);
    cairo_surface_destroy(s);
    return st;
}

static double map_y(const plot_layout_t *L, const plot_t *p, double y)
{
    return plot_axis_row(L, p, p->log_y ? log10(y) : y);
}

bool plot_data_to_pixel(const plot_t *p, int width, int height, double x, double y, double *px,
                        double *py)
{
    plot_layout_t L;
    if (compute_layout(p, width, height, &L) != PP5_OK)
        return false;
    if (p->log_y && !(y > 0))
        return false;
    /* Pixel indices: pixel column i covers device x i .. i + 1. */
    *px = plot_map_x(&L, x) - 0.5;
    *py = map_y(&L, p, y) - 0.5;
    return true;
}

/* Far-off positions (data outside a fixed range) kept finite for cairo. */
static double tame(double v)
{
    return v < -1e6 ? -1e6 : v > 1e6 ? 1e6 : v;
}

static void clip_to_area(cairo_t *cr, const plot_layout_t *L)
{
    cairo_rectangle(cr, L->x0, L->y0, L->x1 - L->x0 + 1, L->y1 - L->y0 + 1);
    cairo_clip(cr);
}

static void draw_grid(cairo_t *cr, const plot_layout_t *L, const plot_t *p)
{
    set_gray(cr, 225);
    cairo_set_line_width(cr, 1.0);
    for (int i = 0; i < L->n_yticks; i++) {
        double y = plot_snap(plot_axis_row(L, p, L->yticks[i]));
        cairo_move_to(cr, L->x0 + 1, y);
        cairo_line_to(cr, L->x1, y);
    }
    for (int i = 0; p->n_categories == 0 && i < L->n_xticks; i++) {
        double x = plot_snap(plot_map_x(L, L->xticks[i]));
        cairo_move_to(cr, x, L->y0 + 1);
        cairo_line_to(cr, x, L->y1);
    }
    cairo_stroke(cr);
}

static void draw_line_series(cairo_t *cr, const plot_layout_t *L, const plot_t *p,
                             const plot_series_t *s)
{
    double t = s->thickness_px > 0 ? s->thickness_px : 1;
    set_rgb(cr, s->rgb);
    cairo_set_line_width(cr, t);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    if (s->style != PLOT_POINTS && s->n > 1) {
        cairo_move_to(cr, tame(plot_map_x(L, s->xs[0])), tame(map_y(L, p, s->ys[0])));
        for (int k = 1; k < s->n; k++) {
            double x = tame(plot_map_x(L, s->xs[k])), y = tame(map_y(L, p, s->ys[k]));
            if (s->style == PLOT_STEPS)
                cairo_line_to(cr, x, tame(map_y(L, p, s->ys[k - 1])));
            cairo_line_to(cr, x, y);
        }
        cairo_stroke(cr);
    }
    if (s->style == PLOT_POINTS || s->style == PLOT_LINE_POINTS || s->n == 1) {
        double half = t + 1.5;
        for (int k = 0; k < s->n; k++)
            cairo_rectangle(cr, tame(plot_map_x(L, s->xs[k])) - half,
                            tame(map_y(L, p, s->ys[k])) - half, 2 * half, 2 * half);
        cairo_fill(cr);
    }
}

static void draw_stacked(cairo_t *cr, const plot_layout_t *L, const plot_t *p)
{
    const plot_series_t *base = NULL;
    plot_stacked_base(p, &base);
    if (!base)
        return;
    bool bars = p->stack_style == PLOT_STACK_BARS;
    double *bottom = calloc((size_t)base->n, sizeof *bottom);
    if (!bottom)
        return;
    for (int i = 0; i < p->n_series; i++) {
        const plot_series_t *s = &p->series[i];
        if (!s->stacked)
            continue;
        set_rgb(cr, s->rgb);
        for (int k = 0; bars && k < base->n; k++) {
            /* Edges on whole device units, at least one wide: crisp bands
             * that a narrow bar cannot blur away. */
            double xa = round(tame(plot_map_x(L, base->xs[k] - L->bar_width / 2)));
            double xb = fmax(round(tame(plot_map_x(L, base->xs[k] + L->bar_width / 2))), xa + 1);
            double ya = round(tame(map_y(L, p, bottom[k])));
            double yb = round(tame(map_y(L, p, bottom[k] + s->ys[k])));
            if (s->ys[k] > 0)
                cairo_rectangle(cr, xa, fmin(ya, yb), xb - xa, fabs(yb - ya));
        }
        if (!bars) {
            /* The band between the cumulative curve below and this one. */
            for (int k = 0; k < base->n; k++)
                cairo_line_to(cr, tame(plot_map_x(L, base->xs[k])),
                              tame(map_y(L, p, bottom[k] + s->ys[k])));
            for (int k = base->n - 1; k >= 0; k--)
                cairo_line_to(cr, tame(plot_map_x(L, base->xs[k])), tame(map_y(L, p, bottom[k])));
            cairo_close_path(cr);
        }
        cairo_fill(cr);
        for (int k = 0; k < base->n; k++)
            bottom[k] += s->ys[k];
    }
    free(bottom);
}

/* Dashed (4 on, 3 off) gray lines with their labels, over the data. */
static void draw_refs(cairo_t *cr, const plot_layout_t *L, const plot_t *p)
{
    static const double dash[2] = {4.0, 3.0};
    for (int i = 0; i < p->n_refs; i++) {
        bool v = p->refs[i].vertical;
        if (!v && p->log_y && !(p->refs[i].at > 0))
            continue;
        double at = v ? plot_map_x(L, p->refs[i].at) : map_y(L, p, p->refs[i].at);
        if (!(at >= (v ? L->x0 : L->y0) && at <= (v ? L->x1 : L->y1)))
            continue;
        double c = plot_snap(at);
        set_gray(cr, 90);
        cairo_set_line_width(cr, 1.0);
        cairo_set_dash(cr, dash, 2, 0.0);
        cairo_move_to(cr, v ? c : L->x0 + 1, v ? L->y0 + 1 : c);
        cairo_line_to(cr, v ? c : L->x1, v ? L->y1 : c);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0.0);
        if (v)
            text_at(cr, c + 4, L->y0 + 4 + L->font_px / 2, p->refs[i].label, 0);
        else
            text_at(cr, L->x1 - 4, c - 3 - L->font_px / 2, p->refs[i].label, 2);
    }
}

static void draw_frame_and_ticks(cairo_t *cr, const plot_layout_t *L, const plot_t *p)
{
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.0);
    cairo_rectangle(cr, L->x0 + 0.5, L->y0 + 0.5, L->x1 - L->x0, L->y1 - L->y0);
    for (int i = 0; i < L->n_yticks; i++) {
        double y = plot_snap(plot_axis_row(L, p, L->yticks[i]));
        cairo_move_to(cr, L->x0, y);
        cairo_line_to(cr, L->x0 - TICK_LEN, y);
    }
    for (int i = 0; i < L->n_xticks; i++) {
        double x = plot_snap(plot_map_x(L, L->xticks[i]));
        cairo_move_to(cr, x, L->y1 + 1);
        cairo_line_to(cr, x, L->y1 + 1 + TICK_LEN);
    }
    cairo_stroke(cr);
}

static void draw_axes(cairo_t *cr, const plot_layout_t *L, const plot_t *p)
{
    char buf[64];
    double ch = L->font_px;
    draw_frame_and_ticks(cr, L, p);
    for (int i = 0; i < L->n_yticks; i++) {
        plot_tick_label(L->yticks[i], L->ystep, p->log_y, buf, sizeof buf);
        text_at(cr, L->x0 - TICK_LEN - 4, plot_axis_row(L, p, L->yticks[i]), buf, 2);
    }
    for (int i = 0; i < L->n_xticks; i++) {
        if (p->n_categories > 0)
            snprintf(buf, sizeof buf, "%s", p->categories[i]);
        else
            plot_tick_label(L->xticks[i], L->xstep, false, buf, sizeof buf);
        text_at(cr, plot_map_x(L, L->xticks[i]), L->y1 + TICK_LEN + 4 + 0.6 * ch, buf, 1);
    }
    double mid_x = (L->x0 + L->x1) / 2, mid_y = (L->y0 + L->y1) / 2;
    if (p->xlabel[0])
        text_at(cr, mid_x, L->y1 + TICK_LEN + 4 + 1.2 * ch + 6 + 0.7 * ch, p->xlabel, 1);
    if (p->ylabel[0]) {
        cairo_save(cr);
        cairo_translate(cr, 8 + 0.7 * ch, mid_y);
        cairo_rotate(cr, -M_PI / 2);
        text_at(cr, 0, 0, p->ylabel, 1);
        cairo_restore(cr);
    }
    if (p->title[0]) {
        use_font(cr, 1.25 * ch);
        text_at(cr, mid_x, 10 + 0.8 * ch, p->title, 1);
        use_font(cr, ch);
    }
}

static void draw_legend(cairo_t *cr, const plot_layout_t *L, const plot_t *p)
{
    if (!p->legend || p->n_series < 2)
        return;
    double ch = L->font_px, row_h = 1.5 * ch, y = L->y0 + 4;
    /* Stacked series listed top band first, as they appear in the bars. */
    for (int pass = 0; pass < 2; pass++) {
        for (int j = 0; j < p->n_series; j++) {
            int i = pass == 0 ? j : p->n_series - 1 - j;
            const plot_series_t *se = &p->series[i];
            if ((pass == 0) == se->stacked)
                continue;
            set_rgb(cr, se->rgb);
            double sx = L->legend_x;
            if (se->stacked)
                cairo_rectangle(cr, sx, y, 2.5 * ch, 0.8 * ch);
            else
                cairo_rectangle(cr, sx, y + 0.4 * ch - 1, 2.5 * ch, 2);
            cairo_fill(cr);
            cairo_set_source_rgb(cr, 0, 0, 0);
            text_at(cr, sx + 2.5 * ch + 6, y + 0.4 * ch, se->name, 0);
            y += row_h;
        }
    }
}

static pp5_status_t draw(cairo_t *cr, const plot_t *p, const plot_layout_t *L, int w, int h)
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    use_font(cr, L->font_px);
    cairo_save(cr);
    clip_to_area(cr, L);
    draw_grid(cr, L, p);
    draw_stacked(cr, L, p);
    for (int i = 0; i < p->n_series; i++)
        if (!p->series[i].stacked)
            draw_line_series(cr, L, p, &p->series[i]);
    cairo_restore(cr);
    draw_refs(cr, L, p);
    draw_axes(cr, L, p);
    draw_legend(cr, L, p);
    cairo_status_t cs = cairo_status(cr);
    if (cs != CAIRO_STATUS_SUCCESS)
        return pp5_fail(PP5_E_IO, "plot '%s' (%dx%d): cairo: %s", p->title, w, h,
                        cairo_status_to_string(cs));
    return PP5_OK;
}

pp5_status_t plot_render(const plot_t *p, int width, int height, image8_t *img)
{
    plot_layout_t L;
    pp5_status_t st = compute_layout(p, width, height, &L);
    if (st != PP5_OK)
        return st;
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
    cairo_t *cr = cairo_create(s);
    st = draw(cr, p, &L, width, height);
    cairo_destroy(cr);
    cairo_surface_flush(s);
    if (st == PP5_OK)
        st = image8_alloc(img, width, height, 3);
    if (st == PP5_OK) {
        const unsigned char *data = cairo_image_surface_get_data(s);
        int stride = cairo_image_surface_get_stride(s);
        for (int y = 0; y < height; y++)
            for (int x = 0; x < width; x++) {
                uint32_t v;
                memcpy(&v, data + (size_t)y * stride + 4 * (size_t)x, 4);
                uint8_t *o = img->pixels + ((size_t)y * width + x) * 3;
                o[0] = (uint8_t)(v >> 16);
                o[1] = (uint8_t)(v >> 8);
                o[2] = (uint8_t)v;
            }
    }
    cairo_surface_destroy(s);
    return st;
}

/* A PDF names the time it was made; SOURCE_DATE_EPOCH (the reproducible-
 * builds convention: seconds since 1970) fixes it, so that the same plot is
 * the same bytes.  Without it cairo writes the present time. */
static void pdf_fixed_date(cairo_surface_t *s)
{
    const char *e = getenv("SOURCE_DATE_EPOCH");
    char *end;
    long long t = e ? strtoll(e, &end, 10) : -1;
    if (!e || end == e || *end || t < 0)
        return;
    time_t tt = (time_t)t;
    struct tm tm;
    char iso[32];
    if (gmtime_r(&tt, &tm) && strftime(iso, sizeof iso, "%Y-%m-%dT%H:%M:%SZ", &tm) > 0)
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATE_DATE, iso);
}

/* SVG or PDF into `tmp`: the surface writes the file as it finishes. */
static pp5_status_t write_vector(const plot_t *p, plot_format_t fmt, const char *tmp, int width,
                                 int height)
{
    plot_layout_t L;
    pp5_status_t st = compute_layout(p, width, height, &L);
    if (st != PP5_OK)
        return st;
    cairo_surface_t *s = fmt == PLOT_FORMAT_SVG ? cairo_svg_surface_create(tmp, width, height)
                                                : cairo_pdf_surface_create(tmp, width, height);
    if (fmt == PLOT_FORMAT_PDF) {
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_TITLE, p->title);
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATOR, "pp5");
        pdf_fixed_date(s);
    }
    cairo_t *cr = cairo_create(s);
    st = draw(cr, p, &L, width, height);
    cairo_destroy(cr);
    cairo_surface_finish(s);
    cairo_status_t cs = cairo_surface_status(s);
    cairo_surface_destroy(s);
    if (st == PP5_OK && cs != CAIRO_STATUS_SUCCESS)
        st = pp5_fail(PP5_E_IO, "%s: cannot write the plot: %s", tmp, cairo_status_to_string(cs));
    return st;
}

pp5_status_t plot_write(const plot_t *p, const char *path, int width, int height)
{
    plot_format_t fmt;
    pp5_status_t st = plot_format_from_name(path, &fmt);
    if (st != PP5_OK)
        return st;
    size_t n = strlen(path) + 16;
    char *tmp = malloc(n);
    if (!tmp)
        return pp5_fail(PP5_E_NOMEM, "plot: out of memory");
    /* The same suffix, so that a reader never mistakes the partial file. */
    snprintf(tmp, n, "%s.part%s", path, path + strlen(path) - 4);
    if (fmt == PLOT_FORMAT_PNG) {
        image8_t img;
        st = plot_render(p, width, height, &img);
        if (st == PP5_OK) {
            st = png_write(tmp, &img);
            image8_free(&img);
        }
    } else {
        st = write_vector(p, fmt, tmp, width, height);
    }
    if (st == PP5_OK && rename(tmp, path) != 0)
        st = pp5_fail(PP5_E_IO, "%s: cannot write the plot (rename from %s failed)", path, tmp);
    if (st != PP5_OK)
        remove(tmp);
    free(tmp);
    return st;
}
