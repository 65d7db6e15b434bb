/* classify.c: Levoy-1988 iso-value contour opacity and the transfer-function
 * presets.  The preset values were read off histograms of the data (see the
 * comments), not tuned to any paper figure.  The real-data presets drop
 * voxels below 5% (2% for the faint ct-bone skin) opacity, as VolPack's
 * examples do: CT and MR noise otherwise scatters faint voxels through the
 * air around the head and fragments the octree. */
#include "classify.h"

#include <math.h>
#include <string.h>

typedef struct {
    const char *name;
    int count;
    classify_contour_t contour[CLASSIFY_MAX_CONTOURS];
    float min_opacity;
} preset_t;

static const preset_t presets[] = {
    /* CThead (u16, 0..3272): air peaks below 100, soft tissue at 1000-1100,
     * bone from ~1600 (histogram of cthead_256x256x113_u16be).  Skin is the
     * air/tissue boundary halfway between the two peaks. */
    {"ct-skin", 1, {{500.0f, 1.0f, 2.0f, {0.95f, 0.75f, 0.62f}, 0.0f}}, 0.05f},
    /* The peers' value ramp (render/peers/): 350 -> 0.8 at 640, 0.8 above. */
    {"ct-skin-ramp", 1, {{495.0f, 0.8f, 0.0f, {0.95f, 0.75f, 0.62f}, 290.0f}}, 0.05f},
    {"ct-bone", 2, {{500.0f, 0.08f, 2.0f, {0.95f, 0.75f, 0.62f}, 0.0f},
                    {1600.0f, 0.9f, 2.0f, {1.0f, 1.0f, 0.92f}, 0.0f}}, 0.02f},
    /* brainsmall MR (u8, 0..202): background below ~15, head tissue 40-90,
     * bright tissue 100-150.  The scalp/skin surface sits near 40. */
    {"mr", 2, {{40.0f, 0.6f, 2.0f, {0.92f, 0.80f, 0.70f}, 0.0f},
               {100.0f, 0.9f, 2.0f, {1.0f, 1.0f, 1.0f}, 0.0f}}, 0.05f},
    /* Shepp-Logan phantom (render/phantom.c): air 0, skull shell 200, brain
     * 40, ventricles 0, lesions 60-120.  Every iso-value above 40 also occurs
     * in the skull shell, so the surfaces are kept semi-transparent: the
     * lesions (contour 70 in the 40 brain) show through the skull. */
    {"shepp-logan", 2, {{150.0f, 0.1f, 2.5f, {0.92f, 0.80f, 0.70f}, 0.0f},
                        {70.0f, 0.3f, 2.5f, {0.55f, 0.75f, 1.0f}, 0.0f}}, 0.0f},
    /* Marschner-Lobb (0..1): the classic iso-surface at 0.5. */
    {"marschner-lobb", 1, {{0.5f, 0.9f, 1.5f, {0.9f, 0.9f, 0.9f}, 0.0f}}, 0.0f},
    /* Sphere shell (0..200): iso 100 gives the inner and outer spheres. */
    {"sphere-shell", 1, {{100.0f, 0.7f, 1.5f, {0.9f, 0.85f, 0.7f}, 0.0f}}, 0.0f},
};

pp5_status_t classify_preset(const char *name, classify_tf_t *tf)
{
    for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++) {
        if (strcmp(presets[i].name, name) == 0) {
            memset(tf, 0, sizeof *tf);
            strncpy(tf->name, presets[i].name, sizeof tf->name - 1);
            tf->count = presets[i].count;
            memcpy(tf->contour, presets[i].contour, sizeof tf->contour);
            tf->min_opacity = presets[i].min_opacity;
            return PP5_OK;
        }
    }
    return pp5_fail(PP5_E_CONFIG, "unknown transfer function '%s' (known: %s)", name,
                    classify_preset_names());
}

const char *classify_preset_names(void)
{
    return "ct-skin, ct-skin-ramp, ct-bone, mr, shepp-logan, marschner-lobb, sphere-shell";
}

/* Index of the last point whose value is <= v (0 when v is below them all),
 * by bisection over the increasing values. */
#define LAST_AT_OR_BELOW(points, n, v, out)                                   \
    do {                                                                      \
        int lo_ = 0, hi_ = (n) - 1;                                           \
        while (lo_ < hi_) {                                                   \
            int mid_ = (lo_ + hi_ + 1) / 2;                                   \
            if ((points)[mid_].value <= (v))                                  \
                lo_ = mid_;                                                   \
            else                                                              \
                hi_ = mid_ - 1;                                               \
        }                                                                     \
        (out) = lo_;                                                          \
    } while (0)

/* The weight of point k + 1 at v between points k and k + 1 (0 outside). */
static float between(float a, float b, float v)
{
    if (!(v > a))
        return 0.0f;
    if (!(v < b))
        return 1.0f;
    return (v - a) / (b - a);
}

static float classify_table(const classify_tf_t *tf, float value, float rgb[3])
{
    int k;
    LAST_AT_OR_BELOW(tf->alpha, tf->n_alpha, value, k);
    float alpha = tf->alpha[k].opacity;
    if (k + 1 < tf->n_alpha) {
        float w = between(tf->alpha[k].value, tf->alpha[k + 1].value, value);
        alpha += w * (tf->alpha[k + 1].opacity - alpha);
    }
    if (tf->n_rgb == 0) {
        rgb[0] = rgb[1] = rgb[2] = 1.0f;
    } else {
        LAST_AT_OR_BELOW(tf->rgb, tf->n_rgb, value, k);
        float w = k + 1 < tf->n_rgb ? between(tf->rgb[k].value, tf->rgb[k + 1].value, value) : 0;
        for (int ch = 0; ch < 3; ch++) {
            float a = tf->rgb[k].rgb[ch];
            rgb[ch] = k + 1 < tf->n_rgb ? a + w * (tf->rgb[k + 1].rgb[ch] - a) : a;
        }
    }
    if (alpha < tf->min_opacity)
        alpha = 0.0f;
    return alpha;
}

float classify_voxel(const classify_tf_t *tf, float value, float grad_mag, float rgb[3])
{
    if (tf->n_alpha > 0)
        return classify_table(tf, value, rgb);
    float transparency = 1.0f, wsum = 0.0f;
    float c[3] = {0.0f, 0.0f, 0.0f};
    for (int i = 0; i < tf->count; i++) {
        const classify_contour_t *k = &tf->contour[i];
        float d = fabsf(k->value - value);
        float a = 0.0f;
        if (k->ramp_width > 0.0f) {
            float f = (value - (k->value - 0.5f * k->ramp_width)) / k->ramp_width;
            a = k->opacity * (f <= 0.0f ? 0.0f : (f >= 1.0f ? 1.0f : f));
        } else if (grad_mag > 0.0f) {
            float f = 1.0f - d / (k->width_vox * grad_mag);
            if (f > 0.0f)
                a = k->opacity * f;
        } else if (d == 0.0f) {
            a = k->opacity;
        }
        if (a > 0.0f) {
            transparency *= 1.0f - a;
            wsum += a;
            for (int ch = 0; ch < 3; ch++)
                c[ch] += a * k->rgb[ch];
        }
    }
    float alpha = 1.0f - transparency;
    if (alpha < tf->min_opacity)
        alpha = 0.0f;
    for (int ch = 0; ch < 3; ch++)
        rgb[ch] = alpha > 0.0f ? c[ch] / wsum : 0.0f;
    return alpha;
}
