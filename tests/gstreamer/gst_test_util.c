/* SPDX-License-Identifier: MIT */
/*
 * Helpers for the GStreamer tests.
 *
 *   gst_test_util info IMAGE             "W H FORMAT" (gray8, gray16, rgb24)
 *   gst_test_util compare A B [TOL]      pixel comparison; exit 0 if every sample is
 *                                        within TOL (default 0), 1 if not, 2 on errors
 *   gst_test_util match IMAGE... -- REF...
 *                                        for each IMAGE the REF closest to it (smallest
 *                                        mean absolute difference): "IMAGE REF MEAN"
 *   gst_test_util free-port              a TCP port free on 127.0.0.1 right now
 *
 * IMAGE is a PNG file or raw pixels "raw:FORMAT:WxH:PATH" with FORMAT gray8,
 * gray16le, rgb, rgba or bgrx (tightly packed rows, as filesink writes them).
 * RGBA/BGRx compare as RGB; gray8 against gray16 compares round(v16 / 257).
 */
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <depthao/frame.h>
#include <depthao/png.h>

struct image {
	uint32_t w, h, ch;
	int depth16; /* samples are 16-bit */
	uint16_t *v; /* w * h * ch samples */
};

static int load_raw(const char *spec, struct image *im)
{
	char fmt[16];
	unsigned w, h;
	int n = 0;
	if (sscanf(spec, "raw:%15[a-z0-9]:%ux%u:%n", fmt, &w, &h, &n) != 3 || !n || !w || !h) {
		fprintf(stderr, "bad raw image '%s' (raw:FORMAT:WxH:PATH)\n", spec);
		return -1;
	}
	const char *path = spec + n;
	unsigned bpp, swap = 0; /* bytes per pixel in the file; BGR order */
	im->w = w;
	im->h = h;
	im->depth16 = 0;
	if (!strcmp(fmt, "gray8")) {
		bpp = 1;
		im->ch = 1;
	} else if (!strcmp(fmt, "gray16le")) {
		bpp = 2;
		im->ch = 1;
		im->depth16 = 1;
	} else if (!strcmp(fmt, "rgb")) {
		bpp = 3;
		im->ch = 3;
	} else if (!strcmp(fmt, "rgba") || !strcmp(fmt, "bgrx")) {
		bpp = 4;
		im->ch = 3;
		swap = fmt[0] == 'b';
	} else {
		fprintf(stderr, "unknown raw format '%s'\n", fmt);
		return -1;
	}
	size_t size = (size_t)w * h * bpp;
	unsigned char *buf = malloc(size + 1);
	FILE *f = fopen(path, "rb");
	if (!buf || !f) {
		fprintf(stderr, "%s: %s\n", path, strerror(errno));
		free(buf);
		if (f)
			fclose(f);
		return -1;
	}
	size_t got = fread(buf, 1, size + 1, f);
	fclose(f);
	if (got != size) {
		fprintf(stderr, "%s: %zu bytes, expected %zu for %s %ux%u\n", path, got, size, fmt, w,
			h);
		free(buf);
		return -1;
	}
	im->v = malloc((size_t)w * h * im->ch * sizeof(uint16_t));
	if (!im->v) {
		free(buf);
		return -1;
	}
	for (size_t i = 0; i < (size_t)w * h; i++) {
		const unsigned char *p = buf + i * bpp;
		if (im->depth16)
			im->v[i] = (uint16_t)(p[0] | p[1] << 8);
		else if (im->ch == 1)
			im->v[i] = p[0];
		else
			for (unsigned c = 0; c < 3; c++)
				im->v[i * 3 + c] = p[swap ? 2 - c : c];
	}
	free(buf);
	return 0;
}

static int load_png(const char *path, struct image *im)
{
	struct dao_frame f;
	struct dao_error err;
	if (dao_png_read(path, &f, &err) < 0) {
		fprintf(stderr, "%s\n", err.message);
		return -1;
	}
	im->w = f.width;
	im->h = f.height;
	im->ch = f.format == DAO_PIXFMT_RGB24 ? 3 : 1;
	im->depth16 = f.format == DAO_PIXFMT_GRAY16;
	im->v = malloc((size_t)f.width * f.height * im->ch * sizeof(uint16_t));
	if (!im->v) {
		dao_frame_free(&f);
		return -1;
	}
	for (uint32_t y = 0; y < f.height; y++) {
		const unsigned char *row = (const unsigned char *)f.data + (size_t)y * (size_t)f.stride;
		for (uint32_t x = 0; x < f.width * im->ch; x++) {
			size_t i = (size_t)y * f.width * im->ch + x;
			if (im->depth16) {
				uint16_t s;
				memcpy(&s, row + 2 * x, 2);
				im->v[i] = s;
			} else {
				im->v[i] = row[x];
			}
		}
	}
	dao_frame_free(&f);
	return 0;
}

