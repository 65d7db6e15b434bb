/* cmd_pp_isa.c: `pp5 pp-isa`: print the PP instruction table (pp_isa.def) as Markdown. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "pp_isa.h"
#include "pp_params.h"
#include "registry.h"

static const char *width_text(unsigned code)
{
    switch (code) {
    case W1: return "1";
    case WN: return "n";
    case WM: return "m";
    case W32: return "32";
    default: return NULL;
    }
}

/* "d[n] a[n] b[n] x=cond +imm(n)" from the table's field columns. */
static void fields_text(const pp_op_info_t *op, char *buf, size_t size)
{
    size_t t = 0;
    buf[0] = '\0';
    const char *names[3] = {"d", "a", "b"};
    unsigned codes[3] = {op->d_width, op->a_width, op->b_width};
    for (int i = 0; i < 3; i++) {
        const char *w = width_text(codes[i]);
        if (w && t < size)
            t += (size_t)snprintf(buf + t, size - t, "%s%s[%s]", t ? " " : "", names[i], w);
    }
    const char *x = NULL;
    switch (op->code) {
    case PP_OP_F_SET: x = "x=value"; break;
    case PP_OP_CMP: case PP_OP_CMPI: x = "x=cond"; break;
    case PP_OP_SHL: case PP_OP_SHR: case PP_OP_SAR: x = "x=shift"; break;
    case PP_OP_QEE: x = "x=frac bits"; break;
    case PP_OP_BSLOAD: case PP_OP_BSSTORE: x = "x=block"; break;
    default: break;
    }
    if (x && t < size)
        t += (size_t)snprintf(buf + t, size - t, "%s%s", t ? " " : "", x);
    if ((op->d_width == WM || op->a_width == WM) && t < size)
        t += (size_t)snprintf(buf + t, size - t, " mod=signed");
    static const char *const imm[] = {NULL, "imm: ceil(n/32) words", "imm: 1 word", "imm: A..F (6 words)"};
    if (op->imm && t < size)
        snprintf(buf + t, size - t, "%s%s", t ? "; " : "", imm[op->imm]);
}

/* The cost expression with the C spelling removed ("in->n" -> "n", "P->x" -> "pp.x"). */
static void cost_text(const char *src, char *buf, size_t size)
{
    size_t o = 0;
    for (const char *p = src; *p && o + 4 < size;) {
        if (strncmp(p, "in->", 4) == 0) {
            p += 4;
        } else if (strncmp(p, "P->", 3) == 0) {
            memcpy(buf + o, "pp.", 3);
            o += 3;
            p += 3;
        } else if (strncmp(p, "(in, P)", 7) == 0) {
            p += 7;
        } else {
            buf[o++] = *p++;
        }
    }
    buf[o] = '\0';
}

/* A Markdown table cell: '|' must be escaped. */
static void cell(FILE *out, const char *s)
{
    fputs(" ", out);
    for (; *s; s++) {
        if (*s == '|')
            fputc('\\', out);
        fputc(*s, out);
    }
    fputs(" |", out);
}

static void print_table(FILE *out)
{
    fprintf(out, "| code | name | class | words | fields | compute cycles | tag | semantics |\n"
                 "|---|---|---|---|---|---|---|---|\n");
    for (unsigned i = 0; i < pp_isa_count(); i++) {
        const pp_op_info_t *op = pp_isa_at(i);
        char fields[128], cost[160];
        fields_text(op, fields, sizeof fields);
        cost_text(op->cost_text, cost, sizeof cost);
        fprintf(out, "| 0x%02X | %s | %s | %d |", op->code, op->name,
                pp_class_name((pp_class_t)op->cls), op->format == PP_FMT_2W ? 2 : 1);
        cell(out, fields);
        cell(out, cost);
        cell(out, op->tag);
        cell(out, op->semantics);
        fputc('\n', out);
    }
}

static int cmd_pp_isa(int argc, char **argv)
{
    static const struct option opts[] = {{"help", no_argument, NULL, 'h'}, {NULL, 0, NULL, 0}};
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        if (c == 'h') {
            printf("usage: pp5 pp-isa\n\n"
                   "Prints the renderer's PP instruction table (emu/pp_isa.def) as a Markdown\n"
                   "table: opcode, class, words, fields, compute-cycle formula, certainty tag\n"
                   "and semantics.  Word formats: emu/pp_isa.h; prose: emu/PP_ISA.md.\n"
                   "In the formulas PASS(k) = k * pp.cycles_per_bit + pp.alu_overhead_cycles.\n\n"
                   "Example:\n"
                   "  pp5 pp-isa > pp-isa.md\n");
            return 0;
        }
        fprintf(stderr, "pp5 pp-isa: unknown option (try --help)\n");
        return 2;
    }
    if (optind < argc) {
        fprintf(stderr, "pp5 pp-isa: unexpected argument '%s' (try --help)\n", argv[optind]);
        return 2;
    }
    print_table(stdout);
    return 0;
}

PP5_COMMAND_NAMED(pp_isa, "pp-isa", "print the PP instruction table (opcodes, costs, tags)",
                  cmd_pp_isa)
