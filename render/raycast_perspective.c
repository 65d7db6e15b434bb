/* raycast_perspective.c: the fast tracer for perspective projection with
 * octree skipping.  It visits the reference's positions (t_{k+1} = t_k *
 * growth, raycast.c) and draws the reference's samples with the same float
 * operations; three things are cheaper:
 *
 * - the 3D level.  The reference evaluates level3d = clamp(log2f(spacing) -
 *   offset, 0, top) at every position to find its floor n and whether it is
 *   exactly an integer.  That function of the spacing is non-decreasing
 *   (subtraction and clamping keep the order, and libm's log2f keeps it
 *   near every bound: checked), so its floor is n exactly for spacings in
 *   [lo[n], lo[n+1]) and it equals n exactly for spacings in [lo[n],
 *   eq_hi[n]]; both bounds are found once per frame by bisection over the
 *   float lattice, evaluating the reference's own expression.  log2f is
 *   then called only where a sample is drawn (its blend weight needs it);
 * - the level boundary of a jump (exp2f of n + 1 + offset over growth - 1),
 *   tabled per n;
 * - the samples: both levels' trilinear lookups four components at a time
 *   (trilerp4's lanes do mip3d_trilerp's arithmetic), then mip3d_sample's
 *   blend.
 * Rays advance in turns, as the reference batch does. */
#include "raycast_parallel.h"

#include <math.h>
#include <string.h>

#define JUMP_TURN 16

typedef struct {
    float base, growth, top, level_step;       /* level_step = growth - 1 */
    int level2d;
    float t_level[MIP3D_MAX_LEVELS];            /* the reference's level boundary for n */
} persp_level_t;

typedef struct {
    float ov[3], dv[3], inv_dv[3], half[3];
    float t, t1, t1_volume, t_start;
    int n;                        /* floor level at the current position (never decreases) */
    float jump_to;                /* > 0: in a jump, stepping while t < jump_to */
    bool terminated;
    float acc[3], acc_a;
    uint64_t n_samples, n_skipped;
} persp_ray_t;

/* The reference's 3D level of a sample standing for `spacing` units. */
static float level_of(const raycast_ctx_t *r, float top, float spacing)
{
    float l = log2f(spacing) - r->level3d_offset;
    return l < 0.0f ? 0.0f : (l > top ? top : l);
}

/* Smallest positive float s whose level is >= n (strict: > n); INFINITY
 * when none is.  Positive floats are ordered as their bits. */
static float first_at_or_above(const raycast_ctx_t *r, float top, float n, bool strict)
{
    uint32_t lo = 0x00000001u, hi = 0x7f800000u;   /* smallest denormal .. +inf */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        float s;
        memcpy(&s, &mid, sizeof s);
        float l = level_of(r, top, s);
        if (strict ? l > n : l >= n)
            hi = mid;
        else
            lo = mid + 1;
    }
    float s;
    memcpy(&s, &lo, sizeof s);
    return s;
}

/* The bisection needs the level to be monotone in the spacing; libm's
 * log2f is not promised to be correctly rounded, so the 4096 spacings on
 * each side of every bound are checked against it.  False: use log2f at
 * every position, as the reference does. */
static bool bound_holds(const raycast_ctx_t *r, float top, float bound, float n, bool strict)
{
    if (!(bound < INFINITY) || !(bound > 0.0f))
        return true;
    float below = bound, above = bound;
    for (int i = 0; i < 4096; i++) {
        below = nextafterf(below, 0.0f);
        float lb = level_of(r, top, below), la = level_of(r, top, above);
        if ((strict ? lb > n : lb >= n) || !(strict ? la > n : la >= n))
            return false;
        above = nextafterf(above, INFINITY);
    }
    return true;
}

void raycast_perspective_tables(raycast_ctx_t *r)
{
    int levels = r->mip->levels;
    float top = (float)(levels - 1);
    bool ok = true;
    for (int n = 0; n <= levels && n <= MIP3D_MAX_LEVELS; n++) {
        r->persp_lo[n] = n == 0 ? 0.0f
                                : (n >= levels ? INFINITY : first_at_or_above(r, top, (float)n, false));
        ok = ok && bound_holds(r, top, r->persp_lo[n], (float)n, false);
    }
    for (int n = 0; n < levels; n++) {
        /* The last spacing whose level is still exactly n. */
        float above = first_at_or_above(r, top, (float)n, true);
        ok = ok && bound_holds(r, top, above, (float)n, true);
        r->persp_eq_hi[n] = above == INFINITY ? INFINITY : nextafterf(above, 0.0f);
    }
    r->persp_tables = ok;
}

static void level_setup(const raycast_ctx_t *r, int level2d, persp_level_t *P)
{
    const camera_t *cam = r->camera;
    P->level2d = level2d;
    P->base = r->sample_step * (float)(1 << level2d);
    P->growth = 1.0f + P->base / cam->eye_distance;
    P->level_step = P->growth - 1.0f;
    P->top = (float)(r->mip->levels - 1);
    for (int n = 0; n < r->mip->levels; n++)
        P->t_level[n] = exp2f((float)(n + 1) + r->level3d_offset) / P->level_step;
}

static bool ray_begin(const raycast_ctx_t *r, const persp_level_t *P, float px, float py,
                      persp_ray_t *s)
{
    float t0;
    memset(s, 0, sizeof *s);
    s->t1_volume = -1.0f;
    if (!raycast_ray_setup(r, px, py, &t0, &s->t1, s->ov, s->dv, s->inv_dv, s->half))
        return false;
    s->t1_volume = s->t1;
    s->t = t0 < 1e-3f ? 1e-3f : t0;
    s->t_start = s->t;
    (void)P;
    return true;
}

