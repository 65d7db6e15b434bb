/* mesh_io_obj.c: a strict Wavefront OBJ reader: `v` and `f` statements
 * (v, v/vt, v/vt/vn, v//vn; negative indices count back from the last
 * vertex), polygons fan-triangulated; attributes and grouping statements are
 * skipped; anything else is an error naming the file and line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io_internal.h"

/* Statements that carry nothing the mesh keeps. */
static int obj_ignored(const char *kw, size_t n)
{
    static const char *const skip[] = {"vt", "vn", "vp", "g", "o", "s", "usemtl", "mtllib",
                                       "l", "p"};
    for (size_t i = 0; i < sizeof skip / sizeof skip[0]; i++)
        if (strlen(skip[i]) == n && memcmp(kw, skip[i], n) == 0)
            return 1;
    return 0;
}

/* One face corner "a", "a/b", "a/b/c" or "a//c": the vertex index (0-based). */
static pp5_status_t obj_corner(const char **s, const char *end, size_t nv, const char *path,
                               int line, int32_t *out)
{
    long idx;
    const char *q = *s;
    while (q < end && (*q == ' ' || *q == '\t'))
        q++;
    const char *tok = q;
    while (q < end && *q != ' ' && *q != '\t' && *q != '/')
        q++;
    char buf[32];
    size_t len = (size_t)(q - tok);
    if (len == 0 || len >= sizeof buf)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad face corner", path, line);
    memcpy(buf, tok, len);
    buf[len] = '\0';
    const char *b = buf;
    if (!text_long(&b, buf + len, &idx))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad vertex index '%s'", path, line, buf);
    while (q < end && *q != ' ' && *q != '\t')
        q++; /* texture and normal indices are not kept */
    *s = q;
    long v = idx < 0 ? (long)nv + idx : idx - 1;
    if (idx == 0 || v < 0 || v >= (long)nv)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: vertex index %ld outside 1..%zu", path, line, idx,
                        nv);
    *out = (int32_t)v;
    return PP5_OK;
}

static pp5_status_t obj_face(mesh_builder_t *b, const char *s, const char *end,
                             const char *path, int line)
{
    int32_t first = -1, prev = -1;
    int n = 0;
    while (!text_rest_blank(s, end)) {
        int32_t v = -1;
        pp5_status_t st = obj_corner(&s, end, b->nv, path, line, &v);
        if (st != PP5_OK)
            return st;
        if (n == 0)
            first = v;
        else if (n >= 2 && (st = mesh_builder_face(b, first, prev, v)) != PP5_OK)
            return pp5_fail(st, "%s:%d: %s", path, line, pp5_error_text());
        prev = v;
        n++;
    }
    if (n < 3)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: a face needs at least 3 vertices, got %d", path,
                        line, n);
    return PP5_OK;
}

pp5_status_t mesh_load_obj(const char *path, const char *text, size_t n, mesh_t *m)
{
    mesh_builder_t b = {0};
    text_cursor_t c = {text, text + n, 0};
    const char *line;
    size_t len;
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && text_next_line(&c, &line, &len)) {
        const char *s = line, *end = line + len;
        while (s < end && (*s == ' ' || *s == '\t'))
            s++;
        if (s == end || *s == '#')
            continue;
        const char *kw = s;
        while (s < end && *s != ' ' && *s != '\t')
            s++;
        size_t kn = (size_t)(s - kw);
        if (kn == 1 && kw[0] == 'v') {
            double p[3];
            if (!text_double(&s, end, &p[0]) || !text_double(&s, end, &p[1]) ||
                !text_double(&s, end, &p[2]))
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: a vertex needs three finite numbers", path,
                              c.line);
            else {
                /* Up to four more numbers (a weight, or an r g b colour
                 * extension) are allowed and not kept. */
                double extra;
                int k = 0;
                while (k < 4 && !text_rest_blank(s, end) && text_double(&s, end, &extra))
                    k++;
                if (!text_rest_blank(s, end))
                    st = pp5_fail(PP5_E_FORMAT, "%s:%d: unexpected text after a vertex", path,
                                  c.line);
                else if ((st = mesh_builder_vertex(&b, p)) != PP5_OK)
                    st = pp5_fail(st, "%s:%d: %s", path, c.line, pp5_error_text());
            }
        } else if (kn == 1 && kw[0] == 'f') {
            st = obj_face(&b, s, end, path, c.line);
        } else if (!obj_ignored(kw, kn)) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: unsupported statement '%.*s'", path, c.line,
                          (int)(kn > 20 ? 20 : kn), kw);
        }
    }
    return mesh_builder_end(&b, st, path, m);
}
