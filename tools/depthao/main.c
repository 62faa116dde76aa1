/* SPDX-License-Identifier: MIT */
#include <stdio.h>
#include <string.h>

#include <depthao/depthao.h>

int main(int argc, char **argv)
{
	if (argc > 1 && strcmp(argv[1], "--version") == 0) {
		printf("depthao %s\n", dao_version());
		return 0;
	}
	return 2;
}
