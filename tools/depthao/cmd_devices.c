/* SPDX-License-Identifier: MIT */
/* depthao devices: the plugins that loaded (and why others did not), and their devices. */
#include <stdio.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

#include "common/cli_plugins.h"
#include "commands.h"

static void usage(FILE *out)
{
	fprintf(out,
		"usage: depthao devices [--help]\n"
		"\n"
		"Lists the source and sink plugins (built in, or modules from $%s and\n"
		"%s), the modules that failed to load and why, and the devices\n"
		"each source can open.  Open a device with 'depthao process --input NAME:URI'.\n",
		DAO_PLUGIN_PATH_ENV, dao_plugins_install_dir());
}

struct count {
	const char *plugin;
	int n;
};

static void print_device(void *user, const struct dao_device_entry *e)
{
	struct count *c = user;
	printf("    %s:%s  %s  (%s)\n", c->plugin, e->uri, e->name, e->detail);
	c->n++;
}

int cmd_devices(int argc, char **argv)
{
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
			usage(stdout);
			return 0;
		}
		return usage_error("devices", "unknown option '%s'", argv[i]);
	}
	struct dao_error err;
	struct dao_plugins *p;
	if (cli_plugins_load(&p, &err)) {
		fprintf(stderr, "depthao: %s\n", err.message);
		return 1;
	}
	printf("plugins:\n");
	for (size_t i = 0; i < dao_plugins_count(p); i++) {
		const struct dao_plugin *pl = dao_plugins_get(p, i);
		printf("  %-10s %s%s%s  [%s]\n", pl->name, pl->source ? "source" : "",
		       pl->source && pl->sink ? "+" : "", pl->sink ? "sink" : "",
		       dao_plugins_origin(p, i));
		printf("             %s\n", pl->description);
	}
	for (size_t i = 0; i < dao_plugins_skipped_count(p); i++)
		printf("  not loaded: %s\n", dao_plugins_skipped(p, i));
	printf("devices:\n");
	int total = 0, status = 0;
	for (size_t i = 0; i < dao_plugins_count(p); i++) {
		const struct dao_plugin *pl = dao_plugins_get(p, i);
		if (!pl->source || !pl->source->list_devices)
			continue;
		struct count c = {pl->name, 0};
		int r = pl->source->list_devices(print_device, &c, &err);
		if (r < 0) {
			fprintf(stderr, "depthao: %s: %s\n", pl->name, err.message);
			status = 1;
			continue;
		}
		total += c.n;
	}
	if (total == 0)
		printf("  none found (recordings: 'depthao process --input FILE.oni')\n");
	dao_plugins_free(p);
	return status;
}
