/* SPDX-License-Identifier: MIT */
/* Shades one 16-bit depth PNG with ambient occlusion, using the installed libdepthao (the AO)
 * and libdepthao-io (the PNG files; its .pc brings libdepthao):
 *   cc shade_depth.c $(pkg-config --cflags --libs depthao-io) -o shade_depth
 *   ./shade_depth depth.png out.png [fx fy cx cy [metres_per_count]] */
#include <stdio.h>
#include <stdlib.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

static int number(const char *s, double *v) /* 0 if all of s is a number */
{
	char *end;
	*v = strtod(s, &end);
	return end == s || *end != '\0';
}

int main(int argc, char **argv)
{
	struct dao_error err = { 0 };
	struct dao_frame depth = DAO_FRAME_INIT, rgb = DAO_FRAME_INIT;
	struct dao_context *ctx = NULL;
	struct dao_camera cam;
	double k[5] = { 525, 525, 0, 0, 0.001 }; /* fx fy cx cy, metres per count */
	int status = 1;

	if (argc != 3 && argc != 7 && argc != 8) {
		fprintf(stderr, "usage: %s depth.png out.png [fx fy cx cy [metres_per_count]]\n", argv[0]);
		return 2;
	}
	for (int i = 3; i < argc; i++)
		if (number(argv[i], &k[i - 3])) {
			fprintf(stderr, "shade_depth: '%s' is not a number\n", argv[i]);
			return 2;
		}
	if (dao_png_read_depth(argv[1], (float)k[4], &depth, &err))
		goto fail;
	if (argc == 3) /* default: the principal point at the image centre */
		k[2] = (depth.width - 1) / 2.0, k[3] = (depth.height - 1) / 2.0;
	if (dao_camera_from_intrinsics(&cam, depth.width, depth.height, k[0], k[1], k[2], k[3], &err) ||
	    dao_context_create(&ctx, &cam, NULL, &err) || /* NULL: the default preset */
	    dao_frame_alloc(&rgb, DAO_PIXFMT_RGB24, depth.width, depth.height, &err) ||
	    dao_context_process(ctx, &depth, NULL, 0, NULL, &err) ||
	    dao_context_shade(ctx, &rgb, &err) ||
	    dao_png_write(argv[2], &rgb, &err))
		goto fail;
	status = 0;
	goto out;
fail:
	fprintf(stderr, "shade_depth: %s\n", err.message);
out:
	dao_context_destroy(ctx);
	dao_frame_free(&depth);
	dao_frame_free(&rgb);
	return status;
}
