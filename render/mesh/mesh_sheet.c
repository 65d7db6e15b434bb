/* mesh_sheet.c: contact sheets of shaded meshes (mesh_sheet.h). */
#include "mesh_sheet.h"

#include <string.h>

#include "plot.h"

static const uint8_t INK[3] = {24, 24, 24}, PAPER[3] = {255, 255, 255};

pp5_status_t mesh_sheet_init(mesh_sheet_t *s, int rows, int cols, int tile_w, int tile_h,
                             const char *title)
{
    memset(s, 0, sizeof *s);
    if (rows < 1 || cols < 1 || rows > 64 || cols > 64)
        return pp5_fail(PP5_E_RANGE, "sheet: %d x %d tiles (1..64 each way)", rows, cols);
    s->rows = rows, s->cols = cols, s->tile_w = tile_w, s->tile_h = tile_h;
    s->left = 100, s->top = 30, s->label_h = 26;
    pp5_status_t st = mesh_raster_init(&s->raster, s->left + cols * tile_w,
                                       s->top + rows * (tile_h + s->label_h));
    if (st != PP5_OK)
        return st;
    raster_viewport_t all = {0, 0, s->raster.image.width, s->raster.image.height};
    mesh_raster_clear(&s->raster, &all, PAPER);
    if (title)
        plot_draw_text(&s->raster.image, 8, 8, title, 2, INK);
    return PP5_OK;
}

void mesh_sheet_free(mesh_sheet_t *s)
{
    mesh_raster_free(&s->raster);
    memset(s, 0, sizeof *s);
}

void mesh_sheet_row_label(mesh_sheet_t *s, int row, const char *label)
{
    if (row < 0 || row >= s->rows || !label)
        return;
    int y = s->top + row * (s->tile_h + s->label_h) + s->tile_h / 2 - 7;
    plot_draw_text(&s->raster.image, 8, y, label, 2, INK);
}

pp5_status_t mesh_sheet_draw(mesh_sheet_t *s, int row, int col, const mesh_t *m,
                             const raster_camera_t *cam, const raster_style_t *style,
                             const char *line1, const char *line2)
{
    if (row < 0 || row >= s->rows || col < 0 || col >= s->cols)
        return pp5_fail(PP5_E_RANGE, "sheet: tile (%d, %d) outside %d x %d", row, col, s->rows,
                        s->cols);
    raster_viewport_t vp = {s->left + col * s->tile_w, s->top + row * (s->tile_h + s->label_h),
                            s->tile_w, s->tile_h};
    pp5_status_t st = mesh_raster_draw(&s->raster, &vp, m, cam, style);
    const char *lines[2] = {line1, line2};
    for (int i = 0; i < 2 && st == PP5_OK; i++)
        if (lines[i]) {
            int x = vp.x0 + (s->tile_w - plot_text_width(lines[i], 1)) / 2;
            plot_draw_text(&s->raster.image, x, vp.y0 + s->tile_h + 2 + 11 * i, lines[i], 1, INK);
        }
    return st;
}

pp5_status_t mesh_sheet_write(const mesh_sheet_t *s, const char *path)
{
    return png_write(path, &s->raster.image);
}
