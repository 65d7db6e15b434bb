/* huge_alloc.c: large arrays on huge pages (huge_alloc.h). */
#include "huge_alloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

enum { HUGE_PAGE = 2 << 20, LINE = 64 };

static size_t whole_pages(size_t bytes)
{
    return (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
}

void *huge_alloc(size_t bytes, bool zero)
{
    /* rounding up to whole pages (plus one to align) must not wrap */
    if (bytes > SIZE_MAX / 2)
        return NULL;
    if (bytes < HUGE_PAGE) {   /* whole cache lines, so records of a line stay on one */
        size_t lines = (bytes + LINE - 1) / LINE * LINE;
        void *p = aligned_alloc(LINE, lines ? lines : LINE);
        if (p && zero)
            memset(p, 0, lines);
        return p;
    }
    size_t whole = whole_pages(bytes);
    /* a huge page more than needed, then the unaligned ends given back */
    char *raw = mmap(NULL, whole + HUGE_PAGE, PROT_READ | PROT_WRITE,
                     MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED)
        return NULL;
    char *p = (char *)(((uintptr_t)raw + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1));
    if (p > raw)
        munmap(raw, (size_t)(p - raw));
    if (p + whole < raw + whole + HUGE_PAGE)
        munmap(p + whole, (size_t)(raw + whole + HUGE_PAGE - (p + whole)));
#ifdef MADV_HUGEPAGE
    /* advice only: without transparent huge pages the array has 4 KB pages */
    madvise(p, whole, MADV_HUGEPAGE);
#endif
    return p;   /* a fresh mapping reads as zeros */
}

void huge_free(void *p, size_t bytes)
{
    if (!p)
        return;
    if (bytes < HUGE_PAGE)
        free(p);
    else
        munmap(p, whole_pages(bytes));
}

void *huge_grow(void *old, size_t used, size_t old_bytes, size_t bytes)
{
    void *p = huge_alloc(bytes, false);
    if (!p)
        return NULL;
    if (used)
        memcpy(p, old, used);
    huge_free(old, old_bytes);
    return p;
}
