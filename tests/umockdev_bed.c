/* umockdev_bed.c: the emulated trackers and the umockdev testbed of the
 * device integration tests (tests/test_track_umockdev*.c; see umockdev_bed.h).
 *
 * The emulated Polhemus (Patriot, or Liberty HS) answers usbdevfs ioctls and
 * the emulated HID page-0x12 eye tracker hidraw ioctls, from handler
 * callbacks (libumockdev API, run on the testbed's own thread); the eye
 * tracker's input reports go through a pty.  The children run `pp5 ...` with
 * LD_PRELOAD=libumockdev-preload.so.0, the way umockdev-run does
 * (../shared/docs/tracker-devices.md §4.4). */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifdef PP5_HAVE_UMOCKDEV

#include <fcntl.h>
#include <linux/hidraw.h>
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>
#include <termios.h>

#include "emu/util/status.h"
#include "harness.h"
#include "tests/fixtures/devices/eye_tracker_desc.h"
#include "umockdev_bed.h"

const emu_polhemus_t EMU_PATRIOT = {0xef12, 0x02, 0x82, "PA", "Patriot (emulated)"};
const emu_polhemus_t EMU_LIBERTY_HS = {0xff20, 0x04, 0x88, "LU", "Liberty HS (emulated)"};

static void emu_init(emu_t *e, const emu_polhemus_t *kind, const trace_t *t, size_t limit,
                     after_end_t after)
{
    memset(e, 0, sizeof *e);
    e->kind = kind;
    pthread_mutex_init(&e->mu, NULL);
    e->trace = t;
    e->limit = limit;
    e->after_end = after;
}

static void emu_free(emu_t *e)
{
    for (int i = 0; i < e->n_flying; i++)
        g_object_unref(e->flying[i]);
    for (int i = 0; i < e->n_reapable; i++)
        g_object_unref(e->reapable[i]);
    pthread_mutex_destroy(&e->mu);
}

/* ---- emulated Polhemus Patriot ---- */

static size_t put_f32(uint8_t *p, double v)
{
    float f = (float)v;
    uint32_t u;
    memcpy(&u, &f, 4);
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(u >> (8 * i));
    return 4;
}

/* One 'PA' record (tracker-devices.md §2.3) for output list O*,2,4,1. */
static size_t patriot_record(uint8_t *p, const char *tag, uint8_t station,
                             const gaze_pose_t *pose)
{
    size_t n = 0;
    p[n++] = (uint8_t)tag[0];
    p[n++] = (uint8_t)tag[1];
    p[n++] = station;
    p[n++] = 'P';
    p[n++] = 0;
    p[n++] = 0;
    p[n++] = 26;
    p[n++] = 0;
    for (int i = 0; i < 3; i++)
        n += put_f32(p + n, pose->pos_mm[i] / 10.0); /* the device speaks cm (U1) */
    n += put_f32(p + n, pose->azimuth_deg);
    n += put_f32(p + n, pose->elevation_deg);
    n += put_f32(p + n, pose->roll_deg);
    p[n++] = '\r';
    p[n++] = '\n';
    return n;
}

static void patriot_command(emu_t *e, const uint8_t *cmd, size_t len)
{
    if (len == 1 && cmd[0] == 'P') {
        if (!e->configured) {
            /* before F1 the device answers in ASCII: pp5 must drain it */
            static const char ascii[] = "  1  10.00  -2.50  30.25   5.00 -10.00   0.50\r\n";
            memcpy(e->pending, ascii, sizeof ascii - 1);
            e->pending_len = sizeof ascii - 1;
            e->has_pending = true;
            return;
        }
        if (e->frames_sent >= e->limit) {
            if (e->after_end == AFTER_END_DISCONNECT)
                e->disconnected = true;
            return; /* silent: the IN transfer will time out */
        }
        size_t frame = e->frames_sent++;
        const gaze_sample_t *s = &e->trace->samples[frame];
        size_t n = patriot_record(e->pending, e->kind->tag, 1, &s->head);
        n += patriot_record(e->pending + n, e->kind->tag, 2, &s->hand);
        if (e->garble_every && frame % e->garble_every == e->garble_every - 1)
            e->pending[0] = e->pending[1] = 'X';
        if (e->hand_error_frame && frame == e->hand_error_frame)
            e->pending[34 + 4] = 'E'; /* error byte of the second record */
        e->pending_len = n;
        e->has_pending = true;
        return;
    }
    size_t used = strlen(e->cmdlog);
    if (used + len + 2 < sizeof e->cmdlog) {
        memcpy(e->cmdlog + used, cmd, len);
        e->cmdlog[used + len] = '|';
        e->cmdlog[used + len + 1] = '\0';
    }
    if (len == 9 && memcmp(cmd, "O*,2,4,1\r", 9) == 0)
        e->configured = true;
}

