/* cmd_test_pattern.c: `pp5 test-pattern`: GPs send QEE streams, renderers draw 80 regions, pixels go to the FB. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cliopt.h"
#include "firmware/host/testpattern_session.h"
#include "machine.h"
#include "outfile.h"
#include "registry.h"
#include "report.h"
#include "stats.h"

static void tp_usage(FILE *out)
{
    fprintf(out,
            "usage: pp5 test-pattern [--out FILE.png] [--report FILE.json] [--timeline FILE.json]\n"
            "                        [--preset NAME] [--config FILE] [--set NAME=VALUE]...\n\n"
            "Runs one frame of a test pattern on the emulated Pixel-Planes 5: every GP bins a set of\n"
            "shaded discs over the screen regions of its renderers and sends them QEE instruction\n"
            "streams; each renderer draws its regions (gradients + discs from quadratic expressions)\n"
            "and ships every finished 128x128 region over the ring to the frame buffer.\n"
            "The frame-time hand calculation is in emu/ARCHITECTURE.md.\n\n"
            "  --out FILE.png       write the frame buffer\n"
            "  --report FILE.json   write the run report (frame time, busy times, ring traffic, parameters)\n"
            "  --timeline FILE.json write a Chrome trace-event timeline (open in ui.perfetto.dev)\n"
            "  --frames N           render N frames (default 1); the report lists each\n"
            PP5_PARAMS_CLI_HELP
            "  --help               this text\n\n"
            "Example:\n"
            "  pp5 test-pattern --out p.png --report r.json --set ring.channels=4\n");
}

/* The figures a reader checks against the hand calculation (README). */
static void tp_print_summary(const machine_t *m, sched_stop_t stop)
{
    double frame_s = stats_frame_time_s(m);
    const pp5_params_t *p = &m->params;
    printf("test-pattern: %u GPs, %u renderers, %ux%u screen (%u regions), ring %g MB/s\n", m->n_gp, m->n_rn,
           p->fb_width, p->fb_height, (p->fb_width / 128) * (p->fb_height / 128),
           pp5_params_ring_aggregate_bytes_per_s(p) / 1e6);
    printf("  program load      %.6f ms (host -> GPs, not part of the frame)\n", ticks_to_s(m->setup_ps) * 1e3);
    printf("  frame time        %.6f ms (stop: %s)%s\n", frame_s * 1e3,
           sched_stop_name(stop), m->n_frames > 1 ? " (mean over frames)" : "");
    printf("  ring bytes        %llu (pixels %llu, commands %llu, host %llu)\n",
           (unsigned long long)ring_total_bytes_sent(&m->ring),
           (unsigned long long)m->ring.bytes_sent[RING_CLASS_PIXELS],
           (unsigned long long)m->ring.bytes_sent[RING_CLASS_COMMAND],
           (unsigned long long)m->ring.bytes_sent[RING_CLASS_HOST]);
    printf("  ring utilization  %.1f %%\n", 100.0 * stats_ring_utilization(m));
    uint64_t rc_max = 0;
    for (unsigned i = 0; i < m->n_rn; i++) {
        rc_max = m->rn[i].cycles > rc_max ? m->rn[i].cycles : rc_max;
    }
    printf("  busiest renderer  %llu cycles\n", (unsigned long long)rc_max);
    printf("  fb                %llu blocks, %llu pixels\n", (unsigned long long)m->fb.blocks_received,
           (unsigned long long)m->fb.pixels_received);
}

static int cmd_test_pattern(int argc, char **argv)
{
    static const struct option opts[] = {
        {"out", required_argument, NULL, 'o'},
        {"report", required_argument, NULL, 'r'},
        {"timeline", required_argument, NULL, 't'},
        {"frames", required_argument, NULL, 'f'},
        {"preset", required_argument, NULL, 'p'},
        {"config", required_argument, NULL, 'c'},
        {"set", required_argument, NULL, 's'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0}};
    const char *out = NULL, *report = NULL, *timeline = NULL;
    long frames = 1;
    pp5_params_cli_t cli;
    memset(&cli, 0, sizeof cli);
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case 'r': report = optarg; break;
        case 't': timeline = optarg; break;
        case 'f':
            if (cliopt_long("--frames", optarg, 1, MACHINE_MAX_FRAMES, &frames) != PP5_OK) {
                return cliopt_report("test-pattern", PP5_E_CONFIG);
            }
            break;
        case 'p': cli.preset = optarg; break;
        case 'c': cli.config = optarg; break;
        case 's':
            if (pp5_params_cli_add_set(&cli, optarg) != PP5_OK) {
                return cliopt_report("test-pattern", PP5_E_CONFIG);
            }
            break;
        case 'h': tp_usage(stdout); return 0;
        default: tp_usage(stderr); return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "pp5 test-pattern: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    pp5_params_t p;
    pp5_status_t st = pp5_params_build(&cli, &p);
    if (st == PP5_OK) {
        /* Every output is checked before the machine runs. */
        st = outpath_check_all("--out", out, "--report", report, "--timeline", timeline, NULL);
    }
    if (st != PP5_OK) {
        return cliopt_report("test-pattern", st);
    }
    report_meta_t meta;
    memset(&meta, 0, sizeof meta);
    meta.argc = argc;
    meta.argv = argv;
    meta.workload = "test-pattern";
    if (cli.config && (st = report_add_input_file(&meta, cli.config)) != PP5_OK) {
        return cliopt_report("test-pattern", st);
    }

    machine_t m;
    st = machine_init(&m, &p);
    if (st != PP5_OK) {
        return cliopt_report("test-pattern", st);
    }
    if (timeline) {
        st = machine_enable_timeline(&m);
    }
    sched_stop_t stop = SCHED_STOP_IDLE;
    if (st == PP5_OK) {
        st = testpattern_session_run(&m, frames, &stop);
    }
    /* Reports and timelines are written even when the run failed (L6). */
    pp5_status_t st2 = PP5_OK;
    char saved[512] = "";
    if (st != PP5_OK) {
        snprintf(saved, sizeof saved, "%s", pp5_error_text());
    }
    if (report) {
        st2 = report_write(&m, &meta, report);
    }
    if (st2 == PP5_OK && timeline && m.tl) {
        st2 = timeline_write(m.tl, timeline);
    }
    if (st2 == PP5_OK && out && st == PP5_OK) {
        st2 = fb_write_png(&m.fb, out);
    }
    if (st == PP5_OK) {
        tp_print_summary(&m, stop);
    }
    machine_free(&m);
    if (st != PP5_OK) {
        pp5_fail(st, "%s", saved);
        return cliopt_report("test-pattern", st);
    }
    return st2 == PP5_OK ? 0 : cliopt_report("test-pattern", st2);
}

PP5_COMMAND_NAMED(test_pattern, "test-pattern", "draw a test pattern on the emulated machine (frame time, ring traffic)",
                  cmd_test_pattern)
