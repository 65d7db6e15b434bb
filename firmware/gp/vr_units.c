/* vr_units.c: the units a GP fetches (boxes of the renderers' bricks), which of them can hold anything, and the cache that keeps received units within the GP's local memory.
 *
 * Image-bands fetches whole bricks and drops them after each pass; resident
 * fetches smaller boxes and keeps them across frames, evicting the least
 * recently used (firmware/ARCHITECTURE.md "Work divisions", "Blocks"). */
#include <string.h>

#include "vr_gp_internal.h"

/* Units per brick along an axis of n voxels: the smallest divisor k of n
 * with n / k <= limit, so that units tile the brick exactly (limit 0: 1). */
static int units_per_axis(int n, int limit)
{
    if (limit <= 0 || n <= limit)
        return 1;
    for (int k = (n + limit - 1) / limit; k < n; k++)
        if (n % k == 0)
            return k;
    return n;
}

static void unit_geometry(vr_state_t *s)
{
    int limit = vr_keeps_units(s) ? s->cfg.unit_edge : 0;
    int id = 0;
    for (int n = 0; n < s->cfg.levels; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        vr_unit_geom_t *u = &s->unit[n];
        u->kx = units_per_axis(g->bx, limit);
        u->ky = units_per_axis(g->by, limit);
        u->kz = units_per_axis(g->bz, limit);
        u->ux = g->bx / u->kx;
        u->uy = g->by / u->ky;
        u->uz = g->bz / u->kz;
        u->ugx = g->gx * u->kx;
        u->ugy = g->gy * u->ky;
        u->ugz = g->gz * u->kz;
        s->unit_base[n] = id;
        id += u->ugx * u->ugy * u->ugz;
    }
    s->n_units = id;
}

void vr_unit_locate(const vr_state_t *s, int id, int *level, int ijk[3])
{
    int n = 0;
    while (n + 1 < s->cfg.levels && id >= s->unit_base[n + 1])
        n++;
    const vr_unit_geom_t *u = &s->unit[n];
    int local = id - s->unit_base[n];
    ijk[0] = local % u->ugx;
    ijk[1] = (local / u->ugx) % u->ugy;
    ijk[2] = local / (u->ugx * u->ugy);
    *level = n;
}

/* The brick holding unit id, and the unit's origin inside the brick. */
static int unit_brick(const vr_state_t *s, int id, int origin[3])
{
    int n, ijk[3];
    vr_unit_locate(s, id, &n, ijk);
    const vr_unit_geom_t *u = &s->unit[n];
    const vr_level_geom_t *g = &s->geom[n];
    int k[3] = {u->kx, u->ky, u->kz}, d[3] = {u->ux, u->uy, u->uz};
    for (int a = 0; a < 3; a++)
        origin[a] = (ijk[a] % k[a]) * d[a];
    return s->brick_base[n] + ((ijk[2] / u->kz) * g->gy + ijk[1] / u->ky) * g->gx + ijk[0] / u->kx;
}

size_t vr_unit_bytes(const vr_state_t *s, int id)
{
    /* Image-bands reads and holds whole backing-store blocks (the baseline's
     * 64 KB per brick, partial bricks included). */
    if (!vr_keeps_units(s))
        return VR_BRICK_VOXELS * 4u;
    int n, ijk[3];
    vr_unit_locate(s, id, &n, ijk);
    const vr_unit_geom_t *u = &s->unit[n];
    return (size_t)u->ux * u->uy * u->uz * 4u;
}

/* Whether any voxel of unit (n, ijk) is set in the level's exact octree grid
 * (opacity > 0 within one voxel: conservative for trilinear reads).  A
 * blend's unit is also needed by the set cells just below its box: their
 * samples read its voxels as their upper corners (true values, cold ones
 * too; vr_blend_kernels.h). */
