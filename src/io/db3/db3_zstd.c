/* SPDX-License-Identifier: MIT */
/*
 * rosbag2's zstd compression (db3_reader.h): a whole .db3.zstd file into a
 * temporary file (compression_mode file), one message (mode message).  Both
 * with a limit on what they decompress to: a small file that claims or
 * inflates to gigabytes (a zstd bomb) is stopped at the limit.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include "core/error_internal.h"
#include "db3/db3_reader.h"

uint64_t dao_db3_unzstd_limit(uint64_t compressed)
{
	uint64_t lim = compressed > DAO_DB3_UNZSTD_MAX / DAO_DB3_UNZSTD_RATIO
			       ? DAO_DB3_UNZSTD_MAX
			       : compressed * DAO_DB3_UNZSTD_RATIO;
	return lim < DAO_DB3_UNZSTD_MIN ? DAO_DB3_UNZSTD_MIN : lim;
}

/* Decompresses in into out up to limit bytes; 0, or negative with err set. */
static int unzstd_stream(FILE *in, FILE *out, const char *src, uint64_t limit,
			 struct dao_error *err)
{
	ZSTD_DCtx *dc = ZSTD_createDCtx();
	size_t icap = ZSTD_DStreamInSize(), ocap = ZSTD_DStreamOutSize(), last = 0;
	void *ib = malloc(icap), *ob = malloc(ocap);
	uint64_t total = 0;
	int r = !dc || !ib || !ob ? dao_error_set(err, -ENOMEM, "out of memory") : 0;
	size_t n;
	while (r == 0 && (n = fread(ib, 1, icap, in)) > 0) {
		ZSTD_inBuffer zi = {ib, n, 0};
		while (r == 0 && zi.pos < zi.size) {
			ZSTD_outBuffer zo = {ob, ocap, 0};
			last = ZSTD_decompressStream(dc, &zo, &zi);
			if (ZSTD_isError(last))
				r = dao_error_set(err, -EINVAL, "%s: not zstd data, or damaged: %s",
						  src, ZSTD_getErrorName(last));
			else if ((total += zo.pos) > limit)
				r = dao_error_set(err, -EOVERFLOW, "%s: decompresses to more than "
						  "%llu bytes (the limit for a file of its size): "
						  "refused (if it is genuine, decompress it with "
						  "zstd -d first)", src, (unsigned long long)limit);
			else if (zo.pos && fwrite(ob, 1, zo.pos, out) != zo.pos)
				r = dao_error_set(err, -errno, "%s: cannot write its decompressed "
						  "copy: %s", src, strerror(errno));
		}
	}
	if (r == 0 && ferror(in))
		r = dao_error_set(err, -EIO, "%s: cannot read: %s", src, strerror(errno));
	else if (r == 0 && last != 0)
		r = dao_error_set(err, -EINVAL, "%s: the zstd data is cut short", src);
	ZSTD_freeDCtx(dc);
	free(ib);
	free(ob);
	return r;
}

int dao_db3_unzstd_file(const char *src, char *tmp, size_t cap, struct dao_error *err)
{
	struct stat st;
	FILE *in = fopen(src, "rb");
	if (!in)
		return dao_error_set(err, -errno, "%s: cannot open: %s", src, strerror(errno));
	if (fstat(fileno(in), &st) < 0 || !S_ISREG(st.st_mode)) {
		fclose(in);
		return dao_error_set(err, -EINVAL, "%s: not a regular file", src);
	}
	const char *dir = getenv("TMPDIR");
	if ((size_t)snprintf(tmp, cap, "%s/depthao-db3-XXXXXX", dir && *dir ? dir : "/tmp") >= cap) {
		fclose(in);
		return dao_error_set(err, -ENAMETOOLONG, "TMPDIR is too long");
	}
	int fd = mkstemp(tmp);
	FILE *out = fd >= 0 ? fdopen(fd, "wb") : NULL;
	if (!out) {
		int e = errno;
		if (fd >= 0) {
			close(fd);
			unlink(tmp);
		}
		fclose(in);
		return dao_error_set(err, -e, "%s: cannot make a file to decompress it into in %s "
				     "(set TMPDIR to a directory with room): %s", src,
				     dir && *dir ? dir : "/tmp", strerror(e));
	}
	int r = unzstd_stream(in, out, src, dao_db3_unzstd_limit((uint64_t)st.st_size), err);
	if (fclose(out) != 0 && r == 0)
		r = dao_error_set(err, -errno, "%s: cannot write its decompressed copy: %s", src,
				  strerror(errno));
	fclose(in);
	if (r < 0)
		unlink(tmp);
	return r;
}

int dao_db3_unzstd_message(const uint8_t *in, uint64_t len, uint64_t max, uint8_t **buf,
			   uint64_t *cap, uint64_t *out, struct dao_error *err)
{
	unsigned long long size = ZSTD_getFrameContentSize(in, (size_t)len);
	if (size == ZSTD_CONTENTSIZE_ERROR)
		return dao_error_set(err, -EINVAL, "not a zstd frame");
	if (size == ZSTD_CONTENTSIZE_UNKNOWN)
		return dao_error_set(err, -EINVAL, "a zstd frame that does not say its size");
	if (size > max)
		return dao_error_set(err, -EFBIG, "decompresses to %llu bytes, over the limit of "
				     "%llu", size, (unsigned long long)max);
	if (size > *cap) {
		uint8_t *b = realloc(*buf, size ? (size_t)size : 1);
		if (!b)
			return dao_error_set(err, -ENOMEM, "out of memory");
		*buf = b;
		*cap = size;
	}
	size_t got = ZSTD_decompress(*buf, (size_t)size, in, (size_t)len);
	if (ZSTD_isError(got) || got != size)
		return dao_error_set(err, -EINVAL, "damaged zstd data: %s",
				     ZSTD_isError(got) ? ZSTD_getErrorName(got) : "another size");
	*out = got;
	return 0;
}
