/* polhemus.c: Polhemus Patriot/Liberty binary records and the libusb bulk
 * transport; see polhemus.h. */
#include "polhemus.h"
#include "pp5_features.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if PP5_HAVE_LIBUSB
#include <libusb.h>
#endif

/* tracker-devices.md §2.1 table ([S]; 'PA' tag [U], see polhemus.h). */
static const polhemus_model_t models[] = {
    {0xef12, "Polhemus Patriot", 0x02, 0x82, "PA"},
    {0xef20, "Polhemus Patriot HS", 0x04, 0x88, "PA"},
    {0xff12, "Polhemus Liberty", 0x02, 0x82, "LY"},
    {0xff20, "Polhemus Liberty HS / Latus", 0x04, 0x88, "LY"},
};
static const uint16_t firmware_pids[] = {0xef11, 0xef21, 0xff11, 0xff21};

const polhemus_model_t *polhemus_model_for_pid(uint16_t pid)
{
    for (size_t i = 0; i < sizeof models / sizeof models[0]; i++)
        if (models[i].pid == pid)
            return &models[i];
    return NULL;
}

bool polhemus_pid_needs_firmware(uint16_t pid)
{
    for (size_t i = 0; i < sizeof firmware_pids / sizeof firmware_pids[0]; i++)
        if (firmware_pids[i] == pid)
            return true;
    return false;
}

static float le_float(const uint8_t *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
                 (uint32_t)p[3] << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

enum { HEADER_BYTES = 8, PAYLOAD_FLOATS = 6 };

pp5_status_t polhemus_parse_records(const uint8_t *buf, size_t len, const char *tag,
                                    polhemus_record_t *recs, size_t max, size_t *n)
{
    *n = 0;
    size_t at = 0;
    if (len == 0)
        return pp5_fail(PP5_E_FORMAT, "Polhemus transfer is empty");
    while (at < len) {
        if (len - at < HEADER_BYTES)
            return pp5_fail(PP5_E_FORMAT,
                            "Polhemus record truncated at byte %zu: %zu bytes left, header needs 8",
                            at, len - at);
        const uint8_t *h = buf + at;
        /* The Liberty HS/Latus answer with 'LU' (VRPN); accept it for 'LY'. */
        bool tag_ok = h[0] == (uint8_t)tag[0] && h[1] == (uint8_t)tag[1];
        if (!tag_ok && tag[0] == 'L' && tag[1] == 'Y' && h[0] == 'L' && h[1] == 'U')
            tag_ok = true;
        if (!tag_ok)
            return pp5_fail(PP5_E_FORMAT,
                            "Polhemus record at byte %zu starts 0x%02x 0x%02x, expected '%c%c'",
                            at, h[0], h[1], tag[0], tag[1]);
        size_t size = (size_t)h[6] | (size_t)h[7] << 8;
        if (size != 4 * PAYLOAD_FLOATS && size != 4 * PAYLOAD_FLOATS + 2)
            return pp5_fail(PP5_E_FORMAT,
                            "Polhemus record at byte %zu has %zu payload bytes; pp5's output "
                            "list O*,2,4,1 gives 24 or 26",
                            at, size);
        if (len - at - HEADER_BYTES < size)
            return pp5_fail(PP5_E_FORMAT,
                            "Polhemus record at byte %zu truncated: %zu of %zu payload bytes", at,
                            len - at - HEADER_BYTES, size);
        if (h[2] == 0 || h[2] > POLHEMUS_MAX_STATIONS)
            return pp5_fail(PP5_E_FORMAT, "Polhemus record at byte %zu: station %u out of 1..%d",
                            at, h[2], POLHEMUS_MAX_STATIONS);
        if (*n == max)
            return pp5_fail(PP5_E_FORMAT, "Polhemus transfer holds more than %zu records", max);
        polhemus_record_t r = {.station = h[2], .command = h[3], .error = h[4]};
        const uint8_t *p = h + HEADER_BYTES;
        for (int i = 0; i < 3; i++) {
            r.pos_cm[i] = le_float(p + 4 * i);
            r.euler_deg[i] = le_float(p + 12 + 4 * i);
        }
        for (int i = 0; i < 3; i++)
            if (!isfinite(r.pos_cm[i]) || !isfinite(r.euler_deg[i]))
                return pp5_fail(PP5_E_FORMAT, "Polhemus record at byte %zu (station %u) holds "
                                              "a non-finite value", at, r.station);
        if (size == 26 && (p[24] != '\r' || p[25] != '\n'))
            return pp5_fail(PP5_E_FORMAT, "Polhemus record at byte %zu does not end in CR LF",
                            at);
        recs[(*n)++] = r;
        at += HEADER_BYTES + size;
    }
    return PP5_OK;
}

/* ------------------------------------------------------------------ */
#if PP5_HAVE_LIBUSB

struct polhemus {
    libusb_context *ctx;
    libusb_device_handle *h;
    const polhemus_model_t *model;
    int timeout_ms;
    bool claimed;
    polhemus_stats_t stats;
    uint8_t bus, address;
};

static pp5_status_t usb_fail(polhemus_t *p, int rc, const char *what)
{
    if (rc == LIBUSB_ERROR_NO_DEVICE)
        return pp5_fail(PP5_E_DEVICE, "%s disconnected (%s: %s) after %llu polls",
                        p->model ? p->model->name : "Polhemus", what, libusb_error_name(rc),
                        (unsigned long long)p->stats.polls);
    if (rc == LIBUSB_ERROR_TIMEOUT)
        return pp5_fail(PP5_E_DEVICE, "timeout: %s did not answer within %d ms (%s) after %llu polls",
                        p->model ? p->model->name : "Polhemus", p->timeout_ms, what,
                        (unsigned long long)p->stats.polls);
    return pp5_fail(PP5_E_DEVICE, "%s: %s failed: %s", p->model ? p->model->name : "Polhemus",
                    what, libusb_error_name(rc));
}

pp5_status_t polhemus_list(polhemus_info_t *out, size_t max, size_t *n)
{
    *n = 0;
    libusb_context *ctx = NULL;
    int rc = libusb_init(&ctx);
    if (rc != 0)
        return pp5_fail(PP5_E_DEVICE, "libusb_init failed: %s", libusb_error_name(rc));
    libusb_device **list = NULL;
    ssize_t cnt = libusb_get_device_list(ctx, &list);
    for (ssize_t i = 0; i < cnt && *n < max; i++) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) != 0 || dd.idVendor != POLHEMUS_VID)
            continue;
        const polhemus_model_t *m = polhemus_model_for_pid(dd.idProduct);
        bool fw = polhemus_pid_needs_firmware(dd.idProduct);
        if (!m && !fw)
            continue;
        out[(*n)++] = (polhemus_info_t){libusb_get_bus_number(list[i]),
                                         libusb_get_device_address(list[i]), dd.idProduct,
                                         m ? m->name : "Polhemus (firmware not loaded)", fw};
    }
    if (cnt > 0)
        libusb_free_device_list(list, 1);
    libusb_exit(ctx);
    return PP5_OK;
}

