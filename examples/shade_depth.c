/* SPDX-License-Identifier: MIT */
/* Shades one 16-bit depth PNG with ambient occlusion, using the installed libdepthao:
 *   cc shade_depth.c $(pkg-config --cflags --libs depthao) -o shade_depth
 *   ./shade_depth depth.png shaded.png [fx fy cx cy] */
#include <stdio.h>
#include <stdlib.h>

#include <depthao/depthao.h>

int main(int argc, char **argv)
{
	if (argc != 3 && argc != 7) {
		fprintf(stderr, "usage: %s depth.png out.png [fx fy cx cy]\n", argv[0]);
		return 2;
	}
	struct dao_error err;
	struct dao_frame depth = { 0 }, rgb = { 0 };
	struct dao_context *ctx = NULL;
	struct dao_camera cam;
	int status = 1;

	if (dao_png_read_depth(argv[1], 0.001f, &depth, &err)) /* millimetres */
		goto fail;
	double fx = 525, fy = 525, cx = (depth.width - 1) / 2.0, cy = (depth.height - 1) / 2.0;
	if (argc == 7)
		fx = atof(argv[3]), fy = atof(argv[4]), cx = atof(argv[5]), cy = atof(argv[6]);
	if (dao_camera_from_intrinsics(&cam, depth.width, depth.height, fx, fy, cx, cy, &err) ||
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
