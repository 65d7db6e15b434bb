/* cmd_render.c: `pp5 render`: the options of one frame (or a sequence) of the gaze-directed volume renderer, natively or on the emulated machine. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cliopt.h"
#include "outfile.h"
#include "plot.h"
#include "render/classify_io.h"
#include "registry.h"
#include "render_cmd.h"

static void render_usage(void)
{
    printf("usage: pp5 render [options]\n\n"
           "Renders one frame with the gaze-directed volume renderer (Levoy & Whitaker\n"
           "1990): a 3D mip map with octree skipping, rays cast into a partially populated\n"
           "2D mip map whose level follows retinal acuity.  Natively by default; with\n"
           "--machine on the emulated Pixel-Planes 5, with its frame time and ring traffic.\n\n"
           "Input (one of):\n"
           "  --phantom NAME        procedural volume: %s (default shepp-logan)\n"
           "  --dataset NAME        mrbrain | cthead from the shared data (../shared/data\n"
           "                        or $PP5_SHARED_DATA)\n"
           "  --volume FILE         .nrrd/.nhdr, .nii[.gz], .den, CThead.1 slices, or raw\n"
           "    --raw-dims NXxNYxNZ --raw-type u8|u16|i16|f32|... --big-endian\n"
           "    --spacing SX,SY,SZ --header-bytes N   (raw; a name like\n"
           "                        x_256x256x113_u16be.raw.gz is understood)\n"
           "Classification and shading:\n"
           "  --tf PRESET|FILE      a preset (%s)\n"
           "                        or a file: pp5's text format or a ParaView preset (.json);\n"
           "                        see man pp5.  Default: the data set's preset;\n"
           "                        for a --volume file, one chosen from its histogram\n"
           "  --tf-out FILE         write the transfer function used, in the text format\n"
           "  --lighting CASE       diffuse (default) | specular | moving (paper §5)\n"
           "  --specular KS         specular coefficient (with specular/moving)\n"
           "View:\n"
           "  --size WxH            image size (default 512x512)\n"
           "  --rot-x DEG --rot-y DEG --rot-z DEG   camera angles (see raycast.h)\n"
           "  --zoom Z              1 = largest volume side spans the image (default)\n"
           "  --projection parallel|perspective   (default parallel)\n"
           "  --eye-distance R      perspective eye distance in bounding radii (3)\n"
           "  --step S              samples per voxel at full resolution = 1/S (1)\n"
           "  --early-termination A stop rays at opacity A (0.95)\n"
           "  --no-octree           disable empty-space skipping\n"
           "  --voxel-format F      3D mip map storage: f32 (default, exact) | u16 | u8\n"
           "                        (fixed point, bricked; u8: 4.6 bytes/voxel diffuse)\n"
           "Gaze:\n"
           "  --mode full|gaze      (default gaze)\n"
           "  --gaze X,Y            fixated pixel (default image centre)\n"
           "  --monitor-diag IN --view-distance IN --subtense DEG\n"
           "                        display geometry (19, 20, 37: paper §6)\n"
           "  --sweet-spot-deg D    full resolution inside this circle diameter (12)\n"
           "  --periphery-deg D     periphery resolution outside this diameter (20)\n"
           "  --periphery-pixels N  pixels per ray in the periphery (16 = paper)\n"
           "  --sigma-deg S         Gaussian falloff width (default: from the paper's\n"
           "                        5-inch level-0 span, see gaze2d.h)\n"
           "  --progressive N       N frames of unchanged view, keeping the 2D mip map\n"
           "Polygons (instead of a volume):\n"
           "  --mesh FILE           one mesh (.obj/.off/.ply[.gz], or gen:sphere|torus|...)\n"
           "  --scene FILE          a scene file (render/mesh/mesh_scene.h), or the built-in\n"
           "                        gen:spheres100k (100 spheres and tori, 100,000 triangles)\n"
           "  --shading flat|gouraud|phong   (default gouraud)\n"
           "                        --mode gaze: levels of detail by eccentricity and the\n"
           "                        variable-resolution Z-buffer (paper §7); --compare adds\n"
           "                        full, LOD-only and VRZ-only frames and the savings table\n"
           "                        (one host thread; --out and --report as for volumes)\n"
           "                        --machine: the frame on the machine's polygon pipeline\n"
           "                        (gaze-directed: the levels of detail into its VRZ), its\n"
           "                        frame report and the agreement with the native frame\n"
           "Outputs:\n"
           "  --out FILE.png        the image\n"
           "  --report FILE.json    rays, samples, timings, settings (and quality)\n"
           "  --compare             also render full resolution: PSNR and acuity-weighted\n"
           "                        error in the report and on stdout\n"
           "  --mip-levels-out P    the populated 2D mip-map levels as P<level>.png (fig. 6)\n"
           "  --fig5 FILE           sweet-spot structure plot (fig. 5): .png, .svg or .pdf\n"
           "  --threads N           host threads (0 = all; output is identical for any N)\n"
           "Machine (emulated Pixel-Planes 5, firmware/):\n"
           "  --machine             render on the emulated machine (GPs + renderers + ring);\n"
           "                        prints the emulated frame time and compares the image\n"
           "                        with the native renderer on the same inputs\n"
           "  --division NAME       work division: image-bands (default), resident,\n"
           "                        object-slabs (firmware/ARCHITECTURE.md)\n"
           "  --split pp|gp         where viewpoint-dependent shading runs (pp: the paper)\n"
           "  --frames N            N frames with the gaze moving (setup reused)\n"
           "  --timeline FILE.json  Chrome trace of the emulated frame (ui.perfetto.dev)\n"
           "%s"
           "                        (--set also takes the firmware's division=, split=,\n"
           "                        plan=rays|samples and level_tables=0|1)\n\n"
           "Examples:\n"
           "  pp5 render --phantom shepp-logan --mode gaze --gaze 300,200 --out g.png\n"
           "  pp5 render --dataset cthead --voxel-format u8 --mode full --out u8.png\n"
           "  pp5 render --volume skull_64x64x64_f32le.raw --out s.png --tf-out skull.tf\n"
           "  pp5 render --machine --division resident --frames 4 --report r.json --out m.png\n"
           "  pp5 render --machine --phantom shepp-logan --blend demip --sphere-weight 0.3 \\\n"
           "      --division resident --out d.png\n"
           "  (--machine casts every --blend, in image-bands or resident; a blend's rays are cast\n"
           "  whole, so image-bands may not fit a GP's memory at 512x512 where resident does)\n"
           "  pp5 render --scene gen:spheres100k --shading phong --mode gaze --gaze 200,300 \\\n"
           "      --compare --size 640x480 --out s.png --report s.json\n",
           phantom_names(), classify_preset_names(), PP5_PARAMS_CLI_HELP);
}

enum {
    OPT_PHANTOM = 256, OPT_DATASET, OPT_VOLUME, OPT_RAW_DIMS, OPT_RAW_TYPE, OPT_BIG_ENDIAN,
    OPT_SPACING, OPT_HEADER_BYTES, OPT_TF, OPT_LIGHTING, OPT_SPECULAR, OPT_SIZE, OPT_ROTX,
    OPT_ROTY, OPT_ROTZ, OPT_ZOOM, OPT_PROJECTION, OPT_EYE, OPT_STEP, OPT_EARLY, OPT_NO_OCTREE,
    OPT_MODE, OPT_GAZE, OPT_MONITOR, OPT_DISTANCE, OPT_SUBTENSE, OPT_PROGRESSIVE, OPT_OUT,
    OPT_REPORT, OPT_COMPARE, OPT_LEVELS_OUT, OPT_FIG5, OPT_THREADS, OPT_HELP, OPT_SWEET,
    OPT_PERIPHERY, OPT_PERIPHERY_PX, OPT_SIGMA, OPT_MACHINE, OPT_DIVISION, OPT_SPLIT, OPT_FRAMES,
    OPT_TIMELINE, OPT_PRESET, OPT_CONFIG, OPT_SET, OPT_VOXEL_FORMAT, OPT_TF_OUT, OPT_MESH,
    OPT_SCENE, OPT_SHADING,
    OPT_BLEND   /* OPT_BLEND + i: blend_options[i] */
};