static pp5_status_t send_cmd(polhemus_t *p, const char *cmd, const char *what)
{
    int done = 0;
    int len = (int)strlen(cmd);
    int rc = libusb_bulk_transfer(p->h, p->model->ep_out, (unsigned char *)cmd, len, &done,
                                  (unsigned)p->timeout_ms);
    if (rc != 0)
        return usb_fail(p, rc, what);
    if (done != len)
        return pp5_fail(PP5_E_DEVICE, "%s: %s: sent %d of %d bytes", p->model->name, what, done,
                        len);
    return PP5_OK;
}

/* Reads one IN transfer; *got = 0 on a timeout when `timeout_is_ok`. */
static pp5_status_t read_in(polhemus_t *p, uint8_t *buf, int *got, int timeout_ms,
                            bool timeout_is_ok, const char *what)
{
    *got = 0;
    int rc = libusb_bulk_transfer(p->h, p->model->ep_in, buf, POLHEMUS_IN_BYTES, got,
                                  (unsigned)timeout_ms);
    if (rc == LIBUSB_ERROR_TIMEOUT && timeout_is_ok)
        return PP5_OK;
    if (rc != 0)
        return usb_fail(p, rc, what);
    return PP5_OK;
}

static pp5_status_t init_sequence(polhemus_t *p)
{
    uint8_t buf[POLHEMUS_IN_BYTES];
    int got;
    /* §2.4: stop any continuous output and drain what is in flight; a
     * drain read that times out is the normal end. */
    pp5_status_t st = send_cmd(p, "P", "stop/poll command 'P'");
    for (int i = 0; st == PP5_OK && i < 16; i++) {
        st = read_in(p, buf, &got, p->timeout_ms < 100 ? p->timeout_ms : 100, true,
                     "draining output");
        if (got == 0)
            break;
    }
    if (st == PP5_OK)
        st = send_cmd(p, "U1\r", "metric units 'U1'");
    if (st == PP5_OK)
        st = send_cmd(p, "F1\r", "binary output 'F1'");
    if (st == PP5_OK)
        st = send_cmd(p, "O*,2,4,1\r", "output list 'O*,2,4,1'");
    return st;
}

