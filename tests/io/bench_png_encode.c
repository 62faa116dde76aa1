/* SPDX-License-Identifier: MIT */
/*
 * Encoder settings for PNG output, measured: each setting encodes the given
 * PNG files in memory (no disk), and the table gives the CPU time per frame
 * (thread CPU time, the least of --reps runs, so other load on the host
 * counts less) and the size against the raw samples.  With --write DIR it
 * then writes the frames as files through dao_png_write_compressed() (what
 * the images sink does: temporary file, rename) at levels 0, 1 and 6 and
 * gives the CPU time per frame (the frame rate one core sustains is its
 * inverse) and the wall time (which includes waiting for the CPU and the
 * disk, so it depends on the host's load).  The
 * docs/perf/png-output.md's table comes from this program; it is a measurement,
 * not a test.
 *
 * usage: bench-png-encode [--reps N] [--write DIR] FILE.png...
 */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <zlib.h>

#include <depthao/depthao.h>
#include <depthao/io.h>

struct setting {
	const char *name;
	int level, filters, strategy; /* filters/strategy -1: libpng's default */
};

static const struct setting settings[] = {
	{"level 6, adaptive filters (before)", 6, -1, -1},
	{"level 1, adaptive filters", 1, -1, -1},
	{"level 1, none", 1, PNG_FILTER_NONE, -1},
	{"level 1, sub", 1, PNG_FILTER_SUB, -1},
	{"level 1, up", 1, PNG_FILTER_UP, -1},
	{"level 1, paeth", 1, PNG_FILTER_PAETH, -1},
	{"level 1, up, Z_RLE", 1, PNG_FILTER_UP, Z_RLE},
	{"level 1, paeth, Z_RLE", 1, PNG_FILTER_PAETH, Z_RLE},
	{"level 1, up, Z_HUFFMAN_ONLY", 1, PNG_FILTER_UP, Z_HUFFMAN_ONLY},
	{"level 2, up", 2, PNG_FILTER_UP, -1},
	{"level 3, up", 3, PNG_FILTER_UP, -1},
	{"level 6, up", 6, PNG_FILTER_UP, -1},
	{"level 9, up", 9, PNG_FILTER_UP, -1},
	{"level 0 (stored)", 0, PNG_FILTER_NONE, -1},
};

struct buf {
	unsigned char *p;
	size_t n, cap;
};

static void on_write(png_structp png, png_bytep data, size_t n)
{
	struct buf *b = png_get_io_ptr(png);
	if (b->n + n > b->cap) {
		b->cap = 2 * (b->n + n);
		if (!(b->p = realloc(b->p, b->cap)))
			abort();
	}
	memcpy(b->p + b->n, data, n);
	b->n += n;
}

static void on_flush(png_structp png)
{
	(void)png;
}

static double wall_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static double cpu_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
	return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static size_t encode(const struct dao_frame *f, const struct setting *s, struct buf *b)
{
	b->n = 0;
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	png_infop info = png_create_info_struct(png);
	if (!png || !info || setjmp(png_jmpbuf(png)))
		abort();
	png_set_write_fn(png, b, on_write, on_flush);
	int depth = f->format == DAO_PIXFMT_GRAY16 ? 16 : 8;
	int color = f->format == DAO_PIXFMT_RGB24 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY;
	png_set_IHDR(png, info, f->width, f->height, depth, color, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_set_compression_level(png, s->level);
	if (s->filters >= 0)
		png_set_filter(png, PNG_FILTER_TYPE_BASE, s->filters);
	if (s->strategy >= 0)
		png_set_compression_strategy(png, s->strategy);
	png_write_info(png, info);
	if (depth == 16)
		png_set_swap(png);
	for (uint32_t y = 0; y < f->height; y++)
		png_write_row(png, (png_bytep)f->data + (size_t)y * (size_t)f->stride);
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	return b->n;
}

int main(int argc, char **argv)
{
	int reps = 5, first = 1;
	const char *write_dir = NULL;
	while (first + 1 < argc && !strncmp(argv[first], "--", 2)) {
		if (!strcmp(argv[first], "--reps"))
			reps = atoi(argv[first + 1]);
		else if (!strcmp(argv[first], "--write"))
			write_dir = argv[first + 1];
		else
			break;
		first += 2;
	}
	int nf = argc - first;
	if (nf < 1 || reps < 1) {
		fprintf(stderr, "usage: %s [--reps N] FILE.png...\n", argv[0]);
		return 2;
	}
	struct dao_frame *frames = calloc((size_t)nf, sizeof(*frames));
	size_t raw = 0;
	for (int i = 0; i < nf; i++) {
		struct dao_error err;
		if (dao_png_read(argv[first + i], &frames[i], &err)) {
			fprintf(stderr, "%s\n", err.message);
			return 1;
		}
		raw += (size_t)frames[i].height * frames[i].width *
		       dao_pixfmt_bytes_per_pixel(frames[i].format);
	}
	printf("%d frames, %s %ux%u\n", nf, dao_pixfmt_name(frames[0].format), frames[0].width,
	       frames[0].height);
	struct buf b = {0};
	for (size_t k = 0; k < sizeof settings / sizeof *settings; k++) {
		double best = 1e30;
		size_t bytes = 0;
		for (int r = 0; r < reps; r++) {
			double t0 = cpu_s();
			size_t total = 0;
			for (int i = 0; i < nf; i++)
				total += encode(&frames[i], &settings[k], &b);
			double t = (cpu_s() - t0) / nf;
			best = t < best ? t : best;
			bytes = total;
		}
		printf("%-36s %7.2f ms/frame %8.1f KB/frame  %5.1f %% of raw\n", settings[k].name,
		       best * 1e3, (double)bytes / 1024.0 / nf, 100.0 * (double)bytes / (double)raw);
	}
	for (int level = 0; write_dir && level <= 6; level += level == 1 ? 5 : 1) {
		/* 300 frames: ten seconds of a 30 fps stream */
		char path[4096];
		struct dao_error err;
		double t0 = wall_s(), c0 = cpu_s();
		for (int i = 0; i < 300; i++) {
			snprintf(path, sizeof path, "%s/%06d.png", write_dir, i % 30);
			if (dao_png_write_compressed(path, &frames[i % nf], level, &err)) {
				fprintf(stderr, "%s\n", err.message);
				return 1;
			}
		}
		double wall = (wall_s() - t0) / 300, cpu = (cpu_s() - c0) / 300;
		printf("files at level %d: %6.2f ms CPU/frame (%4.0f fps on one core), %6.2f ms wall\n",
		       level, cpu * 1e3, 1.0 / cpu, wall * 1e3);
	}
	for (int i = 0; i < nf; i++)
		dao_frame_free(&frames[i]);
	free(frames);
	free(b.p);
	return 0;
}
