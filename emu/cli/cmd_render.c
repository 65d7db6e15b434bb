/* cmd_render.c: `pp5 render`, one frame (or a progressive sequence) of the
 * native gaze-directed volume renderer, with its PNG, figure 5, figure 6 and
 * JSON report. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cliopt.h"
#include "registry.h"
#include "render/render_cli.h"
#include "render/renderer_native.h"
#include "render/scene.h"
/* --- firmware hook (firmware/host/fw_render.h): `pp5 render --machine` --- */
#include "firmware/host/fw_render.h"
/* --- end firmware hook --- */

static void render_usage(void)
{
    printf("usage: pp5 render [options]\n\n"
           "Renders one frame with the native gaze-directed volume renderer (Levoy &\n"
           "Whitaker 1990): a 3D mip map with octree skipping, rays cast into a\n"
           "partially populated 2D mip map whose level follows retinal acuity.\n\n"
           "Input (one of):\n"
           "  --phantom NAME        procedural volume: %s (default shepp-logan)\n"
           "  --dataset NAME        mrbrain | cthead from the shared data (../shared/data\n"
           "                        or $PP5_SHARED_DATA)\n"
           "  --volume FILE         .nrrd/.nhdr, .nii[.gz], .den, CThead.1 slices, or raw\n"
           "    --raw-dims NXxNYxNZ --raw-type u8|u16|i16|f32|... --big-endian\n"
           "    --spacing SX,SY,SZ --header-bytes N   (raw; a name like\n"
           "                        x_256x256x113_u16be.raw.gz is understood)\n"
           "Classification and shading:\n"
           "  --tf PRESET           %s\n"
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
           "Outputs:\n"
           "  --out FILE.png        the image\n"
           "  --report FILE.json    rays, samples, timings, settings (and quality)\n"
           "  --compare             also render full resolution: PSNR and acuity-weighted\n"
           "                        error in the report and on stdout\n"
           "  --mip-levels-out P    the populated 2D mip-map levels as P<level>.png (fig. 6)\n"
           "  --fig5 FILE.png       sweet-spot structure plot (fig. 5)\n"
           "  --threads N           host threads (0 = all; output is identical for any N)\n",
           phantom_names(), classify_preset_names());
}

enum {
    OPT_PHANTOM = 256, OPT_DATASET, OPT_VOLUME, OPT_RAW_DIMS, OPT_RAW_TYPE, OPT_BIG_ENDIAN,
    OPT_SPACING, OPT_HEADER_BYTES, OPT_TF, OPT_LIGHTING, OPT_SPECULAR, OPT_SIZE, OPT_ROTX,
    OPT_ROTY, OPT_ROTZ, OPT_ZOOM, OPT_PROJECTION, OPT_EYE, OPT_STEP, OPT_EARLY, OPT_NO_OCTREE,
    OPT_MODE, OPT_GAZE, OPT_MONITOR, OPT_DISTANCE, OPT_SUBTENSE, OPT_PROGRESSIVE, OPT_OUT,
    OPT_REPORT, OPT_COMPARE, OPT_LEVELS_OUT, OPT_FIG5, OPT_THREADS, OPT_HELP, OPT_SWEET,
    OPT_PERIPHERY, OPT_PERIPHERY_PX, OPT_SIGMA, OPT_BLEND
};

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

