/* seed003_alloc.c: large arrays of seed 003 on huge pages (seed003_alloc.h). */
#include "seed003_alloc.h"

#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

enum { HUGE_PAGE = 2 << 20 };

void *s003_alloc_big(size_t bytes, bool zero)
{
    if (bytes < HUGE_PAGE)
        return zero ? calloc(bytes ? bytes : 1, 1) : malloc(bytes ? bytes : 1);
    size_t whole = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    void *p = aligned_alloc(HUGE_PAGE, whole);
    if (!p)
        return NULL;
#ifdef MADV_HUGEPAGE
    /* advice only: without transparent huge pages the array is as malloc's */
    madvise(p, whole, MADV_HUGEPAGE);
#endif
    if (zero)
        memset(p, 0, whole);
    return p;
}

void *s003_grow_big(void *old, size_t used, size_t bytes)
{
    void *p = s003_alloc_big(bytes, false);
    if (!p)
        return NULL;
    if (used)
        memcpy(p, old, used);
    free(old);
    return p;
}
