/* cmd_track.c: `pp5 track list` and `pp5 track record`: live HID eye
 * trackers and Polhemus trackers, recorded into pp5's trace format with the
 * flush-as-you-go writer (tracker/trace_file.h), so a kill -9 loses at most
 * the samples since the last flush. */
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cliopt.h"
#include "outfile.h"
#include "pp5_features.h"
#include "registry.h"
#include "status.h"
#include "tracker/hid_eye.h"
#include "tracker/polhemus.h"
#include "tracker/trace_file.h"

static void track_usage(FILE *f)
{
    fprintf(f,
"usage: pp5 track list\n"
"       pp5 track record --device DEV --out FILE [options]\n"
"\n"
"Live trackers.  Supported:\n"
"  * HID eye trackers on USB HID usage page 0x12 (\"Eye and Head Trackers\",\n"
"    HUTRR74), read through hidapi's hidraw backend.  pp5 walks the report\n"
"    descriptor, reads the Capabilities (0x11) and Configuration (0x12)\n"
"    feature reports, and turns the gaze point (micrometres on the calibrated\n"
"    screen area) into pixels.  Note: no commodity tracker is known to expose\n"
"    page 0x12 natively on Linux; Tobii's consumer trackers need Tobii's SDK.\n"
"  * Polhemus Patriot, Patriot HS, Liberty, Liberty HS/Latus over USB (libusb,\n"
"    vendor 0f44, products ef12 ef20 ff12 ff20): polled binary records, position\n"
"    in cm and Euler angles; station 1 is recorded as the head, station 2 as\n"
"    the hand (--head-station/--hand-station).  Not supported: Fastrak over\n"
"    USB/serial (its record parser exists, not its transport), Viper, G4.\n"
"\n"
"DEV: hid            the first HID eye tracker\n"
"     hid:/dev/hidrawN\n"
"     polhemus       the first Patriot/Liberty\n"
"     polhemus:BUS:ADDR  (numbers from `pp5 track list`)\n"
"\n"
"record options:\n"
"  --out FILE          trace to write (pp5 trace format, traces/FORMAT.md)\n"
"  --seconds S         stop after S seconds (default: until Ctrl-C)\n"
"  --max-samples N     stop after N samples\n"
"  --timeout-ms MS     a device silent this long is an error (default 1000)\n"
"  --flush-every N     write the file every N samples (default 10; 1 = each)\n"
"  --screen WxH        pixels the eye tracker's calibrated area covers (default 1920x1080)\n"
"  --screen-mm WxH     screen size in mm (default: HID calibrated size; for\n"
"                      Polhemus 386x290, a 19-inch 4:3 monitor as in the paper)\n"
"  --distance-mm D     eye to screen (default: HID optimum tracking distance;\n"
"                      for Polhemus 508, the paper's 20 inches)\n"
"  --rate HZ           nominal rate for the header (default: the device's, else 60)\n"
"  --head-station N, --hand-station N   Polhemus stations (default 1 and 2)\n"
"  --verbose           print a line to stderr after every flush\n"
"\n"
"Errors: a timeout (no data within --timeout-ms), a disconnect, or a run of\n"
"malformed reports stops the recording with a message and exit code 1; the\n"
"samples already received are flushed first (the file then has no '# end'\n"
"line, which marks it as cut short).  Occasional malformed reports are\n"
"counted and reported at the end.  Ctrl-C / SIGTERM end the file cleanly.\n"
"\n"
"Permissions: pp5 needs read/write access to the device nodes.  As root it\n"
"works; otherwise add udev rules, e.g. in /etc/udev/rules.d/70-pp5-trackers.rules:\n"
"  KERNEL==\"hidraw*\", ATTRS{idVendor}==\"VVVV\", ATTRS{idProduct}==\"PPPP\", TAG+=\"uaccess\"\n"
"  SUBSYSTEM==\"usb\", ATTR{idVendor}==\"0f44\", TAG+=\"uaccess\"\n"
"then `udevadm control --reload && udevadm trigger` and replug.  Polhemus\n"
"trackers first appear with a \"needs firmware\" product id (ef11, ef21, ff11,\n"
"ff21): Polhemus' own udev rules load the firmware with fxload; `pp5 track\n"
"list` shows such devices as \"firmware not loaded\".\n"
"\n"
"Example:\n"
"  pp5 track list && pp5 track record --device hid --seconds 30 --out live.trace\n"
"\n"
"pp5 built %s hidapi and %s libusb.\n",
#if PP5_HAVE_HIDAPI
            "with",
#else
            "WITHOUT",
#endif
#if PP5_HAVE_LIBUSB
            "with"
#else
            "WITHOUT"
#endif
    );
}

