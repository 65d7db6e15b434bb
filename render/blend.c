/* blend.c: blend settings (compositing, MIP, DEMIP, MIDA): defaults,
 * validation, command-line options and the report (see blend.h). */
#include "blend.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"

void blend_settings_defaults(blend_settings_t *b)
{
    memset(b, 0, sizeof *b);
    b->mode = BLEND_COMPOSITE;
    b->tolerance = 0.1f;
    b->depth_weight = 0.15f;      /* seed 002 §3.2: "around 0.15" */
    b->sphere_weight = 0.3f;      /* no paper value: see blend.h */
    b->sphere_map = SPHERE_RED_BLUE;
    b->depth = DEMIP_DEPTH_EXACT;
    b->reading = DEMIP_READING_A;
    b->pyramid = SCALAR_PYRAMID_MAX;
    b->legend = true;
}

void blend_settings_fill(blend_settings_t *b, float window_centre, float window_width,
                         const float view_rot_deg[3])
{
    if (!(b->window_width > 0.0f) && window_width > 0.0f) {
        b->window_centre = window_centre;
        b->window_width = window_width;
    }
    if (!b->sphere_rot_given)
        for (int a = 0; a < 3; a++)
            b->sphere_rot_deg[a] = view_rot_deg[a];
}

static bool in_unit(float x)
{
    return x >= 0.0f && x <= 1.0f;
}

pp5_status_t blend_settings_check(const blend_settings_t *b)
{
    if (b->mode < BLEND_COMPOSITE || b->mode > BLEND_MIDA)
        return pp5_fail(PP5_E_RANGE, "blend: unknown mode %d", (int)b->mode);
    if (!isfinite(b->window_centre) || !(b->window_width >= 0.0f) || !isfinite(b->window_width))
        return pp5_fail(PP5_E_RANGE, "blend: window centre must be finite and width >= 0");
    if (!in_unit(b->tolerance) || !in_unit(b->depth_weight) || !in_unit(b->sphere_weight))
        return pp5_fail(PP5_E_RANGE, "blend: tolerance, depth weight and sphere weight must "
                        "lie in [0, 1]");
    for (int a = 0; a < 3; a++)
        if (!(fabsf(b->sphere_rot_deg[a]) <= 3600.0f))
            return pp5_fail(PP5_E_RANGE, "blend: sphere rotation must be finite, |angle| <= 3600");
    if (b->sphere_map < 0 || b->sphere_map >= SPHERE_MAP_COUNT || b->depth < 0 ||
        b->depth > DEMIP_DEPTH_ENTRY_PLUS_LENGTH || b->reading < 0 ||
        b->reading > DEMIP_READING_B || b->pyramid < 0 || b->pyramid > SCALAR_PYRAMID_BOX)
        return pp5_fail(PP5_E_RANGE, "blend: unknown sphere map, depth, reading or pyramid");
    return PP5_OK;
}

const char *blend_mode_name(blend_mode_t m)
{
    static const char *names[] = {"composite", "mip", "demip", "mida"};
    return m >= BLEND_COMPOSITE && m <= BLEND_MIDA ? names[m] : "?";
}

const char *demip_depth_name(demip_depth_t d)
{
    return d == DEMIP_DEPTH_ENTRY_PLUS_LENGTH ? "entry-plus-length" : "exact";
}

const char *scalar_pyramid_kind_name(scalar_pyramid_kind_t k)
{
    return k == SCALAR_PYRAMID_BOX ? "box" : "max";
}

/* ---- options ---- */

static pp5_status_t opt_unit(const char *opt, const char *value, float *out)
{
    double d;
    pp5_status_t st = cliopt_double(opt, value, 0.0, 1.0, &d);
    if (st == PP5_OK)
        *out = (float)d;
    return st;
}

/* "A,B,C" as three finite numbers. */
static pp5_status_t opt_triple(const char *opt, const char *value, double out[3])
{
    const char *s = value;
    for (int i = 0; i < 3; i++) {
        char *end;
        errno = 0;
        out[i] = strtod(s, &end);
        if (end == s || errno == ERANGE || !isfinite(out[i]) || *end != (i < 2 ? ',' : '\0'))
            return pp5_fail(PP5_E_CONFIG, "%s: expected three finite numbers X,Y,Z, got '%s'",
                            opt, value);
        s = end + 1;
    }
    return PP5_OK;
}

/* `value` must be one of the `n` names; its index goes to *out. */
static pp5_status_t opt_choice(const char *opt, const char *value, const char *const *names,
                               int n, int *out)
{
    for (int i = 0; i < n; i++)
        if (strcmp(value, names[i]) == 0) {
            *out = i;
            return PP5_OK;
        }
    char known[128] = "";
    for (int i = 0; i < n; i++) {
        strncat(known, names[i], sizeof known - strlen(known) - 1);
        if (i + 1 < n)
            strncat(known, i + 2 < n ? ", " : " or ", sizeof known - strlen(known) - 1);
    }
    return pp5_fail(PP5_E_CONFIG, "%s: expected %s, got '%s'", opt, known, value);
}

static pp5_status_t opt_window(const char *value, blend_settings_t *b)
{
    double c, w;
    pp5_status_t st = cliopt_pair("--window", value, &c, &w);
    if (st != PP5_OK)
        return st;
    if (!(w > 0.0) || !(fabs(c) < 1e30) || !(w < 1e30))
        return pp5_fail(PP5_E_CONFIG, "--window: expected CENTRE,WIDTH with width > 0, got '%s'",
                        value);
    b->window_centre = (float)c;
    b->window_width = (float)w;
    return PP5_OK;
}

