/* phantom.c: procedural test volumes: the 3D Shepp-Logan head, Marschner-Lobb,
 * and a sphere shell.
 *
 * VALUE RANGES (for transfer functions, such as the presets in classify.c):
 *  - "shepp-logan": 0..200, "MR-like" 8-bit-style units chosen to sit in the
 *    same range as the brainsmall MR data (0..202).  Air 0, outer skull/scalp
 *    shell 200, brain 40, ventricles 0 (dark holes inside the brain), lesions
 *    e, i 80, lesion f 80..120, small lesions g, h 60, lesion j 0.
 *    Surfaces: iso ~100 shows the skull; a ramp over 50..90 with the 40 brain
 *    kept transparent shows the lesions inside.  Voxels on ellipsoid
 *    boundaries hold partial-volume fractions (a linear ramp one voxel wide
 *    across each surface, see ellipsoid_coverage), so shading gradients are
 *    smooth.
 *  - "marschner-lobb": 0..1 (the published function, unscaled); the classic
 *    surface is the iso-value 0.5.
 *  - "sphere-shell": 0..200: 200 between radii 0.55 and 0.80 of the half-box,
 *    0 elsewhere, boundary voxels partial; iso ~100 gives two spheres.
 *
 * GEOMETRY: Shepp-Logan and the shell fill the normalised cube [-1,1]^3 on
 * every axis regardless of the voxel counts, with voxel centres at
 * -1 + (2i+1)/n.  So a 256x256x109 phantom has anisotropic voxels and its
 * spacing is reported as (1, nx/ny, nx/nz) = (1, 1, 2.349): a renderer that
 * ignores volume_t.spacing will show the head squashed along z.  +y of the
 * published table points to image row 0 (top), as in the usual figures;
 * slice 0 is z = -1. */
#include "volume.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* 3D Shepp-Logan head phantom.  Geometry: Kak & Slaney, "Principles of
 * Computerized Tomographic Imaging", IEEE Press 1988, section 3.6 (3D table,
 * p. 102) with the authors' errata; intensities: the higher-contrast variant
 * of Yu, Ye & Wang, "Katsevich-type algorithms for variable radius spiral
 * cone-beam CT", Proc. SPIE 5535, 550-557 (2004).  (Kak & Slaney's own
 * intensities, 2.0, -0.98, -0.02, ... model X-ray attenuation and leave the
 * brain structures at 1-2% contrast, too faint for a volume-rendering demo.)
 * Each ellipsoid: centre (x0,y0,z0), semi-axes (a,b,c) along its own x', y',
 * z axes, rotation phi (degrees) of x' from x about z, additive intensity. */
typedef struct {
    double x0, y0, z0, a, b, c, phi_deg, intensity;
} ellipsoid_t;

static const ellipsoid_t shepp_logan_table[10] = {
    /*  x0      y0      z0      a       b      c      phi   A */
    {0.00,   0.000,  0.000,  0.6900, 0.920, 0.900, 0,   1.0},  /* a: skull */
    {0.00,   0.000,  0.000,  0.6624, 0.874, 0.880, 0,  -0.8},  /* b: brain */
    {-0.22,  0.000, -0.250,  0.4100, 0.160, 0.210, 108, -0.2}, /* c: ventricle */
    {0.22,   0.000, -0.250,  0.3100, 0.110, 0.220, 72,  -0.2}, /* d: ventricle */
    {0.00,   0.350, -0.250,  0.2100, 0.250, 0.500, 0,   0.2},  /* e */
    {0.00,   0.100, -0.250,  0.0460, 0.046, 0.046, 0,   0.2},  /* f */
    {-0.08, -0.650, -0.250,  0.0460, 0.023, 0.020, 0,   0.1},  /* g */
    {0.06,  -0.650, -0.250,  0.0460, 0.023, 0.020, 90,  0.1},  /* h */
    {0.06,  -0.105,  0.625,  0.0560, 0.040, 0.100, 90,  0.2},  /* i */
    {0.00,   0.100,  0.625,  0.0560, 0.056, 0.100, 0,  -0.2},  /* j */
};

/* Scale from the table's unit-free intensities to the MR-like range above. */
#define SHEPP_LOGAN_SCALE 200.0
#define SHELL_VALUE 200.0
#define SHELL_INNER 0.55
#define SHELL_OUTER 0.80
/* Marschner & Lobb, "An evaluation of reconstruction filters for volume
 * rendering", Proc. IEEE Visualization '94, pp. 100-107: f_M = 6, alpha = 0.25,
 * sampled on [-1,1]^3 (41^3 in their tests). */
#define ML_FM 6.0
#define ML_ALPHA 0.25

