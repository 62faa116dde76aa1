/* SPDX-License-Identifier: MIT */
/*
 * Plays a recording through a built-in source with colour (want_color):
 * FILE.oni (as "oni:FILE.oni") or a source URI ("bag:FILE.bag?color=T"),
 * and writes each frame's colour image as OUTDIR/NNNNNN.ppm (binary P6);
 * prints one line per frame: "index depth_seq depth_ts_us color_seq
 * color_ts_us".  For test_oni_color.py and test_bag_color.py, which check
 * the pixels against Python's own decoders and the pairing against the
 * timestamps.
 * Exit 0, or 1 with the error (e.g. no colour) on stderr.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

int main(int argc, char **argv)
{
	struct dao_error err;
	struct dao_plugins *plugins = NULL;
	struct dao_source *src = NULL;
	if (argc != 3) {
		fprintf(stderr, "usage: %s FILE.oni|URI OUTDIR\n", argv[0]);
		return 2;
	}
	char uri[4096];
	size_t n = strlen(argv[1]);
	int is_oni = n > 4 && !strcmp(argv[1] + n - 4, ".oni") && strncmp(argv[1], "oni:", 4);
	snprintf(uri, sizeof uri, "%s%s", is_oni ? "oni:" : "", argv[1]);
	struct dao_source_options so = DAO_SOURCE_OPTIONS_INIT;
	so.want_color = 1;
	if (dao_plugins_load(&plugins, "", &err) || dao_source_open(plugins, uri, &so, &src, &err) ||
	    dao_source_start(src, &err)) {
		fprintf(stderr, "%s\n", err.message);
		return 1;
	}
	struct dao_source_info in;
	dao_source_get_info(src, &in);
	if (!in.has_color) {
		fprintf(stderr, "no colour: %s %s\n", in.description, in.warning);
		return 1;
	}
	int status = 0;
	for (;;) {
		struct dao_source_frame f;
		int r = dao_source_read(src, &f, 1000, &err);
		if (r == DAO_SOURCE_EOS)
			break;
		if (r < 0) {
			fprintf(stderr, "%s\n", err.message);
			status = 1;
			break;
		}
		const struct dao_frame *c = &f.color;
		if (c->format != DAO_PIXFMT_RGB24 || c->width != in.color_width ||
		    c->height != in.color_height) {
			fprintf(stderr, "frame %llu came without colour\n", (unsigned long long)f.index);
			status = 1;
			break;
		}
		char path[4200];
		snprintf(path, sizeof path, "%s/%06llu.ppm", argv[2], (unsigned long long)f.index);
		FILE *out = fopen(path, "wb");
		if (!out) {
			perror(path);
			status = 1;
			break;
		}
		fprintf(out, "P6\n%u %u\n255\n", c->width, c->height);
		for (uint32_t y = 0; y < c->height; y++)
			fwrite((const uint8_t *)c->data + (size_t)y * (size_t)c->stride, 3, c->width, out);
		if (fclose(out) != 0) {
			perror(path);
			status = 1;
			break;
		}
		printf("%llu %llu %llu %llu %llu\n", (unsigned long long)f.index,
		       (unsigned long long)f.depth.sequence,
		       (unsigned long long)(f.depth.timestamp_ns / 1000),
		       (unsigned long long)c->sequence, (unsigned long long)(c->timestamp_ns / 1000));
		dao_source_release(src, &f);
	}
	dao_source_close(src);
	dao_plugins_free(plugins);
	return status;
}
