/* SPDX-License-Identifier: MIT */
/* Command-line options generated from the library's parameter table. */
#ifndef DAO_TOOLS_CLI_PARAMS_H
#define DAO_TOOLS_CLI_PARAMS_H

#include <stdio.h>

#include <depthao/params.h>

/*
 * If argv[*i] is a parameter option (--radius 0.5 or --radius=0.5, any name
 * in the table), applies it to p, advances *i past its value and returns 1;
 * returns 0 if argv[*i] is not a parameter option; on a bad or missing value
 * returns -1 with a one-line reason in msg.
 */
int cli_apply_param_option(struct dao_params *p, int argc, char **argv, int *i, char *msg,
			   size_t len);

/*
 * Applies "PARAM=VALUE:PARAM=VALUE..." (what follows an algorithm's name in
 * --algorithms, e.g. vbao:vbao-thickness-mode=image) to p.  0, or -1 with a
 * message in err naming the entry.
 */
int cli_apply_param_list(const char *list, struct dao_params *p, struct dao_error *err);

/* One help line per parameter: --name <values> help [default]. */
void cli_print_param_help(FILE *out, const struct dao_params *defaults);

#endif
