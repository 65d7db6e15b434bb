/* cmd_machine.c: `pp5 machine`: print every machine parameter with value, unit and source. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cliopt.h"
#include "gp_cost.h"
#include "params.h"
#include "registry.h"

static void machine_usage(FILE *out)
{
    fprintf(out,
            "usage: pp5 machine [--preset NAME] [--config FILE] [--set NAME=VALUE]... [--dump-config]\n\n"
            "Prints every Pixel-Planes 5 machine parameter with its value, unit, meaning and\n"
            "source (certainty tag [C]onfirmed/[S]econdary/[I]nferred/[U]nverified + citation of\n"
            "../shared/docs/pxpl5-facts.md), the plausible range of every uncertain row (what a\n"
            "sensitivity study varies), then the derived ring bandwidth.\n\n"
            PP5_PARAMS_CLI_HELP
            "  --dump-config     print the parameters as a file that --config can load\n"
            "  --help            this text\n\n"
            "Example:\n"
            "  pp5 machine --preset gaze1990-literal --set ring.channels=4\n");
}

static int cmd_machine(int argc, char **argv)
{
    static const struct option opts[] = {
        {"preset", required_argument, NULL, 'p'},
        {"config", required_argument, NULL, 'c'},
        {"set", required_argument, NULL, 's'},
        {"dump-config", no_argument, NULL, 'd'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0}};
    pp5_params_cli_t cli;
    memset(&cli, 0, sizeof cli);
    int dump = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 'p': cli.preset = optarg; break;
        case 'c': cli.config = optarg; break;
        case 's':
            if (pp5_params_cli_add_set(&cli, optarg) != PP5_OK) {
                return cliopt_report("machine", PP5_E_CONFIG);
            }
            break;
        case 'd': dump = 1; break;
        case 'h': machine_usage(stdout); return 0;
        default: machine_usage(stderr); return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "pp5 machine: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    pp5_params_t p;
    pp5_status_t st = pp5_params_build(&cli, &p);
    if (st != PP5_OK) {
        return cliopt_report("machine", st);
    }
    if (dump) {
        printf("# pp5 machine parameters (preset %s); load with --config\n",
               cli.preset ? cli.preset : "default");
        pp5_params_dump(&p, stdout);
        return 0;
    }
    printf("Pixel-Planes 5 machine (preset %s)\n\n", cli.preset ? cli.preset : "default");
    printf("%-30s %14s  %-16s %s\n", "parameter", "value", "unit", "meaning / source");
    for (size_t i = 0; i < params_count(); i++) {
        const param_info_t *row = params_info(i);
        char v[64];
        params_format(&p, row, v, sizeof v);
        printf("%-30s %14s  %-16s %s\n", row->name, v, row->unit, row->description);
        printf("%-30s %14s  %-16s   source: %s\n", "", "", "", row->citation);
        if (params_has_range(row))
            printf("%-30s %14s  %-16s   plausible: %.9g .. %.9g\n", "", "", "", row->plausible_lo,
                   row->plausible_hi);
    }
    int n_cost;
    const gp_cost_row_t *cost = gp_cost_table(&n_cost);
    printf("\ni860 cost table (gp_cost.c; [U] values are the i860.* parameters above):\n");
    for (int i = 0; i < n_cost; i++) {
        printf("  %-10s %s\n  %-10s   source: %s\n", cost[i].op, cost[i].cycles, "", cost[i].citation);
    }
    double ch = pp5_params_ring_channel_bytes_per_s(&p);
    double agg = pp5_params_ring_aggregate_bytes_per_s(&p);
    printf("\nderived:\n");
    printf("  ring channel bandwidth   = %g MB/s (%u bits x %g MHz)\n", ch / 1e6, p.ring_width_bits,
           p.ring_clock_hz / 1e6);
    printf("  ring aggregate bandwidth = %g MB/s = %g Gb/s (%u channels)\n", agg / 1e6, agg * 8 / 1e9,
           p.ring_channels);
    printf("  screen regions           = %u x %u = %u (128x128 pixels each)\n", p.fb_width / 128,
           p.fb_height / 128, (p.fb_width / 128) * (p.fb_height / 128));
    return 0;
}

PP5_COMMAND(machine, "print the machine parameters with units and sources", cmd_machine)
