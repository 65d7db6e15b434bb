/* vr_footprint.c: per pass, which bricks or units the rays still to cast can read: the texels' rectangles per 2D level (and per tile), the 3D levels those rays sample, and the boxes whose padded projection meets them.
 *
 * Conservative: a box is wanted when its padding by one voxel of its level
 * plus one level-0 voxel, projected, comes within 2 pixels of a rectangle, so
 * every voxel a trilinear lookup of the pass can touch is fetched
 * (firmware/ARCHITECTURE.md "Footprint"). */
#include <math.h>
#include <string.h>

#include "vr_gp_internal.h"

/* Project object-space point to image coordinates (inverse of camera_ray). */
static void project(const vr_state_t *s, const float P[3], float *px, float *py)
{
    const vr_frame_t *f = &s->fr;
    float d[3];
    if (f->projection == 0) {
        for (int a = 0; a < 3; a++)
            d[a] = P[a] - f->centre[a];
        *px = (d[0] * f->right[0] + d[1] * f->right[1] + d[2] * f->right[2]) / f->pixel_size +
              0.5f * (float)s->cfg.width;
        *py = (d[0] * f->down[0] + d[1] * f->down[1] + d[2] * f->down[2]) / f->pixel_size +
              0.5f * (float)s->cfg.height;
        return;
    }
    for (int a = 0; a < 3; a++)
        d[a] = P[a] - f->eye[a];
    float z = d[0] * f->forward[0] + d[1] * f->forward[1] + d[2] * f->forward[2];
    if (z < 1e-3f)
        z = 1e-3f;
    float k = f->eye_distance / z;
    *px = k * (d[0] * f->right[0] + d[1] * f->right[1] + d[2] * f->right[2]) / f->pixel_size +
          0.5f * (float)s->cfg.width;
    *py = k * (d[0] * f->down[0] + d[1] * f->down[1] + d[2] * f->down[2]) / f->pixel_size +
          0.5f * (float)s->cfg.height;
}

/* The image rectangle [x0, x1] x [y0, y1] and ray-parameter range of the
 * padded box of level-n voxels lo..hi (inclusive).  Charged per corner. */
