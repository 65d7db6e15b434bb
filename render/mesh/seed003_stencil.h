/* seed003_stencil.h: the new point of seed 003's edge deletion (§2.4): the
 * interpolating-subdivision stencils (Zorin, Schroder, Sweldens 1996) in the
 * paper's six cases, chosen by valence and vertex importance. */
#ifndef PP5_SEED003_STENCIL_H
#define PP5_SEED003_STENCIL_H

#include "simplify_work.h"

#define S003_STENCIL_MAX 40

typedef enum {
    S003_CASE_REGULAR = 1,   /* case 1: both valence 6, the 10-point butterfly (w = 0) */
    S003_CASE_ONE_IRREGULAR, /* case 2: one endpoint of valence K != 6 */
    S003_CASE_TWO_IRREGULAR, /* case 3: both K != 6 (the two stencils averaged) */
    S003_CASE_BOUNDARY,      /* case 4: boundary edge, 4-point rule */
    S003_CASE_FEATURE,       /* case 5: both endpoints important, Table 1 weights */
    S003_CASE_PINNED,        /* case 6: one endpoint important (q = 1), or a corner */
    S003_CASE_FALLBACK       /* a stencil vertex is missing: see seed003_stencil.c */
} s003_case_t;

typedef struct {
    int n;
    int32_t v[S003_STENCIL_MAX];
    double w[S003_STENCIL_MAX];
    s003_case_t which;
    bool distinct;               /* internal: the next adds are new vertices */
} s003_stencil_t;

/* Everything the stencils need to know about a vertex. */
typedef struct {
    const sw_t *w;
    const uint8_t *importance;   /* 0 ordinary, 1 crease, 2 corner (boundary +1, at most 2) */
    const uint8_t *corner;       /* geometric corner (A2 above its threshold) */
    bool pin_corners;
    double cos_crease;           /* cos of the crease angle: feature edges */
    const double *ring_table;    /* s003_ring_table_fill's numbers, or NULL */
} s003_context_t;

/* Is edge (a, b) a feature edge (boundary, or dihedral above the crease angle)? */
bool s003_feature_edge(const s003_context_t *c, int a, int b);
/* The stencil for deleting edge (a, b); false if the edge may not be deleted. */
bool s003_stencil(const s003_context_t *c, int a, int b, s003_stencil_t *s);
/* The modified-butterfly weights at a vertex of valence K >= 3 (case 2):
 * s[0..K-1] for its ring starting at the other endpoint; returns q. */
double s003_ring_weights(int K, double *s);
/* The case-2 weights of every K up to S003_RING_TABLE_K, computed once:
 * at offset s003_ring_table_offset(K), q then s[0..K-1]. */
#define S003_RING_TABLE_K 32
#define S003_RING_TABLE_SIZE ((S003_RING_TABLE_K - 2) * (S003_RING_TABLE_K + 5) / 2)
int s003_ring_table_offset(int K);
void s003_ring_table_fill(double *table);

#endif
