/* SPDX-License-Identifier: MIT */
/* rosbag2's sqlite3 storage through libsqlite3 (db3_reader.h). */
#include "db3/db3_reader.h"

#include <errno.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"

#define MAX_NAME 1024 /* bytes of a topic's name, type or format */

struct msg_ref {
	int64_t id;
	uint64_t time;
};

struct topic {
	struct dao_db3_topic pub;
	int64_t id;
	char *strings; /* name, type, format, one allocation */
	struct msg_ref *msgs;
	uint32_t cap;
};

struct dao_db3 {
	char *path;
	sqlite3 *db;
	sqlite3_stmt *read;   /* data by id; not reset until the next read */
	uint64_t max_message;
	struct topic *topics;
	uint32_t ntopics;
};

const char *dao_db3_path(const struct dao_db3 *db)
{
	return db->path;
}

uint32_t dao_db3_topic_count(const struct dao_db3 *db)
{
	return db->ntopics;
}

const struct dao_db3_topic *dao_db3_topic(const struct dao_db3 *db, uint32_t i)
{
	return i < db->ntopics ? &db->topics[i].pub : NULL;
}

uint64_t dao_db3_message_time(const struct dao_db3 *db, uint32_t topic, uint32_t i)
{
	if (topic >= db->ntopics || i >= db->topics[topic].pub.message_count)
		return 0;
	return db->topics[topic].msgs[i].time;
}

void dao_db3_close(struct dao_db3 *db)
{
	if (!db)
		return;
	sqlite3_finalize(db->read);
	sqlite3_close(db->db);
	for (uint32_t i = 0; i < db->ntopics; i++) {
		free(db->topics[i].strings);
		free(db->topics[i].msgs);
	}
	free(db->topics);
	free(db->path);
	free(db);
}

/* "file:PATH?immutable=1" with the path's bytes that a URI reserves %-escaped. */
static char *file_uri(const char *path)
{
	size_t n = strlen(path);
	char *u = malloc(3 * n + 32);
	if (!u)
		return NULL;
	char *o = u + sprintf(u, "file:");
	for (const unsigned char *p = (const unsigned char *)path; *p; p++) {
		if (*p == '%' || *p == '?' || *p == '#' || *p < 0x20 || *p >= 0x7F)
			o += sprintf(o, "%%%02X", *p);
		else
			*o++ = (char)*p;
	}
	strcpy(o, "?immutable=1");
	return u;
}

/* The file exists and is a SQLite database: 0, or an error saying what it is instead. */
static int check_file(const char *path, struct dao_error *err)
{
	FILE *f = fopen(path, "rb");
	char magic[16] = {0};
	if (!f)
		return dao_error_set(err, -errno, "%s: cannot open: %s", path, strerror(errno));
	size_t n = fread(magic, 1, sizeof magic, f);
	fclose(f);
	if (n < sizeof magic || memcmp(magic, "SQLite format 3", 16))
		return dao_error_set(err, -EINVAL, "%s: not a rosbag2 .db3 file (no SQLite 3 header)",
				     path);
	return 0;
}

static int sql_error(struct dao_db3 *db, const char *what, struct dao_error *err)
{
	int code = sqlite3_errcode(db->db);
	int r = code == SQLITE_NOMEM ? -ENOMEM : code == SQLITE_ERROR ? -EINVAL : -EIO;
	return dao_error_set(err, r, "%s: %s: %s", db->path, what, sqlite3_errmsg(db->db));
}

static int has_table(struct dao_db3 *db, const char *name, struct dao_error *err)
{
	sqlite3_stmt *st;
	if (sqlite3_prepare_v2(db->db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND "
				       "name = ?1", -1, &st, NULL) != SQLITE_OK)
		return sql_error(db, "reading the schema", err);
	sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
	int rc = sqlite3_step(st);
	sqlite3_finalize(st);
	if (rc == SQLITE_ROW)
		return 0;
	if (rc != SQLITE_DONE)
		return sql_error(db, "reading the schema", err);
	return dao_error_set(err, -EINVAL, "%s: no table '%s': not a rosbag2 database (its tables "
			     "are topics and messages)", db->path, name);
}

/* A TEXT column of a topics row, copied to o (at most MAX_NAME bytes). */
static int topic_text(struct dao_db3 *db, sqlite3_stmt *st, int col, const char *name,
		      int64_t id, char **o, struct dao_error *err)
{
	int n = sqlite3_column_bytes(st, col);
	const unsigned char *t = sqlite3_column_text(st, col);
	if (sqlite3_column_type(st, col) != SQLITE_TEXT || !t || n > MAX_NAME ||
	    memchr(t, 0, (size_t)n))
		return dao_error_set(err, -EINVAL, "%s: table topics, id %lld: %s is not a text of "
				     "at most %d bytes", db->path, (long long)id, name, MAX_NAME);
	memcpy(*o, t, (size_t)n);
	(*o)[n] = 0;
	*o += n + 1;
	return 0;
}

