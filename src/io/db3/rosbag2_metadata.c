/* SPDX-License-Identifier: MIT */
/* A rosbag2 directory's metadata.yaml, through libyaml (db3_reader.h). */
#include "db3/db3_reader.h"

#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
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

/* One of relative_file_paths joined to dir, into a new string; a message on failure. */
static int file_path(yaml_document_t *doc, yaml_node_item_t item, const char *dir,
		     const char *name, char **out, struct dao_error *err)
{
	char rel[1024], path[4096];
	if (scalar(yaml_document_get_node(doc, item), rel, sizeof rel) < 0 || !rel[0] ||
	    rel[0] == '/' || strstr(rel, ".."))
		return dao_error_set(err, -EINVAL, "%s: relative_file_paths: not a file name inside "
				     "the directory", name);
	if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, rel) >= sizeof path)
		return dao_error_set(err, -ENAMETOOLONG, "%s: the path of %s is too long", name, rel);
	if (!(*out = strdup(path)))
		return dao_error_set(err, -ENOMEM, "out of memory");
	return 0;
}

/* The storage, compression and files of a loaded document; a message in err on failure. */
static int from_document(yaml_document_t *doc, const char *dir, const char *name,
			 struct dao_rosbag2_meta *m, struct dao_error *err)
{
	yaml_node_t *info = map_get(doc, yaml_document_get_root_node(doc),
				    "rosbag2_bagfile_information");
	if (!info)
		return dao_error_set(err, -EINVAL, "%s: no rosbag2_bagfile_information mapping: not "
				     "a rosbag2 metadata.yaml", name);
	if (scalar(map_get(doc, info, "storage_identifier"), m->storage, sizeof m->storage) < 0)
		return dao_error_set(err, -EINVAL, "%s: no storage_identifier (sqlite3 or mcap)", name);
	/* absent in bags older than compression (empty: none) */
	yaml_node_t *cf = map_get(doc, info, "compression_format"),
		    *cm = map_get(doc, info, "compression_mode");
	if ((cf && scalar(cf, m->compression_format, sizeof m->compression_format) < 0) ||
	    (cm && scalar(cm, m->compression_mode, sizeof m->compression_mode) < 0))
		return dao_error_set(err, -EINVAL, "%s: compression_format or compression_mode is "
				     "not a short text", name);
	yaml_node_t *files = map_get(doc, info, "relative_file_paths");
	if (!files || files->type != YAML_SEQUENCE_NODE ||
	    files->data.sequence.items.top == files->data.sequence.items.start)
		return dao_error_set(err, -EINVAL, "%s: no relative_file_paths list", name);
	const ptrdiff_t n = files->data.sequence.items.top - files->data.sequence.items.start;
	if (n > DAO_ROSBAG2_MAX_FILES)
		return dao_error_set(err, -EFBIG, "%s: the bag is split into %td files, more than "
				     "the %d depthao plays", name, n, DAO_ROSBAG2_MAX_FILES);
	if (!(m->files = calloc((size_t)n, sizeof *m->files)))
		return dao_error_set(err, -ENOMEM, "out of memory");
	for (ptrdiff_t i = 0; i < n; i++) {
		int r = file_path(doc, files->data.sequence.items.start[i], dir, name, &m->files[i],
				  err);
		if (r < 0)
			return r;
		m->file_count = (uint32_t)i + 1;
	}
	return 0;
}

void dao_rosbag2_meta_free(struct dao_rosbag2_meta *m)
{
	for (uint32_t i = 0; m->files && i < m->file_count; i++)
		free(m->files[i]);
	free(m->files);
	memset(m, 0, sizeof *m);
}

int dao_rosbag2_metadata(const char *dir, struct dao_rosbag2_meta *m, struct dao_error *err)
{
	memset(m, 0, sizeof *m);
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
	r = from_document(&doc, dir, name, m, err);
	yaml_document_delete(&doc);
	if (r < 0)
		dao_rosbag2_meta_free(m);
out:
	yaml_parser_delete(&parser);
	fclose(f);
	return r;
}
