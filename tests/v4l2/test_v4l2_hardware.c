/* SPDX-License-Identifier: MIT */
/*
 * A real V4L2 depth camera, when one is attached: it is listed, streams
 * frames of the negotiated size with plausible depth.  Exit 77 (SKIP) when
 * there is none (this machine's kernel has no V4L2 at all).
 */
#include <stdio.h>
#include <string.h>

#include "v4l2_capture.h"

static int count(void *user, const struct dao_device_entry *e)
{
	(void)e;
	return ++*(int *)user;
}

static void on_device(void *user, const struct dao_device_entry *e)
{
	count(user, e);
	printf("found %s: %s (%s)\n", e->uri, e->name, e->detail);
}

int main(void)
{
	const struct v4l2_io *io = v4l2_io_system();
	struct dao_error err = {0};
	int n = 0;
	v4l2cap_list(io, on_device, &n, &err);
	if (n == 0) {
		printf("no V4L2 depth camera here; skipped\n");
		return 77;
	}
	struct dao_source_options o = {.size = sizeof(struct dao_source_options)};
	struct v4l2cap *c;
	if (v4l2cap_open(io, "any", &o, &c, &err) || v4l2cap_start(c, &err)) {
		printf("FAIL: %s\n", err.message);
		return 1;
	}
	struct dao_source_info in;
	memset(&in, 0, sizeof in);
	v4l2cap_info(c, &in);
	printf("%s\n", in.description);
	int frames = 0, valid = 0;
	for (int tries = 0; tries < 60 && frames < 10; tries++) {
		struct dao_source_frame f;
		int r = v4l2cap_read(c, &f, 1000, &err);
		if (r < 0 && r != -11) {
			printf("FAIL: %s\n", err.message);
			v4l2cap_close(c);
			return 1;
		}
		if (r == 0) {
			frames++;
			const uint16_t *d = f.depth.data;
			for (size_t i = 0; i < (size_t)in.width * in.height; i++)
				valid += d[i] != 0;
		}
	}
	v4l2cap_close(c);
	printf("%d frames, %d pixels with depth\n", frames, valid);
	return frames == 10 && valid > 0 ? 0 : 1;
}
