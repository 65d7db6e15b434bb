/* trace_file.c: read and write pp5 gaze traces (grammar in traces/FORMAT.md).
 *
 * Grammar, in short:
 *   line 1            "# pp5-trace v1"
 *   header lines      "# key: value"; required keys source, sample_rate_hz,
 *                     screen_px (W H), screen_mm (W H | unknown),
 *                     distance_mm (D | unknown); px_per_deg required when
 *                     screen_mm or distance_mm is unknown; unknown keys ignored
 *   column line       tab-separated names: t_ms x_px y_px status label
 *                     [head_x_mm head_y_mm head_z_mm head_az_deg head_el_deg head_roll_deg]
 *                     [hand_x_mm ... hand_roll_deg]
 *   data lines        tab-separated, one sample each, t_ms never decreasing
 *   last line         "# end: N samples" (absent in a recording that was killed)
 * The parser reads everything into a temporary trace_t and hands it over only
 * when the whole file validated (STYLE.md L9: validate, then commit). */
#include "trace_file.h"
#include "input_limits.h"
#include "outfile.h"

#include <errno.h>
#include <stdarg.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

/* Off-screen gaze is real data; values beyond 100 screen sizes are refused. */
#define TRACE_GAZE_LIMIT(g) (100.0 * ((g)->width_px + (g)->height_px))

static const char *const pose_suffix[6] = {"x_mm", "y_mm", "z_mm", "az_deg", "el_deg", "roll_deg"};

void trace_init(trace_t *t)
{
    memset(t, 0, sizeof *t);
}

void trace_free(trace_t *t)
{
    free(t->samples);
    trace_init(t);
}

pp5_status_t trace_append(trace_t *t, const gaze_sample_t *s)
{
    if (t->count > 0 && s->t_ns < t->samples[t->count - 1].t_ns)
        return pp5_fail(PP5_E_FORMAT, "sample %zu: time %.6f ms is before the previous sample (%.6f ms)",
                        t->count + 1, s->t_ns / 1e6, t->samples[t->count - 1].t_ns / 1e6);
    if (t->count == t->capacity) {
        size_t cap = t->capacity ? t->capacity * 2 : 1024;
        size_t bytes;
        uint64_t max_samples = pp5_limit(PP5_LIMIT_TRACE_SAMPLES);
        if (t->count >= max_samples)
            return pp5_limit_check(PP5_LIMIT_TRACE_SAMPLES, (uint64_t)t->count + 1, "trace");
        if (cap > max_samples)
            cap = (size_t)max_samples;
        if (!pp5_mul_size(cap, sizeof *t->samples, &bytes))
            return pp5_fail(PP5_E_NOMEM, "trace of %zu samples is too large for this host", cap);
        gaze_sample_t *p = realloc(t->samples, bytes);
        if (!p)
            return pp5_fail(PP5_E_NOMEM, "out of memory for %zu samples", cap);
        t->samples = p;
        t->capacity = cap;
    }
    t->samples[t->count++] = *s;
    return PP5_OK;
}

pp5_status_t trace_header_check(const trace_header_t *h)
{
    const gaze_geometry_t *g = &h->geometry;
    if (!(h->sample_rate_hz > 0 && h->sample_rate_hz <= 1e6))
        return pp5_fail(PP5_E_RANGE, "sample_rate_hz %g is outside (0, 1e6]", h->sample_rate_hz);
    if (g->width_px < 1 || g->height_px < 1 || g->width_px > 100000 || g->height_px > 100000)
        return pp5_fail(PP5_E_RANGE, "screen_px %dx%d is outside 1..100000", g->width_px, g->height_px);
    bool mm_known = g->width_mm > 0 && g->height_mm > 0 && g->distance_mm > 0;
    if (!mm_known && !(g->px_per_deg > 0))
        return pp5_fail(PP5_E_FORMAT, "geometry needs screen_mm and distance_mm, or px_per_deg");
    if (!isfinite(g->width_mm) || !isfinite(g->height_mm) || !isfinite(g->distance_mm) ||
        !isfinite(g->px_per_deg) || g->width_mm < 0 || g->height_mm < 0 || g->distance_mm < 0 ||
        g->px_per_deg < 0 || g->width_mm > 1e6 || g->height_mm > 1e6 || g->distance_mm > 1e6 ||
        g->px_per_deg > 1e6)
        return pp5_fail(PP5_E_RANGE, "screen geometry has a negative, non-finite or absurd "
                        "value (mm and px/deg must be in 0..1e6)");
    return PP5_OK;
}