static int track_list(void)
{
    int unsupported = 0;
    hid_eye_info_t eyes[16];
    size_t n_eyes = 0;
    pp5_status_t st = hid_eye_list(eyes, 16, &n_eyes);
    printf("HID eye trackers (usage page 0x12):\n");
    if (st != PP5_OK) {
        printf("  (%s)\n", pp5_error_text());
        unsupported++;
    } else if (n_eyes == 0) {
        printf("  none found\n");
    }
    for (size_t i = 0; i < n_eyes; i++)
        printf("  hid:%s  %04x:%04x  %s / %s  serial '%s'\n", eyes[i].path, eyes[i].vendor_id,
               eyes[i].product_id, eyes[i].manufacturer[0] ? eyes[i].manufacturer : "?",
               eyes[i].product[0] ? eyes[i].product : "?", eyes[i].serial);
    polhemus_info_t pol[16];
    size_t n_pol = 0;
    st = polhemus_list(pol, 16, &n_pol);
    printf("Polhemus trackers (USB vendor 0f44):\n");
    if (st != PP5_OK) {
        printf("  (%s)\n", pp5_error_text());
        unsupported++;
    } else if (n_pol == 0) {
        printf("  none found\n");
    }
    for (size_t i = 0; i < n_pol; i++)
        printf("  polhemus:%u:%u  0f44:%04x  %s%s\n", pol[i].bus, pol[i].address, pol[i].pid,
               pol[i].model, pol[i].needs_firmware ? " (load firmware first: see --help)" : "");
    return unsupported == 2 ? 1 : 0;
}

static volatile sig_atomic_t stop_requested;

static void on_stop_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

typedef struct {
    const char *device, *out;
    double seconds, rate_hz;
    long max_samples, timeout_ms, flush_every, head_station, hand_station;
    int width_px, height_px;
    double screen_w_mm, screen_h_mm, distance_mm;
    bool verbose;
} record_opts_t;

static int64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* The recording loop shared by both device kinds: pulls samples from the
 * device's gaze_source_t, appends, flushes every N, and stops on time,
 * count, signal or error. */
static pp5_status_t record_loop(trace_writer_t *w, gaze_source_t *src, const record_opts_t *o,
                                size_t *n_out)
{
    int64_t t0 = now_ns();
    size_t n = 0, since_flush = 0;
    pp5_status_t st = PP5_OK;
    while (!stop_requested) {
        if (o->seconds > 0 && (double)(now_ns() - t0) / 1e9 >= o->seconds)
            break;
        if (o->max_samples > 0 && (long)n >= o->max_samples)
            break;
        gaze_sample_t s;
        bool got = false;
        st = gaze_source_next(src, &s, &got);
        if (st == PP5_OK && !got)
            st = pp5_fail(PP5_E_DEVICE, "%s: the stream ended", src->name);
        if (st != PP5_OK) {
            if (stop_requested) /* a signal interrupted the read: a clean stop */
                st = PP5_OK;
            break;
        }
        st = trace_writer_append(w, &s);
        if (st != PP5_OK)
            break;
        n++;
        if (++since_flush >= (size_t)o->flush_every) {
            st = trace_writer_flush(w);
            if (st != PP5_OK)
                break;
            since_flush = 0;
            if (o->verbose)
                fprintf(stderr, "pp5 track: flushed %zu samples\n", n);
        }
    }
    *n_out = n;
    return st;
}

static int finish(const char *what, pp5_status_t st, trace_writer_t *w, size_t n,
                  const char *stats)
{
    if (st == PP5_OK) {
        st = trace_writer_close(w);
        fprintf(stderr, "pp5 track: recorded %zu samples from %s%s\n", n, what, stats);
        return cliopt_report("track", st);
    }
    /* keep what arrived, but no "# end" line: the file says it was cut short */
    char msg[1024];
    snprintf(msg, sizeof msg, "%s", pp5_error_text());
    pp5_status_t fst = trace_writer_abandon(w);
    if (fst != PP5_OK)
        fprintf(stderr, "pp5 track: could not save the last samples: %s\n", pp5_error_text());
    fprintf(stderr, "pp5 track: kept %zu samples in %s (no end line)%s\n", n, w->path, stats);
    pp5_fail(st, "%s", msg);
    return cliopt_report("track", st);
}

