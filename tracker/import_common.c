/* import_common.c: what the importers share: options, format names and
 * detection, line and field splitting, and the display remapping. */
#include "import.h"

#include <errno.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "angles.h"
#include "input_limits.h"

void import_defaults(import_options_t *o)
{
    memset(o, 0, sizeof *o);
    o->pupil_min_confidence = 0.6;
}

static const char *const format_names[] = {"auto", "eyelink", "tobii", "pupil", "shared"};

bool import_format_parse(const char *name, import_format_t *f)
{
    for (int i = 0; i < 5; i++)
        if (strcmp(name, format_names[i]) == 0) {
            *f = (import_format_t)i;
            return true;
        }
    return false;
}

static bool starts(const char *text, size_t len, const char *prefix)
{
    size_t n = strlen(prefix);
    return len >= n && memcmp(text, prefix, n) == 0;
}

static bool first_line_has(const char *text, size_t len, const char *word)
{
    const char *nl = memchr(text, '\n', len);
    size_t n = nl ? (size_t)(nl - text) : len, w = strlen(word);
    for (size_t i = 0; i + w <= n; i++)
        if (memcmp(text + i, word, w) == 0)
            return true;
    return false;
}

import_format_t import_detect(const char *text, size_t len)
{
    if (starts(text, len, "# gaze-trace v1"))
        return IMPORT_SHARED;
    /* EyeLink ASC: edf2asc writes a "** CONVERTED FROM" preamble. */
    if (starts(text, len, "**"))
        return IMPORT_EYELINK;
    if (first_line_has(text, len, "gaze_timestamp") || first_line_has(text, len, "x_norm"))
        return IMPORT_PUPIL;
    if (first_line_has(text, len, "Gaze point X") || first_line_has(text, len, "GazePos2dx"))
        return IMPORT_TOBII;
    return IMPORT_AUTO;   /* unknown */
}

void import_apply_geometry(const import_options_t *o, gaze_geometry_t *g)
{
    if (o->source_width_px > 0 && o->source_height_px > 0) {
        g->width_px = o->source_width_px;
        g->height_px = o->source_height_px;
    }
    if (o->source_width_mm > 0 && o->source_height_mm > 0) {
        g->width_mm = o->source_width_mm;
        g->height_mm = o->source_height_mm;
    }
    if (o->source_distance_mm > 0)
        g->distance_mm = o->source_distance_mm;
    if (o->source_px_per_deg > 0)
        g->px_per_deg = o->source_px_per_deg;
}

bool import_next_line(const char *text, size_t len, size_t *pos, char *buf, size_t size,
                      bool *too_long)
{
    *too_long = false;
    if (*pos >= len)
        return false;
    const char *start = text + *pos;
    const char *nl = memchr(start, '\n', len - *pos);
    size_t n = nl ? (size_t)(nl - start) : len - *pos;
    *pos += n + (nl ? 1 : 0);
    if (n > 0 && start[n - 1] == '\r')
        n--;
    if (n >= size) {
        *too_long = true;
        n = size - 1;
    }
    memcpy(buf, start, n);
    buf[n] = '\0';
    return true;
}

int import_split(char *line, char sep, char **fields, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        if (n == max)
            return -1;
        if (sep == ',' && *p == '"') {
            /* A quoted CSV field: up to the closing quote ("" is a quote). */
            char *w = ++p;
            fields[n++] = w;
            while (*p && !(*p == '"' && p[1] != '"')) {
                if (*p == '"')
                    p++;
                *w++ = *p++;
            }
            if (*p == '"')
                p++;
            *w = '\0';
            if (*p != sep)
                return *p ? -1 : n;
            p++;
            continue;
        }
        fields[n++] = p;
        char *s = strchr(p, sep);
        if (!s)
            return n;
        *s = '\0';
        p = s + 1;
    }
}

bool import_parse_double(const char *s, double *out)
{
    char *end;
    while (*s == ' ')
        s++;
    if (!*s)
        return false;
    errno = 0;
    double v = strtod(s, &end);
    while (*end == ' ')
        end++;
    if (end == s || *end != '\0' || errno == ERANGE)
        return false;
    *out = v;
    return true;
}

pp5_status_t import_file(const char *path, import_format_t format, const import_options_t *o,
                         trace_t *out)
{
    char *text;
    size_t len;
    pp5_status_t st = trace_slurp(path, 0, &text, &len);
    if (st != PP5_OK)
        return st;
    if (format == IMPORT_AUTO) {
        format = import_detect(text, len);
        if (format == IMPORT_AUTO) {
            free(text);
            return pp5_fail(PP5_E_FORMAT, "%s: cannot tell the format (not EyeLink ASC, Tobii "
                            "TSV, Pupil Labs CSV or gaze-trace v1): use --format", path);
        }
    }
    switch (format) {
    case IMPORT_EYELINK: st = import_eyelink(text, len, path, o, out); break;
    case IMPORT_TOBII:   st = import_tobii(text, len, path, o, out); break;
    case IMPORT_PUPIL:   st = import_pupil(text, len, path, o, out); break;
    case IMPORT_SHARED:  st = import_shared(text, len, path, o, out); break;
    default:             st = pp5_fail(PP5_E_CONFIG, "unknown import format"); break;
    }
    free(text);
    return st;
}

pp5_status_t import_to_display(trace_t *t, const gaze_geometry_t *to)
{
    gaze_geometry_t from, dst;
    pp5_status_t st = angles_resolve(&t->header.geometry, &from);
    if (st == PP5_OK)
        st = angles_resolve(to, &dst);
    if (st != PP5_OK)
        return st;
    for (size_t i = 0; i < t->count; i++) {
        gaze_sample_t *s = &t->samples[i];
        if (s->flags & GAZE_FLAG_VALID)
            angles_remap(&from, &dst, s->x_px, s->y_px, &s->x_px, &s->y_px);
    }
    t->header.geometry = *to;
    return PP5_OK;
}

pp5_status_t import_commit(trace_t *t, pp5_status_t st, trace_t *out)
{
    if (st != PP5_OK) {
        trace_free(t);
        return st;
    }
    t->complete = true;
    *out = *t;
    return PP5_OK;
}

char *import_line_buffer(size_t *size)
{
    *size = (size_t)pp5_limit(PP5_LIMIT_LINE_BYTES) + 1;
    char *buf = malloc(*size);
    if (!buf)
        pp5_fail(PP5_E_NOMEM, "out of memory for a %zu-byte line buffer", *size);
    return buf;
}

pp5_status_t import_line_too_long(const char *name, int lineno)
{
    char where[600];
    snprintf(where, sizeof where, "%.500s:%d: the line", name, lineno);
    return pp5_limit_exceeded(PP5_LIMIT_LINE_BYTES, where);
}
