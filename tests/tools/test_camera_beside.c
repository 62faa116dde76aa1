/* SPDX-License-Identifier: MIT */
/*
 * tools/common/camera_file.c's camera_file_beside (depthao process and
 * depthaod both find the intrinsics of PNG input with it): camera.json before
 * camera.yaml, in a directory or in a .png file's (any case, also relative to
 * the working directory); none beside a recording or a path that does not
 * exist, and none when the path does not fit; a camera.json that cannot be
 * read is reported (-1, EACCES), not passed over for camera.yaml (as root,
 * whom permissions do not stop, checked in a child that became nobody).
 */
#include <errno.h>
#include <limits.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

#include "common/camera_file.h"

static void touch(const char *dir, const char *name)
{
	char p[PATH_MAX];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	FILE *f = fopen(p, "w");
	assert_non_null(f);
	fputs("x\n", f);
	fclose(f);
}

static void drop(const char *dir, const char *name)
{
	char p[PATH_MAX];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	unlink(p);
}

/* camera_file_beside(path) finds `want` ("" for none) */
static void expect(const char *path, const char *want)
{
	char out[PATH_MAX];
	const int r = camera_file_beside(path, out, sizeof out);
	if (!*want) {
		if (r)
			fail_msg("%s: found %s, expected none", path, out);
		return;
	}
	if (r != 1 || strcmp(out, want) != 0)
		fail_msg("%s: %s, expected %s", path, r == 1 ? out : "none", want);
}

static void test_beside(void **state)
{
	(void)state;
	char dir[] = "/tmp/depthao-camera-beside-XXXXXX";
	assert_non_null(mkdtemp(dir));
	char json[PATH_MAX], yaml[PATH_MAX], png[PATH_MAX], png_up[PATH_MAX], oni[PATH_MAX];
	snprintf(json, sizeof json, "%s/camera.json", dir);
	snprintf(yaml, sizeof yaml, "%s/camera.yaml", dir);
	snprintf(png, sizeof png, "%s/000001.png", dir);
	snprintf(png_up, sizeof png_up, "%s/DEPTH.PNG", dir);
	snprintf(oni, sizeof oni, "%s/session.oni", dir);
	touch(dir, "000001.png");
	touch(dir, "DEPTH.PNG");
	touch(dir, "session.oni");

	expect(dir, ""); /* nothing there yet */
	touch(dir, "camera.yaml");
	expect(dir, yaml); /* a ROS CameraInfo alone */
	expect(png, yaml);
	touch(dir, "camera.json");
	expect(dir, json); /* JSON first */
	expect(png, json);
	expect(png_up, json);
	expect(oni, ""); /* never beside a recording */
	char missing[PATH_MAX];
	snprintf(missing, sizeof missing, "%s/gone.png", dir);
	expect(missing, ""); /* a path that is not there */
	expect("", "");
	expect(NULL, "");
	char out[8], out2[PATH_MAX] = "";
	assert_int_equal(camera_file_beside(dir, out, sizeof out), 0); /* does not fit */

	/* relative to the working directory: "./camera.json" */
	char cwd[PATH_MAX];
	assert_non_null(getcwd(cwd, sizeof cwd));
	assert_int_equal(chdir(dir), 0);
	expect("000001.png", "./camera.json");
	expect(".", "./camera.json");
	drop(dir, "camera.json");
	expect("000001.png", "./camera.yaml");
	assert_int_equal(chdir(cwd), 0);

	/* unreadable: reported, even with camera.yaml beside it */
	touch(dir, "camera.json");
	assert_int_equal(chmod(json, 0), 0);
	assert_int_equal(chmod(dir, 0755), 0);
	const pid_t pid = fork();
	assert_true(pid >= 0);
	if (pid == 0) { /* as nobody if root (65534), then the check; the exit status says */
		if (geteuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0))
			_exit(2);
		errno = 0;
		const int r = camera_file_beside(dir, out2, sizeof out2);
		_exit(r == -1 && errno == EACCES && strcmp(out2, json) == 0 ? 0 : 1);
	}
	int status = 0;
	assert_int_equal(waitpid(pid, &status, 0), pid);
	assert_true(WIFEXITED(status));
	assert_int_equal(WEXITSTATUS(status), 0);
	drop(dir, "camera.json");
	drop(dir, "camera.yaml");
	drop(dir, "000001.png");
	drop(dir, "DEPTH.PNG");
	drop(dir, "session.oni");
	assert_int_equal(rmdir(dir), 0);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_beside),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
