/* mesh_record.c: the collapse record (a progressive mesh): built from the
 * working mesh, levels extracted at run time, saved and loaded. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "outfile.h"
#include "simplify_work.h"

void mesh_record_free(mesh_record_t *r)
{
    free(r->pos), free(r->parent), free(r->death);
    free(r->tri), free(r->face_death), free(r->face_src);
    free(r->level_step), free(r->level_faces), free(r->level_vertices);
    free(r->scratch_map), free(r->scratch_mstamp), free(r->ck_tri);
    memset(r, 0, sizeof *r);
}

static pp5_status_t record_checkpoints(mesh_record_t *r);

/* What extraction needs besides the record: its scratch and checkpoints. */
static pp5_status_t record_prepare(mesh_record_t *r)
{
    size_t n = (size_t)r->n_vertices + 1;
    r->scratch_map = malloc(sizeof *r->scratch_map * n);
    r->scratch_mstamp = calloc(n, sizeof *r->scratch_mstamp);
    r->stamp = 0;
    if (!r->scratch_map || !r->scratch_mstamp)
        return pp5_fail(PP5_E_NOMEM, "record: out of memory");
    return record_checkpoints(r);
}

typedef struct {
    int32_t death, index;
} face_key_t;

static int cmp_face_key(const void *a, const void *b)
{
    const face_key_t *x = a, *y = b;
    if (x->death != y->death)
        return x->death > y->death ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

pp5_status_t sw_take_record(sw_t *w, const mesh_t *in, mesh_record_t *r)
{
    memset(r, 0, sizeof *r);
    r->n_input_vertices = in->n_vertices;
    r->n_vertices = (int)w->r_nv;
    r->pos = w->r_pos, r->parent = w->r_parent, r->death = w->r_death;
    w->r_pos = NULL, w->r_parent = NULL, w->r_death = NULL;
    r->n_levels = w->r_levels;
    r->level_step = w->r_level_step, r->level_faces = w->r_level_faces;
    r->level_vertices = w->r_level_vertices;
    w->r_level_step = w->r_level_faces = w->r_level_vertices = NULL;
    r->n_faces = in->n_faces;
    size_t nf = (size_t)in->n_faces + 1;
    face_key_t *keys = malloc(sizeof *keys * nf);
    r->tri = malloc(sizeof *r->tri * 3 * nf);
    r->face_death = malloc(sizeof *r->face_death * nf);
    r->face_src = malloc(sizeof *r->face_src * nf);
    if (!keys || !r->tri || !r->face_death || !r->face_src) {
        free(keys);
        mesh_record_free(r);
        return pp5_fail(PP5_E_NOMEM, "record: out of memory");
    }
    for (int f = 0; f < in->n_faces; f++)
        keys[f] = (face_key_t){w->r_face_death[f], f};
    qsort(keys, (size_t)in->n_faces, sizeof *keys, cmp_face_key);
    for (int i = 0; i < in->n_faces; i++) {
        int f = keys[i].index;
        memcpy(r->tri + 3 * i, in->tri + 3 * f, 3 * sizeof *r->tri);
        r->face_death[i] = keys[i].death;
        r->face_src[i] = f;
    }
    free(keys);
    pp5_status_t st = record_prepare(r);
    if (st != PP5_OK)
        mesh_record_free(r);
    return st;
}

int mesh_record_level_for_faces(const mesh_record_t *r, int faces)
{
    int lo = 0, hi = r->n_levels - 1;
    if (r->level_faces[hi] > faces)
        return hi;
    while (lo < hi) {   /* first level with level_faces <= faces */
        int mid = lo + (hi - lo) / 2;
        if (r->level_faces[mid] <= faces)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* The vertices that stand for the input vertices v[0 .. n) after `step`
 * steps (each one's last ancestor alive), written to rep.  A coarse level's
 * chains are long (about 7 merges per corner at 1 % of the bunny) and each
 * link is a load that depends on the one before, so one chain at a time
 * waits on every load.  Eight chains are walked side by side, which keeps
 * eight loads in flight. */
enum { REP_LANES = 8 };

static void record_reps(const mesh_record_t *r, const int32_t *v, int n, int32_t step,
                        int32_t *rep)
{
    const int32_t *death = r->death, *parent = r->parent;
    for (int i = 0; i < n; i += REP_LANES) {
        int32_t u[REP_LANES];
        /* a short last batch repeats its last vertex in the spare lanes */
        for (int k = 0; k < REP_LANES; k++)
            u[k] = v[i + k < n ? i + k : n - 1];
        for (bool moved = true; moved;) {
            moved = false;
            for (int k = 0; k < REP_LANES; k++)
                if (death[u[k]] <= step) {
                    u[k] = parent[u[k]];
                    moved = true;
                }
        }
        for (int k = 0; k < REP_LANES && i + k < n; k++)
            rep[i + k] = u[k];
    }
}

/* A coarse level's chains are long: at 4 faces of the bunny, each corner
 * climbs through dozens of merges.  A checkpoint holds the corners already
 * climbed to its step, so a level starts from the last checkpoint at or
 * before it, where chains are a few links long.  Checkpoint 0 is the
 * input's corners themselves; since each later one has at most half the
 * faces of the one before, together they take at most the room of the
 * faces.  The vertices reached are the same: a chain climbed in two parts
 * ends where it ends climbed at once. */
static const int32_t *record_checkpoint_corners(const mesh_record_t *r, int k)
{
    return k == 0 ? r->tri : r->ck_tri + r->ck_off[k];
}

static pp5_status_t record_checkpoints(mesh_record_t *r)
{
    size_t total = 0;
    int n = 0;
    for (int l = 0, faces = r->n_faces; l < r->n_levels && n < MESH_RECORD_CHECKPOINTS; l++)
        if (l == 0 || (r->level_faces[l] <= faces / 2 && r->level_faces[l] > 0)) {
            r->ck_step[n] = l == 0 ? 0 : r->level_step[l];
            r->ck_faces[n] = faces = l == 0 ? r->n_faces : r->level_faces[l];
            r->ck_off[n] = total;
            total += n == 0 ? 0 : 3 * (size_t)faces;
            n++;
        }
    r->ck_tri = malloc(sizeof *r->ck_tri * (total + 1));
    if (!r->ck_tri)
        return pp5_fail(PP5_E_NOMEM, "record: out of memory for its checkpoints");
    r->n_checkpoints = n;
    for (int k = 1; k < n; k++)
        record_reps(r, record_checkpoint_corners(r, k - 1), 3 * r->ck_faces[k], r->ck_step[k],
                    r->ck_tri + r->ck_off[k]);
    return PP5_OK;
}

/* The last checkpoint at or before `step`. */
static int record_checkpoint_for(const mesh_record_t *r, int32_t step)
{
    int k = 0;
    while (k + 1 < r->n_checkpoints && r->ck_step[k + 1] <= step)
        k++;
    return k;
}

pp5_status_t mesh_record_extract(mesh_record_t *r, int level, mesh_t *out)
{
    if (level < 0 || level >= r->n_levels)
        return pp5_fail(PP5_E_RANGE, "record: level %d outside 0..%d", level, r->n_levels - 1);
    int32_t step = r->level_step[level];
    int nf = r->level_faces[level], cap_v = r->level_vertices[level];
    pp5_status_t st = mesh_alloc(out, cap_v, nf);
    if (st != PP5_OK)
        return st;
    if (++r->stamp == 0) {   /* stamps wrapped: clear them once */
        memset(r->scratch_mstamp, 0, sizeof *r->scratch_mstamp * (size_t)r->n_vertices);
        r->stamp = 1;
    }
    /* the corners' representatives first, into the output's own faces */
    int k = record_checkpoint_for(r, step);
    record_reps(r, record_checkpoint_corners(r, k), 3 * nf, step, out->tri);
    int nv = 0;
    for (int i = 0; i < 3 * nf; i++) {
        int32_t rep = out->tri[i];
        /* each representative numbered once, in order of first use */
        if (r->scratch_mstamp[rep] != r->stamp) {
            if (nv == cap_v) {
                mesh_free(out);
                return pp5_fail(PP5_E_FORMAT, "record: level %d uses more than its %d vertices",
                                level, cap_v);
            }
            r->scratch_mstamp[rep] = r->stamp;
            r->scratch_map[rep] = nv;
            memcpy(out->pos + 3 * nv, r->pos + 3 * rep, 3 * sizeof *out->pos);
            nv++;
        }
        out->tri[i] = r->scratch_map[rep];
    }
    out->n_vertices = nv;
    return PP5_OK;
}

/* File layout (little-endian, the byte order of every host pp5 builds on):
 * "PP5MREC1", u32 version 1, i32 n_input_vertices, n_vertices, n_faces,
 * n_levels, then pos (f64 x 3nv), parent, death (i32 x nv), tri (i32 x 3nf),
 * face_death, face_src (i32 x nf), level_step, level_faces, level_vertices
 * (i32 x n_levels). */
static const char RECORD_MAGIC[8] = {'P', 'P', '5', 'M', 'R', 'E', 'C', '1'};

pp5_status_t mesh_record_save(const char *path, const mesh_record_t *r)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, true);
    if (st != PP5_OK)
        return st;
    FILE *f = o.f;
    int32_t head[5] = {1, r->n_input_vertices, r->n_vertices, r->n_faces, r->n_levels};
    size_t nv = (size_t)r->n_vertices, nf = (size_t)r->n_faces, nl = (size_t)r->n_levels;
    fwrite(RECORD_MAGIC, 1, 8, f);
    fwrite(head, sizeof head, 1, f);
    fwrite(r->pos, sizeof *r->pos, 3 * nv, f);
    fwrite(r->parent, 4, nv, f), fwrite(r->death, 4, nv, f);
    fwrite(r->tri, 4, 3 * nf, f), fwrite(r->face_death, 4, nf, f), fwrite(r->face_src, 4, nf, f);
    fwrite(r->level_step, 4, nl, f), fwrite(r->level_faces, 4, nl, f);
    fwrite(r->level_vertices, 4, nl, f);
    return outfile_commit(&o);
}

/* Every link of the record points where it may: parents are later vertices,
 * faces use input vertices, levels only shrink. */
static pp5_status_t record_check(const char *path, const mesh_record_t *r)
{
    for (int v = 0; v < r->n_vertices; v++) {
        int32_t p = r->parent[v], d = r->death[v];
        if ((p < 0) != (d == INT32_MAX) || (p >= 0 && (p <= v || p >= r->n_vertices)) ||
            (d != INT32_MAX && (d < 1 || d > r->n_vertices - r->n_input_vertices)))
            return pp5_fail(PP5_E_FORMAT, "%s: vertex %d has a bad merge link", path, v);
        for (int k = 0; k < 3; k++)
            if (!(r->pos[3 * v + k] == r->pos[3 * v + k]) || r->pos[3 * v + k] > 1e300 ||
                r->pos[3 * v + k] < -1e300)
                return pp5_fail(PP5_E_FORMAT, "%s: vertex %d is not finite", path, v);
    }
    for (int i = 0; i < 3 * r->n_faces; i++)
        if (r->tri[i] < 0 || r->tri[i] >= r->n_input_vertices)
            return pp5_fail(PP5_E_FORMAT, "%s: face %d uses vertex %d", path, i / 3,
                            (int)r->tri[i]);
    for (int i = 0; i < r->n_faces; i++)
        if (r->face_death[i] < 1 || (i > 0 && r->face_death[i] > r->face_death[i - 1]))
            return pp5_fail(PP5_E_FORMAT, "%s: faces out of order at %d", path, i);
    for (int l = 0; l < r->n_levels; l++)
        if (r->level_faces[l] < 0 || r->level_faces[l] > r->n_faces ||
            r->level_vertices[l] < 0 || r->level_vertices[l] > r->n_vertices ||
            r->level_step[l] < 0 || r->level_step[l] > r->n_vertices - r->n_input_vertices ||
            (l > 0 && (r->level_faces[l] > r->level_faces[l - 1] ||
                       r->level_step[l] <= r->level_step[l - 1])))
            return pp5_fail(PP5_E_FORMAT, "%s: level %d is inconsistent", path, l);
    return PP5_OK;
}

pp5_status_t mesh_record_load(const char *path, mesh_record_t *r)
{
    memset(r, 0, sizeof *r);
    uint8_t *data;
    size_t n;
    pp5_status_t st = mesh_read_file(path, &data, &n);
    if (st != PP5_OK)
        return st;
    int32_t head[5];
    if (n < 28 || memcmp(data, RECORD_MAGIC, 8) != 0) {
        free(data);
        return pp5_fail(PP5_E_FORMAT, "%s: not a pp5 collapse record", path);
    }
    memcpy(head, data + 8, sizeof head);
    r->n_input_vertices = head[1], r->n_vertices = head[2], r->n_faces = head[3];
    r->n_levels = head[4];
    if (head[0] != 1 || head[1] < 0 || head[1] > MESH_MAX_VERTICES || head[2] < head[1] ||
        head[2] > 2 * MESH_MAX_VERTICES || head[3] < 0 || head[3] > MESH_MAX_FACES ||
        head[4] < 1 || head[4] > head[2] - head[1] + 1) {
        free(data);
        memset(r, 0, sizeof *r);
        return pp5_fail(PP5_E_FORMAT, "%s: bad header (version %d, counts %d %d %d %d; at most "
                        "%d vertices and %d faces)", path, head[0], head[1], head[2], head[3],
                        head[4], MESH_MAX_VERTICES, MESH_MAX_FACES);
    }
    size_t nv = (size_t)r->n_vertices, nf = (size_t)r->n_faces, nl = (size_t)r->n_levels;
    size_t want = 28 + 8 * 3 * nv + 4 * 2 * nv + 4 * 5 * nf + 4 * 3 * nl;
    if (n != want) {
        free(data);
        memset(r, 0, sizeof *r);
        return pp5_fail(PP5_E_FORMAT, "%s: %zu bytes, the header implies %zu", path, n, want);
    }
    const uint8_t *p = data + 28;
#define TAKE(field, count, size)                                                  \
    do {                                                                          \
        r->field = malloc((size_t)(count) * (size) + 1);                          \
        if (r->field)                                                             \
            memcpy(r->field, p, (size_t)(count) * (size));                        \
        p += (size_t)(count) * (size);                                            \
    } while (0)
    TAKE(pos, 3 * nv, 8);
    TAKE(parent, nv, 4);
    TAKE(death, nv, 4);
    TAKE(tri, 3 * nf, 4);
    TAKE(face_death, nf, 4);
    TAKE(face_src, nf, 4);
    TAKE(level_step, nl, 4);
    TAKE(level_faces, nl, 4);
    TAKE(level_vertices, nl, 4);
#undef TAKE
    free(data);
    if (!r->pos || !r->parent || !r->death || !r->tri || !r->face_death || !r->face_src ||
        !r->level_step || !r->level_faces || !r->level_vertices)
        st = pp5_fail(PP5_E_NOMEM, "%s: out of memory", path);
    if (st == PP5_OK)
        st = record_check(path, r);
    if (st == PP5_OK)
        st = record_prepare(r);
    if (st != PP5_OK)
        mesh_record_free(r);
    return st;
}
