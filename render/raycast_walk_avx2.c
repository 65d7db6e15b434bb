/* raycast_walk_avx2.c: the fast parallel tracer's walk with eight rays side
 * by side in AVX2 lanes (chosen at run time; raycast_parallel.c keeps the
 * portable walk, which advances the rays in turns).
 *
 * Each round visits the current position of eight rays at once.  The lanes
 * compute the level-n cell as cell_of does and gather the cells' block bytes
 * and occupancy bits; then, still side by side, rays on an empty cell move
 * on by one position, rays in an empty node jump past it (jump()'s
 * arithmetic), and rays on an occupied cell draw their sample (trilerp4's),
 * correct its opacity (raycast_correct_alpha's) and composite it
 * (raycast_composite's).  Every lane does exactly the scalar float
 * operations in the same order (no fused multiply-add in ISO C mode;
 * minps, divps and the conversions round as their scalar forms do), so
 * each ray visits the positions the portable walk visits and its colour,
 * samples and counts are the same bits.  Cases without a vector form here
 * (stride-8 lighting, blended levels, 2D levels beyond the opacity table)
 * draw their samples one lane at a time with draw_sample().  A finished
 * lane takes the next ray of the set, so the lanes stay busy until the last
 * few rays. */
#include "raycast_parallel.h"

#if RAYCAST_HAVE_AVX2_WALK
#pragma GCC target("avx2")
#include <immintrin.h>

#define LANES 8

typedef __m256 vf;
typedef __m256i vi;

/* The lanes' rays: position state, colour and counts (written back to the
 * ray's par_ray_t when it ends). */
typedef struct {
    int32_t k[LANES], k_last[LANES], samples[LANES], k_end[LANES];
    float t0[LANES], ov[3][LANES], acc[4][LANES];
    int ray[LANES];               /* index into the ray set; -1: idle */
} lanes_t;

/* One round's cells: continuous level-n coordinates, floors, clamped cells,
 * block bytes. */
typedef struct {
    vf q[3];
    vi fl[3], c[3], h;
} cells_t;

static inline vf fset(float x)
{
    return _mm256_set1_ps(x);
}

static inline vi iset(int x)
{
    return _mm256_set1_epi32(x);
}

static inline vi iload(const int32_t *p)
{
    return _mm256_loadu_si256((const __m256i *)(const void *)p);
}

static inline void istore(int32_t *p, vi v)
{
    _mm256_storeu_si256((__m256i *)(void *)p, v);
}

static inline vi bits_to_lanes(unsigned m)
{
    const vi bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    return _mm256_cmpeq_epi32(_mm256_and_si256(iset((int)m), bit), bit);
}

static inline unsigned lanes_to_bits(vi m)
{
    return (unsigned)_mm256_movemask_ps(_mm256_castsi256_ps(m));
}

static inline vi select_i(vi m, vi a, vi b)
{
    return _mm256_blendv_epi8(b, a, m);
}

static inline vf select_f(vi m, vf a, vf b)
{
    return _mm256_blendv_ps(b, a, _mm256_castsi256_ps(m));
}

/* floor() of each lane as mip3d_floor_int: truncate, step down where that
 * rounded up. */
static inline vi floor_i(vf x)
{
    vi i = _mm256_cvttps_epi32(x);
    return _mm256_add_epi32(i, _mm256_castps_si256(_mm256_cmp_ps(_mm256_cvtepi32_ps(i), x,
                                                                 _CMP_GT_OQ)));
}

/* t = t0 + (float)k * base per lane, as the scalar walk computes it. */
static inline vf lane_t(const par_level_t *L, const lanes_t *ln, vi k)
{
    return _mm256_add_ps(_mm256_loadu_ps(ln->t0), _mm256_mul_ps(_mm256_cvtepi32_ps(k),
                                                                fset(L->base)));
}

