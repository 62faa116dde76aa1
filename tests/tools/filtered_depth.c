/* SPDX-License-Identifier: MIT */
/*
 * The library's filtered depth of one depth PNG, for test_cli_depth_out.py:
 *   filtered_depth IN.png UNIT FX,FY,CX,CY ALGORITHM OUT.raw
 * reads IN.png in UNIT metres per count, processes it as `depthao process`
 * does PNG input (the default preset, frame 0, ALGORITHM) and writes
 * dao_context_get_depth()'s DEPTH16 counts in UNIT to OUT.raw: width x height
 * little-endian uint16, rows packed, after a line "WIDTH HEIGHT\n".
 */
#include <stdio.h>
#include <stdlib.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

static int fail(const struct dao_error *err)
{
	fprintf(stderr, "filtered_depth: %s\n", err->message);
	return 1;
}

int main(int argc, char **argv)
{
	double k[4];
	if (argc != 6 || sscanf(argv[3], "%lf,%lf,%lf,%lf", &k[0], &k[1], &k[2], &k[3]) != 4) {
		fprintf(stderr, "usage: filtered_depth IN.png UNIT FX,FY,CX,CY ALGORITHM OUT.raw\n");
		return 2;
	}
	float unit = strtof(argv[2], NULL);
	struct dao_error err;
	struct dao_frame in, out;
	struct dao_camera cam;
	struct dao_params p;
	struct dao_context *ctx = NULL;
	if (dao_png_read_depth(argv[1], unit, &in, &err) ||
	    dao_camera_from_intrinsics(&cam, in.width, in.height, k[0], k[1], k[2], k[3], &err))
		return fail(&err);
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	if (dao_params_set(&p, "algorithm", argv[4], &err) ||
	    dao_context_create(&ctx, &cam, &p, &err) ||
	    dao_context_process(ctx, &in, NULL, 0, NULL, &err) ||
	    dao_frame_alloc(&out, DAO_PIXFMT_DEPTH16, in.width, in.height, &err))
		return fail(&err);
	out.depth_unit = unit;
	if (dao_context_get_depth(ctx, &out, &err))
		return fail(&err);
	FILE *f = fopen(argv[5], "wb");
	if (!f) {
		perror(argv[5]);
		return 1;
	}
	fprintf(f, "%u %u\n", out.width, out.height);
	for (uint32_t y = 0; y < out.height; y++) {
		const uint16_t *row = (const uint16_t *)((const uint8_t *)out.data +
							 (size_t)y * (size_t)out.stride);
		for (uint32_t x = 0; x < out.width; x++) {
			unsigned char b[2] = {(unsigned char)(row[x] & 0xff), (unsigned char)(row[x] >> 8)};
			fwrite(b, 1, 2, f);
		}
	}
	int bad = fclose(f) != 0;
	dao_frame_free(&in);
	dao_frame_free(&out);
	dao_context_destroy(ctx);
	return bad;
}