const char *trace_status_name(uint32_t flags)
{
    if (flags & GAZE_FLAG_VALID)
        return "ok";
    return (flags & GAZE_FLAG_BLINK) ? "blink" : "lost";
}

/* ------------------------------------------------------------------ reading */

/* Length of the line still open at the end of buf[0..n) (bytes since the last
 * '\n'), given that `open` bytes of it came before `from`. */
static size_t open_line_length(const char *buf, size_t from, size_t n, size_t open)
{
    for (size_t i = n; i > from; i--)
        if (buf[i - 1] == '\n')
            return n - i;
    return open + (n - from);
}

static pp5_status_t slurp_fail(gzFile f, char *buf, pp5_status_t st)
{
    free(buf);
    gzclose(f);
    return st;
}

/* Reads in chunks so that a hostile file is refused as soon as it breaks a
 * limit: the whole-text limit, or the line limit (a file of one 100 MB line
 * stops after the first PP5_MAX_LINE_BYTES, without reading the rest). */
pp5_status_t trace_slurp(const char *path, size_t max_bytes, char **text, size_t *len)
{
    if (max_bytes == 0)
        max_bytes = (size_t)pp5_limit(PP5_LIMIT_TEXT_BYTES);
    uint64_t max_line = pp5_limit(PP5_LIMIT_LINE_BYTES);
    gzFile f = gzopen(path, "rb");
    if (!f)
        return pp5_fail(PP5_E_IO, "%s: cannot open: %s", path, strerror(errno ? errno : ENOENT));
    size_t cap = 1 << 16, n = 0, line = 0;
    int lineno = 1;
    char *buf = malloc(cap + 1);
    if (!buf)
        return slurp_fail(f, NULL, pp5_fail(PP5_E_NOMEM, "%s: out of memory", path));
    for (;;) {
        if (n == cap) {
            if (cap >= max_bytes)
                return slurp_fail(f, buf, max_bytes == pp5_limit(PP5_LIMIT_TEXT_BYTES)
                                              ? pp5_limit_exceeded(PP5_LIMIT_TEXT_BYTES, path)
                                              : pp5_fail(PP5_E_RANGE, "%s is larger than %zu "
                                                         "bytes", path, max_bytes));
            cap = cap * 2 > max_bytes ? max_bytes : cap * 2;
            char *p = realloc(buf, cap + 1);
            if (!p)
                return slurp_fail(f, buf, pp5_fail(PP5_E_NOMEM, "%s: out of memory", path));
            buf = p;
        }
        unsigned want = (unsigned)((cap - n) > (1u << 20) ? (1u << 20) : (cap - n));
        int got = gzread(f, buf + n, want);
        if (got < 0) {
            int zerr;
            const char *msg = gzerror(f, &zerr);
            return slurp_fail(f, buf, pp5_fail(PP5_E_FORMAT, "%s: corrupt or truncated "
                                               "compressed data (%s)", path, msg));
        }
        if (got == 0)
            break;
        for (size_t i = n; i < n + (size_t)got; i++)
            lineno += buf[i] == '\n';
        line = open_line_length(buf, n, n + (size_t)got, line);
        n += (size_t)got;
        if (line > max_line) {
            char where[600];
            snprintf(where, sizeof where, "%.500s:%d: the line", path, lineno);
            return slurp_fail(f, buf, pp5_limit_exceeded(PP5_LIMIT_LINE_BYTES, where));
        }
    }
    /* zlib reports a gzip stream cut short only through gzerror after EOF. */
    int zerr = Z_OK;
    gzerror(f, &zerr);
    gzclose(f);
    if (zerr != Z_OK && zerr != Z_STREAM_END) {
        free(buf);
        return pp5_fail(PP5_E_FORMAT, "%s: truncated compressed data", path);
    }
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return PP5_OK;
}

/* A finite decimal number occupying the whole field. */
static bool parse_finite(const char *s, double *out)
{
    char *end;
    if (!*s)
        return false;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || !isfinite(v) || errno == ERANGE)
        return false;
    *out = v;
    return true;
}

/* A number or the word "nan" (any case). */
static bool parse_number_or_nan(const char *s, double *out)
{
    if (strcasecmp(s, "nan") == 0) {
        *out = NAN;
        return true;
    }
    return parse_finite(s, out);
}

/* Milliseconds with up to 6 decimals, to integer ns without going through a
 * double (so 0.5 ms steps and microsecond times survive exactly). */
