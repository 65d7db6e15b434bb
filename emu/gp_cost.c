/* gp_cost.c: i860 cost table and the ops -> cycles conversion (facts §8). */
#include "gp_cost.h"

static const gp_cost_row_t cost_rows[] = {
    { "fadd", "1 (issue slot; adder 3 stages x 1 clock, one result per clock)",
      "[C] facts §8: S20 p.90 'three-stage pipelining ... each Ai in one clock'; S21 'adder pipeline, always 3 stages'" },
    { "fmul", "1 (issue slot; single-precision multiplier 3 stages, one result per clock)",
      "[C] facts §8: S21 3 stages SP; S20 p.90; 80 MFLOPS SP = add + mul per clock at 40 MHz S19" },
    { "fdiv", "i860.fdiv_cycles (frcp + Newton; no divide instruction)", "[C] S21 opcode table has frcp, no divide; cycles [I] facts §8 (derivation in params_machine.def)" },
    { "fsqrt", "i860.fsqrt_cycles (frsqr + Newton)", "[C] S21 opcode table has frsqr, no sqrt; cycles [I] facts §8 (derivation in params_machine.def)" },
    { "loads", "1", "[C] one core instruction per clock facts §8 S19" },
    { "load_use", "i860.load_stall_cycles (a load whose value the next instruction uses)", "load-use delay [U] facts §8 'one load-delay cycle on a cache hit'; the rule: gp_cost.h" },
    { "stores", "1", "[C] one core instruction per clock facts §8 S19" },
    { "int_ops", "1", "[C] one integer instruction per clock facts §8 S19; 40 MIPS S22" },
    { "branches", "1 + i860.branch_bubble_cycles", "[C] delayed branch, one delay slot facts §8 S21; fill rate [U]" },
    { "ext_bytes", "1 / i860.ext_bus_bytes_per_cycle", "[I]/[U] facts §8: 64-bit external bus, ~160 MB/s at 40 MHz" },
    { "dcache_hits", "0 (the load or store instruction is its cost)", "[C] 8 KB data cache facts §8 S19; line and ways [U] (i860.dcache_*)" },
    { "dcache_misses", "i860.dcache_miss_cycles + ceil(i860.dcache_line_bytes / i860.ext_bus_bytes_per_cycle)",
      "[U] line fill over the [I]/[U] external bus, facts §8 and open question 9" },
    { "dcache_writebacks", "ceil(i860.dcache_line_bytes / i860.ext_bus_bytes_per_cycle)", "[U] write-back cache assumed (gp_dcache.h)" },
    { "(combine)", "i860.dual_issue ? max(core, fp) : core + fp, then + bus",
      "[C] dual-instruction mode facts §8 S19 'Up to Three Operations per Clock'; [S] S22 compilers rarely used it" },
};

const gp_cost_row_t *gp_cost_table(int *count)
{
    *count = (int)(sizeof cost_rows / sizeof cost_rows[0]);
    return cost_rows;
}

void gp_cost_init(gp_cost_t *c, const pp5_params_t *p)
{
    c->dual_issue = p->i860_dual_issue != 0;
    c->load_stall_cycles = p->i860_load_stall_cycles;
    c->branch_bubble_cycles = p->i860_branch_bubble_cycles;
    c->fdiv_cycles = p->i860_fdiv_cycles;
    c->fsqrt_cycles = p->i860_fsqrt_cycles;
    c->ext_bus_bytes_per_cycle = p->i860_ext_bus_bytes_per_cycle ? p->i860_ext_bus_bytes_per_cycle : 1;
    c->line_bus_cycles = (p->i860_dcache_line_bytes + c->ext_bus_bytes_per_cycle - 1) / c->ext_bus_bytes_per_cycle;
    c->miss_cycles = p->i860_dcache_miss_cycles;
}

uint64_t gp_cost_bus_cycles(const gp_cost_t *c, const fw_ops_t *o)
{
    uint64_t ext = (o->ext_bytes + c->ext_bus_bytes_per_cycle - 1) / c->ext_bus_bytes_per_cycle;
    return ext + o->dcache_misses * ((uint64_t)c->miss_cycles + c->line_bus_cycles) +
           o->dcache_writebacks * c->line_bus_cycles;
}

uint64_t gp_cost_cycles(const gp_cost_t *c, const fw_ops_t *o)
{
    uint64_t core = o->int_ops + o->stores + o->loads + o->load_use * c->load_stall_cycles +
                    o->branches * (1u + c->branch_bubble_cycles);
    uint64_t fp = o->fadd + o->fmul + o->fdiv * c->fdiv_cycles + o->fsqrt * c->fsqrt_cycles;
    uint64_t issue = c->dual_issue ? (core > fp ? core : fp) : core + fp;
    return issue + gp_cost_bus_cycles(c, o);
}

void gp_cost_add(fw_ops_t *t, const fw_ops_t *o)
{
    t->fadd += o->fadd;
    t->fmul += o->fmul;
    t->fdiv += o->fdiv;
    t->fsqrt += o->fsqrt;
    t->loads += o->loads;
    t->stores += o->stores;
    t->int_ops += o->int_ops;
    t->branches += o->branches;
    t->ext_bytes += o->ext_bytes;
    t->load_use += o->load_use;
    t->dcache_hits += o->dcache_hits;
    t->dcache_misses += o->dcache_misses;
    t->dcache_writebacks += o->dcache_writebacks;
}
