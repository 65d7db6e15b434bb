/* hid_desc.h: a HID report-descriptor walker that turns a descriptor into a
 * flat list of fields (report type, report id, bit position, size, usage,
 * parent collection usages, logical/physical range, unit and exponent).
 *
 * Why a walker and not fixed offsets: the reference page-0x12 descriptors
 * differ in detail (constant vs data flags, labelled or unlabelled head
 * fields, a 64-bit timestamp split into 8 x 8-bit fields), see
 * ../shared/docs/tracker-devices.md §1.2 "Quirks a parser must survive".
 *
 * Modelled: short items of all three types (main, global, local), Push/Pop,
 * extended (32-bit) usages, Usage Minimum/Maximum ranges, nested collections,
 * report ids, Input/Output/Feature reports, signed logical ranges.
 * Not modelled: long items (skipped, they carry no field data), delimiters
 * (only the first usage of a set is used), string/designator indices
 * (ignored).  The walker never reads past the end of the descriptor: a
 * truncated item is a PP5_E_FORMAT error naming the byte offset. */
#ifndef PP5_HID_DESC_H
#define PP5_HID_DESC_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

enum { HID_DESC_MAX_FIELDS = 1024, HID_DESC_MAX_DEPTH = 16, HID_DESC_MAX_REPORTS = 64 };

typedef enum { HID_REPORT_INPUT = 0, HID_REPORT_OUTPUT = 1, HID_REPORT_FEATURE = 2 } hid_report_type_t;

/* Main-item flag bits (HID 1.11 §6.2.2.5). */
enum { HID_FLAG_CONSTANT = 0x01, HID_FLAG_VARIABLE = 0x02, HID_FLAG_RELATIVE = 0x04 };

/* One value in one report: a Variable item expands to one field per
 * report_count element; an Array item stays one field with count > 1. */
typedef struct {
    hid_report_type_t type;
    uint8_t report_id;         /* 0 when the descriptor declares no ids */
    uint32_t bit_offset;       /* from the first byte after the report id */
    uint32_t bit_size;         /* report size, 1..32 */
    uint32_t count;            /* 1 for variables; report count for arrays */
    uint16_t usage_page;
    uint16_t usage;            /* 0 when no usage was declared */
    uint16_t parent_usage;     /* usage of the innermost enclosing collection */
    uint16_t parent_page;
    uint16_t app_usage;        /* usage of the outermost (application) collection */
    uint32_t flags;            /* HID_FLAG_* bits of the main item */
    int32_t logical_min, logical_max;
    int32_t physical_min, physical_max; /* both 0: same as logical (HID 1.11 §6.2.2.7) */
    uint32_t unit;             /* HID unit code, e.g. 0x11 = SI linear, cm */
    int8_t unit_exponent;      /* power of ten, from a 4-bit two's-complement nibble */
} hid_field_t;

typedef struct {
    hid_report_type_t type;
    uint8_t report_id;
    uint32_t bits;             /* total size, without the id byte */
} hid_report_info_t;

typedef struct {
    hid_field_t fields[HID_DESC_MAX_FIELDS];
    size_t n_fields;
    hid_report_info_t reports[HID_DESC_MAX_REPORTS];
    size_t n_reports;
    int uses_report_ids;       /* 1 if any Report ID item appeared */
} hid_desc_t;

/* Walks `len` bytes into `out` (fully overwritten).  PP5_E_FORMAT on a
 * truncated item, unbalanced collections, Pop without Push, a field that
 * is not 1..32 bits wide, or a report longer than 64 KiB;
 * PP5_E_RANGE when the descriptor has more fields than HID_DESC_MAX_FIELDS. */
pp5_status_t hid_desc_parse(const uint8_t *desc, size_t len, hid_desc_t *out);

/* First field of report `type` with (page, parent collection usage, usage);
 * parent_usage 0 matches any parent.  NULL if none. */
const hid_field_t *hid_desc_find(const hid_desc_t *d, hid_report_type_t type, uint16_t page,
                                 uint16_t parent_usage, uint16_t usage);
/* The n-th (0-based) field matching like hid_desc_find, NULL if fewer. */
const hid_field_t *hid_desc_find_nth(const hid_desc_t *d, hid_report_type_t type,
                                     uint16_t page, uint16_t parent_usage, uint16_t usage,
                                     size_t n);

/* Size in bytes of report (type, id), including the id byte when the
 * descriptor uses ids; 0 if the report is not declared. */
size_t hid_desc_report_bytes(const hid_desc_t *d, hid_report_type_t type, uint8_t report_id);

/* Raw value of element `index` (< f->count) of `f` from a report buffer
 * that starts with the id byte when the descriptor uses ids.  Sign-extended
 * when logical_min < 0.  PP5_E_FORMAT if the report is too short. */
pp5_status_t hid_field_raw(const hid_desc_t *d, const hid_field_t *f, uint32_t index,
                           const uint8_t *report, size_t len, int64_t *out);

/* Kind of quantity a unit code describes, for the conversions below. */
typedef enum {
    HID_UNIT_NONE = 0, HID_UNIT_LENGTH, HID_UNIT_TIME, HID_UNIT_FREQUENCY, HID_UNIT_ROTATION,
    HID_UNIT_OTHER
} hid_unit_kind_t;

/* Classifies f->unit and gives the factor that turns a value in physical
 * units (after hid_field_physical) into SI base units: metres, seconds,
 * hertz, radians.  Unit exponent is applied here. */
hid_unit_kind_t hid_field_si_factor(const hid_field_t *f, double *factor);

/* Raw value mapped from the logical to the physical range (identity when no
 * physical range is given), not yet scaled by unit or exponent. */
double hid_field_physical(const hid_field_t *f, int64_t raw);

#endif
