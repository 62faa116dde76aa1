/* SPDX-License-Identifier: MIT */
/* A rosbag2 directory's metadata.yaml, through libyaml (db3_reader.h). */
#include "db3/db3_reader.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <yaml.h>

#include "core/error_internal.h"

#define MAX_METADATA (4u << 20) /* bytes of metadata.yaml */

static yaml_node_t *map_get(yaml_document_t *doc, yaml_node_t *map, const char *key)
{
	if (!map || map->type != YAML_MAPPING_NODE)
		return NULL;
	for (yaml_node_pair_t *p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top;
	     p++) {
		yaml_node_t *k = yaml_document_get_node(doc, p->key);
		if (k && k->type == YAML_SCALAR_NODE && k->data.scalar.length == strlen(key) &&
		    !memcmp(k->data.scalar.value, key, k->data.scalar.length))
			return yaml_document_get_node(doc, p->value);
	}
	return NULL;
}

static int scalar(const yaml_node_t *n, char *dst, size_t cap)
{
	if (!n || n->type != YAML_SCALAR_NODE || n->data.scalar.length >= cap ||
	    memchr(n->data.scalar.value, 0, n->data.scalar.length))
		return -EINVAL;
	memcpy(dst, n->data.scalar.value, n->data.scalar.length);
	dst[n->data.scalar.length] = 0;
	return 0;
}

/* The storage and first file of a loaded document; a message in err on failure. */
static int from_document(yaml_document_t *doc, const char *dir, const char *name, char *storage,
			 size_t cap, char *file, size_t fcap, struct dao_error *err)
{
	yaml_node_t *info = map_get(doc, yaml_document_get_root_node(doc),
				    "rosbag2_bagfile_information");
	if (!info)
		return dao_error_set(err, -EINVAL, "%s: no rosbag2_bagfile_information mapping: not "
				     "a rosbag2 metadata.yaml", name);
	if (scalar(map_get(doc, info, "storage_identifier"), storage, cap) < 0)
		return dao_error_set(err, -EINVAL, "%s: no storage_identifier (sqlite3 or mcap)", name);
	yaml_node_t *files = map_get(doc, info, "relative_file_paths");
	if (!files || files->type != YAML_SEQUENCE_NODE ||
	    files->data.sequence.items.top == files->data.sequence.items.start)
		return dao_error_set(err, -EINVAL, "%s: no relative_file_paths list", name);
	if (files->data.sequence.items.top - files->data.sequence.items.start > 1)
		return dao_error_set(err, -ENOTSUP, "%s: the bag is split into %d files: play each "
				     "file on its own", name,
				     (int)(files->data.sequence.items.top -
					   files->data.sequence.items.start));
	char rel[1024];
	if (scalar(yaml_document_get_node(doc, *files->data.sequence.items.start), rel,
		   sizeof rel) < 0 || !rel[0] || rel[0] == '/' || strstr(rel, ".."))
		return dao_error_set(err, -EINVAL, "%s: relative_file_paths: not a file name inside "
				     "the directory", name);
	if ((size_t)snprintf(file, fcap, "%s/%s", dir, rel) >= fcap)
		return dao_error_set(err, -ENAMETOOLONG, "%s: the path of %s is too long", name, rel);
	return 0;
}

int dao_rosbag2_metadata(const char *dir, char *storage, size_t cap, char *file, size_t fcap,
			 struct dao_error *err)
{
	char name[4096];
	if ((size_t)snprintf(name, sizeof name, "%s/metadata.yaml", dir) >= sizeof name)
		return dao_error_set(err, -ENAMETOOLONG, "%s: the path is too long", dir);
	FILE *f = fopen(name, "rb");
	if (!f)
		return dao_error_set(err, -errno, "%s: cannot open: %s", name, strerror(errno));
	yaml_parser_t parser;
	yaml_document_t doc;
	int r;
	if (!yaml_parser_initialize(&parser)) {
		fclose(f);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	if (fseek(f, 0, SEEK_END) == 0 && ftell(f) > (long)MAX_METADATA) {
		r = dao_error_set(err, -EFBIG, "%s: larger than %u bytes", name, MAX_METADATA);
		goto out;
	}
	rewind(f);
	yaml_parser_set_input_file(&parser, f);
	if (!yaml_parser_load(&parser, &doc)) {
		r = dao_error_set(err, -EINVAL, "%s: line %zu: %s", name, parser.problem_mark.line + 1,
				  parser.problem ? parser.problem : "not YAML");
		goto out;
	}
	r = from_document(&doc, dir, name, storage, cap, file, fcap, err);
	yaml_document_delete(&doc);
out:
	yaml_parser_delete(&parser);
	fclose(f);
	return r;
}
