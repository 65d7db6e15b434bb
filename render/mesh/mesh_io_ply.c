/* mesh_io_ply.c: a strict PLY reader (ASCII, binary little- and big-endian).
 *
 * Debian 12 packages no PLY library for C (no RPly; assimp imports scenes and
 * re-indexes vertices), so the format (Turk, "The PLY Polygon File Format")
 * is read here: the header is parsed completely, every element count is
 * bounded (and, for binary files, checked against the bytes left) before
 * anything is allocated, unknown elements and properties are skipped, and
 * every read is bounds-checked, so any truncation is an error naming the file
 * and the element it cut. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io_internal.h"

#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPS 64
#define PLY_MAX_LIST 1000000

typedef enum { PLY_ASCII, PLY_LE, PLY_BE } ply_format_t;

typedef struct {
    char name[32];
    int type;        /* bytes of the scalar (1, 2, 4, 8); 0 = invalid */
    int is_float, is_signed;
    int list_type, list_signed; /* > 0: a list whose count has this many bytes */
} ply_prop_t;

typedef struct {
    char name[32];
    long count;
    ply_prop_t props[PLY_MAX_PROPS];
    int n_props;
} ply_element_t;

typedef struct {
    const char *path;
    ply_format_t format;
    ply_element_t el[PLY_MAX_ELEMENTS];
    int n_el;
    const uint8_t *p, *end;   /* the body */
    int line;                  /* ASCII body line, for errors */
} ply_t;

static int ply_type(const char *t, int *bytes, int *is_float, int *is_signed)
{
    static const struct { const char *a, *b; int bytes, fl, sg; } types[] = {
        {"char", "int8", 1, 0, 1},     {"uchar", "uint8", 1, 0, 0},
        {"short", "int16", 2, 0, 1},   {"ushort", "uint16", 2, 0, 0},
        {"int", "int32", 4, 0, 1},     {"uint", "uint32", 4, 0, 0},
        {"float", "float32", 4, 1, 1}, {"double", "float64", 8, 1, 1},
    };
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].a) == 0 || strcmp(t, types[i].b) == 0) {
            *bytes = types[i].bytes, *is_float = types[i].fl, *is_signed = types[i].sg;
            return 1;
        }
    return 0;
}