typedef struct {
    const ellipsoid_t *e;
    double cos_phi, sin_phi, min_axis, reach;
} prepared_ellipsoid_t;

static void prepare(const ellipsoid_t *e, prepared_ellipsoid_t *p)
{
    double phi = e->phi_deg * M_PI / 180.0;
    p->e = e;
    p->cos_phi = cos(phi);
    p->sin_phi = sin(phi);
    p->min_axis = fmin(e->a, fmin(e->b, e->c));
    p->reach = fmax(e->a, fmax(e->b, e->c));
}

/* Normalised radius: < 1 inside, 1 on the surface. */
static double ellipsoid_radius(const prepared_ellipsoid_t *p, double x, double y, double z)
{
    double dx = x - p->e->x0, dy = y - p->e->y0, dz = z - p->e->z0;
    double u = p->cos_phi * dx + p->sin_phi * dy;    /* along the ellipsoid's x' */
    double v = -p->sin_phi * dx + p->cos_phi * dy;   /* along y' */
    double q = (u / p->e->a) * (u / p->e->a) + (v / p->e->b) * (v / p->e->b) +
               (dz / p->e->c) * (dz / p->e->c);
    return sqrt(q);
}

/* Partial-volume fraction of the voxel centred at (x,y,z) with sides
 * (hx,hy,hz) that lies inside the ellipsoid, modelled as a box filter across
 * a locally flat surface: with d the signed distance from the centre to the
 * surface (negative inside) and w the voxel's extent along the surface
 * normal, the fraction is clamp(1/2 - d/w, 0, 1).  d is estimated as
 * (r - 1) / |grad r| with r the normalised radius, exact for spheres and
 * first-order for ellipsoids.  Why not point sampling or supersampling:
 * both give staircase or quantized boundary values whose gradients make
 * ring artefacts when the surfaces are shaded; the ramp is continuous. */
static double ellipsoid_coverage(const prepared_ellipsoid_t *p, double x, double y, double z,
                                 double hx, double hy, double hz)
{
    double half_diag = 0.5 * sqrt(hx * hx + hy * hy + hz * hz);
    double dx = x - p->e->x0, dy = y - p->e->y0, dz = z - p->e->z0;
    if (fabs(dx) > p->reach + half_diag || fabs(dy) > p->reach + half_diag ||
        fabs(dz) > p->reach + half_diag)
        return 0.0;
    double r = ellipsoid_radius(p, x, y, z);
    /* Far from the surface (by more than the half-diagonal, in the worst
     * direction) the voxel is wholly inside or outside. */
    double band = half_diag / p->min_axis;
    if (r <= 1.0 - band)
        return 1.0;
    if (r >= 1.0 + band)
        return 0.0;
    double u = p->cos_phi * dx + p->sin_phi * dy;
    double v = -p->sin_phi * dx + p->cos_phi * dy;
    double a2 = p->e->a * p->e->a, b2 = p->e->b * p->e->b, c2 = p->e->c * p->e->c;
    /* grad q in the ellipsoid's frame, then turned back to x, y, z; grad r = grad q / 2r. */
    double gu = 2 * u / a2, gv = 2 * v / b2, gz = 2 * dz / c2;
    double gx = p->cos_phi * gu - p->sin_phi * gv;
    double gy = p->sin_phi * gu + p->cos_phi * gv;
    double gq = sqrt(gx * gx + gy * gy + gz * gz);
    if (gq <= 0 || r <= 0)
        return r < 1.0 ? 1.0 : 0.0;
    double d = (r - 1.0) * 2.0 * r / gq;
    double width = (fabs(gx) * hx + fabs(gy) * hy + fabs(gz) * hz) / gq;
    double f = 0.5 - d / width;
    return f <= 0 ? 0.0 : f >= 1 ? 1.0 : f;
}

/* Sums scale * intensity * coverage over a table of ellipsoids, each voxel
 * centre at -1 + (2i+1)/n on each axis (row 0 at y = +1). */
