/* SPDX-License-Identifier: MIT */
/*
 * The library's two file gates (depthao/output_file.h): dao_input_file_open()
 * takes regular files only, decided before reading (a FIFO is refused at once,
 * not waited on), with its size limit from fstat; dao_output_file_open()
 * never replaces a write-protected file, refuses a dangling symlink, writes
 * "-" to standard output.  Each message names the file and what it is.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

#include <depthao/oni.h>
#include <depthao/output_file.h>

static char dir[256];

static const char *at(const char *name)
{
	static char p[2][320];
	static int k;
	k ^= 1;
	snprintf(p[k], sizeof p[k], "%s/%s", dir, name);
	return p[k];
}

static void put(const char *path, const char *text, mode_t mode)
{
	FILE *f = fopen(path, "w");
	assert_non_null(f);
	fputs(text, f);
	fclose(f);
	assert_int_equal(chmod(path, mode), 0);
}

static void has(const struct dao_error *err, const char *needle)
{
	if (!strstr(err->message, needle))
		fail_msg("message '%s' lacks '%s'", err->message, needle);
}

static void test_input(void **state)
{
	(void)state;
	struct dao_error err;
	uint64_t size = 0;
	put(at("a.txt"), "hello", 0644);
	int fd = dao_input_file_open(at("a.txt"), "test file", 0, &size, &err);
	assert_true(fd >= 0);
	assert_int_equal(size, 5);
	char b[8];
	assert_int_equal(read(fd, b, sizeof b), 5); /* blocking, readable */
	close(fd);
	/* the limit: equal is fine, one byte more is refused unread */
	fd = dao_input_file_open(at("a.txt"), "test file", 5, NULL, &err);
	assert_true(fd >= 0);
	close(fd);
	assert_int_equal(dao_input_file_open(at("a.txt"), "test file", 4, NULL, &err), -EFBIG);
	has(&err, "test file '");
	has(&err, "is 5 bytes, larger than the 4");
	/* a FIFO without a writer: refused at once (opening it to read would block) */
	assert_int_equal(mkfifo(at("fifo"), 0600), 0);
	assert_int_equal(dao_input_file_open(at("fifo"), "camera file", 0, NULL, &err), -EINVAL);
	has(&err, "is a FIFO (named pipe), not a regular file");
	has(&err, at("fifo"));
	assert_int_equal(dao_input_file_open(dir, "camera file", 0, NULL, &err), -EINVAL);
	has(&err, "is a directory, not a regular file");
	assert_int_equal(dao_input_file_open("/dev/null", "camera file", 0, NULL, &err), -EINVAL);
	has(&err, "is a character device");
	assert_int_equal(dao_input_file_open(at("none"), "camera file", 0, NULL, &err), -ENOENT);
	has(&err, "No such file");
	/* a symlink to a file is that file */
	assert_int_equal(symlink("a.txt", at("link")), 0);
	fd = dao_input_file_open(at("link"), "test file", 0, &size, &err);
	assert_true(fd >= 0);
	close(fd);
}

/* Writes `text` through the output gate; the result of open (0 or < 0). */
static int write_out(const char *path, const char *text, struct dao_error *err)
{
	struct dao_output_file *o;
	int r = dao_output_file_open(&o, path, err);
	if (r < 0)
		return r;
	assert_int_equal(write(dao_output_file_fd(o), text, strlen(text)), (ssize_t)strlen(text));
	close(dao_output_file_fd(o));
	return dao_output_file_commit(o, err);
}

static void text_is(const char *path, const char *want)
{
	char b[64] = {0};
	FILE *f = fopen(path, "r");
	assert_non_null(f);
	assert_true(fread(b, 1, sizeof b - 1, f) < sizeof b);
	fclose(f);
	assert_string_equal(b, want);
}

