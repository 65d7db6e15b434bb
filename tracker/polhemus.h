/* polhemus.h: Polhemus Patriot and Liberty (and their HS versions, and the
 * Liberty Latus) over USB through libusb bulk transfers: model table,
 * initialisation, polling, and the binary record parser.
 *
 * Facts (../shared/docs/tracker-devices.md §2): VID 0x0f44; PIDs, endpoints
 * and record tags in §2.1 [S] (udev rules, VRPN, PiTerm tables; the 'PA'
 * Patriot tag is from the manual and [U] in code); ASCII 3SPACE command set
 * §2.2; binary record = 8-byte header ('LY'/'PA'/'LU', station, command,
 * error, reserved, u16 size) + little-endian float32 items §2.3; init
 * sequence §2.4.
 *
 * pp5 always selects the output list O*,2,4,1 (position x,y,z; Euler
 * azimuth, elevation, roll; CR/LF), binary (F1) and centimetres (U1), so a
 * record's payload is 6 floats + "\r\n" = 26 bytes.  The parser is driven by
 * the header's size field, so it checks, rather than assumes, that layout.
 *
 * Modelled: polled operation ('P' per sample), any number of stations per
 * transfer, per-record error indicators, timeouts and disconnects.
 * Not modelled: continuous mode ('C'), quaternion output, the Fastrak over
 * USB (its records are parsed by tracker/fastrak.h), the Viper and G4
 * (different protocols), firmware loading (fxload; the user's udev rules). */
#ifndef PP5_POLHEMUS_H
#define PP5_POLHEMUS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gaze.h"
#include "status.h"

#define POLHEMUS_VID 0x0f44
enum { POLHEMUS_MAX_STATIONS = 16, POLHEMUS_IN_BYTES = 512 };

typedef struct {
    uint16_t pid;
    const char *name;
    uint8_t ep_out, ep_in;
    char tag[3];            /* record tag, e.g. "PA" */
} polhemus_model_t;

/* NULL when the PID is not a (post-firmware) Patriot/Liberty. */
const polhemus_model_t *polhemus_model_for_pid(uint16_t pid);
/* Pre-firmware PIDs (ef11, ef21, ff11, ff21): the device needs fxload. */
bool polhemus_pid_needs_firmware(uint16_t pid);

typedef struct {
    uint8_t station;        /* 1-based */
    uint8_t command;        /* initiating command, 'P' when polled */
    uint8_t error;          /* 0 or ' ' for no error */
    double pos_cm[3];       /* x, y, z */
    double euler_deg[3];    /* azimuth, elevation, roll */
} polhemus_record_t;

static inline bool polhemus_record_ok(const polhemus_record_t *r)
{
    return r->error == 0 || r->error == ' ';
}

/* Parses the records of one bulk IN transfer (concatenated, one per active
 * station) with tag `tag` (2 chars).  PP5_E_FORMAT for a wrong tag, a size
 * that is not the O*,2,4,1 payload (24 or 26 bytes), a truncated record, a
 * non-finite value, or more than `max` records; the message names the byte
 * offset. */
pp5_status_t polhemus_parse_records(const uint8_t *buf, size_t len, const char *tag,
                                    polhemus_record_t *recs, size_t max, size_t *n);

/* ---- devices (libusb) ---- */

typedef struct {
    uint8_t bus, address;
    uint16_t pid;
    const char *model;      /* static string */
    bool needs_firmware;
} polhemus_info_t;

pp5_status_t polhemus_list(polhemus_info_t *out, size_t max, size_t *n);

typedef struct polhemus polhemus_t;

typedef struct {
    uint64_t polls, records, record_errors, malformed_transfers;
    uint8_t last_error_station, last_error_code; /* the latest error indicator */
} polhemus_stats_t;

/* Opens the first Patriot/Liberty (or the one at "BUS:ADDR"), claims
 * interface 0 and runs the init sequence.  Every transfer is bounded by
 * timeout_ms.  PP5_E_DEVICE with a message for: none found, needs firmware,
 * permission denied, busy, a command not accepted. */
pp5_status_t polhemus_open(const char *bus_addr, int timeout_ms, polhemus_t **out);
const polhemus_model_t *polhemus_model(const polhemus_t *p);
const polhemus_stats_t *polhemus_stats(const polhemus_t *p);
/* One poll: sends 'P', reads one transfer, parses it.  A transfer that does
 * not parse is counted and retried; more than POLHEMUS_MAX_BAD_IN_A_ROW in a
 * row is an error.  PP5_E_DEVICE on timeout or disconnect. */
enum { POLHEMUS_MAX_BAD_IN_A_ROW = 20 };
pp5_status_t polhemus_poll(polhemus_t *p, polhemus_record_t *recs, size_t max, size_t *n);
void polhemus_close(polhemus_t *p);

/* A gaze_source_t over an open tracker (takes ownership of `p`): one poll
 * per sample, paced at rate_hz (polled records carry no device clock, so
 * the host's monotonic clock stamps them, relative to the first sample).
 * Samples have no gaze; head and hand poses (mm, degrees) come from the
 * given stations, and a station whose record carries an error indicator is
 * left out of that sample (counted in polhemus_stats). */
pp5_status_t polhemus_source_open(polhemus_t *p, int head_station, int hand_station,
                                  double rate_hz, gaze_source_t **out);

#endif