/* render/blend.h parses all of these (blend_option), by name. */
static const char *const blend_options[] = {
    "blend", "window", "tolerance", "depth-weight", "depth", "demip-reading", "sphere-weight",
    "sphere-map", "sphere-rotate", "mip-pyramid",
};
#define N_BLEND_OPTIONS ((int)(sizeof blend_options / sizeof blend_options[0]))

static const struct option longopts[] = {
    {"phantom", required_argument, NULL, OPT_PHANTOM},
    {"dataset", required_argument, NULL, OPT_DATASET},
    {"volume", required_argument, NULL, OPT_VOLUME},
    {"raw-dims", required_argument, NULL, OPT_RAW_DIMS},
    {"raw-type", required_argument, NULL, OPT_RAW_TYPE},
    {"big-endian", no_argument, NULL, OPT_BIG_ENDIAN},
    {"spacing", required_argument, NULL, OPT_SPACING},
    {"header-bytes", required_argument, NULL, OPT_HEADER_BYTES},
    {"tf", required_argument, NULL, OPT_TF},
    {"tf-out", required_argument, NULL, OPT_TF_OUT},
    {"lighting", required_argument, NULL, OPT_LIGHTING},
    {"specular", required_argument, NULL, OPT_SPECULAR},
    {"size", required_argument, NULL, OPT_SIZE},
    {"rot-x", required_argument, NULL, OPT_ROTX},
    {"rot-y", required_argument, NULL, OPT_ROTY},
    {"rot-z", required_argument, NULL, OPT_ROTZ},
    {"zoom", required_argument, NULL, OPT_ZOOM},
    {"projection", required_argument, NULL, OPT_PROJECTION},
    {"eye-distance", required_argument, NULL, OPT_EYE},
    {"step", required_argument, NULL, OPT_STEP},
    {"early-termination", required_argument, NULL, OPT_EARLY},
    {"no-octree", no_argument, NULL, OPT_NO_OCTREE},
    {"voxel-format", required_argument, NULL, OPT_VOXEL_FORMAT},
    {"mode", required_argument, NULL, OPT_MODE},
    {"gaze", required_argument, NULL, OPT_GAZE},
    {"monitor-diag", required_argument, NULL, OPT_MONITOR},
    {"view-distance", required_argument, NULL, OPT_DISTANCE},
    {"subtense", required_argument, NULL, OPT_SUBTENSE},
    {"progressive", required_argument, NULL, OPT_PROGRESSIVE},
    {"sweet-spot-deg", required_argument, NULL, OPT_SWEET},
    {"periphery-deg", required_argument, NULL, OPT_PERIPHERY},
    {"periphery-pixels", required_argument, NULL, OPT_PERIPHERY_PX},
    {"sigma-deg", required_argument, NULL, OPT_SIGMA},
    {"out", required_argument, NULL, OPT_OUT},
    {"report", required_argument, NULL, OPT_REPORT},
    {"compare", no_argument, NULL, OPT_COMPARE},
    {"mip-levels-out", required_argument, NULL, OPT_LEVELS_OUT},
    {"fig5", required_argument, NULL, OPT_FIG5},
    {"threads", required_argument, NULL, OPT_THREADS},
    {"machine", no_argument, NULL, OPT_MACHINE},
    {"division", required_argument, NULL, OPT_DIVISION},
    {"split", required_argument, NULL, OPT_SPLIT},
    {"frames", required_argument, NULL, OPT_FRAMES},
    {"timeline", required_argument, NULL, OPT_TIMELINE},
    {"preset", required_argument, NULL, OPT_PRESET},
    {"config", required_argument, NULL, OPT_CONFIG},
    {"set", required_argument, NULL, OPT_SET},
    {"blend", required_argument, NULL, OPT_BLEND + 0},
    {"window", required_argument, NULL, OPT_BLEND + 1},
    {"tolerance", required_argument, NULL, OPT_BLEND + 2},
    {"depth-weight", required_argument, NULL, OPT_BLEND + 3},
    {"depth", required_argument, NULL, OPT_BLEND + 4},
    {"demip-reading", required_argument, NULL, OPT_BLEND + 5},
    {"sphere-weight", required_argument, NULL, OPT_BLEND + 6},
    {"sphere-map", required_argument, NULL, OPT_BLEND + 7},
    {"sphere-rotate", required_argument, NULL, OPT_BLEND + 8},
    {"mip-pyramid", required_argument, NULL, OPT_BLEND + 9},
    {"mesh", required_argument, NULL, OPT_MESH},
    {"scene", required_argument, NULL, OPT_SCENE},
    {"shading", required_argument, NULL, OPT_SHADING},
    {"help", no_argument, NULL, OPT_HELP},
    {NULL, 0, NULL, 0},
};