pp5_status_t polhemus_open(const char *bus_addr, int timeout_ms, polhemus_t **out)
{
    *out = NULL;
    unsigned want_bus = 0, want_addr = 0;
    if (bus_addr && sscanf(bus_addr, "%u:%u", &want_bus, &want_addr) != 2)
        return pp5_fail(PP5_E_CONFIG, "Polhemus device '%s': expected BUS:ADDRESS", bus_addr);
    polhemus_t *p = calloc(1, sizeof *p);
    if (!p)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    p->timeout_ms = timeout_ms;
    int rc = libusb_init(&p->ctx);
    if (rc != 0) {
        free(p);
        return pp5_fail(PP5_E_DEVICE, "libusb_init failed: %s", libusb_error_name(rc));
    }
    libusb_device **list = NULL;
    ssize_t cnt = libusb_get_device_list(p->ctx, &list);
    libusb_device *found = NULL;
    bool needs_fw = false;
    for (ssize_t i = 0; i < cnt && !found; i++) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) != 0 || dd.idVendor != POLHEMUS_VID)
            continue;
        if (bus_addr && (libusb_get_bus_number(list[i]) != want_bus ||
                         libusb_get_device_address(list[i]) != want_addr))
            continue;
        if (polhemus_pid_needs_firmware(dd.idProduct))
            needs_fw = true;
        const polhemus_model_t *m = polhemus_model_for_pid(dd.idProduct);
        if (m) {
            found = list[i];
            p->model = m;
            p->bus = libusb_get_bus_number(list[i]);
            p->address = libusb_get_device_address(list[i]);
        }
    }
    pp5_status_t st = PP5_OK;
    if (!found) {
        st = pp5_fail(PP5_E_DEVICE, needs_fw
                          ? "the Polhemus tracker has no firmware loaded (pre-firmware product id); "
                            "load it with fxload (see `pp5 track --help`)"
                          : "no Polhemus Patriot/Liberty found on USB%s%s",
                      bus_addr ? " at " : "", bus_addr ? bus_addr : "");
    } else {
        rc = libusb_open(found, &p->h);
        if (rc != 0)
            st = pp5_fail(PP5_E_DEVICE, "%s at %u:%u: cannot open (%s)%s", p->model->name, p->bus,
                          p->address, libusb_error_name(rc),
                          rc == LIBUSB_ERROR_ACCESS ? "; see `pp5 track --help` about udev rules" : "");
    }
    if (cnt > 0)
        libusb_free_device_list(list, 1);
    if (st == PP5_OK) {
        rc = libusb_claim_interface(p->h, 0);
        if (rc != 0)
            st = usb_fail(p, rc, "claiming interface 0");
        else
            p->claimed = true;
    }
    if (st == PP5_OK)
        st = init_sequence(p);
    if (st != PP5_OK) {
        polhemus_close(p);
        return st;
    }
    *out = p;
    return PP5_OK;
}

const polhemus_model_t *polhemus_model(const polhemus_t *p) { return p->model; }
const polhemus_stats_t *polhemus_stats(const polhemus_t *p) { return &p->stats; }

pp5_status_t polhemus_poll(polhemus_t *p, polhemus_record_t *recs, size_t max, size_t *n)
{
    *n = 0;
    uint8_t buf[POLHEMUS_IN_BYTES];
    for (unsigned bad = 0;;) {
        pp5_status_t st = send_cmd(p, "P", "poll 'P'");
        int got = 0;
        if (st == PP5_OK)
            st = read_in(p, buf, &got, p->timeout_ms, false, "reading records");
        if (st != PP5_OK)
            return st;
        p->stats.polls++;
        st = polhemus_parse_records(buf, (size_t)got, p->model->tag, recs, max, n);
        if (st == PP5_OK) {
            p->stats.records += *n;
            for (size_t i = 0; i < *n; i++)
                if (!polhemus_record_ok(&recs[i])) {
                    p->stats.record_errors++;
                    p->stats.last_error_station = recs[i].station;
                    p->stats.last_error_code = recs[i].error;
                }
            return PP5_OK;
        }
        p->stats.malformed_transfers++;
        if (++bad > POLHEMUS_MAX_BAD_IN_A_ROW) {
            char why[512]; /* copy first: pp5_fail writes the buffer it would read */
            snprintf(why, sizeof why, "%s", pp5_error_text());
            return pp5_fail(PP5_E_DEVICE, "%s: %u malformed transfers in a row; last: %s",
                            p->model->name, bad, why);
        }
    }
}

void polhemus_close(polhemus_t *p)
{
    if (!p)
        return;
    if (p->h) {
        if (p->claimed)
            libusb_release_interface(p->h, 0);
        libusb_close(p->h);
    }
    if (p->ctx)
        libusb_exit(p->ctx);
    free(p);
}