/* USBDEVFS_SUBMITURB: OUT transfers are commands, answered at once; an IN
 * transfer completes with the pending record, or stays in flight until
 * libusb discards it on its timeout.  Called with e->mu held. */
static void usb_submit_urb(emu_t *e, UMockdevIoctlClient *client, UMockdevIoctlData *arg,
                           GError **err)
{
    if (e->disconnected) {
        umockdev_ioctl_client_complete(client, -1, ENODEV);
        return;
    }
    UMockdevIoctlData *ud = umockdev_ioctl_data_resolve(arg, 0, sizeof(struct usbdevfs_urb), err);
    if (!ud) {
        umockdev_ioctl_client_complete(client, -1, EFAULT);
        return;
    }
    struct usbdevfs_urb *urb = (struct usbdevfs_urb *)ud->data;
    UMockdevIoctlData *bd = umockdev_ioctl_data_resolve(
        ud, offsetof(struct usbdevfs_urb, buffer), (gsize)urb->buffer_length, err);
    if (!bd || urb->type != USBDEVFS_URB_TYPE_BULK ||
        (urb->endpoint != e->kind->ep_out && urb->endpoint != e->kind->ep_in) ||
        e->n_flying == MAX_URBS || e->n_reapable == MAX_URBS) {
        umockdev_ioctl_client_complete(client, -1, EINVAL);
        if (bd)
            g_object_unref(bd);
        g_object_unref(ud);
        return;
    }
    if (urb->endpoint == e->kind->ep_out) {
        patriot_command(e, bd->data, (size_t)urb->buffer_length);
        urb->actual_length = urb->buffer_length;
        urb->status = 0;
        e->reapable[e->n_reapable++] = ud;
    } else if (e->has_pending && (size_t)urb->buffer_length >= e->pending_len) {
        memcpy(bd->data, e->pending, e->pending_len);
        urb->actual_length = (int)e->pending_len;
        urb->status = 0;
        e->has_pending = false;
        e->reapable[e->n_reapable++] = ud;
    } else {
        e->flying[e->n_flying++] = ud; /* completes only if discarded */
    }
    g_object_unref(bd);
    umockdev_ioctl_client_complete(client, 0, 0);
}

/* USBDEVFS_REAPURB(NDELAY): hands back the oldest completed URB.  Called
 * with e->mu held. */
static void usb_reap_urb(emu_t *e, UMockdevIoctlClient *client, UMockdevIoctlData *arg,
                         GError **err)
{
    if (e->n_reapable == 0) {
        umockdev_ioctl_client_complete(client, -1, e->disconnected ? ENODEV : EAGAIN);
        return;
    }
    UMockdevIoctlData *ud = e->reapable[0];
    memmove(e->reapable, e->reapable + 1, sizeof e->reapable[0] * (size_t)--e->n_reapable);
    UMockdevIoctlData *pd = umockdev_ioctl_data_resolve(arg, 0, sizeof(void *), err);
    if (!pd) {
        umockdev_ioctl_client_complete(client, -1, EFAULT);
        g_object_unref(ud);
        return;
    }
    umockdev_ioctl_data_set_ptr(pd, 0, ud);
    umockdev_ioctl_client_complete(client, 0, 0);
    g_object_unref(pd);
    g_object_unref(ud);
}

/* USBDEVFS_DISCARDURB: kills an IN transfer still in flight (libusb's
 * timeout), which then completes with -ENOENT.  Called with e->mu held. */