static bool parse_time_ms(const char *s, int64_t *t_ns)
{
    const char *p = s;
    int64_t whole = 0;
    int digits = 0;
    if (*p == '+')
        p++;
    while (*p >= '0' && *p <= '9') {
        if (++digits > 12)
            return false;               /* > 31 years of milliseconds: absurd */
        whole = whole * 10 + (*p++ - '0');
    }
    int64_t frac = 0;
    int fdigits = 0;
    bool round_up = false;
    if (*p == '.') {
        p++;
        while (*p >= '0' && *p <= '9') {
            if (fdigits < 6) {
                frac = frac * 10 + (*p - '0');
                fdigits++;
            } else if (fdigits == 6) {
                round_up = *p >= '5';   /* below a nanosecond: round once */
                fdigits++;
            }
            p++;
        }
    }
    if (*p != '\0' || (digits == 0 && fdigits == 0))
        return false;
    for (int i = fdigits > 6 ? 6 : fdigits; i < 6; i++)
        frac *= 10;
    *t_ns = whole * 1000000 + frac + (round_up ? 1 : 0);
    return true;
}

/* Splits `line` in place at tabs; returns the field count (at most max). */
static int split_tabs(char *line, char **fields, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        if (n == max)
            return max + 1;
        fields[n++] = p;
        char *tab = strchr(p, '\t');
        if (!tab)
            break;
        *tab = '\0';
        p = tab + 1;
    }
    return n;
}

enum { COL_T, COL_X, COL_Y, COL_STATUS, COL_LABEL, COL_BASE_COUNT };
#define TRACE_MAX_COLS (COL_BASE_COUNT + 12)

static pp5_status_t parse_columns(char *line, const char *name, int lineno, trace_t *t, int *ncols)
{
    static const char *const base[COL_BASE_COUNT] = {"t_ms", "x_px", "y_px", "status", "label"};
    char *f[TRACE_MAX_COLS + 1];
    int n = split_tabs(line, f, TRACE_MAX_COLS);
    if (n > TRACE_MAX_COLS)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: too many columns", name, lineno);
    if (n < COL_BASE_COUNT)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: column line must start t_ms x_px y_px status label",
                        name, lineno);
    for (int i = 0; i < COL_BASE_COUNT; i++)
        if (strcmp(f[i], base[i]) != 0)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: column %d is '%s', expected '%s'", name, lineno,
                            i + 1, f[i], base[i]);
    int c = COL_BASE_COUNT;
    for (int group = 0; group < 2 && c < n; group++) {
        const char *prefix = strncmp(f[c], "head_", 5) == 0 ? "head_" :
                             strncmp(f[c], "hand_", 5) == 0 ? "hand_" : NULL;
        if (!prefix)
            break;
        if (n - c < 6)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: %s pose needs 6 columns", name, lineno, prefix);
        for (int k = 0; k < 6; k++) {
            char want[32];
            snprintf(want, sizeof want, "%s%s", prefix, pose_suffix[k]);
            if (strcmp(f[c + k], want) != 0)
                return pp5_fail(PP5_E_FORMAT, "%s:%d: column %d is '%s', expected '%s'", name,
                                lineno, c + k + 1, f[c + k], want);
        }
        if (prefix[1] == 'e') {
            if (t->has_head || t->has_hand)
                return pp5_fail(PP5_E_FORMAT, "%s:%d: head columns must come once, before hand",
                                name, lineno);
            t->has_head = true;
        } else {
            if (t->has_hand)
                return pp5_fail(PP5_E_FORMAT, "%s:%d: hand columns appear twice", name, lineno);
            t->has_hand = true;
        }
        c += 6;
    }
    if (c != n)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: unknown column '%s'", name, lineno, f[c]);
    *ncols = n;
    return PP5_OK;
}

static pp5_status_t parse_pose(char **f, const char *name, int lineno, const char *what,
                               gaze_pose_t *pose, bool *present)
{
    double v[6];
    int nans = 0;
    for (int k = 0; k < 6; k++) {
        if (!parse_number_or_nan(f[k], &v[k]))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: %s_%s: '%s' is not a number", name, lineno,
                            what, pose_suffix[k], f[k]);
        nans += isnan(v[k]) ? 1 : 0;
    }
    if (nans != 0 && nans != 6)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: %s pose is partly NaN (all six or none)", name,
                        lineno, what);
    *present = nans == 0;
    if (*present) {
        memcpy(pose->pos_mm, v, sizeof pose->pos_mm);
        pose->azimuth_deg = v[3];
        pose->elevation_deg = v[4];
        pose->roll_deg = v[5];
    }
    return PP5_OK;
}