static int record_hid(const char *path, const record_opts_t *o)
{
    hid_eye_t *dev = NULL;
    pp5_status_t st = hid_eye_open(path, (int)o->timeout_ms, &dev);
    if (st != PP5_OK)
        return cliopt_report("track", st);
    const hid_eye_config_t *cfg = hid_eye_config(dev);
    trace_header_t h;
    memset(&h, 0, sizeof h);
    snprintf(h.source, sizeof h.source, "pp5 track record --device hid:%s", hid_eye_path(dev));
    snprintf(h.tracker, sizeof h.tracker, "HID eye tracker (usage page 0x12) at %s",
             hid_eye_path(dev));
    h.sample_rate_hz = o->rate_hz > 0 ? o->rate_hz : (cfg->sampling_hz > 0 ? cfg->sampling_hz : 60);
    gaze_source_t *src = NULL;
    st = hid_eye_source_open(dev, o->width_px, o->height_px, &src);
    if (st != PP5_OK) {
        hid_eye_close(dev);
        return cliopt_report("track", st);
    }
    h.geometry = src->geometry;
    if (o->screen_w_mm > 0) {
        h.geometry.width_mm = o->screen_w_mm;
        h.geometry.height_mm = o->screen_h_mm;
    }
    h.geometry.distance_mm = o->distance_mm > 0 ? o->distance_mm : cfg->optimum_distance_um / 1000.0;
    trace_writer_t w;
    st = trace_writer_open(&w, o->out, &h, false, false);
    if (st != PP5_OK) {
        gaze_source_close(src);
        if (h.geometry.distance_mm <= 0) {
            char why[512]; /* copy first: pp5_fail writes the buffer it would read */
            snprintf(why, sizeof why, "%s", pp5_error_text());
            pp5_fail(st, "%s (the device reports no optimum tracking distance: give --distance-mm)",
                     why);
        }
        return cliopt_report("track", st);
    }
    size_t n = 0;
    st = record_loop(&w, src, o, &n);
    const hid_eye_stats_t *hs = hid_eye_stats(dev);
    char stats[256];
    snprintf(stats, sizeof stats,
             "; reports %llu, malformed %llu, without gaze %llu, status %llu, clock steps back %llu",
             (unsigned long long)hs->reports, (unsigned long long)hs->malformed,
             (unsigned long long)hs->invalid_gaze, (unsigned long long)hs->status_reports,
             (unsigned long long)hs->clock_backwards);
    int rc = finish(hid_eye_path(dev), st, &w, n, stats);
    gaze_source_close(src);
    return rc;
}

static int record_polhemus(const char *bus_addr, const record_opts_t *o)
{
    polhemus_t *p = NULL;
    pp5_status_t st = polhemus_open(bus_addr, (int)o->timeout_ms, &p);
    if (st != PP5_OK)
        return cliopt_report("track", st);
    const char *model = polhemus_model(p)->name;
    gaze_source_t *src = NULL;
    st = polhemus_source_open(p, (int)o->head_station, (int)o->hand_station, o->rate_hz, &src);
    if (st != PP5_OK) {
        polhemus_close(p);
        return cliopt_report("track", st);
    }
    trace_header_t h;
    memset(&h, 0, sizeof h);
    snprintf(h.source, sizeof h.source, "pp5 track record --device polhemus%s%s",
             bus_addr ? ":" : "", bus_addr ? bus_addr : "");
    snprintf(h.tracker, sizeof h.tracker, "%s (head station %ld, hand station %ld)", model,
             o->head_station, o->hand_station);
    h.sample_rate_hz = o->rate_hz;
    h.geometry.width_px = o->width_px;
    h.geometry.height_px = o->height_px;
    h.geometry.width_mm = o->screen_w_mm > 0 ? o->screen_w_mm : 386.0;
    h.geometry.height_mm = o->screen_w_mm > 0 ? o->screen_h_mm : 290.0;
    h.geometry.distance_mm = o->distance_mm > 0 ? o->distance_mm : 508.0;
    trace_writer_t w;
    st = trace_writer_open(&w, o->out, &h, true, true);
    if (st != PP5_OK) {
        gaze_source_close(src);
        return cliopt_report("track", st);
    }
    size_t n = 0;
    st = record_loop(&w, src, o, &n);
    const polhemus_stats_t *ps = polhemus_stats(p);
    char stats[320];
    int len = snprintf(stats, sizeof stats,
                       "; polls %llu, records %llu, station errors %llu, malformed transfers %llu",
                       (unsigned long long)ps->polls, (unsigned long long)ps->records,
                       (unsigned long long)ps->record_errors,
                       (unsigned long long)ps->malformed_transfers);
    if (ps->record_errors && len > 0 && (size_t)len < sizeof stats) {
        uint8_t code = ps->last_error_code;
        snprintf(stats + len, sizeof stats - (size_t)len,
                 " (last: station %u reported error '%c', 0x%02x)", ps->last_error_station,
                 code >= 32 && code < 127 ? code : '?', code);
    }
    int rc = finish(model, st, &w, n, stats);
    gaze_source_close(src);
    return rc;
}

