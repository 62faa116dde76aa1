/* SPDX-License-Identifier: MIT */
/*
 * The AO core on its own, as someone embedding it builds it:
 *   cc core_only.c $(pkg-config --cflags --libs depthao)
 * (libdepthao alone, no libdepthao-io, no container library; check_example.sh).
 * A wall at 2 m with a box 0.5 m in front of it: the open wall must stay open
 * (AO near 1) and the wall beside the box must be occluded.  Prints the two means.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <depthao/depthao.h>

#define W 160
#define H 120

int main(void)
{
	struct dao_error err = { 0 };
	struct dao_camera cam;
	struct dao_context *ctx = NULL;
	struct dao_frame depth = { 0 }, ao = { 0 };
	int status = 1;

	if (dao_camera_from_intrinsics(&cam, W, H, 130, 130, (W - 1) / 2.0, (H - 1) / 2.0, &err) ||
	    dao_frame_alloc(&depth, DAO_PIXFMT_DEPTH16, W, H, &err) ||
	    dao_frame_alloc(&ao, DAO_PIXFMT_GRAY_F32, W, H, &err))
		goto fail;
	depth.depth_unit = 0.001f;
	for (int y = 0; y < H; y++) {
		uint16_t *row = (uint16_t *)((char *)depth.data + (size_t)y * depth.stride);
		for (int x = 0; x < W; x++) /* the box: columns 70..89, rows 40..79 */
			row[x] = (x >= 70 && x < 90 && y >= 40 && y < 80) ? 1500 : 2000;
	}
	if (dao_context_create(&ctx, &cam, NULL, &err) ||
	    dao_context_process(ctx, &depth, NULL, 0, &ao, &err))
		goto fail;
	/* the open wall far from the box (left quarter) and the wall beside the box */
	double open = 0, beside = 0;
	int n_open = 0, n_beside = 0;
	for (int y = 0; y < H; y++) {
		const float *row = (const float *)((const char *)ao.data + (size_t)y * ao.stride);
		for (int x = 0; x < W; x++) {
			if (!(row[x] >= 0.0f && row[x] <= 1.0f)) {
				fprintf(stderr, "core_only: AO %g at (%d, %d) outside [0, 1]\n", row[x], x, y);
				goto out;
			}
			if (x >= 8 && x < 40 && y >= 8 && y < H - 8)
				open += row[x], n_open++;
			if ((x == 67 || x == 68 || x == 91 || x == 92) && y >= 45 && y < 75)
				beside += row[x], n_beside++;
		}
	}
	open /= n_open;
	beside /= n_beside;
	printf("open wall %.3f, beside the box %.3f\n", open, beside);
	if (open < 0.9 || beside > open - 0.05) {
		fprintf(stderr, "core_only: the open wall must be near 1 and the wall beside the box darker\n");
		goto out;
	}
	status = 0;
	goto out;
fail:
	fprintf(stderr, "core_only: %s\n", err.message);
out:
	dao_context_destroy(ctx);
	dao_frame_free(&depth);
	dao_frame_free(&ao);
	return status;
}
