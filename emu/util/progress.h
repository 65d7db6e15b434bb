/* progress.h: a one-line progress report for long work, on a terminal only.
 *
 *   progress_t p;
 *   progress_begin(&p, "projections", rows);
 *   for (...) { ...; progress_step(&p, "specular, resident"); }
 *   progress_end(&p);
 *
 * The line ("projections: 3/24 (specular, resident), about 40 s left") is
 * rewritten in place on stderr, and only when stderr is a terminal and
 * PP5_QUIET is not set (`pp5 ... --quiet` sets it), so logs, pipes and tests
 * stay clean.  Work that ends within half a second (PP5_PROGRESS_DELAY_S)
 * prints nothing, so short runs do not flicker. */
#ifndef PP5_PROGRESS_H
#define PP5_PROGRESS_H

#include <stdbool.h>

typedef struct {
    const char *label;
    int done, total;
    double t_start;
    bool on;                      /* a terminal, and not quiet */
    bool shown;                   /* a line has been printed */
} progress_t;

/* Whether progress lines would be printed now (a terminal, not quiet). */
bool progress_enabled(void);

void progress_begin(progress_t *p, const char *label, int total);
/* One more step done; `what` names it (may be NULL). */
void progress_step(progress_t *p, const char *what);
/* `done` steps done in all (for work measured in something other than
 * steps, e.g. per mille of a trace's time). */
void progress_set(progress_t *p, int done, const char *what);
/* For work that cannot be counted: says what runs now, at once, without an
 * estimate; progress_end then gives the time it took. */
void progress_note(progress_t *p, const char *what);
void progress_end(progress_t *p);

#endif
