/* mesh_scene_file.c: the scene file reader (format in mesh_scene.h).  Each
 * error is one line "FILE:LINE: what"; a mesh named twice is loaded once. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_gen.h"
#include "mesh_scene_internal.h"

#define MAX_TOKENS 9

typedef struct {
    mesh_scene_t *s;
    const char *path;
    int line;
    char dir[1024];               /* the scene file's folder, with its '/' ("" if none) */
    char (*names)[1100];          /* the resolved path of each mesh, for instancing */
} reader_t;

static pp5_status_t bad(const reader_t *r, const char *what)
{
    return pp5_fail(PP5_E_FORMAT, "%s:%d: %s", r->path, r->line, what);
}

/* The error just raised, prefixed with the file and line (its code kept). */
static pp5_status_t bad_again(const reader_t *r, pp5_status_t st)
{
    char text[1200];
    snprintf(text, sizeof text, "%s", pp5_error_text());
    return pp5_fail(st, "%s:%d: %s", r->path, r->line, text);
}

/* tok[1..n-1] as finite numbers into v (n - 1 of them). */
static pp5_status_t numbers(const reader_t *r, char **tok, int n, double *v)
{
    for (int i = 1; i < n; i++) {
        char *end;
        v[i - 1] = strtod(tok[i], &end);
        if (end == tok[i] || *end || !isfinite(v[i - 1])) {
            char msg[160];
            snprintf(msg, sizeof msg, "%s: '%.40s' is not a finite number", tok[0], tok[i]);
            return bad(r, msg);
        }
    }
    return PP5_OK;
}

static pp5_status_t need_args(const reader_t *r, const char *word, int n, int lo, int hi,
                              const char *form)
{
    if (n - 1 >= lo && n - 1 <= hi)
        return PP5_OK;
    char msg[200];
    snprintf(msg, sizeof msg, "%s takes %s (got %d values)", word, form, n - 1);
    return bad(r, msg);
}

static pp5_status_t stmt_mesh(reader_t *r, char **tok, int n)
{
    pp5_status_t st = need_args(r, "mesh", n, 1, 1, "one path or gen:NAME");
    if (st != PP5_OK)
        return st;
    char full[1100];
    bool gen = strncmp(tok[1], "gen:", 4) == 0;
    snprintf(full, sizeof full, "%s%s", gen || tok[1][0] == '/' ? "" : r->dir, tok[1]);
    int index = -1;
    for (int i = 0; i < r->s->n_meshes && index < 0; i++)
        if (strcmp(r->names[i], full) == 0)
            index = i;
    if (index < 0) {
        mesh_t m;
        st = gen ? mesh_gen_by_name(full, &m) : mesh_load(full, &m);
        if (st != PP5_OK)
            return bad_again(r, st);
        if (m.n_faces == 0) {
            mesh_free(&m);
            return bad(r, "mesh: it has no faces");
        }
        if ((st = scene_add_mesh(r->s, &m, &index)) != PP5_OK) {
            mesh_free(&m);
            return bad_again(r, st);
        }
        snprintf(r->names[index], sizeof r->names[index], "%s", full);
    }
    static const double grey[3] = {0.8, 0.8, 0.8};
    st = scene_add_object(r->s, index, grey);
    return st == PP5_OK ? PP5_OK : bad_again(r, st);
}

