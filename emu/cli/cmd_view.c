/* cmd_view.c: `pp5 view`: the interactive viewer's options (view.h); it takes pp5 render's input, transfer-function, view, display and machine options too. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "registry.h"
#include "view.h"

static void view_usage(void)
{
    printf("usage: pp5 view [options]   (and pp5 render's input, --tf, view, gaze-display and\n"
           "                             machine options: see pp5 render --help)\n\n"
           "Opens a window on the gaze-directed volume renderer.  The sweet spot follows the\n"
           "mouse (standing in for the eye), a replayed trace or a live tracker; the native\n"
           "renderer makes the pixels, and the emulated Pixel-Planes 5 computes the cost of the\n"
           "same frame on a worker thread.  The heads-up display shows both engines' figures:\n"
           "the emulated frame time and frames/s, ring utilisation, rays and samples beside\n"
           "the host's own frame rate, and the latency that pp5 replay's model adds up\n"
           "(tracker + emulated frame + display).  When the machine cannot keep up, the HUD\n"
           "says so and shows the newest figure it has, with how many frames it is behind.\n\n"
           "Options:\n"
           "  --gaze-from SRC     mouse (default); hid[:/dev/hidrawN] or polhemus[:BUS:ADDR]\n"
           "                      for a live tracker (Polhemus: station 1 points the gaze\n"
           "                      with the head, station 2 in the hand turns the object);\n"
           "                      or a trace file, replayed in real time\n"
           "  --machine           the emulator makes the pixels too (slow: a frame appears\n"
           "                      when the machine has emulated it)\n"
           "  --no-machine-cost   do not run the emulator at all\n"
           "  --no-latency        use the newest gaze sample (the default delays the mouse\n"
           "                      and traces by the replay's tracker latency, 33 ms)\n"
           "  --screenshot FILE   with --frames N: render N frames, save the last as FILE\n"
           "                      (PNG, with overlays and HUD) and exit; each frame waits\n"
           "                      for its emulated cost.  Without a display this runs\n"
           "                      without a window.\n"
           "  --frames N          frames to render before --screenshot (default 1)\n"
           "  --screenshot-dir D  where the s key saves pp5-view-NNN.png (default .)\n"
           "  --no-hud, --no-circles, --levels   initial overlays (keys h, c, l)\n\n"
           "Keys:\n%s"
           "Mouse: the pointer is the gaze (with --gaze-from mouse); drag with the left\n"
           "button to rotate, the wheel zooms.\n\n"
           "Examples:\n"
           "  pp5 view --phantom shepp-logan\n"
           "  pp5 view --phantom shepp-logan --gaze-from traces/saccades_10s_250hz.trace\n"
           "  pp5 view --volume head.nrrd --size 256x256 --frames 3 --screenshot v.png\n",
           view_keys_help());
}

enum {
    OPT_GAZE_FROM = 512, OPT_NO_MACHINE_COST, OPT_NO_LATENCY, OPT_SCREENSHOT, OPT_VFRAMES,
    OPT_SHOT_DIR, OPT_NO_HUD, OPT_NO_CIRCLES, OPT_LEVELS, OPT_VHELP
};

static const struct option view_opts[] = {
    {"gaze-from", required_argument, NULL, OPT_GAZE_FROM},
    {"no-machine-cost", no_argument, NULL, OPT_NO_MACHINE_COST},
    {"no-latency", no_argument, NULL, OPT_NO_LATENCY},
    {"screenshot", required_argument, NULL, OPT_SCREENSHOT},
    {"frames", required_argument, NULL, OPT_VFRAMES},
    {"screenshot-dir", required_argument, NULL, OPT_SHOT_DIR},
    {"no-hud", no_argument, NULL, OPT_NO_HUD},
    {"no-circles", no_argument, NULL, OPT_NO_CIRCLES},
    {"levels", no_argument, NULL, OPT_LEVELS},
    {"help", no_argument, NULL, OPT_VHELP},
};

/* pp5 render's options that make no sense here. */
static const char *const render_only[] = {"out", "report", "compare", "mip-levels-out", "fig5",
                                          "progressive", "timeline"};

static bool is_render_only(const char *name)
{
    for (size_t i = 0; i < sizeof render_only / sizeof render_only[0]; i++)
        if (strcmp(render_only[i], name) == 0)
            return true;
    return false;
}

/* The view's options first, then pp5 render's (without the names the view
 * has or refuses), then the terminator. */
static struct option *all_options(void)
{
    int nr;
    const struct option *r = render_cmd_options(&nr);
    size_t nv = sizeof view_opts / sizeof view_opts[0];
    struct option *o = calloc(nv + (size_t)nr + 1, sizeof *o);
    if (!o)
        return NULL;
    memcpy(o, view_opts, sizeof view_opts);
    size_t k = nv;
    for (int i = 0; i < nr; i++) {
        bool taken = is_render_only(r[i].name);
        for (size_t j = 0; j < nv && !taken; j++)
            taken = strcmp(r[i].name, view_opts[j].name) == 0;
        if (!taken)
            o[k++] = r[i];
    }
    return o;
}

