/* SPDX-License-Identifier: MIT */
/*
 * json_get PATH: reads one JSON document from stdin and prints the value at
 * PATH ("stats.sinks.1.frames_out"; numbers index arrays).  Exits 1 if the
 * input is not JSON or the path does not exist: the tests' JSON check.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <json-c/json.h>

int main(int argc, char **argv)
{
	static char buf[1 << 20];
	size_t n = fread(buf, 1, sizeof buf - 1, stdin);
	buf[n] = '\0';
	struct json_object *j = json_tokener_parse(buf);
	if (!j || argc < 2) {
		fprintf(stderr, "json_get: input is not JSON\n");
		return 1;
	}
	struct json_object *cur = j;
	char path[512];
	snprintf(path, sizeof path, "%s", argv[1]);
	for (char *tok = strtok(path, "."); tok && *path; tok = strtok(NULL, ".")) {
		struct json_object *next = NULL;
		if (json_object_is_type(cur, json_type_array)) {
			char *end;
			long i = strtol(tok, &end, 10);
			if (*end || i < 0 || (size_t)i >= json_object_array_length(cur))
				next = NULL;
			else
				next = json_object_array_get_idx(cur, (size_t)i);
		} else if (!json_object_object_get_ex(cur, tok, &next)) {
			next = NULL;
		}
		if (!next) {
			fprintf(stderr, "json_get: no '%s' in %s\n", tok, argv[1]);
			return 1;
		}
		cur = next;
	}
	if (json_object_is_type(cur, json_type_string))
		printf("%s\n", json_object_get_string(cur));
	else
		printf("%s\n", json_object_to_json_string_ext(cur, JSON_C_TO_STRING_PLAIN));
	json_object_put(j);
	return 0;
}