static bool unit_occupied(const vr_state_t *s, int n, const int ijk[3], fw_ops_t *ops)
{
    const vr_unit_geom_t *u = &s->unit[n];
    const bits_t *b = &s->exact[n].occ[0];
    int pad = vr_is_blend(s) ? 1 : 0;
    int x0 = ijk[0] * u->ux - pad, y0 = ijk[1] * u->uy - pad, z0 = ijk[2] * u->uz - pad;
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    z0 = z0 < 0 ? 0 : z0;
    int x1 = (ijk[0] + 1) * u->ux < b->nx ? (ijk[0] + 1) * u->ux : b->nx;
    int y1 = (ijk[1] + 1) * u->uy < b->ny ? (ijk[1] + 1) * u->uy : b->ny;
    int z1 = (ijk[2] + 1) * u->uz < b->nz ? (ijk[2] + 1) * u->uz : b->nz;
    for (int z = z0; z < z1; z++)
        for (int y = y0; y < y1; y++)
            for (int w = x0 >> 6; w <= (x1 - 1) >> 6 && x0 < x1; w++) {
                uint64_t word = b->w[((size_t)z * b->ny + y) * b->wpr + w];
                int lo = w == (x0 >> 6) ? (x0 & 63) : 0, hi = w == ((x1 - 1) >> 6) ? ((x1 - 1) & 63) : 63;
                uint64_t mask = (hi == 63 ? ~0ull : ((1ull << (hi + 1)) - 1)) & ~((1ull << lo) - 1);
                ops->loads++;
                ops->load_use++;     /* masked and tested at once */
                ops->int_ops += 4;
                ops->branches++;
                if (word & mask)
                    return true;
            }
    return false;
}

fw_status_t vr_units_init(gp_t *gp, vr_state_t *s)
{
    unit_geometry(s);
    size_t n = (size_t)s->n_units;
    s->unit_nonempty = fw_alloc(gp, n);
    s->cache = fw_alloc(gp, n * sizeof *s->cache);
    s->cache_n = fw_alloc(gp, n * sizeof *s->cache_n);
    s->unit_state = fw_alloc(gp, n);
    s->unit_tiles = fw_alloc(gp, n);
    s->unit_stamp = fw_alloc(gp, n * sizeof *s->unit_stamp);
    if (!s->unit_nonempty || !s->cache || !s->cache_n || !s->unit_state || !s->unit_tiles ||
        !s->unit_stamp)
        return FW_ERROR;
    fw_ops_t ops = {0};
    for (int id = 0; id < s->n_units; id++) {
        int lv, ijk[3];
        vr_unit_locate(s, id, &lv, ijk);
        if (!vr_keeps_units(s)) {
            /* Whole bricks: the brick table GP 0 sent (exact occupancy). */
            s->unit_nonempty[id] = s->brick_nonempty[lv][id - s->unit_base[lv]];
            continue;
        }
        s->unit_nonempty[id] = unit_occupied(s, lv, ijk, &ops);
    }
    fw_charge(gp, &ops);
    return FW_OK;
}

/* ---- the cache ---- */

static void unit_drop(gp_t *gp, vr_state_t *s, int id)
{
    if (s->unit_state[id] != 0)
        s->cache_bytes -= vr_unit_bytes(s, id);   /* counted from its request */
    if (s->cache[id]) {
        fw_free(gp, s->cache[id]);
        s->cache[id] = NULL;
    }
    if (s->cache_n[id]) {
        fw_free(gp, s->cache_n[id]);
        s->cache_n[id] = NULL;
    }
    s->unit_state[id] = 0;
}

void vr_units_drop_all(gp_t *gp, vr_state_t *s)
{
    for (int id = 0; id < s->n_units; id++)
        if (s->unit_state[id])
            unit_drop(gp, s, id);
    s->cache_bytes = 0;
}

/* Evicts the least recently used present units that this pass does not
 * need (ties: the lowest id) until `bytes` more fit the budget.  The scan is
 * GP work. */
