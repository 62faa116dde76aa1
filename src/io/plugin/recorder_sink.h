/* SPDX-License-Identifier: MIT */
#ifndef DAO_PLUGIN_RECORDER_SINK_H
#define DAO_PLUGIN_RECORDER_SINK_H

/*
 * What the recording sinks (oni_sink.c, mcap_sink.c) share: the path from
 * the URI, the check of its directory, the host's log, and the rule that a
 * recording never replaces a file (output_path.h: PATH-1.EXT, PATH-2.EXT,
 * ... instead, said in the host's log, unless the URI asks to overwrite).
 * Every message starts with the sink's scheme ("oni: ...").
 */
#include <depthao/plugin.h>

struct dao_recorder {
	const char *scheme;         /* "oni", "mcap": the messages' prefix, the file's extension */
	char *path;                 /* as given */
	char *file;                 /* the numbered name written instead of path, or NULL */
	struct dao_sink_host host;  /* from attach_host; zero without a host */
};

/*
 * The path: the first n bytes of uri; -EINVAL when there is none ("no output
 * file given; use SCHEME:PATH.SCHEME" then `help`), -ENOMEM.
 */
int dao_recorder_init(struct dao_recorder *r, const char *scheme, const char *uri, size_t n,
		      const char *help, struct dao_error *err);
void dao_recorder_free(struct dao_recorder *r);

/*
 * The path is a file or nothing (not a directory; with regular_only, not a
 * device, FIFO or socket either), in a directory that exists and is writable.
 */
int dao_recorder_check_dir(const struct dao_recorder *r, int regular_only,
			   struct dao_error *err);

/* A line in the host's log (nothing without a host). */
void dao_recorder_note(const struct dao_recorder *r, int level, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/*
 * open(ctx, name, overwrite, err) at the path (overwrite as asked), then at
 * the first free numbered name (never overwriting) while it says -EEXIST;
 * the name used is noted in the log and kept in r->file.
 */
typedef int (*dao_recorder_open_fn)(void *ctx, const char *name, int overwrite,
				    struct dao_error *err);
int dao_recorder_open_numbered(struct dao_recorder *r, int overwrite, dao_recorder_open_fn open,
			       void *ctx, struct dao_error *err);

/* The file being written: the numbered name, else the path. */
const char *dao_recorder_file(const struct dao_recorder *r);
/* Forgets the numbered name (the file was removed, or is made again). */
void dao_recorder_forget_file(struct dao_recorder *r);

#endif
