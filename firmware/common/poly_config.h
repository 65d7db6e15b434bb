/* poly_config.h: what the host gives the polygon GP program (configuration, triangles), its ring messages, the fixed-point formats and the PP memory layout.
 *
 * The polygon pipeline (firmware/ARCHITECTURE.md "Polygons"): each GP holds
 * a share of the scene's triangles (the host deals them out in order), and
 * per frame transforms, lights, clips, culls and snaps them, sorts them into
 * the 128x128 screen regions and, when a renderer takes a region, sends it
 * one PP instruction stream with its triangles for that region (three QEE
 * edge expressions clearing the Enable of pixels outside, a QEE plane for Z
 * and a compare keeping the nearer, QEE planes for the colour channels or,
 * for Phong, the normal components).  Sort-middle by screen region as the
 * machine was built for (facts §2 "Sort-middle by screen region" [I/S], S4,
 * S5). */
#ifndef PP5_POLY_CONFIG_H
#define PP5_POLY_CONFIG_H

#include <stdint.h>

typedef enum { POLY_FLAT = 0, POLY_GOURAUD = 1, POLY_PHONG = 2 } poly_shading_t;

/* Fixed point (the choices, stated; tests/test_fw_poly.c checks them).
 *  - Screen coordinates: integers in 1/16 pixel (POLY_SUB_BITS), pixel
 *    centres at 16 x + 8.  Clipping to the guard band |ndc| <= POLY_GUARD
 *    keeps them inside +-2^14 pixels for images up to 2048 wide, so edge
 *    deltas are below 2^19 and the QEE edge coefficients below 2^23.
 *  - Edges: e = D x + E y + F exact in 64-bit integers (at most 2^40); the
 *    QEE gets F mod 2^32 and keeps bit 31 only (POLY_EDGE_SHIFT): for an
 *    edge that crosses the region |e| < 127 (|D| + |E|) < 2^31 there, so
 *    bit 31 of (e mod 2^32) is exactly the sign of e.
 *  - Z: z/w in [-1, 1] maps to POLY_Z_LO + (z + 1) * POLY_Z_SCALE, 24 bits
 *    unsigned, margins of 2^21 at both ends for the planes' rounding;
 *    cleared to 2^24 - 1 (farther than anything drawn).
 *  - Colour: 8 bits per channel, the plane holding value + 0.5 so that the
 *    QEE's floor rounds it.
 *  - Phong normals: signed 16 bits, 1.0 = 2^14 (POLY_N_ONE). */
#define POLY_SUB_BITS 4
#define POLY_SUB (1 << POLY_SUB_BITS)
#define POLY_GUARD 8.0f
#define POLY_EDGE_SHIFT 31
#define POLY_Z_BITS 24
#define POLY_Z_LO 2097152.0              /* 2^21 */
#define POLY_Z_SCALE 6291456.0           /* (2^24 - 2^22) / 2 */
#define POLY_Z_FAR 16777215u             /* 2^24 - 1 */
#define POLY_N_ONE 16384.0

/* PP memory (bit addresses in the 208-bit pixel memory). */
enum {
    POLY_PP_Z = 0,        /* 24: depth, unsigned, smaller is nearer */
    POLY_PP_R = 24,       /* 8 each: the colour read out by SEND_PIXELS */
    POLY_PP_G = 32,
    POLY_PP_B = 40,
    POLY_PP_ZT = 48,      /* 24: the triangle's depth at the pixel */
    POLY_PP_T = 72,       /* 1: an edge's sign */
    POLY_PP_BACK = 73,    /* 1, Phong: the front or back colour */
    POLY_PP_COVER = 74,   /* 1, Phong: a triangle was written here */
    POLY_PP_NX = 80,      /* 16 each, Phong: the normal, 1.0 = 2^14 */
    POLY_PP_NY = 96,
    POLY_PP_NZ = 112,
    POLY_PP_D = 128,      /* 32, Phong shading: N.L, 2^28 = 1 */
    POLY_PP_P = 160,      /* 32, Phong shading: products */
    POLY_PP_S = 192,      /* 16, Phong shading: |N|^2, 2^14 = 1 */
    /* Phong shading reuses Z and ZT once the region's triangles are in. */
    POLY_PP_RS = 0,       /* 16: 1/|N| by Newton, 2^14 = 1 */
    POLY_PP_W = 48,       /* 16: Newton's terms */
    POLY_PP_BITS_USED = 208
};

/* The host's configuration of a GP (HOST_LOAD data). */
typedef struct {
    int32_t width, height;          /* image (top-left of the frame buffer), 1..2048 x 1..1024 */
    int32_t shading;                /* poly_shading_t */
    int32_t cull_back;              /* drop faces seen from behind (else two-sided, as render/mesh) */
    int32_t n_triangles;            /* this GP's share */
    float clip_from_world[16];      /* proj x view, row-major */
    float view[16];                 /* camera from world (normals: its 3x3) */
    float light[3];                 /* toward the light, camera space, unit */
    float ambient, diffuse;
    int32_t front_rgb[3], back_rgb[3];  /* for triangles without their own colour */
    uint32_t background_rgb[3];
    /* Phong with colours per triangle: each triangle writes its side's
     * colour into R, G, B, and the shading reads it there per pixel
     * (pp/poly_phong_pp.c); 0: the front and back colours as constants. */
    int32_t colour_per_pixel;
    /* Gaze-directed frames: the variable-resolution Z-buffer of the gaze
     * paper's §7 (seed 004; firmware/ARCHITECTURE.md "Polygons").  The
     * acuity model's constants are render/gaze2d.h gaze_model_t's, from the
     * host, as vr_config_t's g_* (the same 2DLevel, vr_gaze_level). */
    int32_t gaze;                   /* 0: full resolution; 1: the populated levels only */
    int32_t levels2d;               /* 2D levels, 1..POLY_MAX_LEVELS */
    int32_t level_tables;           /* 2DLevel by the paper's two tables (vr_kernels.h), else exact */
    double gaze_x, gaze_y;          /* the gaze point, image pixels (set per frame) */
    double g_inches_per_px, g_view_distance_in, g_e_full_deg, g_e_edge_deg, g_sigma_deg,
        g_rho_min, g_r_zero_px, g_r_max_px;
    int32_t g_max_level;
    float g_level_far;              /* 2DLevel past g_r_max_px (gaze_model_t level_edge) */
} poly_config_t;

/* One input triangle (world space): corners and their unit normals, and
 * its own surface colour for both sides (a scene object's: R | G << 8 |
 * B << 16 | POLY_RGB_OWN) or 0 for the configuration's front and back
 * colours. */
typedef struct {
    float p[3][3];
    float n[3][3];
    uint32_t rgb;
} poly_tri_in_t;
#define POLY_RGB_OWN (1u << 24)

/* GP_USER sub-kinds (args[0]). */
enum {
    POLY_MSG_TRIANGLES = 1,  /* host -> GP: its triangles (payload: poly_tri_in_t[]) */
    POLY_MSG_TOKEN = 2,      /* GP -> GP: args[1] renderer, args[2] round, args[3] frame */
    POLY_MSG_CONFIG = 3      /* host -> GP: a new configuration (camera, light) between frames */
};

/* The GP program (firmware/gp/poly_gp.c). */
#include "fw_api.h"
extern const fw_program_t poly_program;

#define POLY_MAX_GPS 64
#define POLY_MAX_LEVELS 8            /* render/gaze2d.h MIP2D_MAX_LEVELS */
#define POLY_MAX_RENDERERS 64

#endif