/* An option not of this group: the caller tries the next group. */
#define NOT_MINE ((pp5_status_t)-1000)

static pp5_status_t parse_dims3(const char *opt, const char *text, volume_raw_spec_t *spec)
{
    char extra;
    int a, b, c;
    if (sscanf(text, "%dx%dx%d%c", &a, &b, &c, &extra) != 3 || a < 1 || b < 1 || c < 1 ||
        a > VOLUME_MAX_SIDE || b > VOLUME_MAX_SIDE || c > VOLUME_MAX_SIDE)
        return pp5_fail(PP5_E_CONFIG, "%s: expected NXxNYxNZ with sides 1..%d, got '%s'", opt,
                        VOLUME_MAX_SIDE, text);
    spec->nx = a;
    spec->ny = b;
    spec->nz = c;
    return PP5_OK;
}

static pp5_status_t parse_spacing(const char *opt, const char *text, double sp[3])
{
    char extra;
    if (sscanf(text, "%lf,%lf,%lf%c", &sp[0], &sp[1], &sp[2], &extra) != 3 ||
        !(sp[0] > 0 && sp[1] > 0 && sp[2] > 0) || !isfinite(sp[0] + sp[1] + sp[2]))
        return pp5_fail(PP5_E_CONFIG, "%s: expected three positive numbers SX,SY,SZ, got '%s'",
                        opt, text);
    return PP5_OK;
}

