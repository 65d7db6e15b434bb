/* cmd_trace.c: `pp5 trace synth|import|info|events`: make, convert, describe gaze traces
 * and detect their events (cmd_trace_events.c). */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tracker/angles.h"
#include "cliopt.h"
#include "outfile.h"
#include "emu/cli/cmd_trace.h"
#include "tracker/import.h"
#include "registry.h"
#include "tracker/synth.h"
#include "tracker/trace_file.h"

/* "WxH" of two positive finite numbers (millimetres may have decimals). */
static pp5_status_t parse_wh(const char *opt, const char *text, double *w, double *h)
{
    char *end, *end2;
    errno = 0;
    *w = strtod(text, &end);
    if (end == text || (*end != 'x' && *end != 'X'))
        return pp5_fail(PP5_E_CONFIG, "%s: expected WxH (e.g. 509.2x286.4), got '%s'", opt, text);
    *h = strtod(end + 1, &end2);
    if (end2 == end + 1 || *end2 || errno == ERANGE || !isfinite(*w) || !isfinite(*h) ||
        *w <= 0 || *h <= 0 || *w > 1e6 || *h > 1e6)
        return pp5_fail(PP5_E_CONFIG, "%s: expected two positive numbers WxH, got '%s'", opt, text);
    return PP5_OK;
}

/* ----------------------------------------------------------------- synth */

static void synth_usage(FILE *out)
{
    fprintf(out,
        "usage: pp5 trace synth --mode pursuit|saccades|mixed --out FILE [options]\n\n"
        "Generates a synthetic gaze trace on the paper's display (1280x1024 px, 37 deg wide at\n"
        "20 in; see tracker/synth.h for the eye-movement model and its sources).\n"
        "  --mode M            pursuit: follow a moving cursor (the paper's tracking test);\n"
        "                      saccades: free fixations and saccades; mixed: both, alternating\n"
        "  --seconds S         length (default 10)\n"
        "  --rate HZ           sample rate (default 1000)\n"
        "  --seed N            PRNG seed (default 1); the same seed gives the same file\n"
        "  --noise-deg D       RMS sample-to-sample noise (default 0.04; 0 = none)\n"
        "  --max-pursuit-dps V top cursor speed in pursuit (default 200, the paper's figure)\n"
        "  --blinks-per-min B  blink rate (default 12)\n"
        "  --out FILE          the trace to write (pp5 trace format, traces/FORMAT.md)\n");
}

static int cmd_synth(int argc, char **argv)
{
    static const struct option opts[] = {
        {"mode", required_argument, 0, 'm'}, {"seconds", required_argument, 0, 's'},
        {"rate", required_argument, 0, 'r'}, {"seed", required_argument, 0, 'S'},
        {"noise-deg", required_argument, 0, 'n'}, {"max-pursuit-dps", required_argument, 0, 'v'},
        {"blinks-per-min", required_argument, 0, 'b'}, {"out", required_argument, 0, 'o'},
        {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    synth_params_t p;
    synth_defaults(&p, SYNTH_SACCADES);
    bool have_mode = false;
    const char *outp = NULL;
    pp5_status_t st = PP5_OK;
    int c;
    long seed;
    optind = 1;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case 'm':
            if (!synth_mode_parse(optarg, &p.mode))
                st = pp5_fail(PP5_E_CONFIG, "--mode: expected pursuit, saccades or mixed, got '%s'",
                              optarg);
            have_mode = true;
            break;
        case 's': st = cliopt_double("--seconds", optarg, 0.01, 86400, &p.seconds); break;
        case 'r': st = cliopt_double("--rate", optarg, 10, 10000, &p.rate_hz); break;
        case 'S':
            st = cliopt_long("--seed", optarg, 0, 0x7fffffffL, &seed);
            p.seed = (uint64_t)seed;
            break;
        case 'n': st = cliopt_double("--noise-deg", optarg, 0, 5, &p.noise_deg); break;
        case 'v': st = cliopt_double("--max-pursuit-dps", optarg, 5, 1000, &p.max_pursuit_dps); break;
        case 'b': st = cliopt_double("--blinks-per-min", optarg, 0, 120, &p.blinks_per_min); break;
        case 'o': outp = optarg; break;
        case 'h': synth_usage(stdout); return 0;
        default: synth_usage(stderr); return 2;
        }
    }
    if (st == PP5_OK && (!have_mode || !outp || optind != argc))
        st = pp5_fail(PP5_E_CONFIG, "need --mode and --out (and no other arguments); see --help");
    if (st == PP5_OK)
        st = outpath_check("--out", outp);
    trace_t t;
    if (st == PP5_OK)
        st = synth_generate(&p, &t);
    if (st == PP5_OK) {
        st = trace_write_file(outp, &t);
        if (st == PP5_OK)
            printf("wrote %s: %zu samples, %.3f s at %g Hz (%s, seed %llu)\n", outp, t.count,
                   t.count ? t.samples[t.count - 1].t_ns / 1e9 : 0.0, p.rate_hz,
                   synth_mode_name(p.mode), (unsigned long long)p.seed);
        trace_free(&t);
    }
    return st == PP5_OK ? 0 : cliopt_report("trace synth", st);
}

