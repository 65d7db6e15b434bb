/* mesh_io.c: reading whole mesh files (plain or gzip), choosing the reader by
 * extension, the shared builder and text cursor, and the writers. */
#include "mesh_io_internal.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "outfile.h"

pp5_status_t mesh_builder_vertex(mesh_builder_t *b, const double p[3])
{
    if (b->nv >= MESH_MAX_VERTICES)
        return pp5_fail(PP5_E_RANGE, "more than %d vertices", MESH_MAX_VERTICES);
    if (b->nv == b->cap_v) {
        size_t cap = b->cap_v ? 2 * b->cap_v : 1024;
        double *np = realloc(b->pos, cap * 3 * sizeof *np);
        if (!np)
            return pp5_fail(PP5_E_NOMEM, "out of memory at %zu vertices", b->nv);
        b->pos = np;
        b->cap_v = cap;
    }
    memcpy(b->pos + 3 * b->nv++, p, 3 * sizeof *p);
    return PP5_OK;
}

pp5_status_t mesh_builder_face(mesh_builder_t *b, int32_t a, int32_t c, int32_t d)
{
    if (b->nf >= MESH_MAX_FACES)
        return pp5_fail(PP5_E_RANGE, "more than %d faces", MESH_MAX_FACES);
    if (b->nf == b->cap_f) {
        size_t cap = b->cap_f ? 2 * b->cap_f : 1024;
        int32_t *nt = realloc(b->tri, cap * 3 * sizeof *nt);
        if (!nt)
            return pp5_fail(PP5_E_NOMEM, "out of memory at %zu faces", b->nf);
        b->tri = nt;
        b->cap_f = cap;
    }
    int32_t *t = b->tri + 3 * b->nf++;
    t[0] = a, t[1] = c, t[2] = d;
    return PP5_OK;
}

pp5_status_t mesh_builder_finish(mesh_builder_t *b, const char *path, mesh_t *m)
{
    memset(m, 0, sizeof *m);
    m->n_vertices = (int)b->nv;
    m->n_faces = (int)b->nf;
    m->pos = b->pos ? b->pos : calloc(1, sizeof *m->pos);
    m->tri = b->tri ? b->tri : calloc(1, sizeof *m->tri);
    memset(b, 0, sizeof *b);
    const char *slash = strrchr(path, '/');
    snprintf(m->source, sizeof m->source, "%s", slash ? slash + 1 : path);
    if (!m->pos || !m->tri) {
        mesh_free(m);
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", path);
    }
    pp5_status_t st = mesh_validate(m, path);
    if (st != PP5_OK)
        mesh_free(m);
    return st;
}