static void usb_discard_urb(emu_t *e, UMockdevIoctlClient *client, UMockdevIoctlData *arg)
{
    gulong addr = *(gulong *)arg->data;
    int found = -1;
    for (int i = 0; i < e->n_flying; i++)
        if (e->flying[i]->client_addr == addr)
            found = i;
    if (found < 0) {
        umockdev_ioctl_client_complete(client, -1, EINVAL);
        return;
    }
    UMockdevIoctlData *ud = e->flying[found];
    memmove(e->flying + found, e->flying + found + 1,
            sizeof e->flying[0] * (size_t)(e->n_flying - found - 1));
    e->n_flying--;
    struct usbdevfs_urb *urb = (struct usbdevfs_urb *)ud->data;
    urb->status = -ENOENT; /* what usbfs reports for a killed URB */
    urb->actual_length = 0;
    e->reapable[e->n_reapable++] = ud;
    e->discards++;
    umockdev_ioctl_client_complete(client, 0, 0);
}

/* The usbdevfs ioctls libusb issues on the Polhemus's device node. */
static gboolean usb_ioctl(UMockdevIoctlBase *handler, UMockdevIoctlClient *client, gpointer user)
{
    (void)handler;
    emu_t *e = user;
    gulong req = umockdev_ioctl_client_get_request(client);
    UMockdevIoctlData *arg = umockdev_ioctl_client_get_arg(client);
    GError *err = NULL;
    pthread_mutex_lock(&e->mu);
    switch (req) {
    case USBDEVFS_GET_CAPABILITIES: {
        UMockdevIoctlData *d = umockdev_ioctl_data_resolve(arg, 0, sizeof(guint32), &err);
        if (d) {
            *(guint32 *)d->data = USBDEVFS_CAP_NO_PACKET_SIZE_LIM | USBDEVFS_CAP_ZERO_PACKET |
                                  USBDEVFS_CAP_BULK_CONTINUATION;
            umockdev_ioctl_client_complete(client, 0, 0);
            g_object_unref(d);
        } else {
            umockdev_ioctl_client_complete(client, -1, EFAULT);
        }
        break;
    }
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_CLEAR_HALT:
    case USBDEVFS_RESET:
    case USBDEVFS_RESETEP:
        umockdev_ioctl_client_complete(client, e->disconnected ? -1 : 0,
                                       e->disconnected ? ENODEV : 0);
        break;
    case USBDEVFS_SUBMITURB:
        usb_submit_urb(e, client, arg, &err);
        break;
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY:
        usb_reap_urb(e, client, arg, &err);
        break;
    case USBDEVFS_DISCARDURB:
        usb_discard_urb(e, client, arg);
        break;
    default:
        umockdev_ioctl_client_complete(client, -1, ENOTTY);
        break;
    }
    pthread_mutex_unlock(&e->mu);
    if (err)
        g_error_free(err);
    return TRUE;
}

/* ---- emulated HID eye tracker: feature reports by ioctl ---- */

static void le32(uint8_t *p, int32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)((uint32_t)v >> (8 * i));
}

size_t umd_feature_report(uint8_t id, uint8_t *out)
{
    memset(out, 0, 32);
    out[0] = id;
    switch (id) {
    case 0x11: /* Capabilities: quality 1; distances; max screen */
        out[1] = 1;
        le32(out + 2, 450000);
        le32(out + 6, 650000);
        le32(out + 10, 950000);
        le32(out + 14, 600000);
        le32(out + 18, 340000);
        return 22;
    case 0x12: /* Configuration: display ids, serial, date, calibrated size */
        out[1] = 0xac, out[2] = 0x10, out[3] = 0xb1, out[4] = 0xa0;
        le32(out + 5, 12345678);
        out[9] = 0xe1, out[10] = 0x07;
        le32(out + 11, CAL_W_UM);
        le32(out + 15, CAL_H_UM);
        return 19;
    case 0x13: /* Status: ready, EMU_RATE_HZ */
        out[1] = 1;
        out[2] = EMU_RATE_HZ & 0xff;
        out[3] = EMU_RATE_HZ >> 8;
        return 4;
    default:
        return 0;
    }
}

