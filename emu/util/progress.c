/* progress.c: the terminal progress line (progress.h). */
#include "progress.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Seconds of work before a line appears; PP5_PROGRESS_DELAY_S overrides it
 * (the tests set 0 to see lines from short work). */
static double delay_s(void)
{
    const char *d = getenv("PP5_PROGRESS_DELAY_S");
    char *end;
    double v = d ? strtod(d, &end) : 0.5;
    return d && end != d && v >= 0 ? v : 0.5;
}

bool progress_enabled(void)
{
    const char *q = getenv("PP5_QUIET");
    return isatty(STDERR_FILENO) && !(q && *q);
}

void progress_begin(progress_t *p, const char *label, int total)
{
    p->label = label;
    p->done = 0;
    p->total = total;
    p->t_start = now_s();
    p->on = progress_enabled();
    p->shown = false;
}

void progress_step(progress_t *p, const char *what)
{
    progress_set(p, p->done + 1, what);
}

void progress_note(progress_t *p, const char *what)
{
    if (!p->on)
        return;
    p->shown = true;
    fprintf(stderr, "\r%s: %s ...   ", p->label, what);
    fflush(stderr);
}

void progress_set(progress_t *p, int done, const char *what)
{
    p->done = done;
    if (!p->on || now_s() - p->t_start < delay_s())
        return;
    p->shown = true;
    double spent = now_s() - p->t_start;
    double left = p->done > 0 ? spent / p->done * (p->total - p->done) : 0;
    fprintf(stderr, "\r%s: %d/%d%s%s%s, about %.0f s left   ", p->label, p->done, p->total,
            what ? " (" : "", what ? what : "", what ? ")" : "", left);
    fflush(stderr);
}

void progress_end(progress_t *p)
{
    if (p->on && p->shown) {
        fprintf(stderr, "\r%s: done in %.1f s%40s\n", p->label, now_s() - p->t_start, "");
        fflush(stderr);
    }
}