/* Picks names[i] == text; an error lists the choices. */
static pp5_status_t one_of(const char *opt, const char *text, const char *const *names, int n,
                           int *out)
{
    for (int i = 0; i < n; i++)
        if (strcmp(text, names[i]) == 0) {
            *out = i;
            return PP5_OK;
        }
    return pp5_fail(PP5_E_CONFIG, "%s: expected %s%s%s, got '%s'", opt, names[0],
                    n > 2 ? ", " : " or ", n > 2 ? "..." : names[1], text);
}

static pp5_status_t parse_input(render_cmd_t *c, int opt, const char *a)
{
    render_input_t *in = &c->input;
    long l;
    pp5_status_t st = PP5_OK;
    switch (opt) {
    case OPT_PHANTOM: in->kind = RENDER_INPUT_PHANTOM; in->name = a; break;
    case OPT_DATASET: in->kind = RENDER_INPUT_DATASET; in->name = a; break;
    case OPT_VOLUME: in->kind = RENDER_INPUT_FILE; in->name = a; break;
    case OPT_RAW_DIMS: st = parse_dims3("--raw-dims", a, &in->raw); in->have_raw = true; break;
    case OPT_RAW_TYPE: st = voxel_type_parse(a, &in->raw.type); in->have_raw = true; break;
    case OPT_BIG_ENDIAN: in->raw.big_endian = true; break;
    case OPT_SPACING: st = parse_spacing("--spacing", a, in->raw.spacing); in->have_spacing = true;
        break;
    case OPT_HEADER_BYTES:
        st = cliopt_long("--header-bytes", a, 0, 1L << 40, &l);
        in->raw.header_bytes = (uint64_t)l;
        break;
    default: return NOT_MINE;
    }
    return st;
}

