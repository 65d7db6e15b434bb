/* events_score.c: kappa, event F1 and duration statistics (events_score.h). */
#include "events_score.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void kappa_counts_add(kappa_counts_t *k, const int *a, const int *b, size_t n, int cls)
{
    for (size_t i = 0; i < n; i++) {
        bool x = a[i] == cls, y = b[i] == cls;
        if (x && y)
            k->both += 1;
        else if (x)
            k->only_a += 1;
        else if (y)
            k->only_b += 1;
        else
            k->neither += 1;
    }
}

double kappa_of_table(const double *table, int k)
{
    double total = 0, agree = 0, chance = 0;
    for (int i = 0; i < k * k; i++)
        total += table[i];
    if (!(total > 0))
        return NAN;
    for (int i = 0; i < k; i++) {
        double row = 0, col = 0;
        for (int j = 0; j < k; j++) {
            row += table[i * k + j];
            col += table[j * k + i];
        }
        agree += table[i * k + i];
        chance += row * col;
    }
    double po = agree / total, pe = chance / (total * total);
    return pe < 1.0 ? (po - pe) / (1.0 - pe) : NAN;
}

double kappa_of_counts(const kappa_counts_t *k)
{
    double t[4] = {k->both, k->only_a, k->only_b, k->neither};
    return kappa_of_table(t, 2);
}

typedef struct {
    size_t overlap, r, t;
} pair_t;

static int cmp_pair(const void *a, const void *b)
{
    const pair_t *x = a, *y = b;
    if (x->overlap != y->overlap)
        return x->overlap > y->overlap ? -1 : 1;
    if (x->r != y->r)
        return x->r < y->r ? -1 : 1;
    return (x->t > y->t) - (x->t < y->t);
}

/* Events of one class, in order: indices into l. */
static size_t *of_class(const events_list_t *l, int cls, size_t *n)
{
    size_t *idx = malloc((l->count ? l->count : 1) * sizeof *idx);
    *n = 0;
    for (size_t i = 0; idx && i < l->count; i++)
        if (l->events[i].cls == cls)
            idx[(*n)++] = i;
    return idx;
}

pp5_status_t f1_counts_add(f1_counts_t *f, const events_list_t *ref, const events_list_t *test,
                           int cls)
{
    size_t nr, nt, np = 0, cap = 0;
    size_t *r = of_class(ref, cls, &nr), *t = of_class(test, cls, &nt);
    pair_t *pairs = NULL;
    bool *used_r = calloc(nr + 1, 1), *used_t = calloc(nt + 1, 1);
    pp5_status_t st = PP5_OK;
    if (!r || !t || !used_r || !used_t)
        st = pp5_fail(PP5_E_NOMEM, "F1: out of memory");
    /* Events are in time order: walk both lists once for overlapping pairs. */
    size_t j0 = 0;
    for (size_t i = 0; st == PP5_OK && i < nr; i++) {
        const gaze_event_t *a = &ref->events[r[i]];
        while (j0 < nt && test->events[t[j0]].last < a->first)
            j0++;
        for (size_t j = j0; j < nt && test->events[t[j]].first <= a->last; j++) {
            const gaze_event_t *b = &test->events[t[j]];
            size_t lo = a->first > b->first ? a->first : b->first;
            size_t hi = a->last < b->last ? a->last : b->last;
            if (hi < lo)
                continue;
            if (np == cap) {
                cap = cap ? 2 * cap : 64;
                pair_t *grown = realloc(pairs, cap * sizeof *pairs);
                if (!grown) {
                    st = pp5_fail(PP5_E_NOMEM, "F1: out of memory");
                    break;
                }
                pairs = grown;
            }
            pairs[np++] = (pair_t){hi - lo + 1, i, j};
        }
    }
    if (st == PP5_OK) {
        if (np)
            qsort(pairs, np, sizeof *pairs, cmp_pair);
        size_t tp = 0;
        for (size_t k = 0; k < np; k++)
            if (!used_r[pairs[k].r] && !used_t[pairs[k].t]) {
                used_r[pairs[k].r] = used_t[pairs[k].t] = true;
                tp++;
            }
        f->tp += tp;
        f->fp += nt - tp;
        f->fn += nr - tp;
    }
    free(pairs);
    free(used_r);
    free(used_t);
    free(r);
    free(t);
    return st;
}

double f1_of_counts(const f1_counts_t *f)
{
    size_t d = 2 * f->tp + f->fp + f->fn;
    return d ? 2.0 * (double)f->tp / (double)d : NAN;
}

void duration_stats_add(duration_stats_t *d, const events_list_t *l, int cls, size_t n_samples)
{
    for (size_t i = 0; i < l->count; i++)
        if (l->events[i].cls == cls &&
            !(n_samples && (l->events[i].first == 0 || l->events[i].last + 1 >= n_samples))) {
            d->count++;
            d->sum_s += l->events[i].duration_s;
            d->sum2_s += l->events[i].duration_s * l->events[i].duration_s;
        }
}

double duration_stats_mean_ms(const duration_stats_t *d)
{
    return d->count ? 1e3 * d->sum_s / (double)d->count : NAN;
}

double duration_stats_sd_ms(const duration_stats_t *d)
{
    if (d->count < 2)
        return NAN;
    double n = (double)d->count, var = (d->sum2_s - d->sum_s * d->sum_s / n) / (n - 1.0);
    return var > 0 ? 1e3 * sqrt(var) : 0;
}
