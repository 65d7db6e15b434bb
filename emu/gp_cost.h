/* gp_cost.h: the i860 cost model: operation counts (fw_ops_t) -> GP clock cycles.
 *
 * Formula (each term is a row of gp_cost_table[], cited to facts §8):
 *   core = int_ops + stores + loads x (1 + load_stall) + branches x (1 + branch_bubble)
 *   fp   = fadd + fmul + fdiv x fdiv_cycles + fsqrt x fsqrt_cycles
 *   cycles = (dual_issue ? max(core, fp) : core + fp) + ceil(ext_bytes / ext_bus_bytes_per_cycle)
 * The FP adder and multiplier are pipelined (3 stages, one result per clock,
 * facts §8 S20/S21), so each FP operation costs one issue clock; the core
 * unit issues one integer/control/load/store instruction per clock (S19).
 * With dual-instruction mode (i860.dual_issue = 1) core and FP instructions
 * issue in the same clock and the slower stream decides.
 *
 * Modelled: issue slots, divide/sqrt sequences, load-use and branch bubbles,
 * external-bus bytes that the program declares.
 * Not modelled: dependency stalls between dependent FP operations (the 3-clock
 * pipeline latency: code is assumed scheduled/unrolled), register pressure,
 * cache misses that the program does not declare as ext_bytes, traps and
 * context switches (62-2000 cycles, facts §8 S22), double precision. */
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
} gp_cost_t;

/* One documented row of the table (for ARCHITECTURE.md and reports). */
typedef struct {
    const char *op;          /* fw_ops_t field */
    const char *cycles;      /* cost per operation, as a formula */
    const char *citation;
} gp_cost_row_t;

void gp_cost_init(gp_cost_t *c, const pp5_params_t *p);
uint64_t gp_cost_cycles(const gp_cost_t *c, const fw_ops_t *ops);
void gp_cost_add(fw_ops_t *total, const fw_ops_t *ops);
const gp_cost_row_t *gp_cost_table(int *count);

#endif