static fw_status_t make_room(gp_t *gp, vr_state_t *s, size_t bytes)
{
    fw_ops_t ops = {0};
    fw_status_t rc = FW_OK;
    while (s->cache_bytes + bytes > s->cache_budget) {
        int victim = -1;
        for (int id = 0; id < s->n_units; id++) {
            ops.loads += 2;
            ops.load_use += 1;       /* the state, tested at once */
            ops.branches += 2;
            if (s->unit_state[id] == 2 && !s->unit_tiles[id] &&
                (victim < 0 || s->unit_stamp[id] < s->unit_stamp[victim]))
                victim = id;
        }
        if (victim < 0) {
            rc = fw_fail(gp, "vr: GP %d: the units of this pass (%llu bytes) do not fit the "
                             "%llu-byte cache", s->g, (unsigned long long)(s->cache_bytes + bytes),
                         (unsigned long long)s->cache_budget);
            break;
        }
        unit_drop(gp, s, victim);
    }
    fw_charge(gp, &ops);
    return rc;
}

/* ---- reads from the renderers ---- */

/* Backing-store block a GP reads for brick id (and the N block, GP split). */
static unsigned brick_block(const vr_state_t *s, int brick, int which)
{
    unsigned slot = (unsigned)brick / (unsigned)s->n_r;
    unsigned base = slot * (unsigned)s->blocks_per_slot;
    if (s->cfg.lighting == VR_LIGHT_DIFFUSE)
        return base;
    if (s->cfg.split == VR_SPLIT_PP)
        return base + 2;
    return base + (unsigned)which;
}

int vr_unit_reads(const vr_state_t *s)
{
    return s->cfg.lighting != VR_LIGHT_DIFFUSE && s->cfg.split == VR_SPLIT_GP ? 2 : 1;
}

unsigned vr_unit_renderer(const vr_state_t *s, int id)
{
    int origin[3];
    return (unsigned)unit_brick(s, id, origin) % (unsigned)s->n_r;
}

/* Reads unit id for GP `requester`: the whole backing-store block under
 * image-bands (READ_BS), else the unit's box of it (READ_BS_BOX). */
fw_status_t vr_unit_send_read(gp_t *gp, vr_state_t *s, int id, unsigned requester)
{
    int origin[3], lv, ijk[3];
    int brick = unit_brick(s, id, origin);
    vr_unit_locate(s, id, &lv, ijk);
    const vr_unit_geom_t *u = &s->unit[lv];
    const vr_level_geom_t *g = &s->geom[lv];
    bool whole = !vr_keeps_units(s);
    ring_addr_t r = ring_addr(RING_NODE_RENDERER, (unsigned)brick % (unsigned)s->n_r);
    uint32_t reply = ring_addr_pack(ring_addr(RING_NODE_GP, requester));
    for (int w = 0; w < vr_unit_reads(s); w++) {
        uint32_t tag = (uint32_t)id * 2u + (uint32_t)w;
        uint32_t args[RING_MSG_ARGS] = {brick_block(s, brick, w), 0, reply, tag, 0, 0};
        if (!whole) {
            args[1] = (uint32_t)g->bx | (uint32_t)g->bz << 8 | (uint32_t)g->by << 16;
            args[4] = (uint32_t)origin[0] | (uint32_t)origin[2] << 8 | (uint32_t)origin[1] << 16;
            args[5] = (uint32_t)u->ux | (uint32_t)u->uy << 8 | (uint32_t)u->uz << 16;
        }
        if (fw_send(gp, r, whole ? RING_MSG_RENDERER_READ_BS : RING_MSG_RENDERER_READ_BS_BOX, args,
                    NULL, 0) != FW_OK)
            return FW_ERROR;
    }
    return FW_OK;
}

fw_status_t vr_units_request(gp_t *gp, vr_state_t *s, int id)
{
    size_t bytes = vr_unit_bytes(s, id);
    if (make_room(gp, s, bytes) != FW_OK)
        return FW_ERROR;
    /* Counted from the request, not the arrival: otherwise every unit of a
     * pass would find room in the same free bytes, and their arrival could
     * overrun local memory. */
    s->cache_bytes += bytes;
    s->unit_state[id] = 1;
    return FW_OK;
}