/* cell_of for every lane at parameter t. */
static inline void lane_cells(const par_level_t *L, const lanes_t *ln, vf t, cells_t *o)
{
    const vf half = fset(0.5f), inv_scale = fset(L->inv_scale);
    for (int a = 0; a < 3; a++) {
        vf p = _mm256_add_ps(_mm256_loadu_ps(ln->ov[a]), _mm256_mul_ps(t, fset(L->dv[a])));
        o->q[a] = _mm256_sub_ps(_mm256_mul_ps(_mm256_add_ps(p, half), inv_scale), half);
        o->fl[a] = floor_i(o->q[a]);
        o->c[a] = _mm256_min_epi32(_mm256_max_epi32(o->fl[a], _mm256_setzero_si256()),
                                   iset(L->dims[a] - 1));
    }
}

/* Block bytes and occupancy of the cells; returns the occupied lanes and
 * in *node those in an all-empty block. */
static inline unsigned cells_test(const octree_grid_t *g, cells_t *o, unsigned *node)
{
    vi row = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srai_epi32(o->c[2], 2), iset(g->block_ny)),
                              _mm256_srai_epi32(o->c[1], 2));
    vi b = _mm256_add_epi32(_mm256_mullo_epi32(row, iset(g->block_nx)),
                            _mm256_srai_epi32(o->c[0], 2));
    const vi three = iset(3);
    vi bit = _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi32(_mm256_and_si256(o->c[2], three), 4),
                                             _mm256_slli_epi32(_mm256_and_si256(o->c[1], three), 2)),
                             _mm256_and_si256(o->c[0], three));
    /* The block byte as the low byte of a 32-bit load (the array carries
     * three bytes of padding, octree.c), sign-extended. */
    vi h = _mm256_i32gather_epi32((const int *)(const void *)g->block_height, b, 1);
    o->h = _mm256_srai_epi32(_mm256_slli_epi32(h, 24), 24);
    /* The 32-bit half of the block's 64 occupancy bits holding the cell's,
     * its bit moved to the sign. */
    vi word = _mm256_add_epi32(_mm256_slli_epi32(b, 1), _mm256_srli_epi32(bit, 5));
    vi w = _mm256_i32gather_epi32((const int *)(const void *)g->block_bits, word, 4);
    vi set = _mm256_slli_epi32(_mm256_srlv_epi32(w, _mm256_and_si256(bit, iset(31))), 31);
    unsigned mixed = lanes_to_bits(o->h);
    *node = ~mixed & 0xffu;
    return mixed & lanes_to_bits(set);
}

/* jump() for the lanes in m: past the empty node of height h holding cell
 * c (node_exit), checked at the last position passed. */
