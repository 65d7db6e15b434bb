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

void progress_begin(progress_t *p, const char *label, int total)
{
    p->label = label;
    p->done = 0;
    p->total = total;
    p->t_start = now_s();
    p->on = isatty(STDERR_FILENO) && !getenv("PP5_QUIET");
}

void progress_step(progress_t *p, const char *what)
{
    p->done++;
    if (!p->on)
        return;
    double spent = now_s() - p->t_start;
    double left = p->done > 0 ? spent / p->done * (p->total - p->done) : 0;
    fprintf(stderr, "\r%s: %d/%d%s%s%s, about %.0f s left   ", p->label, p->done, p->total,
            what ? " (" : "", what ? what : "", what ? ")" : "", left);
    fflush(stderr);
}

void progress_end(progress_t *p)
{
    if (p->on) {
        fprintf(stderr, "\r%s: %d/%d done in %.0f s%30s\n", p->label, p->done, p->total,
                now_s() - p->t_start, "");
        fflush(stderr);
    }
}
