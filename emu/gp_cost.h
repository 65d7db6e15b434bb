/* gp_cost.h: the i860 cost model: operation counts (fw_ops_t) -> GP clock cycles.
 *
 * Formula (each term is a row of gp_cost_table[], cited to facts §8):
 *   core = int_ops + stores + loads + load_use x load_stall + branches x (1 + branch_bubble)
 *   fp   = fadd + fmul + fdiv x fdiv_cycles + fsqrt x fsqrt_cycles
 *   bus  = ceil(ext_bytes / ext_bus_bytes_per_cycle)
 *        + dcache_misses x (dcache_miss_cycles + line_bytes / ext_bus_bytes_per_cycle)
 *        + dcache_writebacks x line_bytes / ext_bus_bytes_per_cycle   (line terms rounded up)
 *   cycles = (dual_issue ? max(core, fp) : core + fp) + bus
 * The FP adder and multiplier are pipelined (3 stages, one result per clock,
 * facts §8 S20/S21), so each FP operation costs one issue clock; the core
 * unit issues one integer/control/load/store instruction per clock (S19).
 * With dual-instruction mode (i860.dual_issue = 1) core and FP instructions
 * issue in the same clock and the slower stream decides.  The bus term is
 * not overlapped with issue: the i860 waits for a line fill (no
 * hit-under-miss is known, [U]).
 *
 * The load-use rule.  A load costs its issue clock; the load-use delay
 * (i860.load_stall_cycles, [U] facts §8 'one load-delay cycle on a cache
 * hit') is paid only by the loads a program counts in load_use: those whose
 * value the very next instruction needs, with no independent instruction the
 * code could put in between.  Which loads of each kernel those are is stated
 * in firmware/ARCHITECTURE.md ("Cost model notes") and beside each row of
 * firmware/common/vr_cost.h.
 *
 * Modelled: issue slots, divide/sqrt sequences, load-use delays of the loads
 * counted as used at once, branch bubbles, line fills and write-backs of the
 * data cache on the accesses the program declares (gp_dcache.h), external-bus
 * bytes of programmed I/O.
 * Not modelled: dependency stalls between dependent FP operations (the 3-clock
 * pipeline latency: code is assumed scheduled/unrolled), register pressure,
 * accesses the program does not declare (hits), traps and context switches
 * (62-2000 cycles, facts §8 S22), double precision. */
#ifndef PP5_GP_COST_H
#define PP5_GP_COST_H

#include <stdint.h>
#include "fw_api.h"
#include "params.h"

typedef struct {
    int dual_issue;
    uint32_t load_stall_cycles, branch_bubble_cycles;
    uint32_t fdiv_cycles, fsqrt_cycles;
    uint32_t ext_bus_bytes_per_cycle;
    uint32_t line_bus_cycles;     /* ceil(dcache_line_bytes / ext_bus_bytes_per_cycle) */
    uint32_t miss_cycles;         /* i860.dcache_miss_cycles */
} gp_cost_t;

/* One documented row of the table (for ARCHITECTURE.md and reports). */
typedef struct {
    const char *op;          /* fw_ops_t field */
    const char *cycles;      /* cost per operation, as a formula */
    const char *citation;
} gp_cost_row_t;

void gp_cost_init(gp_cost_t *c, const pp5_params_t *p);
uint64_t gp_cost_cycles(const gp_cost_t *c, const fw_ops_t *ops);
/* The bus term alone (cache fills, write-backs, ext_bytes). */
uint64_t gp_cost_bus_cycles(const gp_cost_t *c, const fw_ops_t *ops);
void gp_cost_add(fw_ops_t *total, const fw_ops_t *ops);
const gp_cost_row_t *gp_cost_table(int *count);

#endif
