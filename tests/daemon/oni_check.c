/* SPDX-License-Identifier: MIT */
/*
 * Reads a recording of the daemon tests' camera (testsrc in test_plugins.c:
 * at frame j a box of 900 mm, w/4 wide, from column j % (w/2) and below row
 * h/3, on 1500 mm) with depthao's reader and checks every frame pixel for
 * pixel.  j comes from the timestamp: the recorder stamps frames without a
 * time sequence * 1e6 / fps microseconds.  Prints
 *     frames F header H warning 0|1 first J0 last J1
 * (H: the frame count in the node record, what OpenNI2 plays), or a message
 * and exit 1.  With a second argument "any", frames are only counted (for
 * recordings of other sources).
 * usage: oni_check FILE.oni FPS [any]
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/frame.h>
#include <depthao/oni.h>

static uint32_t header_frames(const char *path)
{
	uint8_t b[256];
	FILE *f = fopen(path, "rb");
	size_t n = f ? fread(b, 1, sizeof b, f) : 0;
	if (f)
		fclose(f);
	if (n < 24 + 28 + 4)
		return 0;
	uint32_t len = b[52] | b[53] << 8 | (uint32_t)b[54] << 16 | (uint32_t)b[55] << 24;
	size_t at = 56 + len + 8; /* name, node type, codec */
	if (len > 64 || at + 4 > n)
		return 0;
	return b[at] | b[at + 1] << 8 | (uint32_t)b[at + 2] << 16 | (uint32_t)b[at + 3] << 24;
}

int main(int argc, char **argv)
{
	if (argc < 3) {
		fprintf(stderr, "usage: oni_check FILE.oni FPS [any]\n");
		return 2;
	}
	const double fps = atof(argv[2]);
	const int any = argc > 3 && !strcmp(argv[3], "any");
	struct dao_oni_reader *r;
	struct dao_error err;
	if (dao_oni_reader_open(argv[1], &r, &err) < 0) {
		fprintf(stderr, "%s\n", err.message);
		return 1;
	}
	int s = dao_oni_reader_depth_stream(r, &err);
	if (s < 0) {
		fprintf(stderr, "%s\n", err.message);
		return 1;
	}
	const struct dao_oni_stream_info *in = dao_oni_reader_stream(r, (uint32_t)s);
	const uint32_t w = in->width, h = in->height;
	struct dao_frame f;
	if (dao_frame_alloc(&f, DAO_PIXFMT_DEPTH16, w, h, &err) < 0)
		return 1;
	long long first = -1, last = -1;
	for (uint32_t k = 0; k < in->frame_count; k++) {
		if (dao_oni_reader_read_depth(r, (uint32_t)s, k, &f, &err) < 0) {
			fprintf(stderr, "frame %u: %s\n", k, err.message);
			return 1;
		}
		long long j = llround((double)(f.timestamp_ns / 1000) * fps / 1e6);
		if (j <= last) {
			fprintf(stderr, "frame %u: camera frame %lld after %lld\n", k, j, last);
			return 1;
		}
		if (first < 0)
			first = j;
		last = j;
		const uint32_t bx = (uint32_t)(j % (w / 2));
		for (uint32_t y = 0; y < h && !any; y++) {
			const uint16_t *row = (const uint16_t *)((const uint8_t *)f.data + (size_t)y * f.stride);
			for (uint32_t x = 0; x < w; x++) {
				uint16_t want = x >= bx && x < bx + w / 4 && y > h / 3 ? 900 : 1500;
				if (row[x] != want) {
					fprintf(stderr, "frame %u (camera frame %lld): pixel (%u, %u) is %u, "
						"expected %u\n", k, j, x, y, row[x], want);
					return 1;
				}
			}
		}
	}
	printf("frames %u header %u warning %d first %lld last %lld\n", in->frame_count,
	       header_frames(argv[1]), dao_oni_reader_warning(r) != NULL, first, last);
	dao_frame_free(&f);
	dao_oni_reader_close(r);
	return 0;
}