static inline vi lanes_jump(const par_level_t *L, const lanes_t *ln, const cells_t *cl, vi k,
                            vi m)
{
    vi first[3], last[3];
    vf t_exit = fset(INFINITY);
    for (int a = 0; a < 3; a++) {
        first[a] = _mm256_sllv_epi32(_mm256_srav_epi32(cl->c[a], cl->h), cl->h);
        last[a] = _mm256_add_epi32(first[a], _mm256_sllv_epi32(iset(1), cl->h));
        bool pos = L->dir_pos[a] != 0, neg = L->dir_neg[a] != 0;
        if (!pos && !neg)
            continue;             /* not moving along this axis: never left */
        vi cell = pos ? last[a] : first[a];
        vi valid = pos ? _mm256_cmpgt_epi32(iset(L->dims[a]), last[a])
                       : _mm256_cmpgt_epi32(first[a], _mm256_setzero_si256());
        vf bound = _mm256_sub_ps(_mm256_mul_ps(_mm256_add_ps(_mm256_cvtepi32_ps(cell), fset(0.5f)),
                                               fset(L->scale)), fset(0.5f));
        vf te = _mm256_mul_ps(_mm256_sub_ps(bound, _mm256_loadu_ps(ln->ov[a])),
                              fset(L->inv_dv_v[a]));
        te = select_f(valid, te, fset(INFINITY));
        /* node_exit takes min(te0, te1), then min(te2, that); an axis
         * without motion contributes INFINITY, which never wins. */
        t_exit = a == 0 ? te : (a == 1 ? _mm256_min_ps(t_exit, te) : _mm256_min_ps(te, t_exit));
    }
    vf t0 = _mm256_loadu_ps(ln->t0), base = fset(L->base);
    vi k_last1 = _mm256_add_epi32(iload(ln->k_last), iset(1));
    vf t_in = _mm256_sub_ps(t_exit, fset(1e-3f));
    vf rel = _mm256_sub_ps(t_in, t0);
    vf window = _mm256_add_ps(_mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(k_last1, k)), base),
                              _mm256_mul_ps(_mm256_cvtepi32_ps(k), base));
    vi inside = _mm256_castps_si256(_mm256_cmp_ps(rel, window, _CMP_LT_OQ));
    vf neg_rel = _mm256_mul_ps(_mm256_xor_ps(rel, fset(-0.0f)), fset(L->inv_base));
    vi kc = _mm256_sub_epi32(_mm256_setzero_si256(), floor_i(neg_rel));
    vi k_new = select_i(_mm256_and_si256(inside, _mm256_cmpgt_epi32(k_last1, kc)), kc, k_last1);
    vi k1 = _mm256_add_epi32(k, iset(1));
    vi far = _mm256_cmpgt_epi32(k_new, k1);
    if (lanes_to_bits(_mm256_and_si256(far, m))) {
        cells_t last_cell;
        lane_cells(L, ln, lane_t(L, ln, _mm256_sub_epi32(k_new, iset(1))), &last_cell);
        vi outside = _mm256_setzero_si256();
        for (int a = 0; a < 3; a++)
            outside = _mm256_or_si256(outside,
                                      _mm256_or_si256(_mm256_cmpgt_epi32(first[a], last_cell.c[a]),
                                                      _mm256_cmpgt_epi32(last[a], last_cell.c[a]) ^
                                                          iset(-1)));
        far = _mm256_andnot_si256(outside, far);
    }
    return select_i(far, k_new, k1);
}

/* trilerp4 for every lane in m (the others read voxel 0 and are dropped):
 * component j of lane i is exactly trilerp4's out[j] for that lane.  The
 * corners are loaded as trilerp4 loads them, four components at once, two
 * lanes to a register (lane i in the low half, lane i + 4 in the high half),
 * and transposed to one register per component at the end. */
