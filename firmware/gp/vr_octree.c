/* vr_octree.c: bit volumes, their box dilation and the OR pyramid: the octree of render/octree.c as row-padded bit grids on a GP.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"

bool vr_bits_alloc(gp_t *gp, bits_t *b, int nx, int ny, int nz)
{
    b->nx = nx;
    b->ny = ny;
    b->nz = nz;
    b->wpr = (nx + 63) / 64;
    b->w = fw_alloc(gp, vr_bits_words(nx, ny, nz) * 8);
    return b->w != NULL;
}

/* Box dilation [i-lo, i+hi] per axis (render/octree.c's window, clamped to
 * the grid), word-parallel. */
static void dilate(const bits_t *in, bits_t *out, int lo, int hi, fw_ops_t *ops)
{
    int wpr = in->wpr;
    size_t rows = (size_t)in->ny * in->nz;
    uint64_t tmp[64];
    /* x: out bit i = OR of in bits i-lo .. i+hi */
    for (size_t r = 0; r < rows; r++) {
        const uint64_t *src = in->w + r * wpr;
        uint64_t *dst = out->w + r * wpr;
        for (int k = 0; k < wpr; k++)
            tmp[k] = 0;
        for (int s = -lo; s <= hi; s++) {
            /* bit i takes in bit i + s */
            for (int k = 0; k < wpr; k++) {
                uint64_t v;
                if (s >= 0) {
                    v = src[k] >> s;
                    if (s > 0 && k + 1 < wpr)
                        v |= src[k + 1] << (64 - s);
                } else {
                    int t = -s;
                    v = src[k] << t;
                    if (k > 0)
                        v |= src[k - 1] >> (64 - t);
                }
                tmp[k] |= v;
            }
        }
        for (int k = 0; k < wpr; k++)
            dst[k] = tmp[k];
        /* clear padding beyond nx */
        if (in->nx & 63)
            dst[wpr - 1] &= (1ull << (in->nx & 63)) - 1;
    }
    ops->int_ops += rows * (size_t)wpr * (size_t)(lo + hi + 1) * 3;
    ops->loads += rows * (size_t)wpr * (size_t)(lo + hi + 1);
    ops->stores += rows * (size_t)wpr;
}

static void dilate_rows(const bits_t *in, bits_t *out, int axis, int lo, int hi, fw_ops_t *ops)
{
    int wpr = in->wpr, n = axis == 1 ? in->ny : in->nz;
    for (int z = 0; z < in->nz; z++)
        for (int y = 0; y < in->ny; y++) {
            int i = axis == 1 ? y : z;
            int a = i - lo < 0 ? 0 : i - lo, b = i + hi > n - 1 ? n - 1 : i + hi;
            uint64_t *dst = out->w + ((size_t)z * in->ny + y) * wpr;
            for (int k = 0; k < wpr; k++)
                dst[k] = 0;
            for (int j = a; j <= b; j++) {
                const uint64_t *src = axis == 1 ? in->w + ((size_t)z * in->ny + j) * wpr
                                                : in->w + ((size_t)j * in->ny + y) * wpr;
                for (int k = 0; k < wpr; k++)
                    dst[k] |= src[k];
            }
            ops->loads += (uint64_t)(b - a + 1) * wpr;
            ops->int_ops += (uint64_t)(b - a + 1) * wpr + 6;
            ops->stores += wpr;
        }
}

bool vr_grid_build(gp_t *gp, octgrid_t *g, const bits_t *occ, int lo, int hi, fw_ops_t *ops)
{
    bits_t t;
    if (!vr_bits_alloc(gp, &t, occ->nx, occ->ny, occ->nz) ||
        !vr_bits_alloc(gp, &g->occ[0], occ->nx, occ->ny, occ->nz))
        return false;
    dilate(occ, &g->occ[0], lo, hi, ops);
    dilate_rows(&g->occ[0], &t, 1, lo, hi, ops);
    dilate_rows(&t, &g->occ[0], 2, lo, hi, ops);
    fw_free(gp, t.w);
    g->heights = 1;
    for (int h = 1; h < VR_MAX_LEVELS; h++) {
        const bits_t *in = &g->occ[h - 1];
        if (in->nx == 1 && in->ny == 1 && in->nz == 1)
            break;
        bits_t *o = &g->occ[h];
        if (!vr_bits_alloc(gp, o, (in->nx + 1) / 2, (in->ny + 1) / 2, (in->nz + 1) / 2))
            return false;
        for (int z = 0; z < in->nz; z++)
            for (int y = 0; y < in->ny; y++)
                for (int k = 0; k < in->wpr; k++) {
                    uint64_t v = in->w[((size_t)z * in->ny + y) * in->wpr + k];
                    ops->loads++;
                    ops->load_use++;     /* tested at once */
                    ops->branches++;
                    while (v) {
                        int bit = __builtin_ctzll(v);
                        v &= v - 1;
                        vr_bits_set(o, (k * 64 + bit) / 2, y / 2, z / 2);
                        ops->int_ops += 6;
                        ops->stores++;
                    }
                }
        g->heights = h + 1;
    }
    return true;
}