static gboolean hid_ioctl(UMockdevIoctlBase *handler, UMockdevIoctlClient *client, gpointer user)
{
    (void)handler;
    emu_t *e = user;
    gulong req = umockdev_ioctl_client_get_request(client);
    UMockdevIoctlData *arg = umockdev_ioctl_client_get_arg(client);
    GError *err = NULL;
    UMockdevIoctlData *d = NULL;
    if (req == HIDIOCGRDESCSIZE) {
        d = umockdev_ioctl_data_resolve(arg, 0, sizeof(int), &err);
        if (d)
            *(int *)d->data = (int)sizeof pp5_fixture_eye_desc;
        umockdev_ioctl_client_complete(client, d ? 0 : -1, d ? 0 : EFAULT);
    } else if (req == HIDIOCGRDESC) {
        d = umockdev_ioctl_data_resolve(arg, 0, sizeof(struct hidraw_report_descriptor), &err);
        if (d) {
            struct hidraw_report_descriptor *rd = (struct hidraw_report_descriptor *)d->data;
            rd->size = sizeof pp5_fixture_eye_desc;
            memcpy(rd->value, pp5_fixture_eye_desc, sizeof pp5_fixture_eye_desc);
        }
        umockdev_ioctl_client_complete(client, d ? 0 : -1, d ? 0 : EFAULT);
    } else if (req == HIDIOCGRAWINFO) {
        d = umockdev_ioctl_data_resolve(arg, 0, sizeof(struct hidraw_devinfo), &err);
        if (d) {
            struct hidraw_devinfo *info = (struct hidraw_devinfo *)d->data;
            info->bustype = 3; /* BUS_USB */
            info->vendor = 0x1209;
            info->product = 0x0001;
        }
        umockdev_ioctl_client_complete(client, d ? 0 : -1, d ? 0 : EFAULT);
    } else if (_IOC_TYPE(req) == 'H' && _IOC_NR(req) == _IOC_NR(HIDIOCGFEATURE(0))) {
        size_t len = _IOC_SIZE(req);
        d = len ? umockdev_ioctl_data_resolve(arg, 0, len, &err) : NULL;
        uint8_t rep[32];
        size_t n = d ? umd_feature_report(d->data[0], rep) : 0;
        if (n == 0 || n > len) {
            umockdev_ioctl_client_complete(client, -1, EINVAL);
        } else {
            memcpy(d->data, rep, n);
            pthread_mutex_lock(&e->mu);
            if (rep[0] == 0x12)
                e->features_read = true;
            pthread_mutex_unlock(&e->mu);
            umockdev_ioctl_client_complete(client, (glong)n, 0);
        }
    } else {
        umockdev_ioctl_client_complete(client, -1, ENOTTY);
    }
    if (d)
        g_object_unref(d);
    if (err)
        g_error_free(err);
    return TRUE;
}

/* A 65-byte Tracking Data report (tracker-devices.md §1.2) for sample s:
 * pixels on a 1920x1080 screen back to micrometres on the calibrated area;
 * no gaze is sent as an out-of-range value (HID null). */
void umd_tracking_report(uint8_t r[65], const gaze_sample_t *s, uint8_t id)
{
    memset(r, 0, 65);
    r[0] = id;
    uint64_t t_us = 1000000u + (uint64_t)(s->t_ns / 1000);
    for (int i = 0; i < 8; i++)
        r[1 + i] = (uint8_t)(t_us >> (8 * i));
    bool valid = (s->flags & GAZE_FLAG_VALID) != 0;
    le32(r + 9, valid ? (int32_t)lround(s->x_px / 1920.0 * CAL_W_UM) : 2000001);
    le32(r + 13, valid ? (int32_t)lround(s->y_px / 1080.0 * CAL_H_UM) : 2000001);
}

/* ---- the testbed ---- */

static char *hex_of(const uint8_t *b, size_t n)
{
    char *s = malloc(2 * n + 1);
    for (size_t i = 0; i < n; i++)
        sprintf(s + 2 * i, "%02x", b[i]);
    return s;
}

/* The sysfs/udev description of both emulated devices, in umockdev's
 * record format (g_free the result).  Also written out for the
 * umockdev-run test and shipped as tests/fixtures/devices/trackers.umockdev. */