/* translate / rotate / scale: the latest object's transform, applied after. */
static pp5_status_t stmt_transform(reader_t *r, char **tok, int n)
{
    if (r->s->n_objects == 0)
        return bad(r, "a transform before any 'mesh' line");
    double v[4], m[16];
    bool rot = strcmp(tok[0], "rotate") == 0, scale = strcmp(tok[0], "scale") == 0;
    pp5_status_t st = rot     ? need_args(r, tok[0], n, 4, 4, "DEG AX AY AZ")
                      : scale ? need_args(r, tok[0], n, 1, 3, "S or SX SY SZ")
                              : need_args(r, tok[0], n, 3, 3, "X Y Z");
    if (st == PP5_OK && scale && n == 3)
        st = bad(r, "scale takes S or SX SY SZ (got 2 values)");
    if (st == PP5_OK)
        st = numbers(r, tok, n, v);
    if (st != PP5_OK)
        return st;
    scene_mat_identity(m);
    if (rot) {
        double l = sqrt(v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
        if (!(l > 0))
            return bad(r, "rotate: the axis is zero");
        const double axis[3] = {v[1] / l, v[2] / l, v[3] / l};
        scene_mat_rotation(v[0], axis, m);
    } else if (scale) {
        double sx = v[0], sy = n == 4 ? v[1] : v[0], sz = n == 4 ? v[2] : v[0];
        if (sx == 0 || sy == 0 || sz == 0)
            return bad(r, "scale: a factor of zero flattens the object");
        m[0] = sx, m[5] = sy, m[10] = sz;
    } else {
        m[3] = v[0], m[7] = v[1], m[11] = v[2];
    }
    scene_mat_premul(m, r->s->objects[r->s->n_objects - 1].xform);
    return PP5_OK;
}

static pp5_status_t unit_rgb(const reader_t *r, const double v[3], double out[3])
{
    for (int k = 0; k < 3; k++)
        if (!(v[k] >= 0 && v[k] <= 1))
            return bad(r, "colours are three numbers in 0..1");
    memcpy(out, v, 3 * sizeof *v);
    return PP5_OK;
}

static pp5_status_t stmt_rest(reader_t *r, char **tok, int n)
{
    mesh_scene_t *s = r->s;
    double v[8];
    const char *w = tok[0];
    pp5_status_t st;
    if (strcmp(w, "colour") == 0 || strcmp(w, "color") == 0 || strcmp(w, "background") == 0) {
        if ((st = need_args(r, w, n, 3, 3, "R G B in 0..1")) != PP5_OK ||
            (st = numbers(r, tok, n, v)) != PP5_OK)
            return st;
        if (w[0] == 'b')
            return unit_rgb(r, v, s->background);
        if (s->n_objects == 0)
            return bad(r, "a colour before any 'mesh' line");
        return unit_rgb(r, v, s->objects[s->n_objects - 1].rgb);
    }
    if (strcmp(w, "camera") == 0) {
        if ((st = need_args(r, w, n, 6, 7, "EX EY EZ TX TY TZ [FOVY]")) != PP5_OK ||
            (st = numbers(r, tok, n, v)) != PP5_OK)
            return st;
        if (n == 8 && !(v[6] > 0 && v[6] < 180))
            return bad(r, "camera: the field of view is in (0, 180) degrees");
        if (v[0] == v[3] && v[1] == v[4] && v[2] == v[5])
            return bad(r, "camera: the eye is the target");
        memcpy(s->eye, v, 3 * sizeof *v), memcpy(s->target, v + 3, 3 * sizeof *v);
        s->fovy_deg = n == 8 ? v[6] : 40;
        s->have_camera = true;
        return PP5_OK;
    }
    if (strcmp(w, "light") == 0) {
        if ((st = need_args(r, w, n, 3, 7, "DX DY DZ [AMBIENT DIFFUSE [SPECULAR SHININESS]]")) !=
                PP5_OK ||
            (st = numbers(r, tok, n, v)) != PP5_OK)
            return st;
        if (n != 4 && n != 6 && n != 8)
            return bad(r, "light takes DX DY DZ [AMBIENT DIFFUSE [SPECULAR SHININESS]]");
        if (v[0] == 0 && v[1] == 0 && v[2] == 0)
            return bad(r, "light: the direction is zero");
        for (int i = 3; i < n - 1; i++)
            if (!(v[i] >= 0 && v[i] <= (i == 6 ? 10000 : 10)))
                return bad(r, "light: ambient, diffuse and specular are 0..10, shininess 0..10000");
        memcpy(s->light_dir, v, 3 * sizeof *v);
        if (n >= 6)
            s->ambient = v[3], s->diffuse = v[4];
        if (n == 8)
            s->specular = v[5], s->shininess = v[6];
        return PP5_OK;
    }
    char msg[160];
    snprintf(msg, sizeof msg, "unknown statement '%.40s' (mesh, translate, rotate, scale, colour, "
             "camera, light, background)", w);
    return bad(r, msg);
}

static pp5_status_t statement(reader_t *r, char *line)
{
    char *tok[MAX_TOKENS + 1], *save = NULL;
    int n = 0;
    char *hash = strchr(line, '#');
    if (hash)
        *hash = 0;
    for (char *t = strtok_r(line, " \t\r", &save); t; t = strtok_r(NULL, " \t\r", &save)) {
        if (n == MAX_TOKENS)
            return bad(r, "too many values on one line");
        tok[n++] = t;
    }
    if (n == 0)
        return PP5_OK;
    if (strcmp(tok[0], "mesh") == 0)
        return stmt_mesh(r, tok, n);
    if (!strcmp(tok[0], "translate") || !strcmp(tok[0], "rotate") || !strcmp(tok[0], "scale"))
        return stmt_transform(r, tok, n);
    return stmt_rest(r, tok, n);
}

pp5_status_t mesh_scene_read_file(const char *path, mesh_scene_t *s)
{
    uint8_t *data;
    size_t size;
    pp5_status_t st = mesh_read_file(path, &data, &size);
    if (st != PP5_OK)
        return st;
    mesh_scene_init(s, path);
    reader_t r = {s, path, 0, "", NULL};
    const char *slash = strrchr(path, '/');
    if (slash && (size_t)(slash - path + 1) < sizeof r.dir)
        snprintf(r.dir, sizeof r.dir, "%.*s", (int)(slash - path + 1), path);
    r.names = calloc(MESH_SCENE_MAX_MESHES, sizeof *r.names);
    if (!r.names)
        st = pp5_fail(PP5_E_NOMEM, "%s: out of memory", path);
    if (st == PP5_OK && memchr(data, 0, size))
        st = pp5_fail(PP5_E_FORMAT, "%s: a NUL byte: not a text scene file", path);
    char *text = (char *)data, *next;
    for (char *line = text; st == PP5_OK && line && *line; line = next) {
        next = strchr(line, '\n');
        if (next)
            *next++ = 0;
        r.line++;
        st = statement(&r, line);
    }
    if (st == PP5_OK && s->n_objects == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: no 'mesh' line: the scene is empty", path);
    free(r.names);
    free(data);
    if (st != PP5_OK)
        mesh_scene_free(s);
    return st;
}
