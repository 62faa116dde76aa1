/* SPDX-License-Identifier: MIT */
#ifndef DAO_TOOLS_COMMANDS_H
#define DAO_TOOLS_COMMANDS_H

/* Subcommands of `depthao`; argv[0] is the subcommand's name.  They return
 * the process exit status: 0 ok, 1 runtime error, 2 usage error. */
int cmd_process(int argc, char **argv);
int cmd_synth(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_devices(int argc, char **argv);
int cmd_ctl(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_sensorstats(int argc, char **argv);
int cmd_realcheck(int argc, char **argv);

/* The version with the build's `git describe`, e.g. "1.0.0 (git 6501cfb-dirty)". */
const char *depthao_version_line(void);

/* Prints "depthao: <reason> (see 'depthao <cmd> --help')" and returns 2. */
int usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
