/* fastrak.h: Polhemus Fastrak (3SPACE) record parser, binary and ASCII.
 *
 * Facts (../shared/docs/tracker-devices.md §2.3, from vrpn_Tracker_Fastrak.C,
 * [S]): a record is '0', the station character '1'..'4', a status character
 * (space, or 'A'..'F' for warnings), then the items of the output list; in
 * binary mode ('f') each value is a little-endian float32, and a trailing
 * space follows when item 0 (space) is in the list.  Positions are inches
 * unless metric mode ('u') is on.  Readers resynchronise on '0' + station.
 *
 * ASCII records (mode 'F') carry the same header and the values as decimal
 * text.  The manual's fixed-width "Sxxx.xx" fields are [U] here (not in our
 * sources), so the parser reads values with strtod one after another, which
 * accepts fixed-width fields (even with no space before a '-') and
 * space-separated ones alike, and requires the record to end in CR LF.
 *
 * Not modelled: stylus and quaternion items' meaning (they parse as floats
 * if counted in n_values), the Fastrak's serial/USB transport. */
#ifndef PP5_FASTRAK_H
#define PP5_FASTRAK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

enum { FASTRAK_MAX_VALUES = 16 };

typedef struct {
    int n_values;           /* floats per record: 6 for items 2,4 (xyz + az,el,roll) */
    bool trailing_space;    /* binary: item 0 appended to the list */
} fastrak_format_t;

typedef struct {
    uint8_t station;        /* 1..4 */
    char status;            /* ' ' or 'A'..'F' */
    double values[FASTRAK_MAX_VALUES];
    int n_values;
} fastrak_record_t;

/* Scans `buf` for the next binary record.  On success *consumed counts the
 * bytes up to the end of the record (garbage skipped while resynchronising
 * included, also reported in *skipped).  PP5_E_FORMAT when no complete
 * record is in the buffer (then *consumed = bytes that can be dropped), or
 * a value is not finite, or the status character is not ' ' / 'A'..'F'. */
pp5_status_t fastrak_parse_binary(const uint8_t *buf, size_t len, const fastrak_format_t *fmt,
                                  fastrak_record_t *rec, size_t *consumed, size_t *skipped);

/* Parses one ASCII record starting at buf (after resynchronising like the
 * binary parser) up to and including its CR LF. */
pp5_status_t fastrak_parse_ascii(const char *buf, size_t len, const fastrak_format_t *fmt,
                                 fastrak_record_t *rec, size_t *consumed, size_t *skipped);

#endif
