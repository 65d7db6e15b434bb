/* hid_desc.c: HID report-descriptor walker (item grammar of HID 1.11 §6.2.2)
 * producing a flat field table; see hid_desc.h. */
#include "hid_desc.h"

#include <math.h>
#include <string.h>

enum { MAX_USAGES = 256, MAX_PUSH = 8, MAX_REPORT_BITS = 65535 * 8 };

/* Global state (HID 1.11 §6.2.2.7): survives main items, saved by Push. */
typedef struct {
    uint16_t usage_page;
    int32_t logical_min, logical_max;
    int32_t physical_min, physical_max;
    uint32_t unit;
    int8_t unit_exponent;
    uint32_t report_size;
    uint32_t report_count;
    uint8_t report_id;
    /* raw item sizes, to reinterpret max values as unsigned when min >= 0 */
    uint8_t logical_max_bytes, physical_max_bytes;
} hid_global_t;

/* Local state (§6.2.2.8): cleared after every main item. */
typedef struct {
    uint32_t usages[MAX_USAGES]; /* page << 16 | usage */
    size_t n_usages;
    uint32_t usage_min;
    int have_min;
} hid_local_t;

typedef struct {
    uint16_t page, usage;
} hid_collection_t;

typedef struct {
    const uint8_t *desc;
    size_t len;
    hid_desc_t *out;
    hid_global_t g;
    hid_global_t stack[MAX_PUSH];
    size_t depth_push;
    hid_local_t l;
    hid_collection_t coll[HID_DESC_MAX_DEPTH];
    size_t depth;
} walker_t;

static uint32_t item_unsigned(const uint8_t *p, size_t n)
{
    uint32_t v = 0;
    for (size_t i = 0; i < n; i++)
        v |= (uint32_t)p[i] << (8 * i);
    return v;
}

static int32_t item_signed(const uint8_t *p, size_t n)
{
    uint32_t v = item_unsigned(p, n);
    if (n == 1)
        return (int8_t)v;
    if (n == 2)
        return (int16_t)v;
    if (n == 4)
        return (int32_t)v;
    return 0;
}

/* Descriptors commonly write e.g. Logical Minimum 0, Logical Maximum 0xFF
 * in one byte; read signed that would be -1, so when the minimum is not
 * negative a maximum below it is reinterpreted as unsigned (what the Linux
 * and Windows parsers do too). */
static int32_t fix_max(int32_t min, int32_t max, uint8_t bytes)
{
    if (min >= 0 && max < min && bytes > 0 && bytes < 4)
        return (int32_t)((uint32_t)max & ((1u << (8 * bytes)) - 1u));
    return max;
}

static hid_report_info_t *report_slot(walker_t *w, hid_report_type_t type, uint8_t id,
                                      pp5_status_t *st)
{
    hid_desc_t *d = w->out;
    for (size_t i = 0; i < d->n_reports; i++)
        if (d->reports[i].type == type && d->reports[i].report_id == id)
            return &d->reports[i];
    if (d->n_reports == HID_DESC_MAX_REPORTS) {
        *st = pp5_fail(PP5_E_RANGE, "HID descriptor declares more than %d reports",
                       HID_DESC_MAX_REPORTS);
        return NULL;
    }
    hid_report_info_t *r = &d->reports[d->n_reports++];
    *r = (hid_report_info_t){type, id, 0};
    return r;
}