/* ---------------------------------------------------------------- import */

static void import_usage(FILE *out)
{
    fprintf(out,
        "usage: pp5 trace import FILE --out FILE [options]\n\n"
        "Converts a recording to the pp5 trace format (FILE may be gzip-compressed).\n"
        "  --format F               auto (default), eyelink (ASC), tobii (Pro Lab TSV or SDK 3\n"
        "                           text), pupil (gaze_positions.csv, surface CSV), shared\n"
        "                           (gaze-trace v1 of ../shared/data/gaze/*/trace)\n"
        "  --source-px WxH          the recording's screen in pixels (required for Tobii and\n"
        "                           Pupil; overrides the file)\n"
        "  --source-mm WxH          its physical size in mm\n"
        "  --source-distance-mm D   eye-to-screen distance in mm\n"
        "  --source-px-per-deg P    pixels per degree at the centre (instead of mm + distance)\n"
        "  --eye L|R                EyeLink binocular: one eye (default: mean of the eyes)\n"
        "  --min-confidence C       Pupil Labs: lower confidence is track loss (default 0.6)\n"
        "  --label-column NAME      gaze-trace v1: take the labels from this column (default\n"
        "                           label; lund2013's second coder: label_RA)\n"
        "  --to paper               carry the gaze through visual angle onto the paper's\n"
        "                           display (19 in monitor at 20 in, 1280x1024, 37 deg wide);\n"
        "                           default: keep the recording's display\n"
        "  --out FILE               the trace to write\n"
        "Example:\n"
        "  pp5 trace import ../shared/data/gaze/lund2013/trace/img/UL23_img_Europe.tsv.gz \\\n"
        "      --format shared --label-column label_RA --out ul23_ra.trace\n");
}

