/* fastrak.c: Polhemus Fastrak binary and ASCII record parsing; see fastrak.h. */
#include "fastrak.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool status_ok(uint8_t c)
{
    return c == ' ' || (c >= 'A' && c <= 'F');
}

/* Index of the next '0' followed by a station digit, or len if none; a
 * lone '0' as the last byte is kept (it may start a record). */
static size_t find_start(const uint8_t *buf, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (buf[i] != '0')
            continue;
        if (i + 1 == len || (buf[i + 1] >= '1' && buf[i + 1] <= '4'))
            return i;
    }
    return len;
}

static pp5_status_t check_format(const fastrak_format_t *fmt)
{
    if (fmt->n_values < 1 || fmt->n_values > FASTRAK_MAX_VALUES)
        return pp5_fail(PP5_E_CONFIG, "Fastrak format with %d values (1..%d)", fmt->n_values,
                        FASTRAK_MAX_VALUES);
    return PP5_OK;
}

pp5_status_t fastrak_parse_binary(const uint8_t *buf, size_t len, const fastrak_format_t *fmt,
                                  fastrak_record_t *rec, size_t *consumed, size_t *skipped)
{
    *consumed = *skipped = 0;
    pp5_status_t st = check_format(fmt);
    if (st != PP5_OK)
        return st;
    size_t start = find_start(buf, len);
    *skipped = start;
    size_t need = 3 + 4 * (size_t)fmt->n_values + (fmt->trailing_space ? 1 : 0);
    if (len - start < need) {
        *consumed = start;
        return pp5_fail(PP5_E_FORMAT, "no complete Fastrak binary record (%zu of %zu bytes)",
                        len - start, need);
    }
    const uint8_t *r = buf + start;
    if (!status_ok(r[2])) {
        *consumed = start + 1; /* drop the false start, resynchronise after it */
        return pp5_fail(PP5_E_FORMAT, "Fastrak record at byte %zu: bad status byte 0x%02x", start,
                        r[2]);
    }
    fastrak_record_t out = {.station = (uint8_t)(r[1] - '0'), .status = (char)r[2],
                            .n_values = fmt->n_values};
    for (int i = 0; i < fmt->n_values; i++) {
        const uint8_t *p = r + 3 + 4 * i;
        uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
                     (uint32_t)p[3] << 24;
        float f;
        memcpy(&f, &u, sizeof f);
        if (!isfinite(f)) {
            *consumed = start + 1;
            return pp5_fail(PP5_E_FORMAT, "Fastrak record at byte %zu: value %d is not finite",
                            start, i);
        }
        out.values[i] = f;
    }
    if (fmt->trailing_space && r[need - 1] != ' ') {
        *consumed = start + 1;
        return pp5_fail(PP5_E_FORMAT, "Fastrak record at byte %zu lacks its trailing space",
                        start);
    }
    *rec = out;
    *consumed = start + need;
    return PP5_OK;
}

pp5_status_t fastrak_parse_ascii(const char *buf, size_t len, const fastrak_format_t *fmt,
                                 fastrak_record_t *rec, size_t *consumed, size_t *skipped)
{
    *consumed = *skipped = 0;
    pp5_status_t st = check_format(fmt);
    if (st != PP5_OK)
        return st;
    const uint8_t *u = (const uint8_t *)buf;
    size_t start = find_start(u, len);
    *skipped = start;
    /* the record must be complete: find its CR LF first, so strtod never
     * runs past the buffer (it stops at '\r', which is not numeric) */
    size_t end = start;
    while (end + 1 < len && !(u[end] == '\r' && u[end + 1] == '\n'))
        end++;
    if (end + 1 >= len) {
        *consumed = start;
        return pp5_fail(PP5_E_FORMAT, "no complete Fastrak ASCII record (no CR LF)");
    }
    size_t rec_len = end - start; /* without CR LF */
    if (rec_len < 3 || !status_ok(u[start + 2])) {
        *consumed = end + 2;
        return pp5_fail(PP5_E_FORMAT, "Fastrak ASCII record at byte %zu: bad header", start);
    }
    char line[512];
    if (rec_len >= sizeof line) {
        *consumed = end + 2;
        return pp5_fail(PP5_E_FORMAT, "Fastrak ASCII record at byte %zu is %zu bytes long",
                        start, rec_len);
    }
    memcpy(line, buf + start, rec_len);
    line[rec_len] = '\0';
    fastrak_record_t out = {.station = (uint8_t)(line[1] - '0'), .status = line[2],
                            .n_values = fmt->n_values};
    const char *p = line + 3;
    for (int i = 0; i < fmt->n_values; i++) {
        char *e;
        double v = strtod(p, &e);
        if (e == p || !isfinite(v)) {
            *consumed = end + 2;
            return pp5_fail(PP5_E_FORMAT,
                            "Fastrak ASCII record at byte %zu: value %d of %d missing or bad",
                            start, i + 1, fmt->n_values);
        }
        out.values[i] = v;
        p = e;
    }
    while (*p == ' ')
        p++;
    *consumed = end + 2;
    if (*p != '\0')
        return pp5_fail(PP5_E_FORMAT, "Fastrak ASCII record at byte %zu: extra text '%.16s'",
                        start, p);
    *rec = out;
    return PP5_OK;
}