static int render_main(int argc, char **argv)
{
    render_cli_t cli;
    render_cli_defaults(&cli);
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
        /* render/blend.h: one parser for all of these (blend_option). */
        {"blend", required_argument, NULL, OPT_BLEND},
        {"window", required_argument, NULL, OPT_BLEND},
        {"tolerance", required_argument, NULL, OPT_BLEND},
        {"depth-weight", required_argument, NULL, OPT_BLEND},
        {"depth", required_argument, NULL, OPT_BLEND},
        {"demip-reading", required_argument, NULL, OPT_BLEND},
        {"sphere-weight", required_argument, NULL, OPT_BLEND},
        {"sphere-map", required_argument, NULL, OPT_BLEND},
        {"sphere-rotate", required_argument, NULL, OPT_BLEND},
        {"mip-pyramid", required_argument, NULL, OPT_BLEND},
        {"help", no_argument, NULL, OPT_HELP},
        {NULL, 0, NULL, 0},
    };
    pp5_status_t st = PP5_OK;
    double d, x, y;
    long l;
    int c, longindex = 0;
    /* --- firmware hook: machine-only options are taken out before parsing --- */
    fw_render_opts_t fw_opts;
    argc = fw_render_filter_args(argc, argv, &fw_opts, &st);
    if (st != PP5_OK)
        return cliopt_report("render", st);
    /* --- end firmware hook --- */
    optind = 1;
    opterr = 1;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "h", longopts, &longindex)) != -1) {
        switch (c) {
        case OPT_PHANTOM: cli.input = RENDER_INPUT_PHANTOM; cli.input_name = optarg; break;
        case OPT_DATASET: cli.input = RENDER_INPUT_DATASET; cli.input_name = optarg; break;
        case OPT_VOLUME: cli.input = RENDER_INPUT_FILE; cli.input_name = optarg; break;
        case OPT_RAW_DIMS: st = parse_dims3("--raw-dims", optarg, &cli.raw); cli.have_raw = true;
            break;
        case OPT_RAW_TYPE: st = voxel_type_parse(optarg, &cli.raw.type); cli.have_raw = true;
            break;
        case OPT_BIG_ENDIAN: cli.raw.big_endian = true; break;
        case OPT_SPACING: st = parse_spacing("--spacing", optarg, cli.raw.spacing);
            cli.have_spacing = true; break;
        case OPT_HEADER_BYTES:
            st = cliopt_long("--header-bytes", optarg, 0, 1L << 40, &l);
            cli.raw.header_bytes = (uint64_t)l;
            break;
        case OPT_TF: st = classify_preset(optarg, &cli.tf); cli.have_tf = true; break;
        case OPT_LIGHTING:
            if (strcmp(optarg, "diffuse") == 0)
                cli.shade.lighting = SHADE_DIFFUSE_FIXED_LIGHT;
            else if (strcmp(optarg, "specular") == 0)
                cli.shade.lighting = SHADE_SPECULAR_FIXED_LIGHT;
            else if (strcmp(optarg, "moving") == 0)
                cli.shade.lighting = SHADE_MOVING_OBJECT;
            else
                st = pp5_fail(PP5_E_CONFIG, "--lighting: expected diffuse, specular or moving, "
                              "got '%s'", optarg);
            break;
        case OPT_SPECULAR:
            st = cliopt_double("--specular", optarg, 0.0, 10.0, &d);
            cli.shade.specular = (float)d;
            break;
        case OPT_SIZE:
            st = cliopt_size2("--size", optarg, 1, 8192, &cli.settings.width,
                              &cli.settings.height);
            break;
        case OPT_ROTX: st = cliopt_double("--rot-x", optarg, -3600, 3600, &d);
            cli.settings.view.rot_x_deg = (float)d; cli.have_rot = true; break;
        case OPT_ROTY: st = cliopt_double("--rot-y", optarg, -3600, 3600, &d);
            cli.settings.view.rot_y_deg = (float)d; cli.have_rot = true; break;
        case OPT_ROTZ: st = cliopt_double("--rot-z", optarg, -3600, 3600, &d);
            cli.settings.view.rot_z_deg = (float)d; cli.have_rot = true; break;
        case OPT_ZOOM: st = cliopt_double("--zoom", optarg, 0.01, 100, &d);
            cli.settings.view.zoom = (float)d; break;
        case OPT_PROJECTION:
            if (strcmp(optarg, "parallel") == 0)
                cli.settings.view.projection = PROJECTION_PARALLEL;
            else if (strcmp(optarg, "perspective") == 0)
                cli.settings.view.projection = PROJECTION_PERSPECTIVE;
            else
                st = pp5_fail(PP5_E_CONFIG, "--projection: expected parallel or perspective, "
                              "got '%s'", optarg);
            break;
        case OPT_EYE: st = cliopt_double("--eye-distance", optarg, 1.05, 1000, &d);
            cli.settings.view.eye_distance = (float)d; break;
        case OPT_STEP: st = cliopt_double("--step", optarg, 0.05, 64, &d);
            cli.settings.view.sample_step = (float)d; break;
        case OPT_EARLY: st = cliopt_double("--early-termination", optarg, 0.01, 1, &d);
            cli.settings.view.early_termination = (float)d; break;
        case OPT_NO_OCTREE: cli.settings.view.use_octree = false; break;
        case OPT_MODE:
            if (strcmp(optarg, "full") == 0)
                cli.settings.mode = RENDER_MODE_FULL;
            else if (strcmp(optarg, "gaze") == 0)
                cli.settings.mode = RENDER_MODE_GAZE;
            else
                st = pp5_fail(PP5_E_CONFIG, "--mode: expected full or gaze, got '%s'", optarg);
            break;
        case OPT_GAZE:
            st = cliopt_pair("--gaze", optarg, &x, &y);
            cli.settings.gaze_x = x;
            cli.settings.gaze_y = y;
            cli.have_gaze = true;
            break;
        case OPT_MONITOR: st = cliopt_double("--monitor-diag", optarg, 1, 1000,
                                             &cli.settings.display.monitor_diag_in); break;
        case OPT_DISTANCE: st = cliopt_double("--view-distance", optarg, 1, 10000,
                                              &cli.settings.display.view_distance_in); break;
        case OPT_SUBTENSE: st = cliopt_double("--subtense", optarg, 0, 160,
                                              &cli.settings.display.image_subtense_deg); break;
        case OPT_SWEET: st = cliopt_double("--sweet-spot-deg", optarg, 0.1, 160,
                                           &cli.settings.display.full_res_diameter_deg); break;
        case OPT_PERIPHERY: st = cliopt_double("--periphery-deg", optarg, 0.1, 160,
                                               &cli.settings.display.periphery_diameter_deg);
            break;
        case OPT_PERIPHERY_PX:
            st = cliopt_double("--periphery-pixels", optarg, 4, 65536, &d);
            cli.settings.display.periphery_rays_per_px = 1.0 / d;
            break;
        case OPT_SIGMA: st = cliopt_double("--sigma-deg", optarg, 0.01, 90,
                                           &cli.settings.display.sigma_deg); break;
        case OPT_PROGRESSIVE: st = cliopt_long("--progressive", optarg, 1, 64, &l);
            cli.progressive_frames = (int)l; break;
        case OPT_OUT: cli.out_png = optarg; break;
        case OPT_REPORT: cli.report_json = optarg; break;
        case OPT_COMPARE: cli.compare = true; break;
        case OPT_LEVELS_OUT: cli.levels_prefix = optarg; break;
        case OPT_FIG5: cli.fig5_png = optarg; break;
        case OPT_THREADS: st = cliopt_long("--threads", optarg, 0, 64, &l);
            cli.settings.threads = (int)l; break;
        case OPT_BLEND: st = blend_option(longopts[longindex].name, optarg, &cli.settings.blend);
            break;
        case OPT_HELP:
        case 'h':
            render_usage();
            fputs(blend_help(), stdout);
            fputs(fw_render_help(), stdout); /* firmware hook */
            return 0;
        default:
            return 2;
        }
    }
    if (st == PP5_OK && optind < argc)
        st = pp5_fail(PP5_E_CONFIG, "unexpected argument '%s' (see --help)", argv[optind]);
    /* --- firmware hook --- */
    if (st == PP5_OK && fw_opts.machine && cli.settings.blend.mode != BLEND_COMPOSITE)
        st = pp5_fail(PP5_E_CONFIG, "--machine renders --blend composite only (firmware "
                      "MIP/DEMIP/MIDA: issue 11)");
    if (st == PP5_OK && fw_opts.machine)
        return (st = fw_render_cli_run(&cli, &fw_opts, stdout)) == PP5_OK ? 0 : cliopt_report("render", st);
    /* --- end firmware hook --- */
    if (st == PP5_OK)
        st = render_cli_run(&cli, stdout);
    return st == PP5_OK ? 0 : cliopt_report("render", st);
}

PP5_COMMAND(render, "render a frame with the native gaze-directed volume renderer", render_main)
