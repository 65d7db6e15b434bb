/* mesh_sheet.h: a contact sheet of shaded meshes: a grid of tiles (one mesh
 * each, drawn by mesh_raster.h), a label under every tile, a label left of
 * every row and a title, written as one PNG.  `pp5 reproduce meshes` shows
 * each simplification level side by side with it. */
#ifndef PP5_MESH_SHEET_H
#define PP5_MESH_SHEET_H

#include "mesh_raster.h"

typedef struct {
    int rows, cols, tile_w, tile_h;
    int left, top, label_h;    /* margins: row labels, title, the two lines under a tile */
    mesh_raster_t raster;
} mesh_sheet_t;

/* A white sheet of rows x cols tiles of tile_w x tile_h pixels. */
pp5_status_t mesh_sheet_init(mesh_sheet_t *s, int rows, int cols, int tile_w, int tile_h,
                             const char *title);
void mesh_sheet_free(mesh_sheet_t *s);
void mesh_sheet_row_label(mesh_sheet_t *s, int row, const char *label);
/* Draws m into tile (row, col) through cam, with up to two lines of text
 * under it (either may be NULL). */
pp5_status_t mesh_sheet_draw(mesh_sheet_t *s, int row, int col, const mesh_t *m,
                             const raster_camera_t *cam, const raster_style_t *style,
                             const char *line1, const char *line2);
pp5_status_t mesh_sheet_write(const mesh_sheet_t *s, const char *path);

#endif
