/* replay_machine.c: the emulated Pixel-Planes 5 running the gaze-directed
 * volume renderer, as the frame-cost source of `pp5 replay` (--cost machine).
 *
 * Every replayed frame is a real frame of the firmware on the machine model
 * (fw_session_frame): its emulated time, rays and ring bytes come from the
 * emulator, never from a constant.  The per-sequence setup (loading the
 * volume, the GPs' 3D mip-map build) runs once when the source opens.
 *
 * Geometry: the rendered image (default 210x210, the size of the paper's
 * Table I / figure 7 images) is shown magnified across the replay's display
 * (default the paper's monitor: 1280 px spanning 37 degrees, paper §6), so a
 * gaze point in display pixels maps to image pixels by one uniform scale
 * about the display centre, and the renderer's own display model (the same
 * 37 degrees across the image width) places the sweet spot. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cliopt.h"
#include "firmware/host/fw_session.h"
#include "firmware/host/replay_options.h"
#include "render/render_job.h"
#include "render/scene.h"
#include "render/volume.h"
#include "tracker/replay.h"

typedef struct {
    fw_session_t session;
    bool session_ok;
    volume_t volume;
    classify_tf_t tf;
    shade_params_t shade;
    render_settings_t settings;
    image8_t image;
    double display_cx, display_cy;   /* display centre, display pixels */
    double image_per_display_px;     /* image pixels per display pixel */
    unsigned frames;                 /* frames emulated so far */
    double emulated_s;               /* their summed emulated time */
} machine_cost_t;

typedef struct {
    char volume[64];      /* "phantom" (Shepp-Logan) or "mrbrain" */
    int width, height;
    char lighting[32];
    fw_options_t fw;      /* division=, split=, plan=, level_tables= */
    replay_machine_params_t mp;   /* preset= and machine parameters given as NAME=VALUE */
} machine_cost_opts_t;

/* One KEY=VALUE item of --cost machine:...: the source's own keys, the
 * firmware's settings, or any machine parameter. */
static pp5_status_t parse_item(void *ctx, const char *item)
{
    machine_cost_opts_t *o = ctx;
    const char *eq = strchr(item, '=');
    if (!eq)
        return pp5_fail(PP5_E_CONFIG, "--cost machine: expected KEY=VALUE, got '%s' "
                        "(keys: volume, size, preset, lighting, division, split, or a machine "
                        "parameter)", item);
    size_t klen = (size_t)(eq - item);
    const char *value = eq + 1;
    bool is_volume = klen == 6 && strncmp(item, "volume", 6) == 0;
    bool is_lighting = klen == 8 && strncmp(item, "lighting", 8) == 0;
    if (is_volume && (strcmp(value, "phantom") == 0 || strcmp(value, "mrbrain") == 0)) {
        snprintf(o->volume, sizeof o->volume, "%s", value);
        return PP5_OK;
    }
    if (klen == 4 && strncmp(item, "size", 4) == 0)
        return cliopt_size2("--cost machine: size", value, 16, 1280, &o->width, &o->height);
    if (klen == 6 && strncmp(item, "preset", 6) == 0) {
        snprintf(o->mp.preset, sizeof o->mp.preset, "%s", value);
        return PP5_OK;
    }
    if (is_lighting && (strcmp(value, "diffuse") == 0 || strcmp(value, "specular") == 0 ||
                        strcmp(value, "moving") == 0)) {
        snprintf(o->lighting, sizeof o->lighting, "%s", value);
        return PP5_OK;
    }
    /* set=PARAM=VALUE spells a machine parameter the way `pp5 machine --set`
     * takes it; a bare PARAM=VALUE means the same. */
    pp5_status_t st = replay_machine_params_unwrap("--cost machine", &item);
    if (st != PP5_OK)
        return st;
    bool taken = false;
    if (is_volume || is_lighting)
        return pp5_fail(PP5_E_CONFIG, "--cost machine: bad option %s (volume=phantom|mrbrain, "
                        "lighting=diffuse|specular|moving)", item);
    st = fw_options_set(&o->fw, item, &taken);
    if (st != PP5_OK || taken)
        return st;
    if (replay_machine_params_add(&o->mp, item))
        return PP5_OK;
    return pp5_fail(PP5_E_CONFIG, "--cost machine: bad option %s (volume=phantom|mrbrain, "
                    "size=WxH, preset=NAME, lighting=diffuse|specular|moving, division=NAME, "
                    "split=pp|gp, or a machine parameter NAME=VALUE)", item);
}