static pp5_status_t ply_property(ply_t *y, char *words[], int nw, int line)
{
    if (y->n_el == 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: property before any element", y->path, line);
    ply_element_t *e = &y->el[y->n_el - 1];
    if (e->n_props == PLY_MAX_PROPS)
        return pp5_fail(PP5_E_RANGE, "%s:%d: more than %d properties", y->path, line,
                        PLY_MAX_PROPS);
    ply_prop_t *pr = &e->props[e->n_props];
    memset(pr, 0, sizeof *pr);
    int ok, fl;
    const char *name;
    if (nw == 5 && strcmp(words[1], "list") == 0) {
        ok = ply_type(words[2], &pr->list_type, &fl, &pr->list_signed) && !fl &&
             ply_type(words[3], &pr->type, &pr->is_float, &pr->is_signed);
        name = words[4];
    } else {
        ok = nw == 3 && ply_type(words[1], &pr->type, &pr->is_float, &pr->is_signed);
        name = words[2];
    }
    if (!ok)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad property line", y->path, line);
    snprintf(pr->name, sizeof pr->name, "%s", name);
    e->n_props++;
    return PP5_OK;
}

static pp5_status_t ply_element(ply_t *y, char *words[], int nw, int line)
{
    if (nw != 3)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: expected 'element NAME COUNT'", y->path, line);
    if (y->n_el == PLY_MAX_ELEMENTS)
        return pp5_fail(PP5_E_RANGE, "%s:%d: more than %d elements", y->path, line,
                        PLY_MAX_ELEMENTS);
    ply_element_t *e = &y->el[y->n_el++];
    memset(e, 0, sizeof *e);
    snprintf(e->name, sizeof e->name, "%s", words[1]);
    char *stop;
    e->count = strtol(words[2], &stop, 10);
    long limit = strcmp(e->name, "face") == 0 ? MESH_MAX_FACES : MESH_MAX_VERTICES;
    if (*stop || e->count < 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad element count '%s'", y->path, line, words[2]);
    if (e->count > limit)
        return pp5_fail(PP5_E_RANGE, "%s:%d: %ld %s elements (at most %ld)", y->path, line,
                        e->count, e->name, limit);
    return PP5_OK;
}

/* Splits one header line into at most 8 words (in place). */
static int split_words(char *s, char *words[8])
{
    int n = 0;
    char *save;
    for (char *w = strtok_r(s, " \t\r", &save); w && n < 8; w = strtok_r(NULL, " \t\r", &save))
        words[n++] = w;
    return n;
}

static pp5_status_t ply_header(ply_t *y, const uint8_t *data, size_t n)
{
    if (n < 4 || memcmp(data, "ply", 3) != 0 || (data[3] != '\n' && data[3] != '\r'))
        return pp5_fail(PP5_E_FORMAT, "%s: not a PLY file (no 'ply' magic line)", y->path);
    const uint8_t *p = data, *end = data + n;
    int line = 0, have_format = 0;
    for (;;) {
        const uint8_t *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl)
            return pp5_fail(PP5_E_FORMAT, "%s: truncated header (no end_header)", y->path);
        line++;
        char buf[512], *words[8];
        size_t len = (size_t)(nl - p);
        if (len >= sizeof buf)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: header line too long", y->path, line);
        memcpy(buf, p, len);
        buf[len] = '\0';
        p = nl + 1;
        int nw = split_words(buf, words);
        pp5_status_t st = PP5_OK;
        if (nw == 0 || (line == 1 && strcmp(words[0], "ply") == 0) ||
            strcmp(words[0], "comment") == 0 || strcmp(words[0], "obj_info") == 0)
            continue;
        if (strcmp(words[0], "end_header") == 0)
            break;
        if (strcmp(words[0], "format") == 0) {
            if (nw != 3 || strcmp(words[2], "1.0") != 0)
                return pp5_fail(PP5_E_FORMAT, "%s:%d: expected 'format KIND 1.0'", y->path,
                                line);
            if (strcmp(words[1], "ascii") == 0)
                y->format = PLY_ASCII;
            else if (strcmp(words[1], "binary_little_endian") == 0)
                y->format = PLY_LE;
            else if (strcmp(words[1], "binary_big_endian") == 0)
                y->format = PLY_BE;
            else
                return pp5_fail(PP5_E_FORMAT, "%s:%d: unknown format '%s'", y->path, line,
                                words[1]);
            have_format = 1;
        } else if (strcmp(words[0], "element") == 0) {
            st = ply_element(y, words, nw, line);
        } else if (strcmp(words[0], "property") == 0) {
            st = ply_property(y, words, nw, line);
        } else {
            return pp5_fail(PP5_E_FORMAT, "%s:%d: unknown header keyword '%.20s'", y->path, line,
                            words[0]);
        }
        if (st != PP5_OK)
            return st;
    }
    if (!have_format)
        return pp5_fail(PP5_E_FORMAT, "%s: header has no format line", y->path);
    y->p = p;
    y->end = end;
    y->line = line;
    return PP5_OK;
}

/* Reads one scalar of the given kind from the body into *v. */
static int ply_read(ply_t *y, int bytes, int is_float, int is_signed, double *v)
{
    if (y->format == PLY_ASCII) {
        while (y->p < y->end && (*y->p == ' ' || *y->p == '\t' || *y->p == '\r' ||
                                 *y->p == '\n'))
            y->line += *y->p++ == '\n';
        const char *s = (const char *)y->p;
        if (!text_double(&s, (const char *)y->end, v))
            return 0;
        y->p = (const uint8_t *)s;
        return is_float || *v == floor(*v);
    }
    if ((size_t)(y->end - y->p) < (size_t)bytes)
        return 0;
    uint8_t b[8];
    for (int i = 0; i < bytes; i++)
        b[i] = y->p[y->format == PLY_BE ? bytes - 1 - i : i];
    y->p += bytes;
    uint64_t u = 0;
    for (int i = bytes - 1; i >= 0; i--)
        u = (u << 8) | b[i];
    if (is_float && bytes == 4) {
        float f;
        uint32_t u32 = (uint32_t)u;
        memcpy(&f, &u32, 4);
        *v = f;
    } else if (is_float) {
        memcpy(v, &u, 8);
    } else if (is_signed) {
        int shift = 64 - 8 * bytes;
        *v = (double)((int64_t)(u << shift) >> shift);
    } else {
        *v = (double)u;
    }
    return isfinite(*v);
}

static int ply_min_bytes(const ply_element_t *e)
{
    int b = 0;
    for (int i = 0; i < e->n_props; i++)
        b += e->props[i].list_type ? e->props[i].list_type : e->props[i].type;
    return b;
}

static pp5_status_t ply_truncated(const ply_t *y, const ply_element_t *e, long i)
{
    if (y->format == PLY_ASCII)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad or missing value in %s %ld of %ld", y->path,
                        y->line + 1, e->name, i + 1, e->count);
    return pp5_fail(PP5_E_FORMAT, "%s: truncated or bad value in %s %ld of %ld", y->path,
                    e->name, i + 1, e->count);
}

/* One element instance: scalars into vals (by property), the vertex-index list
 * (if `list_prop` >= 0) fan-triangulated into the builder. */