char *umd_trackers_umockdev_text(const emu_polhemus_t *k)
{
    /* USB descriptors: device + configuration, written by hand.
     * Polhemus 0f44:PID: interface 0 vendor class, two bulk endpoints. */
    const uint8_t patriot_desc[] = {
        0x12, 0x01, 0x00, 0x02, 0x00, 0x00, 0x00, 0x40, 0x44, 0x0f,
        (uint8_t)(k->pid & 0xff), (uint8_t)(k->pid >> 8), 0x00, 0x01, 0x01, 0x02, 0x00, 0x01,
        0x09, 0x02, 0x20, 0x00, 0x01, 0x01, 0x00, 0x80, 0x32,
        0x09, 0x04, 0x00, 0x00, 0x02, 0xff, 0x00, 0x00, 0x00,
        0x07, 0x05, k->ep_out, 0x02, 0x40, 0x00, 0x00,
        0x07, 0x05, k->ep_in, 0x02, 0x40, 0x00, 0x00,
    };
    /* Eye tracker 1209:0001 (pid.codes test id): one HID interface. */
    uint16_t rlen = (uint16_t)sizeof pp5_fixture_eye_desc;
    const uint8_t eye_desc[] = {
        0x12, 0x01, 0x00, 0x02, 0x00, 0x00, 0x00, 0x40, 0x09, 0x12, 0x01, 0x00, 0x00, 0x01,
        0x01, 0x02, 0x03, 0x01,
        0x09, 0x02, 0x22, 0x00, 0x01, 0x01, 0x00, 0x80, 0x32,
        0x09, 0x04, 0x00, 0x00, 0x01, 0x03, 0x00, 0x00, 0x00,
        0x09, 0x21, 0x11, 0x01, 0x00, 0x01, 0x22, (uint8_t)(rlen & 0xff), (uint8_t)(rlen >> 8),
        0x07, 0x05, 0x81, 0x03, 0x40, 0x00, 0x01,
    };
    char *pat_hex = hex_of(patriot_desc, sizeof patriot_desc);
    char *eye_hex = hex_of(eye_desc, sizeof eye_desc);
    char *rd_hex = hex_of(pp5_fixture_eye_desc, sizeof pp5_fixture_eye_desc);
    const char *usb = "/devices/pci0000:00/0000:00:14.0/usb1";
    char *text = g_strdup_printf(
        "P: %s/1-2\nN: bus/usb/001/002\nE: DEVNAME=/dev/bus/usb/001/002\nE: DEVTYPE=usb_device\n"
        "E: DRIVER=usb\nE: SUBSYSTEM=usb\nE: BUSNUM=001\nE: DEVNUM=002\nE: PRODUCT=f44/%x/100\n"
        "A: busnum=1\\n\nA: devnum=2\\n\nA: idVendor=0f44\\n\nA: idProduct=%04x\\n\n"
        "A: bConfigurationValue=1\\n\nA: speed=12\\n\nA: manufacturer=Polhemus\\n\n"
        "A: product=%s\\n\nH: descriptors=%s\n\n"

        "P: %s/1-3/1-3:1.0/0003:1209:0001.0001/hidraw/hidraw0\nN: hidraw0\n"
        "E: DEVNAME=/dev/hidraw0\nE: SUBSYSTEM=hidraw\nA: dev=240:0\\n\n"
        "L: device=../../../0003:1209:0001.0001\n\n"

        "P: %s/1-3/1-3:1.0/0003:1209:0001.0001\nE: DRIVER=hid-generic\n"
        "E: HID_ID=0003:00001209:00000001\nE: HID_NAME=pp5 emulated HUTRR74 eye tracker\n"
        "E: HID_PHYS=usb-0000:00:14.0-3/input0\nE: HID_UNIQ=ET0001\nE: SUBSYSTEM=hid\n"
        "H: report_descriptor=%s\n\n"

        "P: %s/1-3/1-3:1.0\nE: DEVTYPE=usb_interface\nE: DRIVER=usbhid\nE: SUBSYSTEM=usb\n"
        "E: INTERFACE=3/0/0\nA: bInterfaceNumber=00\\n\nA: bInterfaceClass=03\\n\n\n"

        "P: %s/1-3\nN: bus/usb/001/003\nE: DEVNAME=/dev/bus/usb/001/003\nE: DEVTYPE=usb_device\n"
        "E: DRIVER=usb\nE: SUBSYSTEM=usb\nE: BUSNUM=001\nE: DEVNUM=003\nE: PRODUCT=1209/1/100\n"
        "A: busnum=1\\n\nA: devnum=3\\n\nA: idVendor=1209\\n\nA: idProduct=0001\\n\n"
        "A: bConfigurationValue=1\\n\nA: speed=12\\n\nA: manufacturer=pp5 tests\\n\n"
        "A: product=Emulated eye tracker\\n\nA: serial=ET0001\\n\nH: descriptors=%s\n",
        usb, (unsigned)k->pid, (unsigned)k->pid, k->product, pat_hex, usb, usb, rd_hex, usb, usb,
        eye_hex);
    free(pat_hex);
    free(eye_hex);
    free(rd_hex);
    return text;
}

