/* SPDX-License-Identifier: MIT */
/*
 * A split rosbag2 bag (several .db3 files listed by its metadata.yaml) as one
 * reader (db3_reader.h): topics matched by name across the files, a topic's
 * message i found through the cumulative counts of the files before it.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"
#include "db3/db3_reader.h"

struct dao_db3_multi {
	uint32_t nfiles, ntopics;
	struct dao_db3 **db;
	struct dao_db3_topic *topics; /* names and types: those of the first file with it */
	int32_t *local;               /* [topic * nfiles + file]: its index there, or -1 */
	uint32_t *first;              /* [topic * (nfiles + 1) + file]: its messages before */
	char *path;
	uint64_t zstd_max; /* messages compressed one by one: their limit; 0 = not */
	uint8_t *buf;      /* a decompressed message */
	uint64_t cap;
};

void dao_db3_multi_close(struct dao_db3_multi *m)
{
	if (!m)
		return;
	for (uint32_t f = 0; f < m->nfiles; f++)
		dao_db3_close(m->db[f]);
	free(m->db);
	free(m->topics);
	free(m->local);
	free(m->first);
	free(m->buf);
	free(m->path);
	free(m);
}

static int32_t find_topic(const struct dao_db3_multi *m, const char *name)
{
	for (uint32_t t = 0; t < m->ntopics; t++)
		if (!strcmp(m->topics[t].name, name))
			return (int32_t)t;
	return -1;
}

/* The topics of every file, merged by name; -EINVAL when a name changes its type. */
static int merge_topics(struct dao_db3_multi *m, struct dao_error *err)
{
	for (uint32_t f = 0; f < m->nfiles; f++)
		for (uint32_t i = 0; i < dao_db3_topic_count(m->db[f]); i++) {
			const struct dao_db3_topic *dt = dao_db3_topic(m->db[f], i);
			int32_t t = find_topic(m, dt->name);
			if (t < 0) {
				if (m->ntopics >= DAO_DB3_MAX_TOPICS)
					return dao_error_set(err, -EFBIG, "%s: more than %u topics",
							     m->path, DAO_DB3_MAX_TOPICS);
				t = (int32_t)m->ntopics++;
				m->topics[t] = *dt;
				m->topics[t].message_count = 0;
				for (uint32_t g = 0; g < m->nfiles; g++)
					m->local[(size_t)t * m->nfiles + g] = -1;
			} else if (strcmp(m->topics[t].type, dt->type) ||
				   strcmp(m->topics[t].serialization_format,
					  dt->serialization_format)) {
				return dao_error_set(err, -EINVAL, "%s: topic %s is %s (%s) in %s but "
						     "%s (%s) in %s: not one bag", m->path,
						     dt->name, m->topics[t].type,
						     m->topics[t].serialization_format,
						     dao_db3_path(m->db[0]), dt->type,
						     dt->serialization_format,
						     dao_db3_path(m->db[f]));
			}
			m->local[(size_t)t * m->nfiles + f] = (int32_t)i;
		}
	return 0;
}

/* The cumulative counts, and the files in time order topic by topic. */
static int count_messages(struct dao_db3_multi *m, struct dao_error *err)
{
	uint64_t total = 0;
	for (uint32_t t = 0; t < m->ntopics; t++) {
		uint32_t *first = m->first + (size_t)t * (m->nfiles + 1);
		uint64_t n = 0, last = 0;
		for (uint32_t f = 0; f < m->nfiles; f++) {
			first[f] = (uint32_t)n;
			const int32_t l = m->local[(size_t)t * m->nfiles + f];
			const uint32_t c = l < 0 ? 0 : dao_db3_topic(m->db[f], (uint32_t)l)->message_count;
			if (c && dao_db3_message_time(m->db[f], (uint32_t)l, 0) < last)
				return dao_error_set(err, -EINVAL, "%s: %s starts before the file "
						     "before it ends on topic %s: the files are "
						     "not in the order of their messages' times",
						     m->path, dao_db3_path(m->db[f]), m->topics[t].name);
			if (c)
				last = dao_db3_message_time(m->db[f], (uint32_t)l, c - 1);
			n += c;
		}
		total += n;
		if (total > DAO_DB3_MAX_MESSAGES)
			return dao_error_set(err, -EFBIG, "%s: more than %u messages in its files",
					     m->path, DAO_DB3_MAX_MESSAGES);
		first[m->nfiles] = (uint32_t)n;
		m->topics[t].message_count = (uint32_t)n;
	}
	return 0;
}