static pp5_status_t opt_rotate(const char *value, blend_settings_t *b)
{
    double r[3];
    pp5_status_t st = opt_triple("--sphere-rotate", value, r);
    for (int a = 0; st == PP5_OK && a < 3; a++)
        if (fabs(r[a]) > 3600.0)
            st = pp5_fail(PP5_E_CONFIG, "--sphere-rotate: angles must lie in -3600..3600 "
                          "degrees, got '%s'", value);
    for (int a = 0; st == PP5_OK && a < 3; a++)
        b->sphere_rot_deg[a] = (float)r[a];
    if (st == PP5_OK)
        b->sphere_rot_given = true;
    return st;
}

pp5_status_t blend_option(const char *name, const char *value, blend_settings_t *b)
{
    static const char *const modes[] = {"composite", "mip", "demip", "mida"};
    static const char *const depths[] = {"exact", "entry-plus-length"};
    static const char *const readings[] = {"A", "B"};
    static const char *const pyramids[] = {"max", "box"};
    char opt[48];
    snprintf(opt, sizeof opt, "--%s", name ? name : "");
    if (!name || !value)
        return pp5_fail(PP5_E_CONFIG, "%s: needs a value", opt);
    int i = 0;
    pp5_status_t st;
    if (strcmp(name, "blend") == 0) {
        st = opt_choice(opt, value, modes, 4, &i);
        b->mode = (blend_mode_t)i;
    } else if (strcmp(name, "window") == 0) {
        st = opt_window(value, b);
    } else if (strcmp(name, "tolerance") == 0) {
        st = opt_unit(opt, value, &b->tolerance);
    } else if (strcmp(name, "depth-weight") == 0) {
        st = opt_unit(opt, value, &b->depth_weight);
    } else if (strcmp(name, "sphere-weight") == 0) {
        st = opt_unit(opt, value, &b->sphere_weight);
    } else if (strcmp(name, "sphere-map") == 0) {
        st = colour_sphere_map_parse(value, &b->sphere_map);
    } else if (strcmp(name, "sphere-rotate") == 0) {
        st = opt_rotate(value, b);
    } else if (strcmp(name, "depth") == 0) {
        st = opt_choice(opt, value, depths, 2, &i);
        b->depth = (demip_depth_t)i;
    } else if (strcmp(name, "demip-reading") == 0) {
        st = opt_choice(opt, value, readings, 2, &i);
        b->reading = (demip_reading_t)i;
    } else if (strcmp(name, "mip-pyramid") == 0) {
        st = opt_choice(opt, value, pyramids, 2, &i);
        b->pyramid = (scalar_pyramid_kind_t)i;
    } else {
        st = pp5_fail(PP5_E_CONFIG, "%s: not a blend option", opt);
    }
    return st;
}

const char *blend_help(void)
{
    return "Blend (what a ray does with its samples; each works --mode full or gaze):\n"
           "  --blend composite|mip|demip|mida   compositing (default), maximum intensity\n"
           "                        projection, depth-enhanced MIP (Diaz & Vazquez 2010) or\n"
           "                        MIDA (Bruckner & Groller 2009)\n"
           "  --window C,W          window/level: material 0 at C-W/2 rising to 1 at C+W/2\n"
           "                        (default: the dataset's, else the volume's value range)\n"
           "  --tolerance EPS       DEMIP ray 2 stops at material >= max - EPS (0.1)\n"
           "  --depth-weight DW     DEMIP eq. (1) depth weight (0.15, the paper's)\n"
           "  --depth exact|entry-plus-length   DEMIP depth (default exact)\n"
           "  --demip-reading A|B   eq. (1) everywhere (A, default) or only in front of an\n"
           "                        occluder (B)\n"
           "  --sphere-weight SW    colour sphere weight, eq. (2) (0.3; 0 = off)\n"
           "  --sphere-map NAME     red-blue (default), orange-blue, magenta-green,\n"
           "                        yellow-blue (the last three colour-blind safe)\n"
           "  --sphere-rotate X,Y,Z the sphere's orientation in object space, in the camera's\n"
           "                        angles: its front faces a camera with these angles\n"
           "                        (default: the dataset's default view)\n"
           "  --mip-pyramid max|box coarse rays read a max (default) or box-filtered pyramid\n"
           "  example: pp5 render --dataset cthead --blend demip --sphere-weight 0.3 \\\n"
           "             --mode gaze --out d.png\n";
}

void blend_report_json(json_writer_t *j, const blend_settings_t *b)
{
    json_kv_string(j, "blend", blend_mode_name(b->mode));
    if (b->mode == BLEND_COMPOSITE)
        return;
    json_kv_double(j, "window_centre", b->window_centre);
    json_kv_double(j, "window_width", b->window_width);
    json_kv_string(j, "mip_pyramid", scalar_pyramid_kind_name(b->pyramid));
    if (b->mode != BLEND_DEMIP)
        return;
    json_kv_double(j, "tolerance", b->tolerance);
    json_kv_double(j, "depth_weight", b->depth_weight);
    json_kv_string(j, "depth", demip_depth_name(b->depth));
    json_kv_string(j, "demip_reading", b->reading == DEMIP_READING_B ? "B" : "A");
    json_kv_double(j, "sphere_weight", b->sphere_weight);
    json_kv_string(j, "sphere_map", colour_sphere_map_info(b->sphere_map)->name);
    json_key(j, "sphere_rotate_deg");
    json_begin_array(j);
    for (int a = 0; a < 3; a++)
        json_double(j, b->sphere_rot_deg[a]);
    json_end_array(j);
}