bool umd_bed_open(bed_t *b, const emu_polhemus_t *kind, const trace_t *t, size_t limit,
                  after_end_t after)
{
    memset(b, 0, sizeof *b);
    b->hid_master = -1;
    emu_init(&b->emu, kind, t, limit, after);
    b->tb = umockdev_testbed_new();
    if (!b->tb)
        return false;
    b->usb = umockdev_ioctl_base_new();
    b->hid = umockdev_ioctl_base_new();
    g_signal_connect(b->usb, "handle-ioctl", G_CALLBACK(usb_ioctl), &b->emu);
    g_signal_connect(b->hid, "handle-ioctl", G_CALLBACK(hid_ioctl), &b->emu);
    /* handlers first, then the devices (as libusb's own umockdev test) */
    GError *err = NULL;
    if (!umockdev_testbed_attach_ioctl(b->tb, "/dev/bus/usb/001/002", b->usb, &err) ||
        !umockdev_testbed_attach_ioctl(b->tb, "/dev/hidraw0", b->hid, &err)) {
        fprintf(stderr, "    attach_ioctl: %s\n", err ? err->message : "?");
        return false;
    }
    char *text = umd_trackers_umockdev_text(kind);
    bool ok = umockdev_testbed_add_from_string(b->tb, text, &err);
    if (!ok)
        fprintf(stderr, "    add_from_string: %s\n", err ? err->message : "?");
    g_free(text);
    if (err)
        g_error_free(err);
    if (!ok)
        return false;
    b->hid_master = umockdev_testbed_get_dev_fd(b->tb, "/dev/hidraw0");
    if (b->hid_master >= 0) {
        /* children must not inherit the master side: if they did, closing
         * it here (the disconnect test) would not hang up the pty */
        fcntl(b->hid_master, F_SETFD, FD_CLOEXEC);
        /* raw bytes: no echo, no line editing, no CR/NL mapping */
        struct termios tio;
        if (tcgetattr(b->hid_master, &tio) == 0) {
            cfmakeraw(&tio);
            tcsetattr(b->hid_master, TCSANOW, &tio);
        }
    }
    return b->hid_master >= 0;
}

void umd_bed_close(bed_t *b)
{
    if (b->tb)
        g_object_unref(b->tb);
    if (b->usb)
        g_object_unref(b->usb);
    if (b->hid)
        g_object_unref(b->hid);
    emu_free(&b->emu);
    unsetenv("UMOCKDEV_DIR");
}

static bool write_all(int fd, const uint8_t *p, size_t n)
{
    int stalls = 0;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w < 0 && errno == EAGAIN && stalls++ < CHILD_DEADLINE_S * 1000) {
            umd_sleep_ms(1); /* pty buffer full: the child has not read yet */
            continue;
        }
        if (w <= 0)
            return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

/* Injects reports for samples [from, to) of t into the hidraw pty in one
 * burst: the child reads exactly one report per read (hid_eye_read asks for
 * the longest input report), so the pty's byte stream keeps the boundaries,
 * and no scheduling gap between reports can look like a device timeout. */
bool umd_inject(bed_t *b, const trace_t *t, size_t from, size_t to, uint8_t id)
{
    if (to <= from)
        return true;
    size_t n = to - from;
    uint8_t *buf = malloc(65 * n);
    if (!buf)
        return false;
    for (size_t i = 0; i < n; i++)
        umd_tracking_report(buf + 65 * i, &t->samples[from + i], id);
    bool ok = write_all(b->hid_master, buf, 65 * n);
    free(buf);
    return ok;
}

/* ---- running ./pp5 under the preload library ---- */