pp5_status_t mesh_builder_end(mesh_builder_t *b, pp5_status_t st, const char *path, mesh_t *m)
{
    if (st == PP5_OK && b->nf == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: no faces", path);
    if (st != PP5_OK) {
        mesh_builder_free(b);
        return st;
    }
    return mesh_builder_finish(b, path, m);
}

void mesh_builder_free(mesh_builder_t *b)
{
    free(b->pos);
    free(b->tri);
    memset(b, 0, sizeof *b);
}

int text_next_line(text_cursor_t *c, const char **line, size_t *len)
{
    if (c->p >= c->end)
        return 0;
    const char *nl = memchr(c->p, '\n', (size_t)(c->end - c->p));
    const char *stop = nl ? nl : c->end;
    *line = c->p;
    *len = (size_t)(stop - c->p);
    if (*len && (*line)[*len - 1] == '\r')
        (*len)--;
    c->p = nl ? nl + 1 : c->end;
    c->line++;
    return 1;
}

static void skip_blank(const char **s, const char *end)
{
    while (*s < end && (**s == ' ' || **s == '\t'))
        (*s)++;
}

/* Copies the token at *s into buf (bounded), returns its length or 0. */
static size_t take_token(const char **s, const char *end, char *buf, size_t cap)
{
    skip_blank(s, end);
    size_t n = 0;
    while (*s < end && !isspace((unsigned char)**s) && **s != '#') {
        if (n + 1 >= cap)
            return 0;
        buf[n++] = *(*s)++;
    }
    buf[n] = '\0';
    return n;
}

int text_double(const char **s, const char *end, double *out)
{
    char buf[64], *stop;
    if (!take_token(s, end, buf, sizeof buf))
        return 0;
    errno = 0;
    *out = strtod(buf, &stop);
    return *stop == '\0' && errno != ERANGE && isfinite(*out);
}

int text_long(const char **s, const char *end, long *out)
{
    char buf[32], *stop;
    if (!take_token(s, end, buf, sizeof buf))
        return 0;
    errno = 0;
    *out = strtol(buf, &stop, 10);
    return *stop == '\0' && errno != ERANGE;
}

int text_rest_blank(const char *s, const char *end)
{
    skip_blank(&s, end);
    return s >= end || *s == '#';
}

pp5_status_t mesh_read_file(const char *path, uint8_t **data, size_t *n)
{
    *data = NULL;
    *n = 0;
    gzFile gz = gzopen(path, "rb");
    if (!gz)
        return pp5_fail(PP5_E_IO, "%s: cannot open (%s)", path, strerror(errno));
    size_t cap = 1 << 20, len = 0;
    uint8_t *buf = malloc(cap + 1);
    pp5_status_t st = buf ? PP5_OK : pp5_fail(PP5_E_NOMEM, "%s: out of memory", path);
    while (st == PP5_OK) {
        if (len == cap) {
            if (cap >= MESH_MAX_FILE_BYTES) {
                st = pp5_fail(PP5_E_RANGE, "%s: larger than %zu bytes", path,
                              (size_t)MESH_MAX_FILE_BYTES);
                break;
            }
            uint8_t *nb = realloc(buf, 2 * cap + 1);
            if (!nb) {
                st = pp5_fail(PP5_E_NOMEM, "%s: out of memory at %zu bytes", path, len);
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t want = cap - len > (1u << 30) ? (1u << 30) : cap - len;
        int r = gzread(gz, buf + len, (unsigned)want);
        if (r < 0) {
            int e;
            st = pp5_fail(PP5_E_FORMAT, "%s: %s", path, gzerror(gz, &e));
        } else if (r == 0) {
            break;
        }
        len += r > 0 ? (size_t)r : 0;
    }
    gzclose(gz);
    if (st != PP5_OK) {
        free(buf);
        return st;
    }
    buf[len] = '\0';
    *data = buf;
    *n = len;
    return PP5_OK;
}

/* The extension of path ignoring a trailing ".gz", lower-cased into ext. */
static void mesh_extension(const char *path, char ext[8])
{
    size_t n = strlen(path);
    if (n > 3 && strcmp(path + n - 3, ".gz") == 0)
        n -= 3;
    size_t dot = n;
    while (dot > 0 && path[dot - 1] != '.' && path[dot - 1] != '/')
        dot--;
    ext[0] = '\0';
    if (dot == 0 || path[dot - 1] != '.' || n - dot > 6)
        return;
    for (size_t i = 0; i < n - dot; i++)
        ext[i] = (char)tolower((unsigned char)path[dot + i]);
    ext[n - dot] = '\0';
}

pp5_status_t mesh_load(const char *path, mesh_t *m)
{
    char ext[8];
    mesh_extension(path, ext);
    if (strcmp(ext, "obj") != 0 && strcmp(ext, "off") != 0 && strcmp(ext, "ply") != 0)
        return pp5_fail(PP5_E_FORMAT, "%s: unknown mesh format (expected .obj, .off or .ply, "
                        "optionally .gz)", path);
    uint8_t *data;
    size_t n;
    pp5_status_t st = mesh_read_file(path, &data, &n);
    if (st != PP5_OK)
        return st;
    if (strcmp(ext, "obj") == 0)
        st = mesh_load_obj(path, (const char *)data, n, m);
    else if (strcmp(ext, "off") == 0)
        st = mesh_load_off(path, (const char *)data, n, m);
    else
        st = mesh_load_ply(path, data, n, m);
    free(data);
    return st;
}

static void put_le(FILE *f, const void *v, size_t size)
{
    /* PLY binary_little_endian: the host is little-endian on every platform
     * pp5 builds on (x86-64, arm64); the bytes are written in order. */
    fwrite(v, size, 1, f);
}

static void write_ply(FILE *f, const mesh_t *m)
{
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment written by pp5\n"
               "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
               "element face %d\nproperty list uchar int vertex_indices\nend_header\n",
            m->n_vertices, m->n_faces);
    for (int v = 0; v < m->n_vertices; v++)
        for (int k = 0; k < 3; k++) {
            float x = (float)m->pos[3 * v + k];
            put_le(f, &x, 4);
        }
    for (int t = 0; t < m->n_faces; t++) {
        unsigned char three = 3;
        put_le(f, &three, 1);
        put_le(f, m->tri + 3 * t, 12);
    }
}

pp5_status_t mesh_save(const char *path, const mesh_t *m)
{
    char ext[8];
    mesh_extension(path, ext);
    size_t n = strlen(path);
    if (n > 3 && strcmp(path + n - 3, ".gz") == 0)
        return pp5_fail(PP5_E_CONFIG, "%s: writing compressed meshes is not supported", path);
    int kind = strcmp(ext, "obj") == 0 ? 0 : strcmp(ext, "off") == 0 ? 1
             : strcmp(ext, "ply") == 0 ? 2 : -1;
    if (kind < 0)
        return pp5_fail(PP5_E_CONFIG, "%s: unknown mesh format (use .obj, .off or .ply)", path);
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, true);
    if (st != PP5_OK)
        return st;
    FILE *f = o.f;
    if (kind == 0) {
        fprintf(f, "# %d vertices, %d triangles, written by pp5\n", m->n_vertices, m->n_faces);
        for (int v = 0; v < m->n_vertices; v++)
            fprintf(f, "v %.9g %.9g %.9g\n", m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2]);
        for (int t = 0; t < m->n_faces; t++)
            fprintf(f, "f %d %d %d\n", m->tri[3 * t] + 1, m->tri[3 * t + 1] + 1,
                    m->tri[3 * t + 2] + 1);
    } else if (kind == 1) {
        fprintf(f, "OFF\n%d %d 0\n", m->n_vertices, m->n_faces);
        for (int v = 0; v < m->n_vertices; v++)
            fprintf(f, "%.17g %.17g %.17g\n", m->pos[3 * v], m->pos[3 * v + 1],
                    m->pos[3 * v + 2]);
        for (int t = 0; t < m->n_faces; t++)
            fprintf(f, "3 %d %d %d\n", m->tri[3 * t], m->tri[3 * t + 1], m->tri[3 * t + 2]);
    } else {
        write_ply(f, m);
    }
    return outfile_commit(&o);
}