static pp5_status_t parse_shading(render_cmd_t *c, int opt, const char *a)
{
    static const char *const lightings[] = {"diffuse", "specular", "moving"};
    static const shade_case_t cases[] = {SHADE_DIFFUSE_FIXED_LIGHT, SHADE_SPECULAR_FIXED_LIGHT,
                                         SHADE_MOVING_OBJECT};
    render_choices_t *ch = &c->choices;
    double d;
    int i = 0;
    pp5_status_t st = PP5_OK;
    switch (opt) {
    case OPT_TF: st = render_choices_set_tf(ch, a); break;
    case OPT_TF_OUT: c->tf_out = a; break;
    case OPT_LIGHTING:
        if ((st = one_of("--lighting", a, lightings, 3, &i)) == PP5_OK)
            ch->shade.lighting = cases[i];
        break;
    case OPT_SPECULAR: st = cliopt_double("--specular", a, 0.0, 10.0, &d);
        ch->shade.specular = (float)d; break;
    default: return NOT_MINE;
    }
    return st;
}

static pp5_status_t parse_view(render_cmd_t *c, int opt, const char *a)
{
    static const char *const projections[] = {"parallel", "perspective"};
    render_settings_t *s = &c->choices.settings;
    view_params_t *v = &s->view;
    double d;
    int i = 0;
    pp5_status_t st = PP5_OK;
    switch (opt) {
    case OPT_SIZE: st = cliopt_size2("--size", a, 1, 8192, &s->width, &s->height); break;
    case OPT_ROTX: st = cliopt_double("--rot-x", a, -3600, 3600, &d); v->rot_x_deg = (float)d;
        c->choices.have_rot = true; break;
    case OPT_ROTY: st = cliopt_double("--rot-y", a, -3600, 3600, &d); v->rot_y_deg = (float)d;
        c->choices.have_rot = true; break;
    case OPT_ROTZ: st = cliopt_double("--rot-z", a, -3600, 3600, &d); v->rot_z_deg = (float)d;
        c->choices.have_rot = true; break;
    case OPT_ZOOM: st = cliopt_double("--zoom", a, 0.01, 100, &d); v->zoom = (float)d; break;
    case OPT_PROJECTION:
        if ((st = one_of("--projection", a, projections, 2, &i)) == PP5_OK)
            v->projection = i == 0 ? PROJECTION_PARALLEL : PROJECTION_PERSPECTIVE;
        break;
    case OPT_EYE: st = cliopt_double("--eye-distance", a, 1.05, 1000, &d);
        v->eye_distance = (float)d; break;
    case OPT_STEP: st = cliopt_double("--step", a, 0.05, 64, &d); v->sample_step = (float)d; break;
    case OPT_EARLY: st = cliopt_double("--early-termination", a, 0.01, 1, &d);
        v->early_termination = (float)d; break;
    case OPT_NO_OCTREE: v->use_octree = false; break;
    case OPT_VOXEL_FORMAT:
        if (!mip3d_format_parse(a, &s->voxel_format))
            st = pp5_fail(PP5_E_CONFIG, "--voxel-format: '%s' is not one of f32, u16, u8", a);
        break;
    case OPT_THREADS: {
        long l;
        st = cliopt_long("--threads", a, 0, 64, &l);
        s->threads = (int)l;
        break;
    }
    default: return NOT_MINE;
    }
    return st;
}