static int add_topic(struct dao_db3 *db, sqlite3_stmt *st, struct dao_error *err)
{
	if (sqlite3_column_type(st, 0) != SQLITE_INTEGER)
		return dao_error_set(err, -EINVAL, "%s: table topics: an id that is not an integer",
				     db->path);
	int64_t id = sqlite3_column_int64(st, 0);
	if (db->ntopics >= DAO_DB3_MAX_TOPICS)
		return dao_error_set(err, -EFBIG, "%s: more than %u topics", db->path,
				     DAO_DB3_MAX_TOPICS);
	if (db->ntopics && db->topics[db->ntopics - 1].id == id)
		return dao_error_set(err, -EINVAL, "%s: table topics: id %lld twice", db->path,
				     (long long)id);
	struct topic *t = &db->topics[db->ntopics];
	memset(t, 0, sizeof(*t));
	t->id = id;
	if (!(t->strings = malloc(3 * (MAX_NAME + 1))))
		return dao_error_set(err, -ENOMEM, "out of memory");
	db->ntopics++;
	char *o = t->strings;
	int r;
	t->pub.name = o;
	if ((r = topic_text(db, st, 1, "name", id, &o, err)) < 0)
		return r;
	t->pub.type = o;
	if ((r = topic_text(db, st, 2, "type", id, &o, err)) < 0)
		return r;
	t->pub.serialization_format = o;
	return topic_text(db, st, 3, "serialization_format", id, &o, err);
}

static int read_topics(struct dao_db3 *db, struct dao_error *err)
{
	sqlite3_stmt *st;
	int rc, r = 0;
	if (sqlite3_prepare_v2(db->db, "SELECT id, name, type, serialization_format FROM topics "
				       "ORDER BY id", -1, &st, NULL) != SQLITE_OK)
		return sql_error(db, "table topics (id, name, type, serialization_format)", err);
	if (!(db->topics = calloc(DAO_DB3_MAX_TOPICS, sizeof(*db->topics)))) {
		sqlite3_finalize(st);
		return dao_error_set(err, -ENOMEM, "out of memory");
	}
	while (r == 0 && (rc = sqlite3_step(st)) == SQLITE_ROW)
		r = add_topic(db, st, err);
	if (r == 0 && rc != SQLITE_DONE)
		r = sql_error(db, "reading table topics", err);
	sqlite3_finalize(st);
	return r;
}

