/* SPDX-License-Identifier: MIT */
/*
 * The camera poses a source reports through the public API
 * (dao_source_frame_pose), one line a frame, for test_cli_tf_poses.py:
 *   INDEX STAMP_NS pose TX TY TZ QX QY QZ QW
 *   INDEX STAMP_NS gap MESSAGE
 * then "description ..." and "warning ..." lines once; or "error CODE MESSAGE"
 * and exit 1 when the source cannot give poses (or cannot be read).  With
 * "again", a line "again", a seek back to frame 0 and every frame once more.
 * usage: source_poses URI [again]
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include <depthao/io.h>
#include <depthao/plugin.h>

static int fail(int code, const struct dao_error *err)
{
	printf("error %d %s\n", -code, err->message);
	return 1;
}

static int dump(struct dao_source *src)
{
	struct dao_error err;
	struct dao_source_frame f;
	int r, described = 0;
	while ((r = dao_source_read(src, &f, 1000, &err)) == 0) {
		struct dao_source_pose p = DAO_SOURCE_POSE_INIT;
		int pr = dao_source_frame_pose(src, &f, &p, &err);
		if (pr < 0 && pr != -ENOENT)
			return fail(pr, &err);
		if (pr == 0)
			printf("%" PRIu64 " %" PRIu64 " pose %.12f %.12f %.12f %.12f %.12f %.12f %.12f\n",
			       f.index, f.depth.timestamp_ns, p.translation[0], p.translation[1],
			       p.translation[2], p.rotation[0], p.rotation[1], p.rotation[2],
			       p.rotation[3]);
		else
			printf("%" PRIu64 " %" PRIu64 " gap %s\n", f.index, f.depth.timestamp_ns,
			       err.message);
		if (pr == 0 && !described++)
			printf("description %s\n", p.description);
		if (pr == 0 && p.warning[0])
			printf("warning %s\n", p.warning);
		dao_source_release(src, &f);
	}
	return r == DAO_SOURCE_EOS ? 0 : fail(r, &err);
}

int main(int argc, char **argv)
{
	struct dao_plugins *plugins;
	struct dao_source *src;
	struct dao_error err;
	int r;
	if (argc != 2 && (argc != 3 || strcmp(argv[2], "again"))) {
		fprintf(stderr, "usage: source_poses URI [again]\n");
		return 2;
	}
	if ((r = dao_plugins_load(&plugins, "", &err)) < 0)
		return fail(r, &err);
	if ((r = dao_source_open(plugins, argv[1], NULL, &src, &err)) < 0 ||
	    (r = dao_source_start(src, &err)) < 0) {
		dao_plugins_free(plugins);
		return fail(r, &err);
	}
	int status = dump(src);
	if (!status && argc == 3) {
		printf("again\n");
		status = (r = dao_source_seek(src, 0, &err)) < 0 ? fail(r, &err) : dump(src);
	}
	dao_source_close(src);
	dao_plugins_free(plugins);
	return status;
}