static int track_record(int argc, char **argv)
{
    record_opts_t o = {.timeout_ms = 1000, .flush_every = 10, .head_station = 1,
                       .hand_station = 2, .width_px = 1920, .height_px = 1080};
    static const struct option longopts[] = {
        {"device", required_argument, 0, 'd'}, {"out", required_argument, 0, 'o'},
        {"seconds", required_argument, 0, 's'}, {"max-samples", required_argument, 0, 'n'},
        {"timeout-ms", required_argument, 0, 't'}, {"flush-every", required_argument, 0, 'f'},
        {"screen", required_argument, 0, 'S'}, {"screen-mm", required_argument, 0, 'M'},
        {"distance-mm", required_argument, 0, 'D'}, {"rate", required_argument, 0, 'r'},
        {"head-station", required_argument, 0, 'H'}, {"hand-station", required_argument, 0, 'A'},
        {"verbose", no_argument, 0, 'v'}, {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    optind = 1;
    int c;
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
        int mw, mh;
        switch (c) {
        case 'd': o.device = optarg; break;
        case 'o': o.out = optarg; break;
        case 's': st = cliopt_double("--seconds", optarg, 0.001, 1e7, &o.seconds); break;
        case 'n': st = cliopt_long("--max-samples", optarg, 1, 1000000000L, &o.max_samples); break;
        case 't': st = cliopt_long("--timeout-ms", optarg, 1, 600000, &o.timeout_ms); break;
        case 'f': st = cliopt_long("--flush-every", optarg, 1, 1000000, &o.flush_every); break;
        case 'S': st = cliopt_size2("--screen", optarg, 1, 100000, &o.width_px, &o.height_px); break;
        case 'M':
            st = cliopt_size2("--screen-mm", optarg, 1, 100000, &mw, &mh);
            o.screen_w_mm = mw;
            o.screen_h_mm = mh;
            break;
        case 'D': st = cliopt_double("--distance-mm", optarg, 1, 100000, &o.distance_mm); break;
        case 'r': st = cliopt_double("--rate", optarg, 0.01, 100000, &o.rate_hz); break;
        case 'H': st = cliopt_long("--head-station", optarg, 1, POLHEMUS_MAX_STATIONS, &o.head_station); break;
        case 'A': st = cliopt_long("--hand-station", optarg, 1, POLHEMUS_MAX_STATIONS, &o.hand_station); break;
        case 'v': o.verbose = true; break;
        case 'h': track_usage(stdout); return 0;
        default: track_usage(stderr); return 2;
        }
    }
    if (st != PP5_OK)
        return cliopt_report("track record", st);
    if (optind < argc)
        return cliopt_report("track record", pp5_fail(PP5_E_CONFIG, "unexpected argument '%s'", argv[optind]));
    if (!o.device || !o.out)
        return cliopt_report("track record", pp5_fail(PP5_E_CONFIG, "--device and --out are required "
                                                                    "(see pp5 track --help)"));
    /* Before any device is opened; the recording itself is flushed as it goes. */
    pp5_status_t out_st = outpath_check("--out", o.out);
    if (out_st != PP5_OK)
        return cliopt_report("track record", out_st);
    stop_requested = 0;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_stop_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    if (strcmp(o.device, "hid") == 0)
        return record_hid(NULL, &o);
    if (strncmp(o.device, "hid:", 4) == 0)
        return record_hid(o.device + 4, &o);
    if (o.rate_hz <= 0)
        o.rate_hz = 60; /* Patriot update rate, tracker-devices.md §2.4 */
    if (strcmp(o.device, "polhemus") == 0)
        return record_polhemus(NULL, &o);
    if (strncmp(o.device, "polhemus:", 9) == 0)
        return record_polhemus(o.device + 9, &o);
    return cliopt_report("track record", pp5_fail(PP5_E_CONFIG, "--device '%s': expected hid, "
                                                  "hid:PATH, polhemus or polhemus:BUS:ADDR", o.device));
}

static int cmd_track(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
        strcmp(argv[1], "help") == 0) {
        track_usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    if (strcmp(argv[1], "list") == 0) {
        if (argc > 2 && (strcmp(argv[2], "--help") == 0 || strcmp(argv[2], "-h") == 0)) {
            track_usage(stdout);
            return 0;
        }
        return track_list();
    }
    if (strcmp(argv[1], "record") == 0)
        return track_record(argc - 1, argv + 1);
    fprintf(stderr, "pp5 track: unknown subcommand '%s' (list, record)\n", argv[1]);
    return 2;
}

PP5_COMMAND(track, "live eye/head trackers: list devices, record to a trace", cmd_track)
