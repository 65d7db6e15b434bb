/* shade.c: central-difference gradients and Levoy-1988 Phong shading terms. */
#include "shade.h"

#include <math.h>

void shade_defaults(shade_params_t *s)
{
    s->lighting = SHADE_DIFFUSE_FIXED_LIGHT;
    s->ambient = 0.15f;
    s->diffuse = 0.85f;
    s->specular = 0.0f;
    s->specular_exponent = 20.0f;
    /* From the front-upper-left of the default view (which looks along +z). */
    float l[3] = {-0.35f, -0.45f, -1.0f};
    float n = sqrtf(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (int i = 0; i < 3; i++)
        s->light_dir[i] = l[i] / n;
    s->two_sided = true;
}

const char *shade_case_name(shade_case_t c)
{
    switch (c) {
    case SHADE_DIFFUSE_FIXED_LIGHT: return "diffuse-fixed-light";
    case SHADE_SPECULAR_FIXED_LIGHT: return "specular-fixed-light";
    case SHADE_MOVING_OBJECT: return "moving-object";
    }
    return "?";
}

void shade_gradient(const volume_t *v, int x, int y, int z, const float inv_spacing[3],
                    float g[3])
{
    int p[3] = {x, y, z};
    int n[3] = {v->nx, v->ny, v->nz};
    for (int a = 0; a < 3; a++) {
        int lo[3] = {x, y, z}, hi[3] = {x, y, z};
        lo[a] = p[a] > 0 ? p[a] - 1 : p[a];
        hi[a] = p[a] < n[a] - 1 ? p[a] + 1 : p[a];
        int span = hi[a] - lo[a];
        if (span == 0) {
            g[a] = 0.0f;
            continue;
        }
        float d = volume_at(v, hi[0], hi[1], hi[2]) - volume_at(v, lo[0], lo[1], lo[2]);
        g[a] = d / (float)span * inv_spacing[a];
    }
}

float shade_diffuse(const shade_params_t *s, const float n[3], const float l[3])
{
    float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (len2 == 0.0f)
        return s->ambient + s->diffuse;
    float d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    d = s->two_sided ? fabsf(d) : fmaxf(d, 0.0f);
    return s->ambient + s->diffuse * d;
}

float shade_specular(const shade_params_t *s, const float n[3], const float h[3])
{
    if (s->specular <= 0.0f)
        return 0.0f;
    float d = n[0] * h[0] + n[1] * h[1] + n[2] * h[2];
    d = s->two_sided ? fabsf(d) : fmaxf(d, 0.0f);
    return d > 0.0f ? s->specular * powf(d, s->specular_exponent) : 0.0f;
}

void shade_half_vector(const float l[3], const float e[3], float h[3])
{
    float s[3] = {l[0] + e[0], l[1] + e[1], l[2] + e[2]};
    float n = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int i = 0; i < 3; i++)
        h[i] = n > 0.0f ? s[i] / n : 0.0f;
}
