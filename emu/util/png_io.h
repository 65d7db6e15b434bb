/* png_io.h: 8-bit RGB/gray images and PNG files through libpng.
 *
 * One image type for every module that writes pictures (frame buffer dumps,
 * native renders, mip-map levels, plots), so tests can compare them. */
#ifndef PP5_PNG_IO_H
#define PP5_PNG_IO_H

#include <stdint.h>
#include <stddef.h>
#include "status.h"

typedef struct {
    int width, height;
    int channels;          /* 1 (gray) or 3 (RGB) */
    uint8_t *pixels;       /* row-major, top row first, channels interleaved */
} image8_t;

pp5_status_t image8_alloc(image8_t *img, int width, int height, int channels);
void image8_free(image8_t *img);

/* Writes `img` as a PNG.  Errors name the path. */
pp5_status_t png_write(const char *path, const image8_t *img);
/* Reads any 8-bit PNG, converting to RGB (channels=3) or gray (1) as asked. */
pp5_status_t png_read(const char *path, image8_t *img, int want_channels);

#endif