static int load(const char *spec, struct image *im)
{
	return !strncmp(spec, "raw:", 4) ? load_raw(spec, im) : load_png(spec, im);
}

static int free_port(void)
{
	int fd = socket(AF_INET, SOCK_STREAM, 0);
	struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = 0};
	socklen_t len = sizeof a;
	a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof a) < 0 ||
	    getsockname(fd, (struct sockaddr *)&a, &len) < 0) {
		perror("free-port");
		return 2;
	}
	printf("%u\n", ntohs(a.sin_port));
	close(fd);
	return 0;
}

/* Mean absolute difference of two images of the same layout, < 0 if they differ in layout. */
static double mean_diff(const struct image *a, const struct image *b, long *maxd, size_t *differ)
{
	if (a->w != b->w || a->h != b->h || a->ch != b->ch)
		return -1;
	size_t n = (size_t)a->w * a->h * a->ch;
	double sum = 0;
	*maxd = 0;
	*differ = 0;
	for (size_t i = 0; i < n; i++) {
		long va = a->v[i], vb = b->v[i];
		if (a->depth16 != b->depth16) { /* gray8 against gray16: 16-bit scaled to 8 */
			if (a->depth16)
				va = (va + 128) / 257;
			else
				vb = (vb + 128) / 257;
		}
		long d = labs(va - vb);
		*differ += d != 0;
		*maxd = d > *maxd ? d : *maxd;
		sum += (double)d;
	}
	return sum / (double)n;
}

/* match IMAGE... -- REF...: one line "IMAGE REF MEAN" per image, REF the closest */
static int match(int argc, char **argv)
{
	int sep = 0;
	while (sep < argc && strcmp(argv[sep], "--") != 0)
		sep++;
	int nimg = sep, nref = argc - sep - 1;
	if (nimg < 1 || nref < 1) {
		fprintf(stderr, "usage: match IMAGE... -- REF...\n");
		return 2;
	}
	struct image *refs = calloc((size_t)nref, sizeof(*refs));
	int status = refs ? 0 : 2;
	for (int i = 0; i < nref && status == 0; i++)
		if (load(argv[sep + 1 + i], &refs[i]) < 0)
			status = 2;
	for (int k = 0; k < nimg && status == 0; k++) {
		struct image a;
		if (load(argv[k], &a) < 0) {
			status = 2;
			break;
		}
		int best = -1;
		double best_mean = 1e30;
		for (int i = 0; i < nref; i++) {
			long maxd;
			size_t differ;
			double m = mean_diff(&a, &refs[i], &maxd, &differ);
			if (m >= 0 && m < best_mean) {
				best_mean = m;
				best = i;
			}
		}
		free(a.v);
		if (best < 0) {
			printf("%s: no reference of the same layout\n", argv[k]);
			status = 1;
		} else {
			printf("%s %s %.3f\n", argv[k], argv[sep + 1 + best], best_mean);
		}
	}
	for (int i = 0; refs && i < nref; i++)
		free(refs[i].v);
	free(refs);
	return status;
}

int main(int argc, char **argv)
{
	struct image a, b;
	if (argc >= 2 && !strcmp(argv[1], "match"))
		return match(argc - 2, argv + 2);
	if (argc == 2 && !strcmp(argv[1], "free-port"))
		return free_port();
	if (argc == 3 && !strcmp(argv[1], "info")) {
		if (load(argv[2], &a) < 0)
			return 2;
		printf("%u %u %s\n", a.w, a.h, a.ch == 3 ? "rgb24" : a.depth16 ? "gray16" : "gray8");
		free(a.v);
		return 0;
	}
	if ((argc != 4 && argc != 5) || strcmp(argv[1], "compare") != 0) {
		fprintf(stderr, "usage: %s info IMAGE | compare A B [TOL] | match IMAGE... -- REF... | "
			"free-port\n", argv[0]);
		return 2;
	}
	long tol = argc == 5 ? strtol(argv[4], NULL, 10) : 0;
	if (load(argv[2], &a) < 0)
		return 2;
	if (load(argv[3], &b) < 0) {
		free(a.v);
		return 2;
	}
	if (a.w != b.w || a.h != b.h || a.ch != b.ch) {
		printf("different layouts: %ux%u x%u and %ux%u x%u\n", a.w, a.h, a.ch, b.w, b.h, b.ch);
		free(a.v);
		free(b.v);
		return 1;
	}
	size_t n = (size_t)a.w * a.h * a.ch, differ;
	long maxd;
	double mean = mean_diff(&a, &b, &maxd, &differ);
	printf("%zu of %zu samples differ, largest difference %ld, mean %.3f\n", differ, n, maxd,
	       mean);
	free(a.v);
	free(b.v);
	return maxd <= tol ? 0 : 1;
}