static pp5_status_t view_option(view_options_t *v, int opt, const char *a)
{
    long l;
    pp5_status_t st = PP5_OK;
    switch (opt) {
    case OPT_GAZE_FROM: v->gaze_from = a; break;
    case OPT_NO_MACHINE_COST: v->machine_cost = false; break;
    case OPT_NO_LATENCY: v->latency = false; break;
    case OPT_SCREENSHOT: v->screenshot = a; break;
    case OPT_VFRAMES: st = cliopt_long("--frames", a, 1, 100000, &l); v->frames = (int)l; break;
    case OPT_SHOT_DIR: v->screenshot_dir = a; break;
    case OPT_NO_HUD: v->hud = false; break;
    case OPT_NO_CIRCLES: v->circles = false; break;
    case OPT_LEVELS: v->levels = true; break;
    default: st = render_cmd_option(&v->cmd, opt, a);
    }
    return st;
}

static pp5_status_t parse(view_options_t *v, int argc, char **argv, bool *help)
{
    struct option *opts = all_options();
    if (!opts)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    pp5_status_t st = PP5_OK;
    int opt;
    optind = 1;
    opterr = 1;
    while (st == PP5_OK && !*help && (opt = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        if (opt == OPT_VHELP || opt == 'h')
            *help = true;
        else if (opt == '?')
            st = pp5_fail(PP5_E_CONFIG, "unknown option (see pp5 view --help)");
        else
            st = view_option(v, opt, optarg);
    }
    free(opts);
    if (st == PP5_OK && !*help && optind < argc)
        st = pp5_fail(PP5_E_CONFIG, "unexpected argument '%s' (see --help)", argv[optind]);
    if (st == PP5_OK && v->screenshot && v->frames == 0)
        v->frames = 1;
    if (st == PP5_OK && v->frames > 0 && !v->screenshot)
        st = pp5_fail(PP5_E_CONFIG, "--frames N goes with --screenshot FILE");
    return st;
}

/* --screenshot without a display: the same frames, no window. */
static pp5_status_t run_offscreen(viewer_t *v)
{
    fprintf(stderr, "view: no display: rendering %d frame(s) without a window\n", v->opt->frames);
    pp5_status_t st = PP5_OK;
    for (int f = 0; st == PP5_OK && f < v->opt->frames; f++)
        st = viewer_frame(v, 0.0);
    return st == PP5_OK ? viewer_screenshot(v, v->opt->screenshot) : st;
}

static bool have_display(void)
{
    const char *x = getenv("DISPLAY"), *w = getenv("WAYLAND_DISPLAY");
    return (x && *x) || (w && *w);
}

static pp5_status_t view_run(view_options_t *o)
{
    /* Before any costly loading: an interactive viewer needs a window. */
    if (o->frames == 0 && !have_display())
        return viewer_run_window(NULL);
    scene_t sc;
    pp5_status_t st = render_input_load(&o->cmd.input, &sc, stdout);
    if (st != PP5_OK)
        return st;
    render_job_t job;
    st = render_job_resolve(&job, &sc, &o->cmd.choices);
    if (st == PP5_OK)
        render_job_print_tf(&job, stdout);
    viewer_t *v = st == PP5_OK ? malloc(sizeof *v) : NULL;
    if (st == PP5_OK && !v)
        st = pp5_fail(PP5_E_NOMEM, "view: out of memory");
    if (st == PP5_OK) {
        st = viewer_init(v, o, &job);
        if (st == PP5_OK)
            st = o->frames > 0 && !have_display() ? run_offscreen(v) : viewer_run_window(v);
        /* Scripts read the last frame's figures here (the HUD's lines). */
        for (int i = 0; st == PP5_OK && o->frames > 0 && v->hud && i < VIEW_HUD_LINES - 1; i++)
            if (v->hud_text[i][0])
                printf("hud: %s\n", v->hud_text[i]);
        viewer_free(v);
        free(v);
    }
    if (st == PP5_OK && o->screenshot)
        printf("view: saved %s\n", o->screenshot);
    scene_free(&sc);
    return st;
}

static int view_main(int argc, char **argv)
{
    view_options_t o;
    memset(&o, 0, sizeof o);
    render_cmd_defaults(&o.cmd);
    o.gaze_from = "mouse";
    o.machine_cost = o.latency = o.hud = o.circles = true;
    bool help = false;
    pp5_status_t st = parse(&o, argc, argv, &help);
    if (help) {
        view_usage();
        return 0;
    }
    if (st == PP5_OK)
        st = view_run(&o);
    return st == PP5_OK ? 0 : cliopt_report("view", st);
}

PP5_COMMAND(view, "interactive viewer: the sweet spot follows the mouse or a tracker; HUD with the emulated machine's frame time",
            view_main)