bool umd_child_start(child_t *c, const char *dir, const char *args)
{
    return umd_child_start_cmd(c, dir, "", args, true);
}

/* Runs `CMD_PREFIX pp5 ARGS` in the background (see umockdev_bed.h). */
bool umd_child_start_cmd(child_t *c, const char *dir, const char *prefix, const char *args,
                         bool preload)
{
    const char *bin = getenv("PP5_BIN");
    if (!bin || !*bin)
        bin = "./pp5";
    c->reaped = false;
    snprintf(c->out, sizeof c->out, "%s/stdout.txt", dir);
    snprintf(c->err, sizeof c->err, "%s/stderr.txt", dir);
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "exec %s %s %s >%s 2>%s </dev/null", prefix, bin, args, c->out,
             c->err);
    c->pid = fork();
    if (c->pid < 0)
        return false;
    if (c->pid == 0) {
        /* umockdev's preload must come into the child only; a sanitised
         * pp5 wants its runtime first in the library list, which LD_PRELOAD
         * breaks, so that check is switched off for the child. */
        if (preload)
            setenv("LD_PRELOAD", "libumockdev-preload.so.0", 1);
        const char *asan = getenv("ASAN_OPTIONS");
        char opts[512];
        snprintf(opts, sizeof opts, "%s%sverify_asan_link_order=0", asan ? asan : "",
                 asan && *asan ? ":" : "");
        setenv("ASAN_OPTIONS", opts, 1);
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    return true;
}

bool umd_child_poll(child_t *c)
{
    int status;
    if (!c->reaped && waitpid(c->pid, &status, WNOHANG) == c->pid) {
        c->reaped = true;
        c->code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }
    return c->reaped;
}

/* Waits (bounded) for the child; returns its exit code, 128+signal, or -1
 * when it had to be killed. */
int umd_child_wait(child_t *c, double seconds)
{
    struct timespec t0, now;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (;;) {
        int status;
        if (umd_child_poll(c))
            return c->code;
        clock_gettime(CLOCK_MONOTONIC, &now);
        if ((double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec) > seconds) {
            kill(c->pid, SIGKILL);
            waitpid(c->pid, &status, 0);
            return -1;
        }
        usleep(5000);
    }
}

bool umd_child_running(child_t *c)
{
    return !umd_child_poll(c);
}

void umd_sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* Waits until the child has read the eye tracker's Configuration report
 * (so it has opened the device), bounded. */
bool umd_wait_features(bed_t *b, child_t *c)
{
    for (int i = 0; i < CHILD_DEADLINE_S * 100; i++) {
        pthread_mutex_lock(&b->emu.mu);
        bool done = b->emu.features_read;
        pthread_mutex_unlock(&b->emu.mu);
        if (done)
            return true;
        umd_sleep_ms(10);
    }
    return false;
}

void umd_show_stderr(const child_t *c)
{
    char *e = pp5_test_read_file(c->err);
    printf("    pp5 stderr: %s", e && *e ? e : "(empty)\n");
    free(e);
}

/* ---- the input traces (written to disk and read back: fed from files) ---- */

void umd_make_trace(const char *path, size_t n, bool poses, trace_t *out)
{
    trace_t t;
    trace_init(&t);
    /* the name the traces have always carried: the shipped fixture
     * eyetracker-20.trace is compared byte for byte with one of these */
    snprintf(t.header.source, sizeof t.header.source, "test_track_umockdev");
    t.header.sample_rate_hz = EMU_RATE_HZ;
    t.header.geometry = (gaze_geometry_t){1920, 1080, 527.04, 296.46, 650, 0};
    t.has_head = t.has_hand = poses;
    for (size_t i = 0; i < n; i++) {
        gaze_sample_t s;
        gaze_sample_invalid(&s, (int64_t)i * 4000000); /* 250 Hz */
        if (i % 9 != 4) { /* every 9th sample (from the 5th) has no gaze */
            s.flags = GAZE_FLAG_VALID;
            /* sweeps that stay within the device's +-2 m logical range */
            s.x_px = 100.0 + fmod(37.5 * (double)i, 1700.0);
            s.y_px = 900.0 - fmod(21.25 * (double)i, 800.0);
        }
        if (poses) {
            /* values exact in float32 after mm -> cm */
            s.flags |= GAZE_FLAG_HEAD | GAZE_FLAG_HAND;
            s.head = (gaze_pose_t){{100.0 + (double)i, -25.0, 302.5}, 5.0 + (double)i, -10.0, 0.5};
            s.hand = (gaze_pose_t){{350.0, 120.0 - 2.0 * (double)i, 200.0}, 90.0, 0.0, -45.0};
        }
        REQUIRE(trace_append(&t, &s) == PP5_OK);
    }
    REQUIRE_MSG(trace_write_file(path, &t) == PP5_OK, "%s", pp5_error_text());
    trace_free(&t);
    REQUIRE_MSG(trace_read_file(path, out) == PP5_OK, "%s", pp5_error_text());
}

