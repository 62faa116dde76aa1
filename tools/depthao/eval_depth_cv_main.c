/* SPDX-License-Identifier: MIT */
/*
 * depthao-eval-cv: `depthao eval --depth` built with OpenCV's rgbd
 * DepthCleaner beside depthao's filter and the reference chain (not
 * installed: it exists to measure the anchor, docs/depth-accuracy.md).
 */
#include <stdarg.h>
#include <stdio.h>

#include "commands.h"
#include "eval_depth.h"

int usage_error(const char *cmd, const char *fmt, ...)
{
	va_list ap;
	fputs("depthao-eval-cv: ", stderr);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, " (see 'depthao %s --depth --help')\n", cmd ? cmd : "eval");
	return 2;
}

int main(int argc, char **argv)
{
	return cmd_eval_depth(argc, argv);
}
