/* poly_session.h: the host's side of the polygon pipeline on the emulated machine: deal the triangles to the GPs once, then one call per frame returning the image and the frame's figures.
 *
 * Entry points: poly_session_init_mesh (a mesh_t with render/mesh's camera
 * and style, the shapes `pp5 render --mesh` uses) or poly_session_init (a
 * world-space triangle list).  The GP program is firmware/gp/poly_gp.c
 * (firmware/ARCHITECTURE.md "Polygons").  Every figure comes from emu's
 * named statistics taken as differences around the frame. */
#ifndef PP5_POLY_SESSION_H
#define PP5_POLY_SESSION_H

#include <stdbool.h>
#include <stdint.h>

#include "firmware/common/poly_config.h"
#include "machine.h"
#include "render/gaze2d.h"
#include "render/mesh/mesh_raster.h"

typedef struct {
    poly_shading_t shading;     /* flat, Gouraud (per-vertex light) or Phong (per pixel in the PPs) */
    bool cull_back;             /* drop back faces (default: two-sided, as mesh_raster) */
    bool colour_per_pixel;      /* Phong: the triangles' own colours (poly_tri_in_t.rgb) per pixel */
    uint8_t background[3];
    /* Gaze-directed frames: the variable-resolution Z-buffer (gaze paper
     * §7, seed 004) with this acuity model's 2D levels, gazed at (gaze_x,
     * gaze_y) (image pixels) until poly_session_set_gaze. */
    bool gaze;
    bool level_tables;          /* 2DLevel by the paper's tables (default), else exact */
    gaze_model_t gaze_model;
    double gaze_x, gaze_y;
} poly_options_t;

void poly_options_default(poly_options_t *o);
const char *poly_shading_name(poly_shading_t s);

/* The frame's stages; each is the busiest unit's time in the frame.  With
 * frames pipelined (the GPs transforming frame n + 1 while the renderers
 * draw frame n) the largest bounds the triangle rate: the bottleneck. */
typedef enum {
    POLY_STAGE_GP = 0,          /* transform, sort, encode, sends: the busiest GP */
    POLY_STAGE_RENDERER,        /* PP rasterisation and readout: the busiest renderer */
    POLY_STAGE_RING,            /* the ring: all channel time / channels */
    POLY_STAGE_RN_PORT,         /* the busiest renderer's region transfers through its one transmitter */
    POLY_STAGE_COUNT
} poly_stage_t;

const char *poly_stage_name(poly_stage_t s);

typedef struct {
    double frame_time_s;                  /* one frame alone, start to last activity */
    double stage_s[POLY_STAGE_COUNT];
    const char *bottleneck;
    double tris_per_s_pipelined;          /* input triangles / largest stage */
    double tris_per_s_frame;              /* input triangles / frame time */
    /* GP work (sums over GPs) and the busiest GP's split */
    uint64_t tris_in, tris_setup, pairs_binned, pairs_sent, edges_sent, stream_words, regions;
    uint64_t cycles_transform, cycles_sort, cycles_encode;
    /* regions drawn (gaze-directed frames: the populated level tiles), the
     * texels the GPs received, the GPs' planning and
     * resampling cycles (sums over GPs) */
    uint64_t regions_drawn, texels_in;
    uint64_t cycles_levels, cycles_resample;
    uint64_t gp_fdiv_busiest;             /* fdiv operations charged by the busiest GP */
    double gp_transform_sort_s_max, gp_encode_s_max, gp_busy_s_max, gp_busy_s_mean;
    double gp_sorted_s_max;               /* the last GP's end of transform and sort, from frame start */
    /* renderers */
    uint64_t rn_exec_cycles_total, rn_exec_cycles_max, rn_port_cycles_total;
    uint64_t rn_qee_cycles_total, rn_qee_count;   /* of the exec cycles: QEE instructions */
    double rn_busy_s_max, rn_busy_s_mean;
    /* ring */
    uint64_t ring_bytes[RING_CLASS_COUNT], ring_bytes_total;
    double ring_class_busy_s[RING_CLASS_COUNT];   /* channel time per class, all channels */
    double ring_util_total;
} poly_frame_result_t;

typedef struct {
    machine_t m;
    bool m_ok;
    pp5_params_t params;
    poly_options_t opts;
    poly_config_t cfg;                    /* as sent (n_triangles is each GP's own) */
    uint32_t n_tris;
    double load_s;                        /* emulated time of the load (program and triangles) */
    uint64_t upload_ring_bytes;           /* the last poly_session_set_triangles's wire bytes */
    unsigned frames;
    double gaze_x, gaze_y;                /* image pixels (gaze-directed frames) */
    poly_frame_result_t last;
} poly_session_t;

/* Loads the program and n triangles (dealt round-robin: triangle i to GP
 * i mod n_gp) for a width x height image in the frame buffer's top left,
 * and runs the load.  cam and style as render/mesh/mesh_raster.h; the
 * style's shading is replaced by o->shading. */
pp5_status_t poly_session_init(poly_session_t *s, const pp5_params_t *p, const poly_tri_in_t *tris,
                               size_t n, int width, int height, const raster_camera_t *cam,
                               const raster_style_t *style, const poly_options_t *o);
/* The same from a mesh: per-vertex normals as mesh_raster's (the sum of
 * the area-weighted face normals, normalised). */
pp5_status_t poly_session_init_mesh(poly_session_t *s, const pp5_params_t *p, const mesh_t *m,
                                    int width, int height, const raster_camera_t *cam,
                                    const raster_style_t *style, const poly_options_t *o);
/* The mesh's triangles as the session deals them (caller frees *out). */
pp5_status_t poly_triangles_from_mesh(const mesh_t *m, poly_tri_in_t **out, size_t *n);
/* One frame; img (may be NULL) is allocated here. */
pp5_status_t poly_session_frame(poly_session_t *s, image8_t *img, poly_frame_result_t *r);
/* A new gaze point (image pixels) for the next gaze-directed frames (the GPs
 * get it over the ring). */
pp5_status_t poly_session_set_gaze(poly_session_t *s, double gaze_x, double gaze_y);
/* A new triangle list for the next frames, dealt as poly_session_init
 * deals it.  The host queues it on the ring now; the GPs take it (free the
 * old list, store the new) before the next frame's start reaches them, so
 * its transfer and storing fall inside the next frame's time.  Its wire
 * bytes are left in s->upload_ring_bytes: the ring counts bytes when they
 * are queued, before that frame's figures start. */
pp5_status_t poly_session_set_triangles(poly_session_t *s, const poly_tri_in_t *tris, size_t n);
/* A new camera for the next frames (the GPs get it over the ring). */
pp5_status_t poly_session_set_camera(poly_session_t *s, const raster_camera_t *cam);
void poly_session_free(poly_session_t *s);

#endif