void umd_check_gaze_prefix(const trace_t *got, const trace_t *want, size_t n)
{
    REQUIRE(got->count >= n && want->count >= n);
    int bad = 0;
    for (size_t i = 0; i < n; i++) {
        const gaze_sample_t *g = &got->samples[i], *w = &want->samples[i];
        bool gv = (g->flags & GAZE_FLAG_VALID) != 0, wv = (w->flags & GAZE_FLAG_VALID) != 0;
        if (g->t_ns != w->t_ns || gv != wv) {
            if (bad++ == 0)
                printf("    first difference at sample %zu: t %lld vs %lld ns, valid %d vs %d\n", i,
                       (long long)g->t_ns, (long long)w->t_ns, gv, wv);
        }
        /* integer micrometres on a 527 mm area: under 0.002 px of rounding */
        else if (wv && (fabs(g->x_px - w->x_px) > 0.01 || fabs(g->y_px - w->y_px) > 0.01))
            bad++;
    }
    CHECK_MSG(bad == 0, "%d of %zu samples differ from the trace fed to the device", bad, n);
}

void umd_check_pose_prefix(const trace_t *got, const trace_t *want, size_t n)
{
    REQUIRE(got->count >= n && want->count >= n);
    REQUIRE(got->has_head && got->has_hand);
    int bad = 0;
    for (size_t i = 0; i < n; i++) {
        const gaze_sample_t *g = &got->samples[i], *w = &want->samples[i];
        if (!(g->flags & GAZE_FLAG_HEAD) || !(g->flags & GAZE_FLAG_HAND)) {
            bad++;
            continue;
        }
        for (int k = 0; k < 3; k++)
            if (fabs(g->head.pos_mm[k] - w->head.pos_mm[k]) > 1e-3 ||
                fabs(g->hand.pos_mm[k] - w->hand.pos_mm[k]) > 1e-3)
                bad++;
        if (fabs(g->head.azimuth_deg - w->head.azimuth_deg) > 1e-4 ||
            fabs(g->hand.roll_deg - w->hand.roll_deg) > 1e-4 ||
            fabs(g->head.elevation_deg - w->head.elevation_deg) > 1e-4)
            bad++;
    }
    CHECK_MSG(bad == 0, "%d pose values differ from the trace fed to the device", bad);
    for (size_t i = 1; i < got->count; i++)
        CHECK(got->samples[i].t_ns >= got->samples[i - 1].t_ns);
}

bool umd_file_contains(const char *path, const char *needle)
{
    char *s = pp5_test_read_file(path);
    bool ok = s && strstr(s, needle);
    free(s);
    return ok;
}

/* umockdev's preload library must load into the child; without it the
 * devices would simply be absent and every test would fail for a reason
 * that is not pp5's.  Checked once with a throw-away child. */
static int preload_state; /* 0 unknown, 1 loads, -1 missing */

bool umd_preload_available(void)
{
    if (preload_state == 0) {
        FILE *p = popen("LD_PRELOAD=libumockdev-preload.so.0 /bin/true 2>&1", "r");
        char buf[256] = "";
        size_t n = p ? fread(buf, 1, sizeof buf - 1, p) : 0;
        buf[n] = '\0';
        int rc = p ? pclose(p) : -1;
        preload_state = (rc == 0 && !strstr(buf, "cannot be preloaded")) ? 1 : -1;
    }
    return preload_state == 1;
}

#endif /* PP5_HAVE_UMOCKDEV */