static pp5_status_t parse_gaze(render_cmd_t *c, int opt, const char *a)
{
    static const char *const modes[] = {"full", "gaze"};
    render_settings_t *s = &c->choices.settings;
    gaze_display_t *g = &s->display;
    double d, x, y;
    long l;
    int i = 0;
    pp5_status_t st = PP5_OK;
    switch (opt) {
    case OPT_MODE:
        if ((st = one_of("--mode", a, modes, 2, &i)) == PP5_OK)
            s->mode = i == 0 ? RENDER_MODE_FULL : RENDER_MODE_GAZE;
        break;
    case OPT_GAZE:
        st = cliopt_pair("--gaze", a, &x, &y);
        s->gaze_x = x;
        s->gaze_y = y;
        c->choices.have_gaze = true;
        break;
    case OPT_MONITOR: st = cliopt_double("--monitor-diag", a, 1, 1000, &g->monitor_diag_in); break;
    case OPT_DISTANCE: st = cliopt_double("--view-distance", a, 1, 10000, &g->view_distance_in); break;
    case OPT_SUBTENSE: st = cliopt_double("--subtense", a, 0, 160, &g->image_subtense_deg); break;
    case OPT_SWEET: st = cliopt_double("--sweet-spot-deg", a, 0.1, 160, &g->full_res_diameter_deg);
        break;
    case OPT_PERIPHERY: st = cliopt_double("--periphery-deg", a, 0.1, 160,
                                           &g->periphery_diameter_deg); break;
    case OPT_PERIPHERY_PX:
        st = cliopt_double("--periphery-pixels", a, 4, 65536, &d);
        g->periphery_rays_per_px = 1.0 / d;
        break;
    case OPT_SIGMA: st = cliopt_double("--sigma-deg", a, 0.01, 90, &g->sigma_deg); break;
    case OPT_PROGRESSIVE: st = cliopt_long("--progressive", a, 1, 64, &l);
        c->choices.progressive_frames = (int)l; break;
    default: return NOT_MINE;
    }
    return st;
}

static pp5_status_t parse_output(render_cmd_t *c, int opt, const char *a)
{
    switch (opt) {
    case OPT_OUT: c->out_png = a; break;
    case OPT_REPORT: c->report_json = a; break;
    case OPT_COMPARE: c->compare = true; break;
    case OPT_LEVELS_OUT: c->levels_prefix = a; break;
    case OPT_FIG5: {
        plot_format_t fmt;
        c->fig5_png = a;
        return plot_format_from_name(a, &fmt);   /* refused before any rendering */
    }
    default: return NOT_MINE;
    }
    return PP5_OK;
}

static pp5_status_t parse_machine(render_cmd_t *c, int opt, const char *a)
{
    long l;
    bool taken = false;
    pp5_status_t st = PP5_OK;
    char kv[96];
    switch (opt) {
    case OPT_MACHINE: c->machine = true; break;
    case OPT_DIVISION:
    case OPT_SPLIT:
        snprintf(kv, sizeof kv, "%s=%s", opt == OPT_DIVISION ? "division" : "split", a);
        st = fw_options_set(&c->fw, kv, &taken);
        break;
    case OPT_FRAMES: st = cliopt_long("--frames", a, 1, 100000, &l); c->frames = (int)l; break;
    case OPT_TIMELINE: c->timeline = a; break;
    case OPT_PRESET: c->params.preset = a; break;
    case OPT_CONFIG: c->params.config = a; break;
    case OPT_SET:
        st = fw_options_set(&c->fw, a, &taken);
        if (st == PP5_OK && !taken)
            st = pp5_params_cli_add_set(&c->params, a);
        break;
    default: return NOT_MINE;
    }
    return st;
}

/* Polygons: render_mesh.c. */
static pp5_status_t parse_mesh(render_cmd_t *c, int opt, const char *a)
{
    static const char *const shadings[] = {"flat", "gouraud", "phong"};
    int i = 0;
    pp5_status_t st = PP5_OK;
    switch (opt) {
    case OPT_MESH: c->mesh_file = a; break;
    case OPT_SCENE: c->scene_file = a; break;
    case OPT_SHADING:
        if ((st = one_of("--shading", a, shadings, 3, &i)) == PP5_OK)
            c->shading = (raster_shading_t)i;
        break;
    default: return NOT_MINE;
    }
    return st;
}

/* MIP, DEMIP, MIDA and their settings (seed 002). */
static pp5_status_t parse_blend(render_cmd_t *c, int opt, const char *a)
{
    if (opt < OPT_BLEND || opt >= OPT_BLEND + N_BLEND_OPTIONS)
        return NOT_MINE;
    return blend_option(blend_options[opt - OPT_BLEND], a, &c->choices.settings.blend);
}

