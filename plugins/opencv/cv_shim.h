/* SPDX-License-Identifier: MIT */
/*
 * The C face of the OpenCV shim (cv_shim.cpp): OpenCV has no C API for video
 * writing or windows any more.  Images are 8-bit RGB or gray, row stride in
 * bytes.  Errors come back as text in `err` (cap bytes) and a NULL/negative.
 */
#ifndef DAO_CV_SHIM_H
#define DAO_CV_SHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct cvs_video;
struct cvs_video *cvs_video_open(const char *path, const char fourcc[4], double fps, int width,
				 int height, int color, char *err, size_t cap);
int cvs_video_write(struct cvs_video *v, const uint8_t *data, int stride, char *err, size_t cap);
void cvs_video_close(struct cvs_video *v);
/* What this OpenCV can write: "backend list" for messages. */
void cvs_video_backends(char *out, size_t cap);

struct cvs_control {
	const char *name;   /* AO parameter, e.g. "radius" */
	double min, max, step;
	double value;       /* current */
};

struct cvs_window;
struct cvs_window *cvs_window_open(const char *title, struct cvs_control *controls, int ncontrols,
				   char *err, size_t cap);
/*
 * Shows a frame with `overlay` text (e.g. fps) and runs the event loop once.
 * Returns a bit set of controls the user moved (values updated in place),
 * or -1 when the window was closed.
 */
int cvs_window_show(struct cvs_window *w, const uint8_t *data, int width, int height, int stride,
		    int channels, const char *overlay);
void cvs_window_close(struct cvs_window *w);

#ifdef __cplusplus
}
#endif
#endif
