/* SPDX-License-Identifier: MIT */
/*
 * depthao eval --depth: the filtered depth against the true depth of the
 * synthetic scenes (eval_depth.c), on the real frames' planes
 * (eval_depth_real.c), beside the librealsense-style reference chain
 * (synth/rs_reference.h); docs/depth-accuracy.md.
 */
#ifndef DAO_TOOLS_EVAL_DEPTH_H
#define DAO_TOOLS_EVAL_DEPTH_H

#include <stdint.h>

#include <depthao/depthao.h>

/* `depthao eval --depth [options]` (argv[0] is "eval"); the exit status. */
int cmd_eval_depth(int argc, char **argv);

/* What the options change of depthao's filter: depth-fill (px, 0 = off),
 * depth-temporal (< 0: the stream default) and any other parameter options
 * (--prefilter-iterations 1 ...: argv's words, checked when parsed). */
#define EVAL_DEPTH_MAX_PARAM_ARGS 64
struct eval_depth_filter {
	int fill;
	float temporal;
	int nparam_args;
	char *param_args[EVAL_DEPTH_MAX_PARAM_ARGS];
};

/* The depthao filter as a stream runs it (the default preset, the stream defaults,
 * algorithm none) on one thread, so that the thread's CPU time is the filter's;
 * with `f`'s changes.  0, or -1 with a message in err (a parameter option's
 * value the parameters refuse together). */
int eval_depth_params(struct dao_params *p, const struct eval_depth_filter *f,
		      struct dao_error *err);

/* CPU time of the calling thread, ms. */
double eval_thread_ms(void);

/* The real frames' plane-fit residuals, raw, filtered and reference; the exit status. */
int eval_depth_real(const char *data_dir, int check, const struct eval_depth_filter *f);

/*
 * Writes a PNG of five w/2 x h/2 panels side by side: raw, filtered, truth
 * (depth as gray, near bright), |raw - truth| and |filtered - truth| (0 to
 * white to black at 5 cm); 0 or the exit status after a message.
 */
int eval_depth_picture(const char *path, const float *raw, const float *filt, const float *truth,
		       int w, int h);

/*
 * OpenCV's rgbd DepthCleaner (method NIL, window 5) on depth in metres (0 =
 * none) into `out`, w x h; 0 or -1.  Only in depthao-eval-cv, the build of
 * this evaluation with OpenCV (eval_depth_cv.cpp), not in depthao.
 */
int eval_cv_depth_clean(const float *in, int w, int h, float *out);

#endif
