/* colour_sphere.c: DEMIP's colour sphere (seed 002 §3.3): maps, orientation
 * and the legend (see colour_sphere.h). */
#include "colour_sphere.h"

#include <string.h>

#include "plot.h"
#include "raycast.h"

/* Okabe & Ito's Color Universal Design palette, in 8-bit sRGB / 255. */
#define OI(r, g, b) {(r) / 255.0f, (g) / 255.0f, (b) / 255.0f}

static const sphere_map_info_t maps[SPHERE_MAP_COUNT] = {
    {"red-blue", {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f},
     "the paper's red front, blue back (seed 002 §3.3)"},
    {"orange-blue", OI(230, 159, 0), OI(0, 114, 178),
     "Okabe-Ito orange / blue: distinct under protan, deutan and tritan colour vision"},
    {"magenta-green", OI(204, 121, 167), OI(0, 158, 115),
     "Okabe-Ito reddish purple / bluish green: their replacement for red / green"},
    {"yellow-blue", OI(240, 228, 66), OI(0, 114, 178),
     "Okabe-Ito yellow / blue: the largest lightness difference of the pairs"},
};

const sphere_map_info_t *colour_sphere_map_info(sphere_map_t m)
{
    return m >= 0 && m < SPHERE_MAP_COUNT ? &maps[m] : &maps[0];
}

pp5_status_t colour_sphere_map_parse(const char *name, sphere_map_t *out)
{
    for (int i = 0; i < SPHERE_MAP_COUNT; i++)
        if (strcmp(name, maps[i].name) == 0) {
            *out = (sphere_map_t)i;
            return PP5_OK;
        }
    return pp5_fail(PP5_E_CONFIG, "--sphere-map: unknown map '%s' (known: %s)", name,
                    colour_sphere_map_names());
}

const char *colour_sphere_map_names(void)
{
    return "red-blue, orange-blue, magenta-green, yellow-blue";
}

void colour_sphere_init(colour_sphere_t *s, sphere_map_t map, const float rot_deg[3])
{
    const sphere_map_info_t *info = colour_sphere_map_info(map);
    memcpy(s->front, info->front, sizeof s->front);
    memcpy(s->back, info->back, sizeof s->back);
    view_params_t v;
    view_defaults(&v);
    v.rot_x_deg = rot_deg[0];
    v.rot_y_deg = rot_deg[1];
    v.rot_z_deg = rot_deg[2];
    float right[3], down[3], forward[3];
    view_basis(&v, right, down, forward);
    for (int a = 0; a < 3; a++)
        s->pole[a] = -forward[a];
}

/* One legend disc: pixel (x, y) of a disc of radius r centred at (cx, cy)
 * shows the sphere point with normal n = u right + w down + z `toward`,
 * where `toward` is the hemisphere's pole and `side` its right-hand axis. */
static void draw_disc(const colour_sphere_t *s, const float side[3], const float down[3],
                      const float toward[3], int cx, int cy, int r, image8_t *img)
{
    const uint8_t ring[3] = {160, 160, 160};
    for (int y = cy - r - 1; y <= cy + r + 1; y++) {
        for (int x = cx - r - 1; x <= cx + r + 1; x++) {
            if (x < 0 || y < 0 || x >= img->width || y >= img->height)
                continue;
            float u = ((float)x + 0.5f - (float)cx) / (float)r;
            float w = ((float)y + 0.5f - (float)cy) / (float)r;
            float q = u * u + w * w;
            uint8_t *px = img->pixels + ((size_t)y * img->width + x) * 3;
            if (q > 1.0f) {
                if (q <= (1.0f + 1.5f / (float)r) * (1.0f + 1.5f / (float)r))
                    memcpy(px, ring, 3);
                continue;
            }
            float z = sqrtf(1.0f - q), n[3], rgb[3];
            for (int a = 0; a < 3; a++)
                n[a] = u * side[a] + w * down[a] + z * toward[a];
            colour_sphere_colour(s, n, rgb);
            float shade = 0.45f + 0.55f * z;   /* a hint of roundness, not a light model */
            for (int k = 0; k < 3; k++) {
                float c = rgb[k] * shade;
                px[k] = (uint8_t)(c <= 0.0f ? 0 : (c >= 1.0f ? 255 : c * 255.0f + 0.5f));
            }
        }
    }
}

int colour_sphere_draw_legend(const colour_sphere_t *s, const float right[3],
                              const float down[3], const float forward[3], image8_t *img)
{
    int side = img->width < img->height ? img->width : img->height;
    if (side < 64 || img->channels != 3)
        return 0;
    int r = side / 16;
    r = r < 8 ? 8 : (r > 40 ? 40 : r);
    int scale = r >= 24 ? 2 : 1;
    int label_h = 9 * scale;
    int cy = img->height - label_h - r - r / 2 - 2;
    int cx_near = r + r / 2 + 1, cx_far = cx_near + 2 * r + r / 2 + 4;
    float toward_eye[3], left[3];
    for (int a = 0; a < 3; a++) {
        toward_eye[a] = -forward[a];
        left[a] = -right[a];
    }
    /* Near: the hemisphere facing the viewer.  Far: the other one, seen
     * from behind (so its right-hand axis is the viewer's left). */
    draw_disc(s, right, down, toward_eye, cx_near, cy, r, img);
    draw_disc(s, left, down, forward, cx_far, cy, r, img);
    const uint8_t white[3] = {230, 230, 230};
    int ty = cy + r + 3;
    plot_draw_text(img, cx_near - plot_text_width("near", scale) / 2, ty, "near", scale, white);
    plot_draw_text(img, cx_far - plot_text_width("far", scale) / 2, ty, "far", scale, white);
    return r;
}