static void fill_ellipsoids(volume_t *v, const ellipsoid_t *table, int count, double scale)
{
    prepared_ellipsoid_t prep[16];
    PP5_ASSERT(count <= 16, "ellipsoid table too long");
    /* Scaled intensities rounded to 1e-6, so that the table's decimal values
     * (e.g. 200 * -0.8 = -160) are exact in binary and uniform regions hold
     * exact sums (brain 200 - 160 = 40, ventricles 40 - 40 = 0, not 1e-14). */
    double weight[16];
    for (int e = 0; e < count; e++) {
        prepare(&table[e], &prep[e]);
        weight[e] = round(table[e].intensity * scale * 1e6) / 1e6;
    }
    double hx = 2.0 / v->nx, hy = 2.0 / v->ny, hz = 2.0 / v->nz;
    for (int k = 0; k < v->nz; k++) {
        double z = -1.0 + (2 * k + 1) / (double)v->nz;
        for (int j = 0; j < v->ny; j++) {
            double y = 1.0 - (2 * j + 1) / (double)v->ny;
            float *row = v->data + ((size_t)k * v->ny + j) * v->nx;
            for (int i = 0; i < v->nx; i++) {
                double x = -1.0 + (2 * i + 1) / (double)v->nx;
                double sum = 0.0;
                for (int e = 0; e < count; e++)
                    sum += weight[e] * ellipsoid_coverage(&prep[e], x, y, z, hx, hy, hz);
                row[i] = (float)sum;
            }
        }
    }
    v->spacing[0] = 1.0;
    v->spacing[1] = (double)v->nx / v->ny;
    v->spacing[2] = (double)v->nx / v->nz;
}

static void make_sphere_shell(volume_t *v)
{
    static const ellipsoid_t shell[2] = {
        {0, 0, 0, SHELL_OUTER, SHELL_OUTER, SHELL_OUTER, 0, 1.0},
        {0, 0, 0, SHELL_INNER, SHELL_INNER, SHELL_INNER, 0, -1.0},
    };
    fill_ellipsoids(v, shell, 2, SHELL_VALUE);
}

double phantom_marschner_lobb(double x, double y, double z)
{
    double r = sqrt(x * x + y * y);
    double rho_r = cos(2.0 * M_PI * ML_FM * cos(M_PI * r / 2.0));
    return (1.0 - sin(M_PI * z / 2.0) + ML_ALPHA * (1.0 + rho_r)) / (2.0 * (1.0 + ML_ALPHA));
}

/* Samples include both ends of [-1,1] (x_i = -1 + 2i/(n-1)), as in the
 * published 41^3 sampling, so the grid is isotropic with spacing 1. */
static void make_marschner_lobb(volume_t *v)
{
    for (int k = 0; k < v->nz; k++) {
        double z = v->nz > 1 ? -1.0 + 2.0 * k / (v->nz - 1) : 0.0;
        for (int j = 0; j < v->ny; j++) {
            double y = v->ny > 1 ? -1.0 + 2.0 * j / (v->ny - 1) : 0.0;
            for (int i = 0; i < v->nx; i++) {
                double x = v->nx > 1 ? -1.0 + 2.0 * i / (v->nx - 1) : 0.0;
                v->data[((size_t)k * v->ny + j) * v->nx + i] =
                    (float)phantom_marschner_lobb(x, y, z);
            }
        }
    }
    v->spacing[0] = v->spacing[1] = v->spacing[2] = 1.0;
}

const char *phantom_names(void)
{
    return "shepp-logan, marschner-lobb, sphere-shell";
}

pp5_status_t phantom_make(const char *name, int nx, int ny, int nz, volume_t *out)
{
    int dx, dy, dz;
    int kind;
    if (name && strcmp(name, "shepp-logan") == 0) {
        kind = 0; dx = 256; dy = 256; dz = 109;   /* the paper's MR scan size (seed §6) */
    } else if (name && strcmp(name, "marschner-lobb") == 0) {
        kind = 1; dx = dy = dz = 41;
    } else if (name && strcmp(name, "sphere-shell") == 0) {
        kind = 2; dx = dy = dz = 64;
    } else {
        return pp5_fail(PP5_E_CONFIG, "unknown phantom '%s' (known: %s)", name ? name : "(null)",
                        phantom_names());
    }
    if (nx == 0 && ny == 0 && nz == 0) {
        nx = dx; ny = dy; nz = dz;
    } else if (nx <= 0 || ny <= 0 || nz <= 0) {
        return pp5_fail(PP5_E_RANGE, "phantom %s: size %dx%dx%d: give all three sides >= 1 "
                        "(or 0x0x0 for the default %dx%dx%d)", name, nx, ny, nz, dx, dy, dz);
    }
    volume_t tmp;
    pp5_status_t st = volume_alloc(&tmp, nx, ny, nz);
    if (st != PP5_OK)
        return st;
    if (kind == 0)
        fill_ellipsoids(&tmp, shepp_logan_table, 10, SHEPP_LOGAN_SCALE);
    else if (kind == 1)
        make_marschner_lobb(&tmp);
    else
        make_sphere_shell(&tmp);
    snprintf(tmp.source, sizeof tmp.source, "phantom %s %dx%dx%d", name, nx, ny, nz);
    volume_update_stats(&tmp);
    *out = tmp;
    return PP5_OK;
}