static pp5_status_t add_main(walker_t *w, hid_report_type_t type, uint32_t flags, size_t at)
{
    hid_global_t *g = &w->g;
    if (g->report_count == 0)
        return PP5_OK;
    if (g->report_size == 0 || g->report_size > 32)
        return pp5_fail(PP5_E_FORMAT,
                        "HID descriptor byte %zu: main item with report size %u (need 1..32)",
                        at, g->report_size);
    if (g->report_count > 4096)
        return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: report count %u is absurd", at,
                        g->report_count);
    pp5_status_t st = PP5_OK;
    hid_report_info_t *r = report_slot(w, type, g->report_id, &st);
    if (!r)
        return st;
    uint64_t total_bits = (uint64_t)g->report_size * g->report_count;
    if (r->bits + total_bits > MAX_REPORT_BITS)
        return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: report %u longer than 64 KiB",
                        at, g->report_id);
    uint32_t base = r->bits;
    r->bits += (uint32_t)total_bits;

    hid_local_t *l = &w->l;
    bool is_const = (flags & HID_FLAG_CONSTANT) != 0;
    if (l->n_usages == 0 && is_const)
        return PP5_OK; /* padding: occupies bits, names nothing */

    hid_field_t proto = {0};
    proto.type = type;
    proto.report_id = g->report_id;
    proto.bit_size = g->report_size;
    proto.flags = flags;
    proto.logical_min = g->logical_min;
    proto.logical_max = fix_max(g->logical_min, g->logical_max, g->logical_max_bytes);
    proto.physical_min = g->physical_min;
    proto.physical_max = fix_max(g->physical_min, g->physical_max, g->physical_max_bytes);
    proto.unit = g->unit;
    proto.unit_exponent = g->unit_exponent;
    if (w->depth > 0) {
        proto.parent_usage = w->coll[w->depth - 1].usage;
        proto.parent_page = w->coll[w->depth - 1].page;
        proto.app_usage = w->coll[0].usage;
    }

    bool variable = (flags & HID_FLAG_VARIABLE) != 0;
    uint32_t n_new = variable ? g->report_count : 1;
    if (w->out->n_fields + n_new > HID_DESC_MAX_FIELDS)
        return pp5_fail(PP5_E_RANGE, "HID descriptor has more than %d fields",
                        HID_DESC_MAX_FIELDS);
    for (uint32_t i = 0; i < n_new; i++) {
        hid_field_t f = proto;
        /* HID 1.11 §6.2.2.8: with fewer usages than values, the last usage
         * applies to the remaining values. */
        uint32_t u = 0;
        if (l->n_usages > 0)
            u = l->usages[i < l->n_usages ? i : l->n_usages - 1];
        else
            u = (uint32_t)g->usage_page << 16;
        f.usage_page = (uint16_t)(u >> 16);
        f.usage = (uint16_t)(u & 0xFFFF);
        if (variable) {
            f.bit_offset = base + i * g->report_size;
            f.count = 1;
        } else {
            f.bit_offset = base;
            f.count = g->report_count;
        }
        w->out->fields[w->out->n_fields++] = f;
    }
    return PP5_OK;
}

static void add_usage(walker_t *w, uint32_t u)
{
    if (w->l.n_usages < MAX_USAGES)
        w->l.usages[w->l.n_usages++] = u;
}

static uint32_t full_usage(const walker_t *w, uint32_t data, size_t size)
{
    /* A 4-byte usage carries its own page in the high half (§6.2.2.8). */
    return size == 4 ? data : ((uint32_t)w->g.usage_page << 16) | (data & 0xFFFF);
}

static pp5_status_t do_main(walker_t *w, unsigned tag, uint32_t data, size_t at)
{
    pp5_status_t st = PP5_OK;
    switch (tag) {
    case 0x8: st = add_main(w, HID_REPORT_INPUT, data, at); break;
    case 0x9: st = add_main(w, HID_REPORT_OUTPUT, data, at); break;
    case 0xB: st = add_main(w, HID_REPORT_FEATURE, data, at); break;
    case 0xA: { /* Collection */
        if (w->depth == HID_DESC_MAX_DEPTH)
            return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: collections nested deeper than %d",
                            at, HID_DESC_MAX_DEPTH);
        uint32_t u = w->l.n_usages ? w->l.usages[0] : 0;
        w->coll[w->depth++] = (hid_collection_t){(uint16_t)(u >> 16), (uint16_t)(u & 0xFFFF)};
        break;
    }
    case 0xC: /* End Collection */
        if (w->depth == 0)
            return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: End Collection without Collection",
                            at);
        w->depth--;
        break;
    default:
        return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: unknown main item tag 0x%x", at,
                        tag);
    }
    memset(&w->l, 0, sizeof w->l);
    return st;
}