static int cmd_import(int argc, char **argv)
{
    static const struct option opts[] = {
        {"format", required_argument, 0, 'f'}, {"source-px", required_argument, 0, 'p'},
        {"source-mm", required_argument, 0, 'm'}, {"source-distance-mm", required_argument, 0, 'd'},
        {"source-px-per-deg", required_argument, 0, 'g'}, {"eye", required_argument, 0, 'e'},
        {"min-confidence", required_argument, 0, 'c'}, {"to", required_argument, 0, 't'},
        {"label-column", required_argument, 0, 'L'},
        {"out", required_argument, 0, 'o'}, {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    import_options_t o;
    import_defaults(&o);
    import_format_t fmt = IMPORT_AUTO;
    const char *outp = NULL;
    bool to_paper = false;
    pp5_status_t st = PP5_OK;
    int c;
    optind = 1;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case 'f':
            if (!import_format_parse(optarg, &fmt))
                st = pp5_fail(PP5_E_CONFIG, "--format: expected auto, eyelink, tobii, pupil or "
                              "shared, got '%s'", optarg);
            break;
        case 'p':
            st = cliopt_size2("--source-px", optarg, 1, 100000, &o.source_width_px,
                              &o.source_height_px);
            break;
        case 'm': st = parse_wh("--source-mm", optarg, &o.source_width_mm, &o.source_height_mm); break;
        case 'd': st = cliopt_double("--source-distance-mm", optarg, 1, 1e5, &o.source_distance_mm); break;
        case 'g': st = cliopt_double("--source-px-per-deg", optarg, 0.01, 1e5, &o.source_px_per_deg); break;
        case 'e':
            if (strcmp(optarg, "L") && strcmp(optarg, "R"))
                st = pp5_fail(PP5_E_CONFIG, "--eye: expected L or R, got '%s'", optarg);
            o.eye = optarg[0];
            break;
        case 'c': st = cliopt_double("--min-confidence", optarg, 0, 1, &o.pupil_min_confidence); break;
        case 't':
            if (strcmp(optarg, "paper") != 0)
                st = pp5_fail(PP5_E_CONFIG, "--to: only 'paper' is known, got '%s'", optarg);
            to_paper = true;
            break;
        case 'L': o.label_column = optarg; break;
        case 'o': outp = optarg; break;
        case 'h': import_usage(stdout); return 0;
        default: import_usage(stderr); return 2;
        }
    }
    if (st == PP5_OK && (!outp || optind != argc - 1))
        st = pp5_fail(PP5_E_CONFIG, "need one input FILE and --out FILE; see --help");
    if (st == PP5_OK)
        st = outpath_check("--out", outp);
    trace_t t;
    if (st == PP5_OK)
        st = import_file(argv[optind], fmt, &o, &t);
    if (st == PP5_OK) {
        if (to_paper) {
            gaze_geometry_t paper;
            angles_paper_geometry(&paper);
            st = import_to_display(&t, &paper);
        }
        if (st == PP5_OK)
            st = trace_write_file(outp, &t);
        if (st == PP5_OK)
            printf("wrote %s: %zu samples, %.3f s, %g Hz, screen %dx%d px%s\n", outp, t.count,
                   t.samples[t.count - 1].t_ns / 1e9, t.header.sample_rate_hz,
                   t.header.geometry.width_px, t.header.geometry.height_px,
                   to_paper ? " (carried to the paper's display)" : "");
        trace_free(&t);
    }
    return st == PP5_OK ? 0 : cliopt_report("trace import", st);
}

/* ------------------------------------------------------------------ info */