static inline void lanes_trilerp4(const mip3d_level_t *V, const cells_t *cl, vi m, vf out[4])
{
    vf w[3];
    vi lo[3], hi[3];
    const int dims[3] = {V->nx, V->ny, V->nz};
    for (int a = 0; a < 3; a++) {
        w[a] = _mm256_sub_ps(cl->q[a], _mm256_cvtepi32_ps(cl->fl[a]));
        vi top = iset(dims[a] - 1), zero = _mm256_setzero_si256();
        /* Lanes outside m read voxel 0 (always there). */
        lo[a] = _mm256_and_si256(m, _mm256_min_epi32(_mm256_max_epi32(cl->fl[a], zero), top));
        hi[a] = _mm256_and_si256(m, _mm256_min_epi32(_mm256_max_epi32(_mm256_add_epi32(cl->fl[a],
                                                                                    iset(1)),
                                                                   zero), top));
    }
    const int row = V->nx, slice = V->nx * V->ny;
    int32_t off[8][LANES];        /* voxel index of corner c (x fastest) per lane */
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 2; y++) {
            vi zy = _mm256_add_epi32(_mm256_mullo_epi32(z ? hi[2] : lo[2], iset(slice)),
                                     _mm256_mullo_epi32(y ? hi[1] : lo[1], iset(row)));
            for (int x = 0; x < 2; x++)
                istore(off[4 * z + 2 * y + x], _mm256_add_epi32(zy, x ? hi[0] : lo[0]));
        }
    vf res[4];
    for (int i = 0; i < 4; i++) {
        /* Weights of lanes i and i + 4, each across its half. */
        const vi pick = _mm256_setr_epi32(i, i, i, i, i + 4, i + 4, i + 4, i + 4);
        vf wx = _mm256_permutevar8x32_ps(w[0], pick), wy = _mm256_permutevar8x32_ps(w[1], pick);
        vf wz = _mm256_permutevar8x32_ps(w[2], pick);
        vf v[8];
        for (int c = 0; c < 8; c++)
            v[c] = _mm256_loadu2_m128(V->data + (size_t)off[c][i + 4] * 4,
                                      V->data + (size_t)off[c][i] * 4);
        vf a = _mm256_add_ps(v[0], _mm256_mul_ps(wx, _mm256_sub_ps(v[1], v[0])));
        vf b = _mm256_add_ps(v[2], _mm256_mul_ps(wx, _mm256_sub_ps(v[3], v[2])));
        vf c = _mm256_add_ps(v[4], _mm256_mul_ps(wx, _mm256_sub_ps(v[5], v[4])));
        vf d = _mm256_add_ps(v[6], _mm256_mul_ps(wx, _mm256_sub_ps(v[7], v[6])));
        vf e = _mm256_add_ps(a, _mm256_mul_ps(wy, _mm256_sub_ps(b, a)));
        vf f = _mm256_add_ps(c, _mm256_mul_ps(wy, _mm256_sub_ps(d, c)));
        res[i] = _mm256_add_ps(e, _mm256_mul_ps(wz, _mm256_sub_ps(f, e)));
    }
    /* res[i] = [R G B A of lane i | of lane i + 4]: a 4x4 transpose per
     * half gives [component of lanes 0-3 | of lanes 4-7]. */
    vf t0 = _mm256_unpacklo_ps(res[0], res[1]), t1 = _mm256_unpackhi_ps(res[0], res[1]);
    vf t2 = _mm256_unpacklo_ps(res[2], res[3]), t3 = _mm256_unpackhi_ps(res[2], res[3]);
    out[0] = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(t0), _mm256_castps_pd(t2)));
    out[1] = _mm256_castpd_ps(_mm256_unpackhi_pd(_mm256_castps_pd(t0), _mm256_castps_pd(t2)));
    out[2] = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(t1), _mm256_castps_pd(t3)));
    out[3] = _mm256_castpd_ps(_mm256_unpackhi_pd(_mm256_castps_pd(t1), _mm256_castps_pd(t3)));
}

/* The packed formats' trilerp for every lane in m, stride 4: the corners'
 * bricked indices (mip3d_packed.c's layout, computed rather than looked
 * up), one 32-bit gather per corner for U8 (all four components) or two for
 * U16, each component converted and scaled as mip3d_packed_voxel does, then
 * the float arithmetic of mip3d_trilerp_packed. */
static inline vi brick_offset(vi v, int step, int inner)
{
    return _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srai_epi32(v, 2), iset(step)),
                            _mm256_mullo_epi32(_mm256_and_si256(v, iset(3)), iset(inner)));
}