static struct topic *topic_by_id(struct dao_db3 *db, int64_t id)
{
	uint32_t lo = 0, hi = db->ntopics;
	while (lo < hi) {
		uint32_t mid = lo + (hi - lo) / 2;
		if (db->topics[mid].id < id)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo < db->ntopics && db->topics[lo].id == id ? &db->topics[lo] : NULL;
}

static int add_message(struct dao_db3 *db, sqlite3_stmt *st, uint64_t *total,
		       struct dao_error *err)
{
	if (sqlite3_column_type(st, 0) != SQLITE_INTEGER)
		return dao_error_set(err, -EINVAL, "%s: table messages: an id that is not an integer",
				     db->path);
	for (int c = 1; c < 3; c++)
		if (sqlite3_column_type(st, c) != SQLITE_INTEGER)
			return dao_error_set(err, -EINVAL, "%s: table messages, id %lld: %s is not an "
					     "integer", db->path, (long long)sqlite3_column_int64(st, 0),
					     c == 1 ? "topic_id" : "timestamp");
	int64_t id = sqlite3_column_int64(st, 0), tid = sqlite3_column_int64(st, 1);
	int64_t ts = sqlite3_column_int64(st, 2);
	struct topic *t = topic_by_id(db, tid);
	if (!t)
		return dao_error_set(err, -EINVAL, "%s: table messages, id %lld: topic_id %lld is "
				     "not in table topics", db->path, (long long)id, (long long)tid);
	if (++*total > DAO_DB3_MAX_MESSAGES)
		return dao_error_set(err, -EFBIG, "%s: more than %u messages", db->path,
				     DAO_DB3_MAX_MESSAGES);
	if (t->pub.message_count == t->cap) {
		uint32_t cap = t->cap ? 2 * t->cap : 256;
		struct msg_ref *m = realloc(t->msgs, (size_t)cap * sizeof(*m));
		if (!m)
			return dao_error_set(err, -ENOMEM, "out of memory");
		t->msgs = m;
		t->cap = cap;
	}
	t->msgs[t->pub.message_count++] = (struct msg_ref){id, ts < 0 ? 0 : (uint64_t)ts};
	return 0;
}

/* Every message's id and time, by topic, in timestamp order (the timestamp index). */
static int read_index(struct dao_db3 *db, struct dao_error *err)
{
	sqlite3_stmt *st;
	uint64_t total = 0;
	int rc, r = 0;
	if (sqlite3_prepare_v2(db->db, "SELECT id, topic_id, timestamp FROM messages ORDER BY "
				       "timestamp, id", -1, &st, NULL) != SQLITE_OK)
		return sql_error(db, "table messages (id, topic_id, timestamp, data)", err);
	while (r == 0 && (rc = sqlite3_step(st)) == SQLITE_ROW)
		r = add_message(db, st, &total, err);
	if (r == 0 && rc != SQLITE_DONE)
		r = sql_error(db, "reading table messages", err);
	sqlite3_finalize(st);
	if (r == 0 && sqlite3_prepare_v2(db->db, "SELECT typeof(data), length(data), data FROM "
					 "messages WHERE id = ?1", -1, &db->read, NULL) != SQLITE_OK)
		r = sql_error(db, "table messages (data)", err);
	return r;
}

int dao_db3_open(const char *path, uint64_t max_message, struct dao_db3 **out,
		 struct dao_error *err)
{
	struct dao_db3 *db = calloc(1, sizeof(*db));
	char *uri = NULL;
	int r;
	*out = NULL;
	if (!db || !(db->path = strdup(path)) || !(uri = file_uri(path))) {
		r = dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	db->max_message = max_message;
	if ((r = check_file(path, err)) < 0)
		goto fail;
	if (sqlite3_open_v2(uri, &db->db, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, NULL) !=
	    SQLITE_OK) {
		r = db->db ? sql_error(db, "cannot open", err)
			   : dao_error_set(err, -ENOMEM, "out of memory");
		goto fail;
	}
	if ((r = has_table(db, "topics", err)) < 0 || (r = has_table(db, "messages", err)) < 0 ||
	    (r = read_topics(db, err)) < 0 || (r = read_index(db, err)) < 0)
		goto fail;
	free(uri);
	*out = db;
	return 0;
fail:
	free(uri);
	dao_db3_close(db);
	return r;
}

int dao_db3_read_message(struct dao_db3 *db, uint32_t topic, uint32_t i, const uint8_t **data,
			 uint64_t *len, uint64_t *log_time, struct dao_error *err)
{
	static const uint8_t empty[1];
	if (topic >= db->ntopics || i >= db->topics[topic].pub.message_count)
		return dao_error_set(err, -EINVAL, "%s: no message %u of topic %u", db->path, i,
				     topic);
	const struct msg_ref *m = &db->topics[topic].msgs[i];
	sqlite3_reset(db->read);
	sqlite3_bind_int64(db->read, 1, m->id);
	int rc = sqlite3_step(db->read);
	if (rc != SQLITE_ROW)
		return rc == SQLITE_DONE ? dao_error_set(err, -EIO, "%s: message id %lld is gone",
							 db->path, (long long)m->id)
					 : sql_error(db, "reading a message", err);
	const char *type = (const char *)sqlite3_column_text(db->read, 0);
	if (!type || strcmp(type, "blob"))
		return dao_error_set(err, -EINVAL, "%s: table messages, id %lld: data is %s, not a "
				     "blob", db->path, (long long)m->id, type ? type : "?");
	int64_t n = sqlite3_column_int64(db->read, 1);
	if (n < 0 || (uint64_t)n > db->max_message)
		return dao_error_set(err, -EFBIG, "%s: table messages, id %lld: %lld bytes of data, "
				     "over the limit of %llu", db->path, (long long)m->id,
				     (long long)n, (unsigned long long)db->max_message);
	const uint8_t *d = sqlite3_column_blob(db->read, 2);
	if (!d && n > 0)
		return sql_error(db, "reading a message's data", err);
	if (sqlite3_column_bytes(db->read, 2) != n)
		return dao_error_set(err, -EIO, "%s: table messages, id %lld: the data changed size",
				     db->path, (long long)m->id);
	*data = d ? d : empty;
	*len = (uint64_t)n;
	if (log_time)
		*log_time = m->time;
	return 0;
}