static pp5_status_t parse_sample(char *line, const char *name, int lineno, const trace_t *t,
                                 int ncols, gaze_sample_t *s)
{
    char *f[TRACE_MAX_COLS + 1];
    int n = split_tabs(line, f, TRACE_MAX_COLS);
    if (n != ncols)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the column line has %d", name, lineno,
                        n > TRACE_MAX_COLS ? TRACE_MAX_COLS + 1 : n, ncols);
    int64_t t_ns;
    if (!parse_time_ms(f[COL_T], &t_ns))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: t_ms '%s' is not a non-negative time in ms "
                        "(NaN is not allowed)", name, lineno, f[COL_T]);
    gaze_sample_invalid(s, t_ns);
    double x, y;
    if (!parse_number_or_nan(f[COL_X], &x) || !parse_number_or_nan(f[COL_Y], &y))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze '%s' '%s' is not a number or nan", name,
                        lineno, f[COL_X], f[COL_Y]);
    if (strcmp(f[COL_STATUS], "ok") == 0) {
        if (isnan(x) || isnan(y))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: NaN gaze in a sample whose status is ok "
                            "(use status lost or blink)", name, lineno);
        /* Off-screen gaze is real data (PROVENANCE: up to 1.35 screen heights);
         * only values absurdly far away are refused. */
        double lim = TRACE_GAZE_LIMIT(&t->header.geometry);
        if (fabs(x) > lim || fabs(y) > lim)
            return pp5_fail(PP5_E_RANGE, "%s:%d: gaze %g,%g is absurdly far off the screen", name,
                            lineno, x, y);
        s->x_px = x;
        s->y_px = y;
        s->flags = GAZE_FLAG_VALID;
    } else if (strcmp(f[COL_STATUS], "blink") == 0) {
        s->flags = GAZE_FLAG_BLINK;
    } else if (strcmp(f[COL_STATUS], "lost") != 0) {
        return pp5_fail(PP5_E_FORMAT, "%s:%d: status '%s' is not ok, blink or lost", name, lineno,
                        f[COL_STATUS]);
    }
    char *end;
    long label = strtol(f[COL_LABEL], &end, 10);
    if (end == f[COL_LABEL] || *end != '\0' || label < 0 || label > GAZE_LABEL_MAX)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: label '%s' is not 0..%d", name, lineno,
                        f[COL_LABEL], GAZE_LABEL_MAX);
    s->label = (int)label;
    int c = COL_BASE_COUNT;
    bool present;
    if (t->has_head) {
        pp5_status_t st = parse_pose(f + c, name, lineno, "head", &s->head, &present);
        if (st != PP5_OK)
            return st;
        s->flags |= present ? GAZE_FLAG_HEAD : 0;
        c += 6;
    }
    if (t->has_hand) {
        pp5_status_t st = parse_pose(f + c, name, lineno, "hand", &s->hand, &present);
        if (st != PP5_OK)
            return st;
        s->flags |= present ? GAZE_FLAG_HAND : 0;
    }
    return PP5_OK;
}

/* "W H" of two finite numbers; or "unknown" (both 0) when allowed. */
static bool parse_two(const char *v, double *a, double *b, bool allow_unknown)
{
    if (allow_unknown && strcmp(v, "unknown") == 0) {
        *a = *b = 0;
        return true;
    }
    char *end;
    errno = 0;
    *a = strtod(v, &end);
    if (end == v || (*end != ' ' && *end != '\t'))
        return false;
    const char *p = end;
    *b = strtod(p, &end);
    if (end == p || *end != '\0' || errno == ERANGE)
        return false;
    return isfinite(*a) && isfinite(*b);
}

enum { KEY_SOURCE = 1, KEY_RATE = 2, KEY_PX = 4, KEY_MM = 8, KEY_DIST = 16 };