static void test_output(void **state)
{
	(void)state;
	struct dao_error err;
	/* new and writable files are written and replaced */
	assert_int_equal(write_out(at("new.txt"), "one", &err), 0);
	text_is(at("new.txt"), "one");
	assert_int_equal(write_out(at("new.txt"), "two", &err), 0);
	text_is(at("new.txt"), "two");
	/* write-protected: never replaced, even by root (the rename could) */
	put(at("ro.txt"), "keep", 0444);
	assert_int_equal(write_out(at("ro.txt"), "lost", &err), -EACCES);
	has(&err, "is write-protected (mode 0444");
	has(&err, "chmod u+w");
	text_is(at("ro.txt"), "keep");
	/* through a symlink: the same rule at the file it points to */
	assert_int_equal(symlink("ro.txt", at("ro-link")), 0);
	assert_int_equal(write_out(at("ro-link"), "lost", &err), -EACCES);
	text_is(at("ro.txt"), "keep");
	assert_int_equal(symlink("new.txt", at("rw-link")), 0);
	assert_int_equal(write_out(at("rw-link"), "three", &err), 0);
	text_is(at("new.txt"), "three");
	struct stat st;
	assert_int_equal(lstat(at("rw-link"), &st), 0);
	assert_true(S_ISLNK(st.st_mode));
	/* a dangling symlink: refused, nothing created */
	assert_int_equal(symlink("nowhere.txt", at("dangling")), 0);
	assert_int_equal(write_out(at("dangling"), "x", &err), -ENOENT);
	has(&err, "symlink to something that does not exist");
	assert_int_equal(lstat(at("nowhere.txt"), &st), -1);
	assert_int_equal(lstat(at("dangling"), &st), 0);
	assert_true(S_ISLNK(st.st_mode));
	/* "-": standard output (a pipe here), never a file named "-" */
	int p[2];
	assert_int_equal(pipe(p), 0);
	int saved = dup(STDOUT_FILENO);
	assert_int_equal(dup2(p[1], STDOUT_FILENO), STDOUT_FILENO);
	close(p[1]);
	int r = write_out("-", "piped", &err);
	assert_int_equal(dup2(saved, STDOUT_FILENO), STDOUT_FILENO);
	close(saved);
	assert_int_equal(r, 0);
	char b[16] = {0};
	assert_int_equal(read(p[0], b, sizeof b - 1), 5);
	close(p[0]);
	assert_string_equal(b, "piped");
	assert_int_equal(lstat("-", &st), -1);
}

/* The recorder's overwrite follows the same rule; a recording never goes to "-". */
static void test_recorder(void **state)
{
	(void)state;
	struct dao_error err;
	struct dao_oni_writer *w = NULL;
	struct dao_oni_writer_options o = DAO_ONI_WRITER_OPTIONS_INIT;
	o.width = 8;
	o.height = 6;
	o.fps = 30;
	o.codec = DAO_ONI_CODEC_16ZT;
	o.pixel_format = DAO_ONI_PIXEL_DEPTH_1_MM;
	o.hfov = 1.0;
	o.vfov = 0.8;
	o.overwrite = 1;
	put(at("ro.oni"), "keep", 0444);
	assert_int_equal(dao_oni_writer_open(at("ro.oni"), &o, &w, &err), -EACCES);
	assert_null(w);
	has(&err, "is write-protected");
	text_is(at("ro.oni"), "keep");
	assert_int_equal(dao_oni_writer_open("-", &o, &w, &err), -EINVAL);
	has(&err, "standard output");
	struct stat st;
	assert_int_equal(lstat("-", &st), -1);
	/* a writable file is replaced with overwrite, as before */
	put(at("rw.oni"), "old", 0644);
	assert_int_equal(dao_oni_writer_open(at("rw.oni"), &o, &w, &err), 0);
	dao_oni_writer_abort(w); /* no frames: the file is removed */
}

int main(void)
{
	snprintf(dir, sizeof dir, "%s/dao-test-files-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	assert_non_null(mkdtemp(dir));
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_input),
		cmocka_unit_test(test_output),
		cmocka_unit_test(test_recorder),
	};
	int r = cmocka_run_group_tests(tests, NULL, NULL);
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return r;
}