static pp5_status_t parse_options(const char *text, machine_cost_opts_t *o)
{
    memset(o, 0, sizeof *o);
    snprintf(o->volume, sizeof o->volume, "phantom");
    o->width = o->height = 210;
    replay_machine_params_init(&o->mp);
    snprintf(o->lighting, sizeof o->lighting, "diffuse");
    fw_options_default(&o->fw);
    return replay_options_each("--cost machine", text, parse_item, o);
}

/* The volume the paper projects for (§6: 128x128x109): the Shepp-Logan phantom
 * made at that size, or the MR subject (brainsmall 128x128x84) resampled to it. */
static pp5_status_t load_volume_now(const char *name, volume_t *v, classify_tf_t *tf,
                                    render_settings_t *settings)
{
    render_input_t in;
    render_input_default(&in);
    in.kind = strcmp(name, "mrbrain") == 0 ? RENDER_INPUT_DATASET : RENDER_INPUT_PHANTOM;
    in.name = strcmp(name, "mrbrain") == 0 ? "mrbrain" : "shepp-logan";
    scene_t sc;
    pp5_status_t st = render_input_load(&in, &sc, stderr);
    if (st != PP5_OK)
        return st;
    *tf = sc.tf;
    settings->view.rot_x_deg = sc.rot_x_deg;
    settings->view.rot_y_deg = sc.rot_y_deg;
    settings->view.rot_z_deg = sc.rot_z_deg;
    st = scene_paper_volume(&sc, v);
    scene_free(&sc);
    return st;
}

/* The last volume loaded, kept for the next source opened in this process:
 * a batch of replays (pp5 replay --batch) opens one source per replay, and
 * making and resampling the volume takes as long as a machine's setup.  It is
 * reused only for the same volume name (the inputs are fixed files or a
 * generated phantom); each source gets its own copy. */
static struct {
    pthread_mutex_t lock;
    char name[64];
    volume_t volume;
    classify_tf_t tf;
    float rot_deg[3];
    bool ok;
} volume_cache = {.lock = PTHREAD_MUTEX_INITIALIZER};

static pp5_status_t copy_volume(const volume_t *from, volume_t *to)
{
    pp5_status_t st = volume_alloc(to, from->nx, from->ny, from->nz);
    if (st != PP5_OK)
        return st;
    float *data = to->data;
    *to = *from;
    to->data = data;
    memcpy(to->data, from->data, (size_t)from->nx * from->ny * from->nz * sizeof *to->data);
    return PP5_OK;
}

static pp5_status_t load_volume(const machine_cost_opts_t *o, machine_cost_t *c)
{
    pthread_mutex_lock(&volume_cache.lock);
    pp5_status_t st = PP5_OK;
    if (!volume_cache.ok || strcmp(volume_cache.name, o->volume) != 0) {
        if (volume_cache.ok)
            volume_free(&volume_cache.volume);
        volume_cache.ok = false;
        render_settings_t rs;
        render_settings_defaults(&rs);
        st = load_volume_now(o->volume, &volume_cache.volume, &volume_cache.tf, &rs);
        if (st == PP5_OK) {
            snprintf(volume_cache.name, sizeof volume_cache.name, "%s", o->volume);
            volume_cache.rot_deg[0] = rs.view.rot_x_deg;
            volume_cache.rot_deg[1] = rs.view.rot_y_deg;
            volume_cache.rot_deg[2] = rs.view.rot_z_deg;
            volume_cache.ok = true;
        }
    }
    if (st == PP5_OK) {
        c->tf = volume_cache.tf;
        c->settings.view.rot_x_deg = volume_cache.rot_deg[0];
        c->settings.view.rot_y_deg = volume_cache.rot_deg[1];
        c->settings.view.rot_z_deg = volume_cache.rot_deg[2];
        st = copy_volume(&volume_cache.volume, &c->volume);
    }
    pthread_mutex_unlock(&volume_cache.lock);
    return st;
}