static int cmd_info(int argc, char **argv)
{
    if (argc != 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        fprintf(argc == 2 ? stdout : stderr,
                "usage: pp5 trace info FILE\n\nPrints a pp5 trace's header and statistics "
                "(duration, valid and blink fractions, gaps, labels, field of view), its data\n"
                "quality (precision RMS-S2S and STD in fixations, data loss, effective rate) and\n"
                "the events the adaptive detector finds (see pp5 trace events --help).\n"
                "Example: pp5 trace info traces/saccades_10s_250hz.trace\n");
        return argc == 2 ? 0 : 2;
    }
    trace_t t;
    pp5_status_t st = trace_read_file(argv[1], &t);
    if (st != PP5_OK)
        return cliopt_report("trace info", st);
    const trace_header_t *h = &t.header;
    const gaze_geometry_t *g = &h->geometry;
    gaze_geometry_t r;
    size_t valid = 0, blink = 0, labels[GAZE_LABEL_MAX + 1] = {0};
    int64_t max_gap = 0;
    for (size_t i = 0; i < t.count; i++) {
        valid += (t.samples[i].flags & GAZE_FLAG_VALID) != 0;
        blink += (t.samples[i].flags & GAZE_FLAG_BLINK) != 0;
        labels[t.samples[i].label]++;
        if (i && t.samples[i].t_ns - t.samples[i - 1].t_ns > max_gap)
            max_gap = t.samples[i].t_ns - t.samples[i - 1].t_ns;
    }
    printf("file:          %s%s\n", argv[1], t.complete ? "" : "  (no end line: a recording "
           "that stopped early; valid up to its last sample)");
    printf("source:        %s\n", h->source);
    if (h->tracker[0])
        printf("tracker:       %s\n", h->tracker);
    printf("sample rate:   %g Hz\n", h->sample_rate_hz);
    printf("screen:        %d x %d px", g->width_px, g->height_px);
    if (g->width_mm > 0)
        printf(", %.1f x %.1f mm at %.0f mm", g->width_mm, g->height_mm, g->distance_mm);
    if (g->px_per_deg > 0)
        printf(", %.2f px/deg", g->px_per_deg);
    if (angles_resolve(g, &r) == PP5_OK) {
        double ax, ay;
        angles_px_to_deg(&r, g->width_px, g->height_px, &ax, &ay);
        printf(" (%.1f x %.1f deg)", 2 * ax, 2 * ay);
    }
    printf("\nsamples:       %zu over %.3f s\n", t.count,
           t.count ? t.samples[t.count - 1].t_ns / 1e9 : 0.0);
    printf("valid:         %.1f %%  blink: %.1f %%  lost: %.1f %%\n",
           t.count ? 100.0 * valid / t.count : 0, t.count ? 100.0 * blink / t.count : 0,
           t.count ? 100.0 * (t.count - valid - blink) / t.count : 0);
    printf("largest gap:   %.3f ms\n", max_gap / 1e6);
    static const char *const ln[] = {"none", "fixation", "saccade", "PSO", "pursuit", "blink",
                                     "noise"};
    printf("labels:       ");
    for (int i = 0; i <= GAZE_LABEL_MAX; i++)
        if (labels[i])
            printf(" %s %.1f%%", ln[i], 100.0 * labels[i] / t.count);
    printf("\n");
    if (t.has_head || t.has_hand)
        printf("poses:         %s%s\n", t.has_head ? "head " : "", t.has_hand ? "hand" : "");
    st = t.count >= 2 ? trace_info_print_events(&t) : PP5_OK;
    trace_free(&t);
    return st == PP5_OK ? 0 : cliopt_report("trace info", st);
}

/* --------------------------------------------------------------- dispatch */

static int cmd_trace(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        fprintf(argc < 2 ? stderr : stdout,
                "usage: pp5 trace synth|import|info|events ...   (pp5 trace SUBCOMMAND --help)\n\n"
                "  synth    generate a synthetic gaze trace (pursuit, saccades, mixed)\n"
                "  import   convert EyeLink ASC, Tobii TSV, Pupil Labs CSV or gaze-trace v1\n"
                "  info     describe a pp5 trace file, its data quality and events\n"
                "  events   detect fixations, saccades, PSOs, blinks; write events.tsv\n\n"
                "Example:\n"
                "  pp5 trace synth --mode saccades --seconds 10 --out s.trace && pp5 trace info s.trace\n");
        return argc < 2 ? 2 : 0;
    }
    if (strcmp(argv[1], "synth") == 0)
        return cmd_synth(argc - 1, argv + 1);
    if (strcmp(argv[1], "import") == 0)
        return cmd_import(argc - 1, argv + 1);
    if (strcmp(argv[1], "info") == 0)
        return cmd_info(argc - 1, argv + 1);
    if (strcmp(argv[1], "events") == 0)
        return cmd_trace_events(argc - 1, argv + 1);
    fprintf(stderr, "pp5 trace: no subcommand '%s' (synth, import, info, events)\n", argv[1]);
    return 2;
}

PP5_COMMAND(trace, "make, import and describe gaze traces, detect their events (synth, import, "
            "info, events)", cmd_trace)
