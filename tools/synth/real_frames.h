/* SPDX-License-Identifier: MIT */
/*
 * The real sensor frames of ../shared/data (tools and tests only): which
 * files they are, their units and cameras, and a loader that turns any of
 * them (or any depth PNG or .oni frame) into metres.
 */
#ifndef DAO_SYNTH_REAL_FRAMES_H
#define DAO_SYNTH_REAL_FRAMES_H

#include <depthao/camera.h>
#include <depthao/error.h>

#include "synth/sensor.h"

struct synth_real_frame {
	const char *name;          /* short, unique: "kinect-oni-00", "redwood-0", ... */
	const char *file;          /* relative to the data directory */
	const char *sensor;        /* what recorded it */
	enum synth_sensor model;   /* the simulated sensor class it is compared with */
	double unit;               /* m per count of a PNG (a recording has its own) */
	double fx, fy, cx, cy;     /* 0: from the recording's field of view */
	int frame;                 /* frame of a recording, -1 for a PNG */
};

/* The frames of ../shared/data/README.md, in a fixed order; *count gets their number. */
const struct synth_real_frame *synth_real_frames(int *count);

/* The data directory: $DAO_SHARED_DATA, else "../shared/data". */
const char *synth_real_data_dir(void);

/*
 * Loads frame `frame` of a recording (.oni) or a depth PNG (frame ignored;
 * `png_unit` m per count) into metres (*z, malloc'ed, 0 = no data).  A
 * recording's field of view gives *cam (if has_cam is not NULL, *has_cam = 1);
 * for a PNG *has_cam = 0 and *cam is untouched.  Frames recorded mirrored are
 * mirrored back, so that the image is the camera's view (projector shadows
 * fall on their physical side).  *unit gets the source's m per count.
 */
int synth_depth_load(const char *path, int frame, double png_unit, float **z, uint32_t *w,
		     uint32_t *h, double *unit, struct dao_camera *cam, int *has_cam,
		     struct dao_error *err);

/* Loads a frame of the list from `data_dir` with its camera. */
int synth_real_frame_load(const struct synth_real_frame *f, const char *data_dir, float **z,
			  struct dao_camera *cam, double *unit, struct dao_error *err);

/* Number of frames of a recording (1 for a PNG); -errno with a message. */
int synth_depth_frame_count(const char *path, struct dao_error *err);

#endif