static inline void lanes_trilerp_packed(const mip3d_t *mp, const mip3d_level_t *V,
                                        const mip3d_packed_t *P, const cells_t *cl, vi m,
                                        vf out[4])
{
    vf w[3];
    vi o[3][2];
    const int dims[3] = {V->nx, V->ny, V->nz};
    const int bx = (V->nx + 3) / 4, by = (V->ny + 3) / 4;
    const int step[3] = {64, 64 * bx, 64 * bx * by}, inner[3] = {1, 4, 16};
    for (int a = 0; a < 3; a++) {
        w[a] = _mm256_sub_ps(cl->q[a], _mm256_cvtepi32_ps(cl->fl[a]));
        vi top = iset(dims[a] - 1), zero = _mm256_setzero_si256();
        vi lo = _mm256_min_epi32(_mm256_max_epi32(cl->fl[a], zero), top);
        vi hi = _mm256_min_epi32(_mm256_max_epi32(_mm256_add_epi32(cl->fl[a], iset(1)), zero), top);
        o[a][0] = brick_offset(lo, step[a], inner[a]);
        o[a][1] = brick_offset(hi, step[a], inner[a]);
    }
    const vf mf = _mm256_castsi256_ps(m);
    vf v[4][8];                   /* component, corner (x fastest) */
    for (int c = 0; c < 8; c++) {
        vi idx = _mm256_add_epi32(_mm256_add_epi32(o[0][c & 1], o[1][(c >> 1) & 1]),
                                  o[2][c >> 2]);
        if (mp->format == MIP3D_U8) {
            vi word = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), P->data, idx,
                                                  _mm256_castps_si256(mf), 4);
            for (int j = 0; j < 4; j++)
                v[j][c] = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(
                                            _mm256_srli_epi32(word, 8 * j), iset(255))),
                                        fset(mp->unit[j]));
        } else {
            for (int half = 0; half < 2; half++) {
                vi word = _mm256_mask_i32gather_epi32(
                    _mm256_setzero_si256(), (const int *)P->data + half,
                    _mm256_slli_epi32(idx, 1), _mm256_castps_si256(mf), 4);
                v[2 * half][c] = _mm256_mul_ps(
                    _mm256_cvtepi32_ps(_mm256_and_si256(word, iset(0xffff))),
                    fset(mp->unit[2 * half]));
                v[2 * half + 1][c] = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_srli_epi32(word, 16)),
                                                   fset(mp->unit[2 * half + 1]));
            }
        }
    }
    for (int j = 0; j < 4; j++) {
        vf *c = v[j];
        vf a = _mm256_add_ps(c[0], _mm256_mul_ps(w[0], _mm256_sub_ps(c[1], c[0])));
        vf b = _mm256_add_ps(c[2], _mm256_mul_ps(w[0], _mm256_sub_ps(c[3], c[2])));
        vf cc = _mm256_add_ps(c[4], _mm256_mul_ps(w[0], _mm256_sub_ps(c[5], c[4])));
        vf d = _mm256_add_ps(c[6], _mm256_mul_ps(w[0], _mm256_sub_ps(c[7], c[6])));
        vf e = _mm256_add_ps(a, _mm256_mul_ps(w[1], _mm256_sub_ps(b, a)));
        vf f = _mm256_add_ps(cc, _mm256_mul_ps(w[1], _mm256_sub_ps(d, cc)));
        out[j] = _mm256_add_ps(e, _mm256_mul_ps(w[2], _mm256_sub_ps(f, e)));
    }
}

/* raycast_accumulate for the diffuse case in every lane of m: opacity
 * correction from the per-level table, compositing; returns the lanes that
 * reached early termination. */