void render_cmd_defaults(render_cmd_t *c)
{
    memset(c, 0, sizeof *c);
    render_input_default(&c->input);
    render_choices_default(&c->choices);
    fw_options_default(&c->fw);
    c->frames = 1;
    c->shading = RASTER_GOURAUD;
}

const struct option *render_cmd_options(int *count)
{
    *count = (int)(sizeof longopts / sizeof longopts[0]) - 1;
    return longopts;
}

pp5_status_t render_cmd_option(render_cmd_t *c, int opt, const char *arg)
{
    pp5_status_t (*const groups[])(render_cmd_t *, int, const char *) = {
        parse_input, parse_shading, parse_view, parse_gaze, parse_output, parse_machine,
        parse_blend, parse_mesh,
    };
    for (size_t i = 0; i < sizeof groups / sizeof groups[0]; i++) {
        pp5_status_t st = groups[i](c, opt, arg);
        if (st != NOT_MINE)
            return st;
    }
    return pp5_fail(PP5_E_CONFIG, "unknown option (see --help)");
}

static pp5_status_t render_run(render_cmd_t *c)
{
    /* Polygons check their own outputs (render_mesh.c). */
    if (c->mesh_file || c->scene_file)
        return render_mesh_run(c, stdout);
    /* A bad output path is reported before the volume is loaded and rendered. */
    pp5_status_t st = outpath_check_all("--out", c->out_png, "--report", c->report_json, "--fig5",
                                        c->fig5_png, "--timeline", c->timeline, "--tf-out",
                                        c->tf_out, NULL);
    if (st != PP5_OK)
        return st;
    scene_t sc;
    st = render_input_load(&c->input, &sc, stdout);
    if (st != PP5_OK)
        return st;
    render_job_t job;
    st = render_job_resolve(&job, &sc, &c->choices);
    if (st == PP5_OK && c->machine && job.settings.voxel_format != MIP3D_F32)
        st = pp5_fail(PP5_E_CONFIG, "--voxel-format %s is a native option; the machine keeps "
                      "its own RGBA8 voxels (drop --machine or --voxel-format)",
                      mip3d_format_name(job.settings.voxel_format));
    if (st == PP5_OK) {
        if (c->choices.tf_note[0])
            printf("note: --tf: %s\n", c->choices.tf_note);
        render_job_print_tf(&job, stdout);
    }
    if (st == PP5_OK && c->tf_out) {
        char header[700];
        snprintf(header, sizeof header, "transfer function of %s, written by pp5 render --tf-out",
                 sc.volume.source);
        st = classify_tf_save(c->tf_out, &job.tf, header);
        if (st == PP5_OK)
            printf("wrote %s (give it back with --tf %s)\n", c->tf_out, c->tf_out);
    }
    if (st == PP5_OK)
        st = c->machine ? render_machine_run(c, &job, stdout) : render_native_run(c, &job, &sc, stdout);
    scene_free(&sc);
    return st;
}

static int render_main(int argc, char **argv)
{
    render_cmd_t c;
    render_cmd_defaults(&c);
    pp5_status_t st = PP5_OK;
    int opt;
    optind = 1;
    opterr = 1;
    while (st == PP5_OK && (opt = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
        if (opt == OPT_HELP || opt == 'h') {
            render_usage();
            fputs(blend_help(), stdout);
            return 0;
        }
        if (opt == '?')
            return 2;
        st = render_cmd_option(&c, opt, optarg);
    }
    if (st == PP5_OK && optind < argc)
        st = pp5_fail(PP5_E_CONFIG, "unexpected argument '%s' (see --help)", argv[optind]);
    if (st == PP5_OK)
        st = render_run(&c);
    return st == PP5_OK ? 0 : cliopt_report("render", st);
}

PP5_COMMAND(render, "render a frame natively or on the emulated machine (gaze-directed volume rendering)",
            render_main)
