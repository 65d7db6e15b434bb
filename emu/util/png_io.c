/* png_io.c: PNG reading and writing with libpng (error handling via setjmp,
 * as libpng requires). */
#include "png_io.h"
#include "outfile.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Images larger than this are refused as absurd (the largest pp5 writes is a
 * few thousand pixels wide). */
#define PNG_MAX_SIDE 32768

/* libpng prints errors itself by default; pp5 reports them through pp5_fail
 * instead, so the handlers only jump back (and warnings are dropped). */
static void quiet_error(png_structp png, png_const_charp msg)
{
    (void)msg;
    png_longjmp(png, 1);
}

static void quiet_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

pp5_status_t image8_alloc(image8_t *img, int width, int height, int channels)
{
    memset(img, 0, sizeof *img);
    if (width <= 0 || height <= 0 || width > PNG_MAX_SIDE || height > PNG_MAX_SIDE)
        return pp5_fail(PP5_E_RANGE, "image size %dx%d is outside 1..%d", width, height,
                        PNG_MAX_SIDE);
    if (channels != 1 && channels != 3)
        return pp5_fail(PP5_E_RANGE, "image channels must be 1 or 3, not %d", channels);
    size_t bytes;
    if (!pp5_mul3_size((size_t)width, (size_t)height, (size_t)channels, &bytes))
        return pp5_fail(PP5_E_NOMEM, "image %dx%d too large", width, height);
    img->pixels = calloc(bytes, 1);
    if (!img->pixels)
        return pp5_fail(PP5_E_NOMEM, "cannot allocate a %dx%d image", width, height);
    img->width = width;
    img->height = height;
    img->channels = channels;
    return PP5_OK;
}

void image8_free(image8_t *img)
{
    free(img->pixels);
    img->pixels = NULL;
    img->width = img->height = 0;
}

pp5_status_t png_write(const char *path, const image8_t *img)
{
    /* Written to a temporary beside `path` and renamed when complete, so a
     * failure never leaves a truncated PNG under the real name. */
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, true);
    if (st != PP5_OK)
        return st;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, quiet_error, quiet_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        outfile_discard(&o);
        return pp5_fail(PP5_E_NOMEM, "libpng could not start writing %s", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        outfile_discard(&o);
        return pp5_fail(PP5_E_IO, "libpng failed while writing %s", path);
    }
    png_init_io(png, o.f);
    png_set_IHDR(png, info, (png_uint_32)img->width, (png_uint_32)img->height, 8,
                 img->channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    size_t stride = (size_t)img->width * (size_t)img->channels;
    for (int y = 0; y < img->height; y++)
        png_write_row(png, img->pixels + (size_t)y * stride);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return outfile_commit(&o);
}

pp5_status_t png_read(const char *path, image8_t *img, int want_channels)
{
    memset(img, 0, sizeof *img);
    if (want_channels != 1 && want_channels != 3)
        return pp5_fail(PP5_E_RANGE, "png_read: channels must be 1 or 3");
    FILE *f = fopen(path, "rb");
    if (!f)
        return pp5_fail(PP5_E_IO, "cannot open %s: %s", path, strerror(errno));
    unsigned char sig[8];
    if (fread(sig, 1, 8, f) != 8 || png_sig_cmp(sig, 0, 8) != 0) {
        fclose(f);
        return pp5_fail(PP5_E_FORMAT, "%s is not a PNG file", path);
    }
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, quiet_error, quiet_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile pixels = NULL;
    if (!png || !info) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(f);
        return pp5_fail(PP5_E_NOMEM, "libpng could not start reading %s", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(f);
        free(pixels);
        return pp5_fail(PP5_E_FORMAT, "%s is a damaged or truncated PNG", path);
    }
    png_init_io(png, f);
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    if (w == 0 || h == 0 || w > PNG_MAX_SIDE || h > PNG_MAX_SIDE)
        png_error(png, "size");
    png_set_strip_16(png);
    png_set_strip_alpha(png);
    png_set_packing(png);
    png_set_palette_to_rgb(png);
    png_set_expand_gray_1_2_4_to_8(png);
    int ct = png_get_color_type(png, info);
    bool is_gray = !(ct & PNG_COLOR_MASK_COLOR) && ct != PNG_COLOR_TYPE_PALETTE;
    if (want_channels == 3 && is_gray)
        png_set_gray_to_rgb(png);
    if (want_channels == 1 && !is_gray)
        png_set_rgb_to_gray_fixed(png, 1, -1, -1);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != (size_t)w * (size_t)want_channels)
        png_error(png, "layout");
    pixels = malloc((size_t)w * h * (size_t)want_channels);
    if (!pixels)
        png_error(png, "memory");
    for (png_uint_32 y = 0; y < h; y++)
        png_read_row(png, pixels + (size_t)y * w * (size_t)want_channels, NULL);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
    img->pixels = pixels;
    img->width = (int)w;
    img->height = (int)h;
    img->channels = want_channels;
    return PP5_OK;
}
