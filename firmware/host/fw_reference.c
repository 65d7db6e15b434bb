/* fw_reference.c: render/'s mip map shaded per voxel and quantised as the machine holds it (fw_reference.h). */
#include "fw_reference.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/common/vr_shade_fixed.h"
#include "huge_alloc.h"

/* The frame's light and half vector in object space, as the GPs compute
 * them at FRAME_START, and the PP shading constants from them. */
typedef struct {
    float light[3], half[3];
    vr_shade_consts_t consts;
} view_shading_t;

static void view_shading(const mip3d_t *mp, const render_job_t *job, view_shading_t *v)
{
    memset(v, 0, sizeof *v);
    if (mp->lighting == SHADE_DIFFUSE_FIXED_LIGHT)
        return;
    const shade_params_t *sh = &job->shade;
    const render_settings_t *rs = &job->settings;
    camera_t cam;
    camera_setup(&cam, &rs->view, mp, rs->width, rs->height);
    for (int a = 0; a < 3; a++)
        v->light[a] = mp->lighting == SHADE_MOVING_OBJECT
                          ? sh->light_dir[0] * cam.right[a] + sh->light_dir[1] * cam.down[a] +
                                sh->light_dir[2] * cam.forward[a]
                          : sh->light_dir[a];
    float view[3] = {-cam.forward[0], -cam.forward[1], -cam.forward[2]};
    shade_half_vector(v->light, view, v->half);
    vr_shade_consts(&v->consts, v->half, sh->specular, (int)sh->specular_exponent, sh->two_sided);
    if (mp->lighting == SHADE_MOVING_OBJECT)
        vr_shade_consts_diffuse(&v->consts, v->light, sh->ambient, sh->diffuse);
}

/* The renormalised filtered normal of a stride-8 voxel (zero stays zero). */
static float unit_normal(const float *o, float n[3])
{
    n[0] = o[4];
    n[1] = o[5];
    n[2] = o[6];
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0.0f)
        for (int k = 0; k < 3; k++)
            n[k] /= len;
    return len;
}

/* One voxel as the machine holds it: the A block (and N, shaded per voxel
 * with the PP's integer function), back to floats. */
static void voxel_quantised(const float *o, int stride, const view_shading_t *v, float d[4])
{
    uint32_t a = vr_q8(o[0]) | vr_q8(o[1]) << 8 | vr_q8(o[2]) << 16 | vr_q8(o[3]) << 24;
    if (stride == 8) {
        float n[3];
        unit_normal(o, n);
        a = vr_shade_voxel(&v->consts, a, vr_pack_normal(n));
    }
    for (int k = 0; k < 4; k++)
        d[k] = (float)((a >> (8 * k)) & 255u) / 255.0f;
}

/* One voxel shaded per voxel in float (render/'s shade_sample applied to the
 * voxel, not to the interpolated sample). */
static void voxel_float(const float *o, int stride, shade_case_t lighting, const shade_params_t *sh,
                        const view_shading_t *v, float d[4])
{
    for (int k = 0; k < 4; k++)
        d[k] = o[k];
    if (stride != 8 || !(o[3] > 0.0f))
        return;
    float n[3];
    float len = unit_normal(o, n);
    if (lighting == SHADE_MOVING_OBJECT) {
        float dd = shade_diffuse(sh, n, v->light);
        for (int k = 0; k < 3; k++)
            d[k] *= dd;
    }
    if (len > 0.0f) {
        float sp = o[3] * shade_specular(sh, n, v->half);
        for (int k = 0; k < 3; k++)
            d[k] += sp;
    }
}

pp5_status_t fw_reference_init(native_renderer_t *nr, const render_job_t *job, bool quantised)
{
    pp5_status_t st = native_renderer_init(nr, job->volume, &job->tf, &job->shade,
                                           job->settings.threads);
    if (st != PP5_OK)
        return st;
    mip3d_t *mp = &nr->mip;
    view_shading_t v;
    view_shading(mp, job, &v);
    for (int n = 0; n < mp->levels; n++) {
        mip3d_level_t *L = &mp->level[n];
        size_t count = (size_t)L->nx * L->ny * L->nz, bytes = count * 4 * sizeof(float);
        float *out = huge_alloc(bytes, false);   /* a level's data is mip3d's: huge_alloc */
        if (!out)
            return pp5_fail(PP5_E_NOMEM, "reference: out of memory");
        for (size_t i = 0; i < count; i++) {
            const float *o = L->data + i * (size_t)mp->stride;
            if (quantised)
                voxel_quantised(o, mp->stride, &v, out + i * 4);
            else
                voxel_float(o, mp->stride, mp->lighting, &job->shade, &v, out + i * 4);
        }
        huge_free(L->data, L->data_bytes);
        L->data = out;
        L->data_bytes = bytes;
    }
    mp->stride = 4;
    mp->lighting = SHADE_DIFFUSE_FIXED_LIGHT;
    return PP5_OK;
}