static inline unsigned lanes_accumulate(const raycast_ctx_t *r, const par_level_t *L,
                                        lanes_t *ln, const vf s[4], vi m)
{
    vf a = s[MIP3D_A], c[3] = {s[MIP3D_R], s[MIP3D_G], s[MIP3D_B]};
    vi lit = _mm256_and_si256(m, _mm256_castps_si256(_mm256_cmp_ps(a, _mm256_setzero_ps(),
                                                                   _CMP_GT_OQ)));
    if (!lanes_to_bits(lit))
        return 0;
    if (L->alpha_spacing != 1.0f) {
        const float *tab = r->alpha_lut[L->level2d];
        vf x = _mm256_mul_ps(a, fset((float)RAYCAST_LUT_SIZE));
        /* Clamped below too: an opacity at or above 1 (table unused) must
         * still give an index inside the table. */
        vi i = _mm256_min_epi32(_mm256_cvttps_epi32(x), iset(RAYCAST_LUT_SIZE - 1));
        i = _mm256_max_epi32(i, _mm256_setzero_si256());
        vf f = _mm256_sub_ps(x, _mm256_cvtepi32_ps(i));
        vf ti = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), tab, i, _mm256_castsi256_ps(lit), 4);
        vf tj = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), tab + 1, i,
                                         _mm256_castsi256_ps(lit), 4);
        vf ac = _mm256_add_ps(ti, _mm256_mul_ps(f, _mm256_sub_ps(tj, ti)));
        vi opaque = _mm256_castps_si256(_mm256_cmp_ps(a, fset(1.0f), _CMP_GE_OQ));
        ac = select_f(opaque, fset(1.0f), ac);
        vf scale = _mm256_div_ps(ac, select_f(lit, a, fset(1.0f)));
        for (int k = 0; k < 3; k++)
            c[k] = _mm256_mul_ps(c[k], scale);
        a = ac;
    }
    vf acc_a = _mm256_loadu_ps(ln->acc[3]);
    vf t = _mm256_sub_ps(fset(1.0f), acc_a);
    for (int k = 0; k < 3; k++) {
        vf acc = _mm256_loadu_ps(ln->acc[k]);
        _mm256_storeu_ps(ln->acc[k], select_f(lit, _mm256_add_ps(acc, _mm256_mul_ps(t, c[k])), acc));
    }
    acc_a = select_f(lit, _mm256_add_ps(acc_a, _mm256_mul_ps(t, a)), acc_a);
    _mm256_storeu_ps(ln->acc[3], acc_a);
    vi done = _mm256_castps_si256(_mm256_cmp_ps(acc_a, fset(r->early_termination), _CMP_GE_OQ));
    return lanes_to_bits(_mm256_and_si256(lit, done));
}

/* Lane j takes ray i (or goes idle, i >= count). */
static inline void lane_load(lanes_t *ln, int j, const par_ray_t *s, int i, int count)
{
    ln->ray[j] = i < count ? i : -1;
    ln->k[j] = i < count ? (int32_t)s[i].k : 1;
    ln->k_last[j] = i < count ? (int32_t)s[i].k_last : 0;
    ln->samples[j] = 0;
    ln->k_end[j] = -1;
    ln->t0[j] = i < count ? s[i].t0 : 0.0f;
    for (int a = 0; a < 3; a++) {
        ln->ov[a][j] = i < count ? s[i].ov[a] : 0.0f;
        ln->acc[a][j] = 0.0f;
    }
    ln->acc[3][j] = 0.0f;
}

/* Lane j's ray has ended: its colour and counts back into the ray. */
static inline void lane_store(const lanes_t *ln, int j, par_ray_t *s)
{
    par_ray_t *ray = &s[ln->ray[j]];
    ray->n_samples = (uint64_t)ln->samples[j];
    ray->k_end = ln->k_end[j];
    for (int a = 0; a < 3; a++)
        ray->acc[a] = ln->acc[a][j];
    ray->acc_a = ln->acc[3][j];
}

/* The next ray of the set that has positions to visit, from *next. */
static inline int next_ray(const par_ray_t *s, const bool *live, int count, int *next)
{
    while (*next < count && !(live[*next] && s[*next].k <= s[*next].k_last))
        (*next)++;
    return (*next)++;
}

/* draw_sample for lane j, one lane at a time (the cases above without a
 * vector form); true when the ray terminated. */
static bool lane_draw(const raycast_ctx_t *r, const par_level_t *L, lanes_t *ln, int j,
                      par_ray_t *ray)
{
    ray->k = ln->k[j];
    for (int a = 0; a < 3; a++)
        ray->acc[a] = ln->acc[a][j];
    ray->acc_a = ln->acc[3][j];
    ray->n_samples = 0;
    float p[3], q[3];
    int fl[3], c[3];
    position_cell(L, ray, ray->k, p, q, fl, c);
    bool done = draw_sample(r, L, ray, p, q, fl);
    for (int a = 0; a < 3; a++)
        ln->acc[a][j] = ray->acc[a];
    ln->acc[3][j] = ray->acc_a;
    return done;
}