static pp5_status_t do_global(walker_t *w, unsigned tag, const uint8_t *p, size_t size,
                              size_t at)
{
    hid_global_t *g = &w->g;
    uint32_t u = item_unsigned(p, size);
    switch (tag) {
    case 0x0: g->usage_page = (uint16_t)u; break;
    case 0x1: g->logical_min = item_signed(p, size); break;
    case 0x2: g->logical_max = item_signed(p, size); g->logical_max_bytes = (uint8_t)size; break;
    case 0x3: g->physical_min = item_signed(p, size); break;
    case 0x4: g->physical_max = item_signed(p, size); g->physical_max_bytes = (uint8_t)size; break;
    case 0x5:
        /* HID 1.11 stores the exponent as a 4-bit two's-complement nibble
         * (0x0C = -4); some devices write a full signed byte (0xFC). */
        if (u <= 0xF)
            g->unit_exponent = (int8_t)(u >= 8 ? (int)u - 16 : (int)u);
        else
            g->unit_exponent = (int8_t)item_signed(p, size);
        break;
    case 0x6: g->unit = u; break;
    case 0x7: g->report_size = u; break;
    case 0x8:
        if (u == 0 || u > 255)
            return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: report id %u (need 1..255)",
                            at, u);
        g->report_id = (uint8_t)u;
        w->out->uses_report_ids = 1;
        break;
    case 0x9: g->report_count = u; break;
    case 0xA:
        if (w->depth_push == MAX_PUSH)
            return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: Push nested deeper than %d",
                            at, MAX_PUSH);
        w->stack[w->depth_push++] = *g;
        break;
    case 0xB:
        if (w->depth_push == 0)
            return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: Pop without Push", at);
        *g = w->stack[--w->depth_push];
        break;
    default:
        return pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: reserved global item tag 0x%x",
                        at, tag);
    }
    return PP5_OK;
}

static void do_local(walker_t *w, unsigned tag, uint32_t data, size_t size)
{
    hid_local_t *l = &w->l;
    switch (tag) {
    case 0x0: add_usage(w, full_usage(w, data, size)); break;
    case 0x1: l->usage_min = full_usage(w, data, size); l->have_min = 1; break;
    case 0x2:
        if (l->have_min) {
            uint32_t max = full_usage(w, data, size);
            /* expand the range, bounded by MAX_USAGES so a hostile 0..0xFFFF
             * range costs nothing */
            for (uint32_t u = l->usage_min; u <= max && l->n_usages < MAX_USAGES; u++)
                add_usage(w, u);
            l->have_min = 0;
        }
        break;
    default: break; /* designators, strings, delimiters: not needed */
    }
}

pp5_status_t hid_desc_parse(const uint8_t *desc, size_t len, hid_desc_t *out)
{
    memset(out, 0, sizeof *out);
    if (!desc || len == 0)
        return pp5_fail(PP5_E_FORMAT, "HID descriptor is empty");
    walker_t *w = &(walker_t){0};
    w->desc = desc;
    w->len = len;
    w->out = out;
    size_t i = 0;
    while (i < len) {
        uint8_t prefix = desc[i];
        if (prefix == 0xFE) { /* long item: FE, size, tag, data (§6.2.2.3) */
            if (len - i < 3)
                return pp5_fail(PP5_E_FORMAT, "HID descriptor truncated in long item at byte %zu", i);
            size_t n = desc[i + 1];
            if (len - i - 3 < n)
                return pp5_fail(PP5_E_FORMAT, "HID descriptor truncated in long item at byte %zu", i);
            i += 3 + n;
            continue;
        }
        size_t size = prefix & 3;
        if (size == 3)
            size = 4;
        unsigned type = (prefix >> 2) & 3, tag = prefix >> 4;
        if (len - i - 1 < size)
            return pp5_fail(PP5_E_FORMAT,
                            "HID descriptor truncated: item 0x%02x at byte %zu needs %zu data "
                            "bytes, %zu left", prefix, i, size, len - i - 1);
        const uint8_t *p = desc + i + 1;
        uint32_t data = item_unsigned(p, size);
        pp5_status_t st = PP5_OK;
        if (type == 0)
            st = do_main(w, tag, data, i);
        else if (type == 1)
            st = do_global(w, tag, p, size, i);
        else if (type == 2)
            do_local(w, tag, data, size);
        else
            st = pp5_fail(PP5_E_FORMAT, "HID descriptor byte %zu: reserved item type 3", i);
        if (st != PP5_OK)
            return st;
        i += 1 + size;
    }
    if (w->depth != 0)
        return pp5_fail(PP5_E_FORMAT, "HID descriptor ends inside %zu open collection(s)",
                        w->depth);
    if (out->n_fields == 0)
        return pp5_fail(PP5_E_FORMAT, "HID descriptor declares no fields");
    return PP5_OK;
}

