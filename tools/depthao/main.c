/* SPDX-License-Identifier: MIT */
/* depthao: ambient occlusion from depth images, on the command line. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <depthao/depthao.h>

#include "build_id.h"
#include "commands.h"

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao <command> [options]\n"
		"\n"
		"commands:\n"
		"  process   depth PNGs, .oni recordings or devices -> AO and shaded PNGs\n"
		"  synth     write synthetic scenes with ray-traced ground-truth AO\n"
		"  eval      measure every quality preset against the ground truth\n"
		"  compare   the algorithms side by side in one picture\n"
		"  sensorstats  plane residuals, depth bands and holes of real or simulated sensors\n"
		"  realcheck false occlusion on the open planar regions of real sensor frames\n"
		"  bench     time the pipeline and its stages per size, preset and thread count\n"
		"  devices   list source/sink plugins and the devices they can open\n"
		"  ctl       talk to a running depthaod (stats, get/set, pause, snapshot)\n"
		"\n"
		"  depthao <command> --help   options of a command\n"
		"  depthao --version          version\n");
}

int usage_error(const char *cmd, const char *fmt, ...)
{
	va_list ap;
	fputs("depthao: ", stderr);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	if (cmd)
		fprintf(stderr, " (see 'depthao %s --help')\n", cmd);
	else
		fputs(" (see 'depthao --help')\n", stderr);
	return 2;
}

const char *depthao_version_line(void)
{
	static char line[96];
	/* two calls: outside a git checkout (a tarball) the choice of format folds to
	 * "%s" at compile time, and gcc's -Wformat-extra-args fails -Dwerror=true */
	if (line[0])
		return line;
	if (strcmp(DAO_BUILD_ID, "unknown"))
		snprintf(line, sizeof line, "%s (git %s)", dao_version(), DAO_BUILD_ID);
	else
		snprintf(line, sizeof line, "%s", dao_version());
	return line;
}

int main(int argc, char **argv)
{
	if (argc < 2)
		return usage_error(NULL, "no command given");
	const char *cmd = argv[1];
	if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
		usage(stdout);
		return 0;
	}
	if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "-V") == 0) {
		printf("depthao %s\n", depthao_version_line());
		return 0;
	}
	if (strcmp(cmd, "process") == 0)
		return cmd_process(argc - 1, argv + 1);
	if (strcmp(cmd, "synth") == 0)
		return cmd_synth(argc - 1, argv + 1);
	if (strcmp(cmd, "eval") == 0)
		return cmd_eval(argc - 1, argv + 1);
	if (strcmp(cmd, "realcheck") == 0)
		return cmd_realcheck(argc - 1, argv + 1);
	if (strcmp(cmd, "sensorstats") == 0)
		return cmd_sensorstats(argc - 1, argv + 1);
	if (strcmp(cmd, "compare") == 0)
		return cmd_compare(argc - 1, argv + 1);
	if (strcmp(cmd, "ctl") == 0)
		return cmd_ctl(argc - 1, argv + 1);
	if (strcmp(cmd, "devices") == 0)
		return cmd_devices(argc - 1, argv + 1);
	if (strcmp(cmd, "bench") == 0)
		return cmd_bench(argc - 1, argv + 1);
	return usage_error(NULL, "unknown command '%s'", cmd);
}
