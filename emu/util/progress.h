/* progress.h: a one-line progress report for long work, on a terminal only.
 *
 *   progress_t p;
 *   progress_begin(&p, "projections", rows);
 *   for (...) { ...; progress_step(&p, "specular, resident"); }
 *   progress_end(&p);
 *
 * The line ("projections: 3/24 (specular, resident), about 40 s left") is
 * rewritten in place on stderr, and only when stderr is a terminal and
 * PP5_QUIET is not set, so logs, pipes and tests stay clean. */
#ifndef PP5_PROGRESS_H
#define PP5_PROGRESS_H

#include <stdbool.h>

typedef struct {
    const char *label;
    int done, total;
    double t_start;
    bool on;
} progress_t;

void progress_begin(progress_t *p, const char *label, int total);
/* One more step done; `what` names it (may be NULL). */
void progress_step(progress_t *p, const char *what);
void progress_end(progress_t *p);

#endif
