/* SPDX-License-Identifier: MIT */
/*
 * The MCAP sink read back through depthao's own MCAP source:
 *   mcap_roundtrip FILE.mcap AO_DIR REC
 * plays the /depthao/ao topic of FILE.mcap (the AO as 16-bit counts) and REC
 * (the recording the AO was made from) side by side: every frame's pixels
 * equal AO_DIR/NNNNNN.png, its timestamp REC's frame's, and the
 * CameraInfo's intrinsics the pinhole of REC's field of view.  Prints
 * "frames N fx FX"; exit 1 on a difference.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <depthao/depthao.h>
#include <depthao/io.h>
#include <depthao/plugin.h>

static int open_src(struct dao_plugins *p, const char *uri, struct dao_source **s,
		    struct dao_source_info *info)
{
	struct dao_error err;
	struct dao_source_options o = DAO_SOURCE_OPTIONS_INIT;
	if (dao_source_open(p, uri, &o, s, &err) || dao_source_start(*s, &err)) {
		fprintf(stderr, "%s: %s\n", uri, err.message);
		return 1;
	}
	dao_source_get_info(*s, info);
	return 0;
}

/* Frame i of both sources against the PNG: 0 or 1. */
static int compare(const char *dir, uint64_t i, const struct dao_frame *got,
		   const struct dao_frame *rec)
{
	char path[4096];
	struct dao_error err;
	struct dao_frame png;
	snprintf(path, sizeof path, "%s/%06llu.png", dir, (unsigned long long)i);
	if (dao_png_read(path, &png, &err)) {
		fprintf(stderr, "%s\n", err.message);
		return 1;
	}
	int bad = png.width != got->width || png.height != got->height;
	for (uint32_t y = 0; !bad && y < png.height; y++)
		bad = memcmp((char *)png.data + (size_t)y * png.stride,
			     (char *)got->data + (size_t)y * got->stride, 2 * (size_t)png.width) != 0;
	if (bad)
		fprintf(stderr, "frame %llu: the pixels differ from %s\n", (unsigned long long)i, path);
	if (got->timestamp_ns != rec->timestamp_ns) {
		fprintf(stderr, "frame %llu: timestamp %llu, the recording's %llu\n",
			(unsigned long long)i, (unsigned long long)got->timestamp_ns,
			(unsigned long long)rec->timestamp_ns);
		bad = 1;
	}
	dao_frame_free(&png);
	return bad;
}

int main(int argc, char **argv)
{
	struct dao_error err;
	struct dao_plugins *p = NULL;
	struct dao_source *m = NULL, *r = NULL;
	struct dao_source_info mi, ri;
	char uri[4200];
	if (argc != 4) {
		fprintf(stderr, "usage: mcap_roundtrip FILE.mcap AO_DIR REC\n");
		return 2;
	}
	snprintf(uri, sizeof uri, "mcap:%s?topic=/depthao/ao&unit=0.0001", argv[1]);
	if (dao_plugins_load(&p, "", &err)) {
		fprintf(stderr, "%s\n", err.message);
		return 1;
	}
	int bad = open_src(p, uri, &m, &mi) || open_src(p, argv[3], &r, &ri);
	double fx = (ri.width / 2.0) / tan(ri.hfov / 2);
	if (!bad && (!mi.has_intrinsics || fabs(mi.fx - fx) > 1e-6 || fabs(mi.cx - (ri.width - 1) / 2.0) > 1e-9)) {
		fprintf(stderr, "intrinsics fx %.9g cx %.9g, the recording's field of view gives %.9g %.9g\n",
			mi.fx, mi.cx, fx, (ri.width - 1) / 2.0);
		bad = 1;
	}
	uint64_t n = 0;
	while (!bad) {
		struct dao_source_frame a, b;
		int ra = dao_source_read(m, &a, 1000, &err);
		int rb = ra == 0 ? dao_source_read(r, &b, 1000, &err) : ra;
		if (ra == DAO_SOURCE_EOS)
			break;
		if (ra < 0 || rb != 0) {
			fprintf(stderr, "frame %llu: %s\n", (unsigned long long)n,
				rb == DAO_SOURCE_EOS ? "the recording has fewer frames" : err.message);
			bad = 1;
			if (ra == 0)
				dao_source_release(m, &a);
			break;
		}
		bad = compare(argv[2], n++, &a.depth, &b.depth);
		dao_source_release(m, &a);
		dao_source_release(r, &b);
	}
	printf("frames %llu fx %.6f\n", (unsigned long long)n, mi.fx);
	dao_source_close(m);
	dao_source_close(r);
	dao_plugins_free(p);
	return bad;
}