#else /* !PP5_HAVE_LIBUSB */

struct polhemus {
    polhemus_stats_t stats;
};

#define NO_LIBUSB "pp5 was built without libusb: Polhemus trackers are not available " \
                  "(install libusb-1.0-0-dev and rebuild)"

pp5_status_t polhemus_list(polhemus_info_t *out, size_t max, size_t *n)
{
    *n = 0;
    return pp5_fail(PP5_E_UNSUPPORTED, NO_LIBUSB);
}
pp5_status_t polhemus_open(const char *bus_addr, int timeout_ms, polhemus_t **out)
{
    *out = NULL;
    return pp5_fail(PP5_E_UNSUPPORTED, NO_LIBUSB);
}
const polhemus_model_t *polhemus_model(const polhemus_t *p) { return NULL; }
const polhemus_stats_t *polhemus_stats(const polhemus_t *p) { return &p->stats; }
pp5_status_t polhemus_poll(polhemus_t *p, polhemus_record_t *recs, size_t max, size_t *n)
{
    *n = 0;
    return pp5_fail(PP5_E_UNSUPPORTED, NO_LIBUSB);
}
void polhemus_close(polhemus_t *p) {}

#endif

/* ---- gaze_source_t over a tracker ---- */

typedef struct {
    polhemus_t *p;
    int head_station, hand_station;
    int64_t period_ns, t0_ns, last_ns;
} polhemus_src_t;

static int64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static void pose_from(const polhemus_record_t *r, gaze_pose_t *pose)
{
    for (int i = 0; i < 3; i++)
        pose->pos_mm[i] = r->pos_cm[i] * 10.0; /* U1: the tracker speaks cm */
    pose->azimuth_deg = r->euler_deg[0];
    pose->elevation_deg = r->euler_deg[1];
    pose->roll_deg = r->euler_deg[2];
}

static pp5_status_t src_next(gaze_source_t *src, gaze_sample_t *out, bool *got)
{
    polhemus_src_t *s = src->impl;
    *got = false;
    /* pace the polls: the Patriot updates at 60 Hz, the Liberty at 240 Hz
     * (tracker-devices.md §2.4); polling faster only repeats records */
    int64_t now = mono_ns();
    if (s->last_ns && s->last_ns + s->period_ns > now) {
        int64_t wait = s->last_ns + s->period_ns - now;
        struct timespec ts = {(time_t)(wait / 1000000000), (long)(wait % 1000000000)};
        nanosleep(&ts, NULL);
    }
    polhemus_record_t recs[POLHEMUS_MAX_STATIONS];
    size_t n = 0;
    pp5_status_t st = polhemus_poll(s->p, recs, POLHEMUS_MAX_STATIONS, &n);
    if (st != PP5_OK)
        return st;
    int64_t t = mono_ns();
    if (!s->last_ns)
        s->t0_ns = t;
    s->last_ns = t;
    gaze_sample_invalid(out, t - s->t0_ns);
    for (size_t i = 0; i < n; i++) {
        if (!polhemus_record_ok(&recs[i]))
            continue;
        if (recs[i].station == s->head_station) {
            pose_from(&recs[i], &out->head);
            out->flags |= GAZE_FLAG_HEAD;
        } else if (recs[i].station == s->hand_station) {
            pose_from(&recs[i], &out->hand);
            out->flags |= GAZE_FLAG_HAND;
        }
    }
    *got = true;
    return PP5_OK;
}

static void src_close(gaze_source_t *src)
{
    if (!src)
        return;
    polhemus_src_t *s = src->impl;
    if (s)
        polhemus_close(s->p);
    free(s);
    free(src);
}

static const gaze_source_ops_t polhemus_source_ops = {src_next, src_close};

pp5_status_t polhemus_source_open(polhemus_t *p, int head_station, int hand_station,
                                  double rate_hz, gaze_source_t **out)
{
    *out = NULL;
    if (!(rate_hz > 0 && rate_hz <= 10000))
        return pp5_fail(PP5_E_CONFIG, "Polhemus poll rate %g Hz outside (0, 10000]", rate_hz);
    gaze_source_t *src = calloc(1, sizeof *src);
    polhemus_src_t *s = calloc(1, sizeof *s);
    if (!src || !s) {
        free(src);
        free(s);
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    }
    s->p = p;
    s->head_station = head_station;
    s->hand_station = hand_station;
    s->period_ns = (int64_t)(1e9 / rate_hz);
    src->ops = &polhemus_source_ops;
    src->impl = s;
    const polhemus_model_t *m = polhemus_model(p);
    src->name = m ? m->name : "Polhemus";
    src->sample_rate_hz = rate_hz;
    *out = src;
    return PP5_OK;
}
