/* poly_report.h: the polygon frame report (JSON) and its text form: the frame as the volume renderer reports it (GP transform and sort, ring command bytes, PP rasterisation cycles, region transfer, the bottleneck) and the comparison with render/mesh. */
#ifndef PP5_POLY_REPORT_H
#define PP5_POLY_REPORT_H

#include <stdio.h>

#include "poly_session.h"

/* The image against mesh_raster on the same mesh and camera (filled by the
 * caller that ran both; have = false: none). */
typedef struct {
    bool have;
    double psnr_db;
    int max_abs_diff;
    long covered_native, covered_one_only;   /* pixels drawn by mesh_raster; drawn by one image only */
} poly_compare_t;

/* Fills *out from the machine's image and mesh_raster's of the same view
 * (same size), a pixel counting as covered where it is not `background`. */
pp5_status_t poly_compare_images(const image8_t *machine, const image8_t *native,
                                 const uint8_t background[3], poly_compare_t *out);
/* The frame in text, a line per stage. */
void poly_report_print(FILE *log, const poly_session_t *s, const poly_frame_result_t *r);
/* The JSON report (written whole or not at all); cmp may be NULL. */
pp5_status_t poly_report_write(const char *path, const poly_session_t *s, const poly_frame_result_t *r,
                               const char *scene_name, const poly_compare_t *cmp);

#endif
