/* plot_internal.h: drawing helpers shared by plot.c and plot_font.c. */
#ifndef PP5_PLOT_INTERNAL_H
#define PP5_PLOT_INTERNAL_H

#include "png_io.h"

/* Sets one pixel (ignored outside the image); gray images get the luma. */
void plot_put_pixel(image8_t *img, int x, int y, const uint8_t rgb[3]);
/* Text turned 90 degrees counter-clockwise; (x, y) is the top-left corner. */
void plot_draw_text_up(image8_t *img, int x, int y, const char *text, int scale,
                       const uint8_t rgb[3]);

#endif