/* Level-m trilinear lookup of level-0 position p, four components. */
static inline void lookup4(const mip3d_t *m, int lv, const float p[3], float out[4])
{
    float q[3];
    int fl[3];
    for (int a = 0; a < 3; a++) {
        q[a] = mip3d_level_coord(p[a], lv);
        fl[a] = mip3d_floor_int(q[a]);
    }
    trilerp4(&m->level[lv], q, fl, out);
}

/* mip3d_sample, with the four-component lookups where they apply. */
static inline void sample(const raycast_ctx_t *r, float level3d, const float p[3], float *out)
{
    const mip3d_t *m = r->mip;
    if (m->stride != 4 || m->format != MIP3D_F32) {
        mip3d_sample(m, level3d, p, out);
        return;
    }
    int lo = (int)level3d;
    float t = level3d - (float)lo;
    lookup4(m, lo, p, out);
    if (t > 0.0f && lo + 1 < m->levels) {
        float hi[4];
        lookup4(m, lo + 1, p, hi);
        for (int k = 0; k < 4; k++)
            out[k] += t * (hi[k] - out[k]);
    }
}

/* The reference's ray_step for a perspective ray (raycast.c). */
static inline bool ray_step(const raycast_ctx_t *r, const persp_level_t *P, persp_ray_t *s)
{
    if (s->jump_to > 0.0f) {
        /* A jump's positions, at most JUMP_TURN per turn so that the rays'
         * multiplication chains overlap. */
        for (int i = 0; i < JUMP_TURN; i++) {
            s->t *= P->growth;
            s->n_skipped++;
            if (!(s->t < s->jump_to && s->t <= s->t1)) {
                s->jump_to = 0.0f;
                break;
            }
        }
        return true;
    }
    if (!(s->t <= s->t1))
        return false;
    float spacing = s->t * P->level_step;
    int n;
    bool exact;
    float level3d = -1.0f;        /* computed where needed */
    if (r->persp_tables) {
        while (spacing >= r->persp_lo[s->n + 1])
            s->n++;
        n = s->n;
        exact = spacing <= r->persp_eq_hi[n];
    } else {
        level3d = level_of(r, P->top, spacing);
        n = (int)level3d;
        exact = level3d == (float)n;
    }
    const float t = s->t;
    float p[3] = {s->ov[0] + t * s->dv[0], s->ov[1] + t * s->dv[1], s->ov[2] + t * s->dv[2]};
    float lo[3], hi[3];
    int height = octree_empty_node(r->octree, n, exact, p, lo, hi);
    if (height >= 0) {
        float t_exit = raycast_node_exit(s->ov, s->dv, s->inv_dv, lo, hi);
        if (!(t_exit <= s->t1))
            return false;
        t_exit -= 1e-3f;
        if (n + 1 <= (int)P->top && P->t_level[n] < t_exit)
            t_exit = P->t_level[n];
        /* The reference's do { t *= growth } while (t < t_exit && t <= t1),
         * a turn at a time.  t_exit > 0: it lies beyond the current t. */
        s->jump_to = t_exit > 0.0f ? t_exit : 0.0f;
        if (s->jump_to == 0.0f) {
            s->t *= P->growth;
            s->n_skipped++;
        }
        return true;
    }
    float comp[8];
    sample(r, level3d >= 0.0f ? level3d : level_of(r, P->top, spacing), p, comp);
    s->n_samples++;
    if (raycast_accumulate(r, comp, s->half, P->level2d, true, spacing / r->opacity_unit, s->acc,
                           &s->acc_a)) {
        s->terminated = true;
        return false;
    }
    s->t *= P->growth;
    return true;
}

static void ray_end(const persp_level_t *P, const persp_ray_t *s, float rgb[3],
                    raycast_counts_t *counts)
{
    counts->rays++;
    counts->samples += s->n_samples;
    uint64_t skipped = s->n_skipped;
    if (!s->terminated) {
        long all = 0;
        for (float t = s->t_start; t <= s->t1_volume; t *= P->growth)
            all++;
        skipped = (uint64_t)all - s->n_samples;
    }
    counts->samples_skipped += skipped;
    rgb[0] = s->acc[0];
    rgb[1] = s->acc[1];
    rgb[2] = s->acc[2];
}

void raycast_perspective_batch(const raycast_ctx_t *r, int count, const float *px,
                               const float *py, int level2d, float (*rgb)[3],
                               raycast_counts_t *counts)
{
    persp_level_t P;
    level_setup(r, level2d, &P);
    persp_ray_t s[RAYCAST_CHUNK];
    bool live[RAYCAST_CHUNK];
    for (int i0 = 0; i0 < count; i0 += RAYCAST_BATCH) {
        int n = count - i0 < RAYCAST_BATCH ? count - i0 : RAYCAST_BATCH, remaining = 0;
        for (int i = i0; i < i0 + n; i++)
            remaining += live[i] = ray_begin(r, &P, px[i], py[i], &s[i]);
        while (remaining > 0)
            for (int i = i0; i < i0 + n; i++)
                if (live[i] && !ray_step(r, &P, &s[i])) {
                    live[i] = false;
                    remaining--;
                }
    }
    for (int i = 0; i < count; i++)
        ray_end(&P, &s[i], rgb[i], counts);
}
