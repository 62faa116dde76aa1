/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include <depthao/error.h>

#include "cli_params.h"

int cli_apply_param_option(struct dao_params *p, int argc, char **argv, int *i, char *msg,
			   size_t msg_len)
{
	const char *arg = argv[*i];
	if (strncmp(arg, "--", 2) != 0)
		return 0;
	char name[64];
	const char *eq = strchr(arg + 2, '=');
	size_t len = eq ? (size_t)(eq - (arg + 2)) : strlen(arg + 2);
	if (len == 0 || len >= sizeof name)
		return 0;
	memcpy(name, arg + 2, len);
	name[len] = '\0';
	const struct dao_param_info *pi = dao_param_find(name);
	if (!pi)
		return 0;
	const char *value = eq ? eq + 1 : NULL;
	if (!value) {
		if (*i + 1 >= argc) {
			snprintf(msg, msg_len, "--%s needs a value", pi->name);
			return -1;
		}
		value = argv[++*i];
	}
	struct dao_error err;
	if (dao_params_set(p, pi->name, value, &err)) {
		snprintf(msg, msg_len, "%s", err.message);
		return -1;
	}
	return 1;
}

static void describe_values(const struct dao_param_info *pi, char *buf, size_t len)
{
	size_t used = 0;
	switch (pi->type) {
	case DAO_PARAM_FLOAT:
		snprintf(buf, len, "%g..%g%s%s", pi->min, pi->max, pi->unit ? " " : "",
			 pi->unit ? pi->unit : "");
		break;
	case DAO_PARAM_INT:
		snprintf(buf, len, "%d..%d%s%s", (int)pi->min, (int)pi->max, pi->unit ? " " : "",
			 pi->unit ? pi->unit : "");
		break;
	case DAO_PARAM_ENUM:
		buf[0] = '\0';
		for (int k = 0; pi->enum_names[k] && used < len; k++)
			used += (size_t)snprintf(buf + used, len - used, "%s%s", k ? "|" : "",
						 pi->enum_names[k]);
		break;
	case DAO_PARAM_COLOR:
		snprintf(buf, len, "RRGGBB");
		break;
	}
}

void cli_print_param_help(FILE *out, const struct dao_params *defaults)
{
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	for (size_t k = 0; k < n; k++) {
		char values[96], def[48];
		describe_values(&t[k], values, sizeof values);
		if (dao_params_get(defaults, t[k].name, def, sizeof def, NULL))
			def[0] = '\0';
		fprintf(out, "  --%-20s %-24s %s [%s]\n", t[k].name, values, t[k].help, def);
	}
}

int cli_apply_param_list(const char *list, struct dao_params *p, struct dao_error *err)
{
	char buf[256];
	if (snprintf(buf, sizeof buf, "%s", list) >= (int)sizeof buf) {
		dao_error_set(err, -EINVAL, "parameters of an algorithm in --algorithms too long: '%s'",
			      list);
		return -1;
	}
	char *save = NULL;
	for (char *kv = strtok_r(buf, ":", &save); kv; kv = strtok_r(NULL, ":", &save)) {
		char *eq = strchr(kv, '=');
		if (!eq) {
			dao_error_set(err, -EINVAL,
				      "'%s' in --algorithms: give PARAM=VALUE after the algorithm, e.g. "
				      "vbao:vbao-thickness-mode=constant", kv);
			return -1;
		}
		*eq = '\0';
		if (dao_params_set(p, kv, eq + 1, err))
			return -1;
	}
	return 0;
}