static pp5_status_t ply_instance(ply_t *y, const ply_element_t *e, long i, int list_prop,
                                 mesh_builder_t *b, long nv, double *vals)
{
    for (int k = 0; k < e->n_props; k++) {
        const ply_prop_t *pr = &e->props[k];
        double v;
        if (!pr->list_type) {
            if (!ply_read(y, pr->type, pr->is_float, pr->is_signed, &v))
                return ply_truncated(y, e, i);
            vals[k] = v;
            continue;
        }
        double cnt;
        if (!ply_read(y, pr->list_type, 0, pr->list_signed, &cnt))
            return ply_truncated(y, e, i);
        if (cnt < 0 || cnt > PLY_MAX_LIST)
            return pp5_fail(PP5_E_RANGE, "%s: %s %ld: list of %.0f items (at most %d)", y->path,
                            e->name, i + 1, cnt, PLY_MAX_LIST);
        if (k == list_prop && cnt < 3)
            return pp5_fail(PP5_E_FORMAT, "%s: face %ld has %.0f vertices (at least 3)", y->path,
                            i + 1, cnt);
        int32_t first = 0, prev = 0;
        for (long j = 0; j < (long)cnt; j++) {
            if (!ply_read(y, pr->type, pr->is_float, pr->is_signed, &v))
                return ply_truncated(y, e, i);
            if (k != list_prop)
                continue;
            if (v < 0 || v >= (double)nv || v != floor(v))
                return pp5_fail(PP5_E_FORMAT, "%s: face %ld uses vertex %.0f of %ld", y->path,
                                i + 1, v, nv);
            int32_t vi = (int32_t)v;
            if (j == 0)
                first = vi;
            else if (j >= 2) {
                pp5_status_t st = mesh_builder_face(b, first, prev, vi);
                if (st != PP5_OK)
                    return pp5_fail(st, "%s: %s", y->path, pp5_error_text());
            }
            prev = vi;
        }
    }
    return PP5_OK;
}

static int prop_index(const ply_element_t *e, const char *a, const char *b)
{
    for (int k = 0; k < e->n_props; k++)
        if (strcmp(e->props[k].name, a) == 0 || (b && strcmp(e->props[k].name, b) == 0))
            return k;
    return -1;
}

static pp5_status_t ply_body(ply_t *y, mesh_builder_t *b)
{
    long nv = 0;
    int seen_vertex = 0, seen_face = 0;
    double vals[PLY_MAX_PROPS];
    for (int ei = 0; ei < y->n_el; ei++) {
        const ply_element_t *e = &y->el[ei];
        int is_vertex = strcmp(e->name, "vertex") == 0, is_face = strcmp(e->name, "face") == 0;
        int ix = -1, iy = -1, iz = -1, il = -1;
        if (is_vertex) {
            ix = prop_index(e, "x", NULL), iy = prop_index(e, "y", NULL);
            iz = prop_index(e, "z", NULL);
            if (ix < 0 || iy < 0 || iz < 0 || e->props[ix].list_type ||
                e->props[iy].list_type || e->props[iz].list_type)
                return pp5_fail(PP5_E_FORMAT, "%s: vertex element lacks scalar x, y, z", y->path);
            seen_vertex = 1;
            nv = e->count;
        }
        if (is_face) {
            il = prop_index(e, "vertex_indices", "vertex_index");
            if (il < 0 || !e->props[il].list_type || e->props[il].is_float)
                return pp5_fail(PP5_E_FORMAT, "%s: face element lacks an integer list "
                                "vertex_indices", y->path);
            if (!seen_vertex)
                return pp5_fail(PP5_E_FORMAT, "%s: faces come before vertices", y->path);
            seen_face = 1;
        }
        /* A binary body must hold at least the fixed bytes of every instance:
         * checked before allocating, so an absurd count is an error at once. */
        if (y->format != PLY_ASCII &&
            (double)e->count * ply_min_bytes(e) > (double)(y->end - y->p))
            return pp5_fail(PP5_E_FORMAT, "%s: truncated: %ld %s elements need at least %.0f "
                            "bytes, %ld left", y->path, e->count, e->name,
                            (double)e->count * ply_min_bytes(e), (long)(y->end - y->p));
        for (long i = 0; i < e->count; i++) {
            pp5_status_t st = ply_instance(y, e, i, il, b, nv, vals);
            if (st == PP5_OK && is_vertex)
                st = mesh_builder_vertex(b, (double[3]){vals[ix], vals[iy], vals[iz]});
            if (st != PP5_OK)
                return st;
        }
    }
    if (!seen_vertex || !seen_face)
        return pp5_fail(PP5_E_FORMAT, "%s: needs a vertex and a face element", y->path);
    if (y->format == PLY_ASCII) {
        const char *s = (const char *)y->p, *end = (const char *)y->end;
        while (s < end && (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n'))
            s++;
        if (s < end)
            return pp5_fail(PP5_E_FORMAT, "%s: text after the last element", y->path);
    } else if (y->p != y->end) {
        return pp5_fail(PP5_E_FORMAT, "%s: %ld bytes after the last element", y->path,
                        (long)(y->end - y->p));
    }
    return PP5_OK;
}

pp5_status_t mesh_load_ply(const char *path, const uint8_t *data, size_t n, mesh_t *m)
{
    ply_t y;
    memset(&y, 0, sizeof y);
    y.path = path;
    pp5_status_t st = ply_header(&y, data, n);
    if (st != PP5_OK)
        return st;
    mesh_builder_t b = {0};
    st = ply_body(&y, &b);
    return mesh_builder_end(&b, st, path, m);
}
