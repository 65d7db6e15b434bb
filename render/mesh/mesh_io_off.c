/* mesh_io_off.c: a strict OFF reader (Geomview's Object File Format, as CGAL
 * and most mesh archives write it): an "OFF" header (COFF/NOFF/CNOFF allowed,
 * their per-vertex extras skipped), a counts line "V F E", then one vertex
 * and one polygon per line; polygons are fan-triangulated.  Counts are
 * bounded before anything is allocated. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_io_internal.h"

/* The next non-blank, non-comment line; 0 at the end of the file. */
static int off_line(text_cursor_t *c, const char **s, const char **end)
{
    const char *line;
    size_t len;
    while (text_next_line(c, &line, &len)) {
        if (!text_rest_blank(line, line + len)) {
            *s = line;
            *end = line + len;
            return 1;
        }
    }
    return 0;
}

static pp5_status_t off_header(text_cursor_t *c, const char *path, long counts[3])
{
    const char *s, *end;
    if (!off_line(c, &s, &end))
        return pp5_fail(PP5_E_FORMAT, "%s: empty file", path);
    while (s < end && (*s == ' ' || *s == '\t'))
        s++;
    static const char *const kinds[] = {"CNOFF", "NOFF", "COFF", "OFF"};
    size_t k = 0, klen = 0;
    for (; k < 4; k++) {
        klen = strlen(kinds[k]);
        if ((size_t)(end - s) >= klen && memcmp(s, kinds[k], klen) == 0)
            break;
    }
    if (k == 4)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: not an OFF file (no OFF header)", path, c->line);
    s += klen;
    if (text_rest_blank(s, end) && !off_line(c, &s, &end))
        return pp5_fail(PP5_E_FORMAT, "%s: no counts line", path);
    for (int i = 0; i < 3; i++)
        if (!text_long(&s, end, &counts[i]) || counts[i] < 0)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: expected the counts 'vertices faces edges'",
                            path, c->line);
    if (!text_rest_blank(s, end))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: unexpected text after the counts", path, c->line);
    if (counts[0] > MESH_MAX_VERTICES)
        return pp5_fail(PP5_E_RANGE, "%s:%d: %ld vertices (at most %d)", path, c->line,
                        counts[0], MESH_MAX_VERTICES);
    if (counts[1] > MESH_MAX_FACES)
        return pp5_fail(PP5_E_RANGE, "%s:%d: %ld faces (at most %d)", path, c->line, counts[1],
                        MESH_MAX_FACES);
    return PP5_OK;
}

static pp5_status_t off_face(mesh_builder_t *b, const char *s, const char *end, long nv,
                             const char *path, int line)
{
    long k, first = 0, prev = 0;
    if (!text_long(&s, end, &k) || k < 3 || k > 1000000)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: a polygon needs a corner count of at least 3",
                        path, line);
    for (long i = 0; i < k; i++) {
        long v;
        if (!text_long(&s, end, &v))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: polygon has fewer than %ld indices", path,
                            line, k);
        if (v < 0 || v >= nv)
            return pp5_fail(PP5_E_FORMAT, "%s:%d: vertex index %ld outside 0..%ld", path, line,
                            v, nv - 1);
        if (i == 0)
            first = v;
        else if (i >= 2) {
            pp5_status_t st = mesh_builder_face(b, (int32_t)first, (int32_t)prev, (int32_t)v);
            if (st != PP5_OK)
                return pp5_fail(st, "%s:%d: %s", path, line, pp5_error_text());
        }
        prev = v;
    }
    /* Anything after the indices is a colour (up to 4 numbers). */
    double colour;
    for (int i = 0; i < 4 && !text_rest_blank(s, end); i++)
        if (!text_double(&s, end, &colour))
            break;
    if (!text_rest_blank(s, end))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: unexpected text after a polygon", path, line);
    return PP5_OK;
}

pp5_status_t mesh_load_off(const char *path, const char *text, size_t n, mesh_t *m)
{
    text_cursor_t c = {text, text + n, 0};
    long counts[3];
    pp5_status_t st = off_header(&c, path, counts);
    if (st != PP5_OK)
        return st;
    mesh_builder_t b = {0};
    const char *s, *end;
    for (long v = 0; v < counts[0] && st == PP5_OK; v++) {
        double p[3], extra;
        if (!off_line(&c, &s, &end))
            st = pp5_fail(PP5_E_FORMAT, "%s: truncated: %ld of %ld vertices", path, v,
                          counts[0]);
        else if (!text_double(&s, end, &p[0]) || !text_double(&s, end, &p[1]) ||
                 !text_double(&s, end, &p[2]))
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: a vertex needs three finite numbers", path,
                          c.line);
        else {
            for (int i = 0; i < 7 && !text_rest_blank(s, end); i++)
                if (!text_double(&s, end, &extra))
                    break;
            if (!text_rest_blank(s, end))
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: unexpected text after a vertex", path,
                              c.line);
            else
                st = mesh_builder_vertex(&b, p);
        }
    }
    for (long f = 0; f < counts[1] && st == PP5_OK; f++) {
        if (!off_line(&c, &s, &end))
            st = pp5_fail(PP5_E_FORMAT, "%s: truncated: %ld of %ld faces", path, f, counts[1]);
        else
            st = off_face(&b, s, end, counts[0], path, c.line);
    }
    if (st == PP5_OK && off_line(&c, &s, &end))
        st = pp5_fail(PP5_E_FORMAT, "%s:%d: text after the last face", path, c.line);
    return mesh_builder_end(&b, st, path, m);
}