static void box_extent(const vr_state_t *s, int n, const int lo[3], const int hi[3], float out[4],
                       float *tmin, float *tmax, fw_ops_t *ops)
{
    float sc = (float)(1 << n);
    float plo[3], phi[3];
    for (int a = 0; a < 3; a++) {
        /* level-0 voxel positions, padded by one level-n spacing and a margin */
        plo[a] = (((float)lo[a] + 0.5f) * sc - 0.5f - sc - 1.0f) * s->cfg.spacing[a];
        phi[a] = (((float)hi[a] + 0.5f) * sc - 0.5f + sc + 1.0f) * s->cfg.spacing[a];
    }
    out[0] = out[2] = INFINITY;
    out[1] = out[3] = -INFINITY;
    *tmin = INFINITY;
    *tmax = -INFINITY;
    const vr_frame_t *f = &s->fr;
    for (int k = 0; k < 8; k++) {
        float P[3] = {(k & 1) ? phi[0] : plo[0], (k & 2) ? phi[1] : plo[1], (k & 4) ? phi[2] : plo[2]};
        float px, py;
        project(s, P, &px, &py);
        /* Ray parameter of the corner: parallel t = depth + radius + 1;
         * perspective: between the depth along the view axis (a lower
         * bound, minimal at a corner) and the distance (maximal at one). */
        float tl, th;
        if (f->projection == 0) {
            tl = th = (P[0] - f->centre[0]) * f->forward[0] + (P[1] - f->centre[1]) * f->forward[1] +
                      (P[2] - f->centre[2]) * f->forward[2] + f->radius + 1.0f;
        } else {
            float d[3] = {P[0] - f->eye[0], P[1] - f->eye[1], P[2] - f->eye[2]};
            tl = d[0] * f->forward[0] + d[1] * f->forward[1] + d[2] * f->forward[2];
            th = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
        *tmin = tl < *tmin ? tl : *tmin;
        *tmax = th > *tmax ? th : *tmax;
        out[0] = px < out[0] ? px : out[0];
        out[1] = px > out[1] ? px : out[1];
        out[2] = py < out[2] ? py : out[2];
        out[3] = py > out[3] ? py : out[3];
    }
    ops->fadd += 8 * 8;
    ops->fmul += 8 * 8;
    ops->fdiv += 8 * 2;
    ops->branches += 8 * 4 + 4;
}

static bool meets(const float box[4], const float rect[4])
{
    return !(box[1] < rect[0] - 2.0f || box[0] > rect[1] + 2.0f || box[3] < rect[2] - 2.0f ||
             box[2] > rect[3] + 2.0f);
}

static bool in_depth(float tmin, float tmax, const float tseg[2])
{
    return !(tmax < tseg[0] - 1.0f || tmin > tseg[1] + 1.0f);
}

/* The tile of pixel row py (rows past the band go to the last tile). */
static int tile_of(const vr_state_t *s, int py)
{
    int t = 0;
    while (t + 1 < s->tiles && py >= s->tile_y0[t + 1])
        t++;
    return t;
}

/* Rectangles of the texel points still to cast in this pass: per tile and
 * 2D level (rect), and per 2D level over the whole pass (all). */
typedef struct {
    float rect[VR_MAX_TILES][VR_MAX_2D_LEVELS][4], all[VR_MAX_2D_LEVELS][4];
    bool any[VR_MAX_TILES][VR_MAX_2D_LEVELS], any_all[VR_MAX_2D_LEVELS];
} pass_rects_t;

static void grow(float r[4], float px, float py)
{
    r[0] = px < r[0] ? px : r[0];
    r[1] = px > r[1] ? px : r[1];
    r[2] = py < r[2] ? py : r[2];
    r[3] = py > r[3] ? py : r[3];
}

static void pass_rects(const vr_state_t *s, pass_rects_t *pr, fw_ops_t *ops)
{
    float px0, px1;
    vr_plan_pass_range(s, s->pass, &px0, &px1);
    for (int m = 0; m < s->levels2d; m++) {
        pr->all[m][0] = pr->all[m][2] = INFINITY;
        pr->all[m][1] = pr->all[m][3] = -INFINITY;
        pr->any_all[m] = false;
        for (int t = 0; t < s->tiles; t++) {
            memcpy(pr->rect[t][m], pr->all[m], sizeof pr->all[m]);
            pr->any[t][m] = false;
        }
        for (int j = s->jlo[m]; j <= s->jhi[m]; j++) {
            size_t row = (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *nd = s->need[m] + row, *cf = s->castf[m] + row, *rsx = s->ray_state[m] + row;
            int t = tile_of(s, j << m);
            for (int i = 0; i < s->tw[m]; i++) {
                if (!nd[i] || cf[i] || rsx[i] == 2)
                    continue;
                float px = (float)(i << m) + 0.5f, py = (float)(j << m) + 0.5f;
                if (px < px0 || px >= px1)
                    continue;
                grow(pr->all[m], px, py);
                grow(pr->rect[t][m], px, py);
                pr->any_all[m] = pr->any[t][m] = true;
            }
            /* the need flag of each texel, tested at once */
            ops->loads += (uint64_t)s->tw[m];
            ops->load_use += (uint64_t)s->tw[m];
            ops->branches += (uint64_t)s->tw[m];
        }
    }
}

/* 3D levels a level-m ray reads: m exactly under parallel projection
 * (raycast.h); under perspective the spacing grows along the ray, so
 * floor(L(t_near)) .. ceil(L(t_far)) over the bounding sphere. */
static void level_range(const vr_state_t *s, int m, int *n_lo, int *n_hi)
{
    const vr_config_t *c = &s->cfg;
    float lstep = log2f(c->sample_step);
    float base3d = log2f(c->sample_step * (float)(1 << m)) - lstep;
    *n_lo = *n_hi = (int)floorf(base3d);
    if (s->fr.projection != 0) {
        float base = c->sample_step * (float)(1 << m);
        float ed = s->fr.eye_distance, rad = s->fr.radius + 1.0f;
        float t_near = ed - rad > 1e-3f ? ed - rad : 1e-3f, t_far = ed + rad;
        *n_lo = (int)floorf(log2f(t_near * base / ed) - lstep);
        *n_hi = (int)floorf(log2f(t_far * base / ed) - lstep) + 1;
    }
}

static int clamp_level(const vr_state_t *s, int n)
{
    return n < 0 ? 0 : (n >= s->cfg.levels ? s->cfg.levels - 1 : n);
}

static bool brick_hits(const vr_state_t *s, int n, int bx, int by, int bz, const float rect[4],
                       const float tseg[2], fw_ops_t *ops)
{
    const vr_level_geom_t *g = &s->geom[n];
    int lo[3] = {bx * g->bx, by * g->by, bz * g->bz};
    int hi[3] = {lo[0] + g->bx - 1, lo[1] + g->by - 1, lo[2] + g->bz - 1};
    float box[4], tmin, tmax;
    box_extent(s, n, lo, hi, box, &tmin, &tmax, ops);
    return in_depth(tmin, tmax, tseg) && meets(box, rect);
}

fw_status_t vr_footprint_bricks(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n_out)
{
    fw_ops_t ops = {0};
    float tseg[2];
    vr_plan_seg_range(s, s->pass, &tseg[0], &tseg[1]);
    pass_rects_t pr;
    pass_rects(s, &pr, &ops);
    uint8_t *wanted = fw_alloc(gp, (size_t)s->n_bricks);
    if (!wanted)
        return FW_ERROR;
    size_t n_want = 0;
    for (int m = 0; m < s->levels2d; m++) {
        if (!pr.any_all[m])
            continue;
        int n_lo, n_hi;
        level_range(s, m, &n_lo, &n_hi);
        for (int n = n_lo; n <= n_hi; n++) {
            int nn = clamp_level(s, n);
            const vr_level_geom_t *g = &s->geom[nn];
            for (int bz = 0; bz < g->gz; bz++)
                for (int by = 0; by < g->gy; by++)
                    for (int bx = 0; bx < g->gx; bx++) {
                        int local = (bz * g->gy + by) * g->gx + bx;
                        int id = s->brick_base[nn] + local;
                        ops.loads++;
                        ops.load_use++;      /* tested at once */
                        ops.branches++;
                        if (wanted[id] || !s->brick_nonempty[nn][local])
                            continue;
                        if (!brick_hits(s, nn, bx, by, bz, pr.all[m], tseg, &ops))
                            continue;
                        wanted[id] = 1;
                        if (want)
                            want[n_want] = (uint32_t)id;
                        n_want++;
                    }
        }
    }
    fw_charge(gp, &ops);
    fw_free(gp, wanted);
    *n_out = n_want;
    return FW_OK;
}

/* The tiles (bit mask) whose level-m rectangles unit `id`'s padded box meets. */
static uint8_t unit_mask(const vr_state_t *s, int id, int m, const pass_rects_t *pr,
                         const float tseg[2], fw_ops_t *ops)
{
    int n, ijk[3];
    vr_unit_locate(s, id, &n, ijk);
    const vr_unit_geom_t *u = &s->unit[n];
    int d[3] = {u->ux, u->uy, u->uz}, lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = ijk[a] * d[a];
        hi[a] = lo[a] + d[a] - 1;
    }
    float box[4], tmin, tmax;
    box_extent(s, n, lo, hi, box, &tmin, &tmax, ops);
    if (!in_depth(tmin, tmax, tseg))
        return 0;
    uint8_t mask = 0;
    for (int t = 0; t < s->tiles; t++) {
        ops->branches += 2;
        if (pr->any[t][m] && meets(box, pr->rect[t][m]))
            mask |= (uint8_t)(1u << t);
    }
    return mask;
}

/* The units of brick (n, bx, by, bz) that the pass's level-m rays need:
 * their tile masks or-ed into mask[]; newly wanted ones appended to list. */
static void brick_units(const vr_state_t *s, int n, int bx, int by, int bz, int m,
                        const pass_rects_t *pr, const float tseg[2], uint8_t *mask, uint32_t *list,
                        size_t *n_list, fw_ops_t *ops)
{
    const vr_unit_geom_t *u = &s->unit[n];
    for (int kz = 0; kz < u->kz; kz++)
        for (int ky = 0; ky < u->ky; ky++)
            for (int kx = 0; kx < u->kx; kx++) {
                int ix = bx * u->kx + kx, iy = by * u->ky + ky, iz = bz * u->kz + kz;
                int id = s->unit_base[n] + (iz * u->ugy + iy) * u->ugx + ix;
                ops->loads++;
                ops->load_use++;     /* tested at once */
                ops->branches++;
                if (!s->unit_nonempty[id])
                    continue;
                uint8_t t = unit_mask(s, id, m, pr, tseg, ops);
                if (t && !mask[id])
                    list[(*n_list)++] = (uint32_t)id;
                mask[id] |= t;
            }
}

/* Resident: the units of this pass, tile by tile (units of tile 0 first, so
 * that tile 0 can be cast while the others are in flight); with want, each
 * unit's tile mask goes to unit_tiles.  Bytes: their sizes summed. */
fw_status_t vr_footprint_units(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n_out,
                               uint64_t *bytes_out)
{
    fw_ops_t ops = {0};
    float tseg[2];
    vr_plan_seg_range(s, s->pass, &tseg[0], &tseg[1]);
    pass_rects_t pr;
    pass_rects(s, &pr, &ops);
    uint8_t *mask = fw_alloc(gp, (size_t)s->n_units);
    uint32_t *list = fw_alloc(gp, (size_t)s->n_units * sizeof *list);
    if (!mask || !list)
        return FW_ERROR;
    size_t n_list = 0;
    for (int m = 0; m < s->levels2d; m++) {
        if (!pr.any_all[m])
            continue;
        int n_lo, n_hi;
        level_range(s, m, &n_lo, &n_hi);
        for (int n = n_lo; n <= n_hi; n++) {
            int nn = clamp_level(s, n);
            const vr_level_geom_t *g = &s->geom[nn];
            for (int bz = 0; bz < g->gz; bz++)
                for (int by = 0; by < g->gy; by++)
                    for (int bx = 0; bx < g->gx; bx++) {
                        int local = (bz * g->gy + by) * g->gx + bx;
                        ops.loads++;
                        ops.load_use++;      /* tested at once */
                        ops.branches++;
                        if (s->brick_nonempty[nn][local] &&
                            brick_hits(s, nn, bx, by, bz, pr.all[m], tseg, &ops))
                            brick_units(s, nn, bx, by, bz, m, &pr, tseg, mask, list, &n_list, &ops);
                    }
        }
    }
    size_t n_want = 0;
    uint64_t bytes = 0;
    for (int t = 0; t < s->tiles; t++)
        for (size_t i = 0; i < n_list; i++) {
            uint32_t id = list[i];
            ops.loads += 2;
            ops.load_use += 1;       /* the mask, scanned at once */
            ops.branches += 2;
            int first = __builtin_ctz(mask[id]);
            if (first != t)
                continue;
            if (want) {
                want[n_want] = id;
                s->unit_tiles[id] = mask[id];
            }
            bytes += vr_unit_bytes(s, (int)id);
            n_want++;
        }
    fw_charge(gp, &ops);
    fw_free(gp, mask);
    fw_free(gp, list);
    *n_out = n_want;
    if (bytes_out)
        *bytes_out = bytes;
    return FW_OK;
}
