/* pp5_time.h: pp5's single time base (integer picoseconds) and clock-domain helpers.
 *
 * Every unit counts emulated time in pp5_tick_t = picoseconds (STYLE L3).
 * 2^64 ps is about 213 days of emulated time, far beyond any run.  Each clock
 * domain (GP i860, renderer, ring) stores period_ps computed ONCE from its
 * *_hz parameter by clock_period_ps(): 1e12 / hz rounded to the nearest
 * picosecond.  40 MHz -> 25,000 ps and 20 MHz -> 50,000 ps are exact; a
 * 33.3 MHz part becomes 30,030 ps (0.0009 % slow), which is the only rounding
 * anywhere: after that all time arithmetic is integer. */
#ifndef PP5_TIME_H
#define PP5_TIME_H

#include <math.h>
#include <stdint.h>

typedef uint64_t pp5_tick_t;          /* picoseconds of emulated time */

#define PP5_PS_PER_S  1000000000000ULL
#define PP5_PS_PER_US 1000000ULL
#define PP5_TICK_MAX  UINT64_MAX

/* Period of a clock in ps, rounded to nearest; never 0 (params validation
 * keeps every *_hz far below 1e12). */
static inline pp5_tick_t clock_period_ps(double hz)
{
    double p = floor(1e12 / hz + 0.5);
    return p < 1.0 ? 1 : (pp5_tick_t)p;
}

/* Duration of `cycles` cycles of a clock whose period is period_ps. */
static inline pp5_tick_t clock_cycles_ps(uint64_t cycles, pp5_tick_t period_ps)
{
    return cycles * period_ps;
}

/* Seconds for reports only (never fed back into the model). */
static inline double ticks_to_s(pp5_tick_t t)
{
    return (double)t / 1e12;
}

static inline pp5_tick_t tick_max(pp5_tick_t a, pp5_tick_t b) { return a > b ? a : b; }

#endif
