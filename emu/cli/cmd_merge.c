/* cmd_merge.c: `pp5 merge PARTS... --out FILE.csv`: combines the parts that
 * `pp5 sweep --shard K/N` and `pp5 replay --batch ... --shard K/N` write
 * (unit logs, emu/util/workunit.h) into the outputs of the whole batch,
 * byte for byte those of a single run. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>

#include "cliopt.h"
#include "registry.h"
#include "workunit.h"

static void merge_usage(FILE *out)
{
    fprintf(out,
            "usage: pp5 merge PART... --out FILE.csv [--report FILE.json]\n\n"
            "Combines the parts of a batch run in shards (pp5 sweep --shard K/N, pp5 replay\n"
            "--batch LIST --shard K/N) into the CSV, and the JSON report, that one run of the\n"
            "whole batch writes: the rows in unit order, byte for byte the same.  The parts\n"
            "must come from the same batch (same command, arguments and pp5 build) and\n"
            "together hold every unit; a part may be given twice, and a unit that failed in\n"
            "one part and was retried in another counts as done.\n\n"
            "  --out FILE.csv      the batch's CSV (required)\n"
            "  --report FILE.json  every unit's key, status and result as JSON\n"
            "  --help              this text\n\n"
            "Exit code: 0; 8 when the batch holds failed units (their rows say why); 3 when\n"
            "the parts do not make a whole batch, 2 for a bad command line (then nothing is\n"
            "written).\n\n"
            "Example (a job array of 4 shards):\n"
            "  for k in 0 1 2 3; do pp5 sweep --set gp.count=4,8,16,32 --shard $k/4 \\\n"
            "      --out part$k.units; done\n"
            "  pp5 merge part0.units part1.units part2.units part3.units --out sweep.csv\n");
}

static int cmd_merge(int argc, char **argv)
{
    static const struct option opts[] = {{"out", required_argument, NULL, 'o'},
                                         {"report", required_argument, NULL, 'j'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *out = NULL, *report = NULL;
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        if (c == 'o')
            out = optarg;
        else if (c == 'j')
            report = optarg;
        else {
            merge_usage(c == 'h' ? stdout : stderr);
            return c == 'h' ? 0 : 2;
        }
    }
    if (!out || optind >= argc)
        return cliopt_report("merge", pp5_fail(PP5_E_CONFIG, "need PART... and --out FILE.csv "
                                               "(see --help)"));
    workunit_list_t l;
    workunit_run_t run;
    char *command = NULL, *header = NULL;
    pp5_status_t st = workunit_merge((const char *const *)argv + optind, argc - optind, &l, &run,
                                     &command, &header);
    if (st == PP5_OK)
        st = workunit_write_csv(out, header, &run);
    if (st == PP5_OK && report)
        st = workunit_write_json(report, command, &l, &run);
    int rc = 0;
    if (st != PP5_OK)
        rc = cliopt_report("merge", st);
    else {
        printf("merge: %d parts of a %s batch, %zu units (%zu failed): wrote %s%s%s\n",
               argc - optind, command, run.count, run.failed, out, report ? " and " : "",
               report ? report : "");
        rc = run.failed ? WORKUNIT_EXIT_UNITS_FAILED : 0;
    }
    workunit_run_free(&run);
    workunit_list_free(&l);
    free(command);
    free(header);
    return rc;
}

PP5_COMMAND(merge, "combine the parts of a sharded sweep or replay batch into its CSV and report",
            cmd_merge)