static pp5_status_t parse_header_line(char *line, const char *name, int lineno, trace_t *t,
                                      unsigned *seen)
{
    /* "# key: value" */
    char *key = line + 2;
    char *colon = strstr(key, ": ");
    if (line[1] != ' ' || !colon)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: header line must be '# key: value'", name, lineno);
    *colon = '\0';
    char *v = colon + 2;
    trace_header_t *h = &t->header;
    gaze_geometry_t *g = &h->geometry;
    double a, b;
    if (strcmp(key, "source") == 0) {
        snprintf(h->source, sizeof h->source, "%s", v);
        *seen |= KEY_SOURCE;
    } else if (strcmp(key, "tracker") == 0) {
        snprintf(h->tracker, sizeof h->tracker, "%s", v);
    } else if (strcmp(key, "sample_rate_hz") == 0) {
        if (!parse_finite(v, &a) || a <= 0)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: sample_rate_hz '%s' is not a positive number",
                            name, lineno, v);
        h->sample_rate_hz = a;
        *seen |= KEY_RATE;
    } else if (strcmp(key, "screen_px") == 0) {
        if (!parse_two(v, &a, &b, false) || a != floor(a) || b != floor(b) || a < 1 || b < 1 ||
            a > 100000 || b > 100000)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: screen_px '%s' is not 'W H' in 1..100000", name,
                            lineno, v);
        g->width_px = (int)a;
        g->height_px = (int)b;
        *seen |= KEY_PX;
    } else if (strcmp(key, "screen_mm") == 0) {
        if (!parse_two(v, &a, &b, true) || a < 0 || b < 0)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: screen_mm '%s' is not 'W H' or 'unknown'", name,
                            lineno, v);
        g->width_mm = a;
        g->height_mm = b;
        *seen |= KEY_MM;
    } else if (strcmp(key, "distance_mm") == 0) {
        if (strcmp(v, "unknown") == 0)
            a = 0;
        else if (!parse_finite(v, &a) || a <= 0)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: distance_mm '%s' is not a positive number or "
                            "'unknown'", name, lineno, v);
        g->distance_mm = a;
        *seen |= KEY_DIST;
    } else if (strcmp(key, "px_per_deg") == 0) {
        if (!parse_finite(v, &a) || a <= 0)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: px_per_deg '%s' is not a positive number", name,
                            lineno, v);
        g->px_per_deg = a;
    }
    /* Other keys: informative, ignored (FORMAT.md). */
    return PP5_OK;
}

pp5_status_t trace_parse(const char *text, size_t len, const char *name, trace_t *out)
{
    if (memchr(text, '\0', len))
        return pp5_fail(PP5_E_FORMAT, "%s: contains a NUL byte (not a text trace)", name);
    char *copy = malloc(len + 1);
    if (!copy)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", name);
    memcpy(copy, text, len);
    copy[len] = '\0';

    trace_t t;
    trace_init(&t);
    pp5_status_t st = PP5_OK;
    enum { IN_MAGIC, IN_HEADER, IN_DATA, AFTER_END } state = IN_MAGIC;
    unsigned seen = 0;
    int ncols = 0, lineno = 0;
    char *p = copy, *stop = copy + len;
    while (st == PP5_OK && p < stop) {
        char *nl = memchr(p, '\n', (size_t)(stop - p));
        lineno++;
        if (!nl) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: truncated: the last line has no end of line",
                          name, lineno);
            break;
        }
        *nl = '\0';
        if (nl > p && nl[-1] == '\r')
            nl[-1] = '\0';
        char *line = p;
        p = nl + 1;
        switch (state) {
        case IN_MAGIC:
            if (strcmp(line, TRACE_MAGIC) != 0)
                st = pp5_fail(PP5_E_FORMAT, "%s: not a pp5 trace (line 1 must be '%s')", name,
                              TRACE_MAGIC);
            state = IN_HEADER;
            break;
        case IN_HEADER:
            if (line[0] == '#') {
                st = parse_header_line(line, name, lineno, &t, &seen);
                break;
            }
            {
                static const struct { unsigned bit; const char *key; } req[] = {
                    {KEY_SOURCE, "source"}, {KEY_RATE, "sample_rate_hz"}, {KEY_PX, "screen_px"},
                    {KEY_MM, "screen_mm"}, {KEY_DIST, "distance_mm"}};
                for (size_t i = 0; i < sizeof req / sizeof req[0]; i++)
                    if (!(seen & req[i].bit)) {
                        st = pp5_fail(PP5_E_FORMAT, "%s: header key '%s' is missing", name,
                                      req[i].key);
                        break;
                    }
            }
            if (st == PP5_OK && (st = trace_header_check(&t.header)) != PP5_OK)
                st = pp5_fail(st, "%s: header: %s", name, pp5_error_text());
            if (st == PP5_OK)
                st = parse_columns(line, name, lineno, &t, &ncols);
            state = IN_DATA;
            break;
        case IN_DATA:
            if (line[0] == '\0')
                break;                           /* blank lines are harmless */
            if (line[0] == '#') {
                unsigned long long n;
                char tail;
                if (sscanf(line, "# end: %llu samples%c", &n, &tail) == 1) {
                    if (n != t.count)
                        st = pp5_fail(PP5_E_FORMAT, "%s:%d: end line says %llu samples, file "
                                      "has %zu", name, lineno, n, t.count);
                    t.complete = true;
                    state = AFTER_END;
                }
                break;                           /* other comments are ignored */
            }
            {
                gaze_sample_t s;
                st = parse_sample(line, name, lineno, &t, ncols, &s);
                if (st == PP5_OK && t.count > 0 && s.t_ns < t.samples[t.count - 1].t_ns)
                    st = pp5_fail(PP5_E_FORMAT, "%s:%d: time goes backwards (%.6f ms after "
                                  "%.6f ms)", name, lineno, s.t_ns / 1e6,
                                  t.samples[t.count - 1].t_ns / 1e6);
                if (st == PP5_OK)
                    st = trace_append(&t, &s);
            }
            break;
        case AFTER_END:
            if (line[0] != '\0')
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: text after the end line", name, lineno);
            break;
        }
    }
    if (st == PP5_OK && state == IN_MAGIC)
        st = pp5_fail(PP5_E_FORMAT, "%s: empty file", name);
    if (st == PP5_OK && state == IN_HEADER)
        st = pp5_fail(PP5_E_FORMAT, "%s: truncated: no column line after the header", name);
    free(copy);
    if (st != PP5_OK) {
        trace_free(&t);
        return st;
    }
    *out = t;
    return PP5_OK;
}

