/* plot_text.c: labels drawn into an 8-bit image (contact sheets, the colour
 * sphere's legend, comparison strips) with the same cairo and fontconfig text
 * as the charts.
 *
 * The text is drawn into a cairo A8 mask as large as the image, then the
 * colour is blended into the image through that mask, so labels are
 * anti-aliased over whatever the image holds.  Hinting is off, as for the
 * charts, so a label's shape does not depend on where it lands. */
#include "plot.h"

#include <cairo.h>
#include <math.h>
#include <string.h>

#define LABEL_FONT "DejaVu Sans Mono"

/* A monospaced face whose advance at this size is about 6 pixels per
 * character at scale 1 (DejaVu Sans Mono: 0.602 em), the spacing callers
 * were laid out for. */
static void label_font(cairo_t *cr, int scale)
{
    cairo_select_font_face(cr, LABEL_FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 10.0 * (scale < 1 ? 1 : scale));
    cairo_font_options_t *fo = cairo_font_options_create();
    cairo_font_options_set_antialias(fo, CAIRO_ANTIALIAS_GRAY);
    cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
    cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
    cairo_set_font_options(cr, fo);
    cairo_font_options_destroy(fo);
}

int plot_text_width(const char *text, int scale)
{
    plot_text_setup();
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1);
    cairo_t *cr = cairo_create(s);
    label_font(cr, scale);
    cairo_text_extents_t te;
    cairo_text_extents(cr, text, &te);
    cairo_destroy(cr);
    cairo_surface_destroy(s);
    return (int)ceil(te.x_advance);
}

void plot_draw_text(image8_t *img, int x, int y, const char *text, int scale, const uint8_t rgb[3])
{
    if (!img->pixels || img->width <= 0 || img->height <= 0 || !text[0])
        return;
    plot_text_setup();
    cairo_surface_t *mask = cairo_image_surface_create(CAIRO_FORMAT_A8, img->width, img->height);
    if (cairo_surface_status(mask) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(mask);
        return;
    }
    cairo_t *cr = cairo_create(mask);
    label_font(cr, scale);
    cairo_font_extents_t fe;
    cairo_font_extents(cr, &fe);
    /* (x, y) is the top-left corner of the label: the baseline sits one
     * ascent below it. */
    cairo_move_to(cr, x, y + fe.ascent);
    cairo_show_text(cr, text);
    cairo_destroy(cr);
    cairo_surface_flush(mask);
    const uint8_t *m = cairo_image_surface_get_data(mask);
    int stride = cairo_image_surface_get_stride(mask), ch = img->channels;
    for (int row = 0; row < img->height; row++)
        for (int col = 0; col < img->width; col++) {
            unsigned a = m[(size_t)row * (size_t)stride + (size_t)col];
            if (a == 0)
                continue;
            uint8_t *p = img->pixels + ((size_t)row * (size_t)img->width + (size_t)col) * (size_t)ch;
            for (int k = 0; k < ch; k++) {
                /* a gray image takes the mean of the three channels */
                unsigned want = ch == 3 ? rgb[k] : (rgb[0] + rgb[1] + rgb[2]) / 3u;
                p[k] = (uint8_t)((want * a + p[k] * (255u - a) + 127u) / 255u);
            }
        }
    cairo_surface_destroy(mask);
}