int dao_db3_multi_open(struct dao_db3 **dbs, uint32_t n, const char *path,
		       struct dao_db3_multi **out, struct dao_error *err)
{
	uint32_t cap = 0;
	for (uint32_t f = 0; f < n; f++)
		cap += dao_db3_topic_count(dbs[f]);
	struct dao_db3_multi *m = calloc(1, sizeof *m);
	if (m) {
		m->nfiles = n;
		m->db = malloc(n * sizeof *m->db);
		m->path = strdup(path);
	}
	if (!m || !m->db || !m->path) {
		for (uint32_t f = 0; f < n; f++)
			dao_db3_close(dbs[f]);
		if (m)
			m->nfiles = 0;
		dao_db3_multi_close(m);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	memcpy(m->db, dbs, n * sizeof *m->db);
	m->topics = calloc(cap + 1, sizeof *m->topics);
	m->local = calloc(((size_t)cap + 1) * n, sizeof *m->local);
	m->first = calloc(((size_t)cap + 1) * (n + 1), sizeof *m->first);
	int r = !m->topics || !m->local || !m->first ? dao_error_set(err, -ENOMEM, "out of memory")
						       : merge_topics(m, err);
	if (r == 0)
		r = count_messages(m, err);
	if (r < 0) {
		dao_db3_multi_close(m);
		return r;
	}
	*out = m;
	return 0;
}

const char *dao_db3_multi_path(const struct dao_db3_multi *m)
{
	return m->path;
}

uint32_t dao_db3_multi_topic_count(const struct dao_db3_multi *m)
{
	return m->ntopics;
}

const struct dao_db3_topic *dao_db3_multi_topic(const struct dao_db3_multi *m, uint32_t i)
{
	return i < m->ntopics ? &m->topics[i] : NULL;
}

/* The file holding message i of topic t (t and i valid), and its index there. */
static uint32_t locate(const struct dao_db3_multi *m, uint32_t t, uint32_t i, uint32_t *local)
{
	const uint32_t *first = m->first + (size_t)t * (m->nfiles + 1);
	uint32_t lo = 0, hi = m->nfiles; /* first[lo] <= i < first[hi] */
	while (hi - lo > 1) {
		const uint32_t mid = lo + (hi - lo) / 2;
		if (first[mid] <= i)
			lo = mid;
		else
			hi = mid;
	}
	*local = i - first[lo];
	return lo;
}

int dao_db3_multi_read_message(struct dao_db3_multi *m, uint32_t topic, uint32_t i,
			       const uint8_t **data, uint64_t *len, uint64_t *log_time,
			       struct dao_error *err)
{
	if (topic >= m->ntopics || i >= m->topics[topic].message_count)
		return dao_error_set(err, -EINVAL, "%s: no message %u of topic %u", m->path, i,
				     topic);
	uint32_t k;
	const uint32_t f = locate(m, topic, i, &k);
	int r = dao_db3_read_message(m->db[f], (uint32_t)m->local[(size_t)topic * m->nfiles + f],
				     k, data, len, log_time, err);
	if (r < 0 || !m->zstd_max)
		return r;
	struct dao_error e;
	if ((r = dao_db3_unzstd_message(*data, *len, m->zstd_max, &m->buf, &m->cap, len, &e)) < 0)
		return dao_error_set(err, r, "%s: message %u of '%s' (zstd, compression_mode "
				     "message): %s", m->path, i, m->topics[topic].name, e.message);
	*data = m->buf;
	return 0;
}

void dao_db3_multi_zstd_messages(struct dao_db3_multi *m, uint64_t max)
{
	m->zstd_max = max;
}

uint64_t dao_db3_multi_message_time(const struct dao_db3_multi *m, uint32_t topic, uint32_t i)
{
	if (topic >= m->ntopics || i >= m->topics[topic].message_count)
		return 0;
	uint32_t k;
	const uint32_t f = locate(m, topic, i, &k);
	return dao_db3_message_time(m->db[f], (uint32_t)m->local[(size_t)topic * m->nfiles + f], k);
}