/* Draws the samples of the occupied lanes m; returns those that terminated. */
static inline unsigned lanes_draw(const raycast_ctx_t *r, const par_level_t *L, lanes_t *ln,
                                  const cells_t *cl, unsigned m, par_ray_t *s)
{
    istore(ln->samples, _mm256_sub_epi32(iload(ln->samples), bits_to_lanes(m)));
    const mip3d_level_t *V = &r->mip->level[L->n];
    if (L->exact && r->mip->stride == 4 && r->mip->format == MIP3D_F32 &&
        L->level2d < RAYCAST_LUT_LEVELS &&
        (double)V->nx * V->ny * V->nz * 4.0 < 2147483647.0) {
        vf comp[4];
        vi mv = bits_to_lanes(m);
        lanes_trilerp4(V, cl, mv, comp);
        return lanes_accumulate(r, L, ln, comp, mv);
    }
    if (L->exact && r->mip->stride == 4 && r->mip->format != MIP3D_F32 &&
        L->level2d < RAYCAST_LUT_LEVELS) {
        vf comp[4];
        vi mv = bits_to_lanes(m);
        lanes_trilerp_packed(r->mip, V, &r->mip->packed[L->n], cl, mv, comp);
        return lanes_accumulate(r, L, ln, comp, mv);
    }
    unsigned done = 0;
    for (unsigned left = m; left; left &= left - 1u) {
        int j = __builtin_ctz(left);
        done |= (unsigned)lane_draw(r, L, ln, j, &s[ln->ray[j]]) << j;
    }
    return done;
}

bool raycast_walk_avx2_supported(void)
{
    return __builtin_cpu_supports("avx2");
}

void raycast_walk_avx2(const raycast_ctx_t *r, const par_level_t *L, par_ray_t *s,
                       const bool *live, int count)
{
    lanes_t ln;
    int next = 0;
    unsigned idle = 0;
    for (int j = 0; j < LANES; j++) {
        lane_load(&ln, j, s, next_ray(s, live, count, &next), count);
        idle |= (unsigned)(ln.ray[j] < 0) << j;
    }
    for (;;) {
        vi k = iload(ln.k);
        unsigned finished = lanes_to_bits(_mm256_cmpgt_epi32(k, iload(ln.k_last))) & ~idle;
        if (finished) {
            for (; finished; finished &= finished - 1u) {
                int j = __builtin_ctz(finished);
                lane_store(&ln, j, s);
                lane_load(&ln, j, s, next_ray(s, live, count, &next), count);
                idle |= (unsigned)(ln.ray[j] < 0) << j;
            }
            k = iload(ln.k);
        }
        unsigned active = ~idle & 0xffu;
        if (!active)
            return;
        cells_t cl;
        lane_cells(L, &ln, lane_t(L, &ln, k), &cl);
        unsigned node, occ = cells_test(L->g, &cl, &node);
        occ &= active;
        node &= active;
        /* Empty cells: one position on; empty nodes: past the node. */
        vi k_next = _mm256_add_epi32(k, iset(1));
        if (node)
            k_next = select_i(bits_to_lanes(node), lanes_jump(L, &ln, &cl, k, bits_to_lanes(node)),
                              k_next);
        if (occ) {
            unsigned done = lanes_draw(r, L, &ln, &cl, occ, s);
            if (done) {
                /* Terminated at k: k + 1 positions visited; the lane ends. */
                vi d = bits_to_lanes(done);
                istore(ln.k_end, select_i(d, k_next, iload(ln.k_end)));
                k_next = select_i(d, _mm256_add_epi32(iload(ln.k_last), iset(1)), k_next);
            }
        }
        istore(ln.k, select_i(bits_to_lanes(active), k_next, k));
    }
}

#else

bool raycast_walk_avx2_supported(void)
{
    return false;
}

void raycast_walk_avx2(const raycast_ctx_t *r, const par_level_t *L, par_ray_t *s,
                       const bool *live, int count)
{
    (void)r;
    (void)L;
    (void)s;
    (void)live;
    (void)count;
}

#endif