pp5_status_t trace_read_file(const char *path, trace_t *out)
{
    char *text;
    size_t len;
    pp5_status_t st = trace_slurp(path, 0, &text, &len);
    if (st != PP5_OK)
        return st;
    st = trace_parse(text, len, path, out);
    free(text);
    return st;
}

/* ------------------------------------------------------------------ writing */

static pp5_status_t wbuf_reserve(trace_writer_t *w, size_t more)
{
    if (w->len + more <= w->cap)
        return PP5_OK;
    size_t cap = w->cap ? w->cap : 1 << 16;
    while (cap < w->len + more)
        cap *= 2;
    char *p = realloc(w->buf, cap);
    if (!p)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", w->path);
    w->buf = p;
    w->cap = cap;
    return PP5_OK;
}

static pp5_status_t wbuf_printf(trace_writer_t *w, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static pp5_status_t wbuf_printf(trace_writer_t *w, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    pp5_status_t st = wbuf_reserve(w, (size_t)n + 1);
    if (st != PP5_OK)
        return st;
    va_start(ap, fmt);
    vsnprintf(w->buf + w->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    w->len += (size_t)n;
    return PP5_OK;
}

/* Shortest text that reads back within 0.0005 (pixels, mm, degrees). */
static void fmt_value(char *out, size_t size, double v)
{
    if (isnan(v)) {
        snprintf(out, size, "nan");
        return;
    }
    snprintf(out, size, "%.3f", v);
    char *dot = strchr(out, '.');
    if (dot) {
        char *e = out + strlen(out) - 1;
        while (e > dot && *e == '0')
            *e-- = '\0';
        if (e == dot)
            *e = '\0';
    }
    if (strcmp(out, "-0") == 0)
        snprintf(out, size, "0");
}

static void fmt_time(char *out, size_t size, int64_t t_ns)
{
    int64_t ms = t_ns / 1000000, frac = t_ns % 1000000;
    if (frac == 0) {
        snprintf(out, size, "%lld", (long long)ms);
        return;
    }
    snprintf(out, size, "%lld.%06lld", (long long)ms, (long long)frac);
    char *e = out + strlen(out) - 1;
    while (*e == '0')
        *e-- = '\0';
}

pp5_status_t trace_writer_flush(trace_writer_t *w)
{
    size_t off = 0;
    while (off < w->len) {
        ssize_t n = write(w->fd, w->buf + off, w->len - off);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return pp5_fail(PP5_E_IO, "%s: write failed: %s", w->path, strerror(errno));
        }
        off += (size_t)n;
    }
    w->len = 0;
    return PP5_OK;
}

pp5_status_t trace_writer_open(trace_writer_t *w, const char *path, const trace_header_t *h,
                               bool has_head, bool has_hand)
{
    memset(w, 0, sizeof *w);
    w->fd = -1;
    snprintf(w->path, sizeof w->path, "%s", path);
    pp5_status_t st = trace_header_check(h);
    if (st != PP5_OK)
        return st;
    if (strchr(h->source, '\n') || strchr(h->tracker, '\n'))
        return pp5_fail(PP5_E_FORMAT, "trace header text may not contain a line break");
    w->fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (w->fd < 0)
        return pp5_fail(PP5_E_IO, "%s: cannot create: %s", path, strerror(errno));
    w->has_head = has_head;
    w->has_hand = has_hand;
    w->limit_px = TRACE_GAZE_LIMIT(&h->geometry);
    const gaze_geometry_t *g = &h->geometry;
    char a[32], b[32];
    st = wbuf_printf(w, "%s\n# source: %s\n", TRACE_MAGIC, h->source[0] ? h->source : "unknown");
    if (st == PP5_OK && h->tracker[0])
        st = wbuf_printf(w, "# tracker: %s\n", h->tracker);
    fmt_value(a, sizeof a, h->sample_rate_hz);
    if (st == PP5_OK)
        st = wbuf_printf(w, "# sample_rate_hz: %s\n# screen_px: %d %d\n", a, g->width_px,
                         g->height_px);
    if (st == PP5_OK) {
        if (g->width_mm > 0 && g->height_mm > 0) {
            fmt_value(a, sizeof a, g->width_mm);
            fmt_value(b, sizeof b, g->height_mm);
            st = wbuf_printf(w, "# screen_mm: %s %s\n", a, b);
        } else {
            st = wbuf_printf(w, "# screen_mm: unknown\n");
        }
    }
    if (st == PP5_OK) {
        fmt_value(a, sizeof a, g->distance_mm);
        st = wbuf_printf(w, "# distance_mm: %s\n", g->distance_mm > 0 ? a : "unknown");
    }
    if (st == PP5_OK && g->px_per_deg > 0) {
        fmt_value(a, sizeof a, g->px_per_deg);
        st = wbuf_printf(w, "# px_per_deg: %s\n", a);
    }
    if (st == PP5_OK)
        st = wbuf_printf(w, "t_ms\tx_px\ty_px\tstatus\tlabel");
    for (int group = 0; group < 2 && st == PP5_OK; group++) {
        if (!(group == 0 ? has_head : has_hand))
            continue;
        for (int k = 0; k < 6 && st == PP5_OK; k++)
            st = wbuf_printf(w, "\t%s_%s", group == 0 ? "head" : "hand", pose_suffix[k]);
    }
    if (st == PP5_OK)
        st = wbuf_printf(w, "\n");
    if (st == PP5_OK)
        st = trace_writer_flush(w);        /* the header is on disk before any sample */
    if (st != PP5_OK) {
        close(w->fd);
        w->fd = -1;
        free(w->buf);
        w->buf = NULL;
    }
    w->started = st == PP5_OK;
    return st;
}

static pp5_status_t write_pose(trace_writer_t *w, const gaze_pose_t *p, bool present)
{
    double v[6] = {p->pos_mm[0], p->pos_mm[1], p->pos_mm[2], p->azimuth_deg, p->elevation_deg,
                   p->roll_deg};
    pp5_status_t st = PP5_OK;
    for (int k = 0; k < 6 && st == PP5_OK; k++) {
        char a[48];
        if (present && !(isfinite(v[k]) && fabs(v[k]) <= 1e9))
            return pp5_fail(PP5_E_RANGE, "%s: non-finite or absurd pose value", w->path);
        fmt_value(a, sizeof a, present ? v[k] : NAN);
        st = wbuf_printf(w, "\t%s", a);
    }
    return st;
}

pp5_status_t trace_writer_append(trace_writer_t *w, const gaze_sample_t *s)
{
    if (!w->started)
        return pp5_fail(PP5_E_IO, "%s: writer is not open", w->path);
    if (s->t_ns < 0 || (w->samples > 0 && s->t_ns < w->last_t_ns))
        return pp5_fail(PP5_E_FORMAT, "%s: sample time %.6f ms is negative or before the "
                        "previous one", w->path, s->t_ns / 1e6);
    bool valid = (s->flags & GAZE_FLAG_VALID) != 0;
    if (valid && !(isfinite(s->x_px) && isfinite(s->y_px) && fabs(s->x_px) <= w->limit_px &&
                   fabs(s->y_px) <= w->limit_px))
        return pp5_fail(PP5_E_RANGE, "%s: a valid sample has non-finite or absurd gaze", w->path);
    if (s->label < 0 || s->label > GAZE_LABEL_MAX)
        return pp5_fail(PP5_E_RANGE, "%s: label %d outside 0..%d", w->path, s->label,
                        GAZE_LABEL_MAX);
    size_t mark = w->len;
    char t[40], x[48], y[48];
    fmt_time(t, sizeof t, s->t_ns);
    fmt_value(x, sizeof x, valid ? s->x_px : NAN);
    fmt_value(y, sizeof y, valid ? s->y_px : NAN);
    pp5_status_t st = wbuf_printf(w, "%s\t%s\t%s\t%s\t%d", t, x, y, trace_status_name(s->flags),
                                  s->label);
    if (st == PP5_OK && w->has_head)
        st = write_pose(w, &s->head, (s->flags & GAZE_FLAG_HEAD) != 0);
    if (st == PP5_OK && w->has_hand)
        st = write_pose(w, &s->hand, (s->flags & GAZE_FLAG_HAND) != 0);
    if (st == PP5_OK)
        st = wbuf_printf(w, "\n");
    if (st != PP5_OK) {
        w->len = mark;                      /* never leave half a line in the buffer */
        return st;
    }
    w->samples++;
    w->last_t_ns = s->t_ns;
    if (w->len >= (1u << 20))
        return trace_writer_flush(w);
    return PP5_OK;
}

pp5_status_t trace_writer_close(trace_writer_t *w)
{
    pp5_status_t st = PP5_OK;
    if (w->started) {
        st = wbuf_printf(w, "# end: %zu samples\n", w->samples);
        if (st == PP5_OK)
            st = trace_writer_flush(w);
    }
    if (w->fd >= 0 && close(w->fd) != 0 && st == PP5_OK)
        st = pp5_fail(PP5_E_IO, "%s: close failed: %s", w->path, strerror(errno));
    free(w->buf);
    w->buf = NULL;
    w->fd = -1;
    w->started = false;
    return st;
}

pp5_status_t trace_writer_abandon(trace_writer_t *w)
{
    pp5_status_t st = w->started ? trace_writer_flush(w) : PP5_OK;
    w->started = false;                    /* so close writes no end line */
    pp5_status_t cst = trace_writer_close(w);
    return st != PP5_OK ? st : cst;
}

pp5_status_t trace_write_file(const char *path, const trace_t *t)
{
    /* A whole trace goes to a temporary beside `path`, renamed once its end
     * line is written: an interrupted write never leaves a short trace under
     * the real name.  (Live recording keeps its flush-as-you-go file.) */
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    outfile_release_stream(&o);
    trace_writer_t w;
    st = trace_writer_open(&w, outfile_write_path(&o), &t->header, t->has_head, t->has_hand);
    for (size_t i = 0; st == PP5_OK && i < t->count; i++)
        st = trace_writer_append(&w, &t->samples[i]);
    pp5_status_t cst = trace_writer_close(&w);
    if (st == PP5_OK)
        st = cst;
    if (st != PP5_OK) {
        outfile_discard(&o);
        return st;
    }
    return outfile_commit(&o);
}

/* ------------------------------------------------------------ gaze source */

typedef struct {
    trace_t trace;
    size_t next;
    gaze_source_t src;
    char name[TRACE_TEXT_MAX];
} trace_source_t;

static pp5_status_t trace_source_next(gaze_source_t *src, gaze_sample_t *out, bool *got)
{
    trace_source_t *ts = src->impl;
    *got = ts->next < ts->trace.count;
    if (*got)
        *out = ts->trace.samples[ts->next++];
    return PP5_OK;
}

static void trace_source_close(gaze_source_t *src)
{
    trace_source_t *ts = src->impl;
    trace_free(&ts->trace);
    free(ts);
}

static const gaze_source_ops_t trace_source_ops = {trace_source_next, trace_source_close};

pp5_status_t trace_source_open(trace_t *t, const char *name, gaze_source_t **out)
{
    trace_source_t *ts = calloc(1, sizeof *ts);
    if (!ts)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    ts->trace = *t;
    trace_init(t);
    snprintf(ts->name, sizeof ts->name, "%s", name ? name : "trace");
    ts->src.ops = &trace_source_ops;
    ts->src.impl = ts;
    ts->src.name = ts->name;
    ts->src.sample_rate_hz = ts->trace.header.sample_rate_hz;
    ts->src.geometry = ts->trace.header.geometry;
    *out = &ts->src;
    return PP5_OK;
}

pp5_status_t trace_collect(gaze_source_t *src, size_t max_samples, trace_t *out)
{
    trace_t t;
    trace_init(&t);
    snprintf(t.header.source, sizeof t.header.source, "%s", src->name ? src->name : "source");
    t.header.sample_rate_hz = src->sample_rate_hz;
    t.header.geometry = src->geometry;
    pp5_status_t st = PP5_OK;
    bool got = true;
    while (st == PP5_OK && (max_samples == 0 || t.count < max_samples)) {
        gaze_sample_t s;
        st = gaze_source_next(src, &s, &got);
        if (st != PP5_OK || !got)
            break;
        t.has_head |= (s.flags & GAZE_FLAG_HEAD) != 0;
        t.has_hand |= (s.flags & GAZE_FLAG_HAND) != 0;
        st = trace_append(&t, &s);
    }
    if (st != PP5_OK) {
        trace_free(&t);
        return st;
    }
    t.complete = !got;
    *out = t;
    return PP5_OK;
}