static void machine_cost_close(void *ctx)
{
    machine_cost_t *c = ctx;
    if (!c)
        return;
    if (c->session_ok)
        fw_session_free(&c->session);
    volume_free(&c->volume);
    image8_free(&c->image);
    free(c);
}

static pp5_status_t machine_cost_open(const char *options, const gaze_geometry_t *display,
                                      void **ctx)
{
    machine_cost_opts_t o;
    pp5_status_t st = parse_options(options, &o);
    if (st != PP5_OK)
        return st;
    if (display->width_px <= 0 || display->height_px <= 0)
        return pp5_fail(PP5_E_CONFIG, "--cost machine: the display has no size in pixels");
    machine_cost_t *c = calloc(1, sizeof *c);
    if (!c)
        return pp5_fail(PP5_E_NOMEM, "--cost machine: out of memory");
    render_settings_defaults(&c->settings);
    shade_defaults(&c->shade);
    if (strcmp(o.lighting, "specular") == 0)
        c->shade.lighting = SHADE_SPECULAR_FIXED_LIGHT;
    else if (strcmp(o.lighting, "moving") == 0)
        c->shade.lighting = SHADE_MOVING_OBJECT;
    c->settings.width = o.width;
    c->settings.height = o.height;
    c->settings.mode = RENDER_MODE_GAZE;
    c->settings.threads = 1;
    c->display_cx = 0.5 * display->width_px;
    c->display_cy = 0.5 * display->height_px;
    c->image_per_display_px = (double)o.width / display->width_px;
    st = load_volume(&o, c);
    pp5_params_t params;
    if (st == PP5_OK)
        st = replay_machine_params_build(&o.mp, &params);
    if (st == PP5_OK) {
        fprintf(stderr, "machine: setting up the gaze-directed renderer (%s 128x128x109, %dx%d "
                "image, preset %s, division %s)...\n", o.volume, o.width, o.height, o.mp.preset,
                fw_division_name(o.fw.division));
        render_job_t job = {.volume = &c->volume, .volume_name = c->volume.source, .tf = c->tf,
                            .shade = c->shade, .settings = c->settings, .frames = 1};
        st = fw_session_init(&c->session, &job, &params, &o.fw);
        c->session_ok = true;
    }
    if (st != PP5_OK) {
        machine_cost_close(c);
        return st;
    }
    *ctx = c;
    return PP5_OK;
}

static pp5_status_t machine_cost_frame(void *ctx, double gaze_x, double gaze_y,
                                       replay_frame_cost_t *out)
{
    machine_cost_t *c = ctx;
    double ix = (gaze_x - c->display_cx) * c->image_per_display_px + 0.5 * c->settings.width;
    double iy = (gaze_y - c->display_cy) * c->image_per_display_px + 0.5 * c->settings.height;
    fw_frame_result_t r;
    image8_free(&c->image);
    pp5_status_t st = fw_session_frame(&c->session, ix, iy, out->want_image ? &c->image : NULL,
                                       &r);
    if (st != PP5_OK)
        return st;
    out->frame_s = r.frame_time_s;
    out->rays = r.rays;
    out->ring_bytes = r.ring_bytes_total;
    out->image = out->want_image ? &c->image : NULL;
    /* Long traces take minutes of host time: say how far we are (on a
     * terminal only, so logs and tests stay clean). */
    c->frames++;
    c->emulated_s += r.frame_time_s;
    if (c->frames % 25 == 0 && isatty(STDERR_FILENO))
        fprintf(stderr, "machine: %u frames emulated (%.1f s of trace time)\r", c->frames,
                c->emulated_s);
    return PP5_OK;
}

static const replay_cost_source_t machine_cost_source = {
    .name = "machine",
    .summary = "the emulated Pixel-Planes 5 running the gaze-directed renderer (options: "
               "volume=phantom|mrbrain,size=WxH,preset=NAME,lighting=diffuse|specular|moving,"
               "division=NAME,split=pp|gp, PARAM=VALUE or set=PARAM=VALUE as pp5 machine --set, "
               "repeatable)",
    .open = machine_cost_open,
    .cost = machine_cost_frame,
    .close = machine_cost_close,
};

__attribute__((constructor)) static void machine_cost_register(void)
{
    replay_register_cost_source(&machine_cost_source);
}