const hid_field_t *hid_desc_find_nth(const hid_desc_t *d, hid_report_type_t type,
                                     uint16_t page, uint16_t parent_usage, uint16_t usage,
                                     size_t n)
{
    for (size_t i = 0; i < d->n_fields; i++) {
        const hid_field_t *f = &d->fields[i];
        if (f->type != type || f->usage_page != page || f->usage != usage)
            continue;
        if (parent_usage != 0 && f->parent_usage != parent_usage)
            continue;
        if (n-- == 0)
            return f;
    }
    return NULL;
}

const hid_field_t *hid_desc_find(const hid_desc_t *d, hid_report_type_t type, uint16_t page,
                                 uint16_t parent_usage, uint16_t usage)
{
    return hid_desc_find_nth(d, type, page, parent_usage, usage, 0);
}

size_t hid_desc_report_bytes(const hid_desc_t *d, hid_report_type_t type, uint8_t report_id)
{
    for (size_t i = 0; i < d->n_reports; i++)
        if (d->reports[i].type == type && d->reports[i].report_id == report_id)
            return (d->reports[i].bits + 7) / 8 + (d->uses_report_ids ? 1 : 0);
    return 0;
}

pp5_status_t hid_field_raw(const hid_desc_t *d, const hid_field_t *f, uint32_t index,
                           const uint8_t *report, size_t len, int64_t *out)
{
    if (index >= f->count)
        return pp5_fail(PP5_E_RANGE, "HID field element %u of %u", index, f->count);
    uint64_t bit = (uint64_t)f->bit_offset + (uint64_t)index * f->bit_size +
                   (d->uses_report_ids ? 8u : 0u);
    uint64_t end_byte = (bit + f->bit_size + 7) / 8;
    if (end_byte > len)
        return pp5_fail(PP5_E_FORMAT,
                        "HID report 0x%02x too short: %zu bytes, field needs %llu", f->report_id,
                        len, (unsigned long long)end_byte);
    uint64_t v = 0;
    for (uint32_t b = 0; b < f->bit_size; b++) {
        uint64_t pos = bit + b;
        if ((report[pos / 8] >> (pos % 8)) & 1u)
            v |= (uint64_t)1 << b;
    }
    if (f->logical_min < 0 && f->bit_size < 64 && (v >> (f->bit_size - 1)) & 1u)
        v |= ~(uint64_t)0 << f->bit_size; /* sign-extend */
    *out = (int64_t)v;
    return PP5_OK;
}

double hid_field_physical(const hid_field_t *f, int64_t raw)
{
    if ((f->physical_min == 0 && f->physical_max == 0) || f->logical_max == f->logical_min)
        return (double)raw;
    /* HID 1.11 §6.2.2.7: linear map of the logical onto the physical range. */
    double t = ((double)raw - f->logical_min) / ((double)f->logical_max - f->logical_min);
    return f->physical_min + t * ((double)f->physical_max - f->physical_min);
}

static int unit_nibble(uint32_t unit, int i)
{
    int v = (int)((unit >> (4 * i)) & 0xF);
    return v >= 8 ? v - 16 : v;
}

hid_unit_kind_t hid_field_si_factor(const hid_field_t *f, double *factor)
{
    double scale = pow(10.0, f->unit_exponent);
    *factor = scale;
    uint32_t u = f->unit;
    if (u == 0)
        return HID_UNIT_NONE;
    int system = (int)(u & 0xF);
    int length = unit_nibble(u, 1), time = unit_nibble(u, 3);
    uint32_t others = u & 0xFFF0F00u; /* mass, temperature, current, luminous */
    if (others != 0)
        return HID_UNIT_OTHER;
    if (length == 1 && time == 0) {
        /* HID 1.11 §6.2.2.7 unit table: SI linear cm, English linear inch,
         * SI rotation radians, English rotation degrees. */
        switch (system) {
        case 1: *factor = scale * 0.01; return HID_UNIT_LENGTH;
        case 3: *factor = scale * 0.0254; return HID_UNIT_LENGTH;
        case 2: *factor = scale; return HID_UNIT_ROTATION;
        case 4: *factor = scale * M_PI / 180.0; return HID_UNIT_ROTATION;
        default: return HID_UNIT_OTHER;
        }
    }
    if (length == 0 && time == 1 && system >= 1 && system <= 4)
        return HID_UNIT_TIME;
    if (length == 0 && time == -1 && system >= 1 && system <= 4)
        return HID_UNIT_FREQUENCY;
    return HID_UNIT_OTHER;
}
