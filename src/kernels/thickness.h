/* SPDX-License-Identifier: MIT */
/*
 * Thickness of what the depth image shows, estimated per pixel from the
 * image (README.md, "Algorithms": vbao-thickness-mode=image), for the
 * visibility bitmask AO, which samples it at each occluder.
 *
 * A surface's run along a row (and a column) is the stretch of pixels
 * without a depth step; where a run ends at a step to something farther (or
 * at a hole with something farther beyond it, or nothing up to the border)
 * on both sides, the object lies in front of what is around it
 * and the run's extent in metres, its chord, is its visible width: a pole
 * 4 cm wide on screen is taken to be 4 cm deep (on noisy depth whose
 * dropouts are not filled, a column's run of 5 px or more whose chord is
 * under half a spacing, with a hole of 2 px or more beside an end, gets the
 * bound instead: a board's face may lie hidden in the hole; thickness_run.c,
 * hidden_face).  Where a run ends at an occluder (a step to something
 * nearer) or at the image border, the surface goes on out of sight and its
 * extent is unknown.  Where a run in front
 * ends in a slab's edge face (a straight stretch, a convex crease, a straight broad
 * face), the slab's thickness is the edge's extent across the broad face
 * and each pixel of the run gets the length of its ray through the slab
 * (scaled, below).  Where a run ends at a step to
 * something farther and goes straight to its end (or to an edge face of a
 * few pixels), the face at right angles behind that end would show if the
 * object were thick: its absence bounds the thickness, even where the run's
 * other end is not an outline (a board standing on the floor;
 * thickness_bound.c, face_bound_at), or at a short hole with something
 * farther beyond it (the hole can hide as many pixels of edge face: noisy
 * sensors lose them).  The
 * thickness is the smaller of the row's and the column's value, at most the
 * bound.
 */
#ifndef DAO_KERNELS_THICKNESS_H
#define DAO_KERNELS_THICKNESS_H

#include <depthao/camera.h>

#include <stddef.h>

/* Two neighbours whose depths differ by more than this share of the nearer
 * one lie on different surfaces. */
#define DAO_THICKNESS_JUMP 0.03f

/*
 * What a slab's pixels get: 3 times the length of their ray through it.
 * VBAO's samples land on a broad face several centimetres apart, each
 * occluding only the sectors between its front and its back; with the true
 * thickness the light passes between them where the slab is solid (chair
 * and floating plate brighter than the truth, bias +0.01).  The factor was
 * chosen on the tune split (README.md: 1, 2, 3 and 4 tried).
 */
#define DAO_THICKNESS_SLAB_SCALE 3.0f

struct dao_thickness_setup {
	int width, height;
	float ax, ay, bx, by;   /* view position x = (u ax + bx) z, y = (v ay + by) z */
	float max;              /* upper bound, m (also where the extent is unknown) */
	float crease_cos;       /* a slab's crease turns by more than acos(this) */
	float spacing;          /* VBAO's step between samples, m (below); 0: none */
	float noise_k;          /* the depth noise the rules allow for: noise_k z^2, m
				 * (dao_thickness_setup_noise); 0: none */
	int fill_px;            /* dropouts of at most this many pixels are filled
				 * (dao_thickness_fill_rows, dao_thickness_setup_noise) */
};

/*
 * A slab's pixel gets at least the length of its ray through the slab plus
 * the spacing of VBAO's samples (the search radius over the steps): the
 * factor DAO_THICKNESS_SLAB_SCALE makes up for the gaps between samples, but
 * a thin slab seen face-on (a plate from above, 2 cm crossed over 3.5 cm)
 * times 3 still spans less than one gap, and the light passes between its
 * samples (README.md, the ceiling: the true thickness plus a sample spacing
 * is VBAO's best model).  The pipeline sets it (context_frame.c); init leaves 0.
 */

/*
 * ... and at most the length plus the larger of the spacing and
 * DAO_SLAB_EXTRA_SEC spacings over the cosine of the ray to the slab's normal:
 * the factor 3 where the ray meets the slab obliquely (shelves seen from
 * below at a grazing angle want it), the spacing alone where it meets it
 * within 60 degrees of its normal (boards seen face-on: a 20 cm board no
 * longer gets 3 times 20 cm).  Chosen on the tune split (README.md, "No
 * visible edge face": 0.2 - 1.6 tried; the ceiling's truth agrees).  With
 * no spacing (0), the factor 3 alone.
 */
#define DAO_SLAB_EXTRA_SEC 0.5f

/*
 * A run in front of both its neighbours (a pole, a leg) and thinner than a
 * spacing gets its chord plus DAO_CHORD_EXTRA spacings, at most one spacing,
 * where the surface beyond one of its ends lies within DAO_CHORD_GAP spacings
 * behind that end (a pole before a wall: VBAO's samples pass light between
 * the two).  Not beyond: a chair's legs over the floor falling away behind
 * them, where the extra only darkens the floor around their feet; not over a
 * spacing: spheres on the floor.  On noisy depth too since its dropouts are
 * filled (dao_thickness_fill_rows): before, the chair's back and seat read
 * too thick there (their runs cut by holes) and the extra darkened the floor
 * between its legs further.  Chosen on the tune split (README.md, "A pole's
 * chord plus half a spacing", "Noisy input").
 */
#define DAO_CHORD_EXTRA 0.5f
#define DAO_CHORD_GAP 3.0f

/* crease_cos: DAO_SLAB_CREASE_DEG, for depth the prefilter left sharp. */
void dao_thickness_setup_init(struct dao_thickness_setup *t, const struct dao_camera *cam,
			      float max);

/*
 * The least turn of a slab's crease on depth the domain prefilter smoothed
 * at spatial scale `scale` px (noise-model=auto: the scale the frame's
 * measured noise asked for, dao_noise_info.prefilter_scale).  A slab's edge
 * face is a few pixels wide; where the noise is large enough for the
 * prefilter to average over more than that, the crease between it and the
 * broad face comes out rounded (the 3 cm floating plate: a turn of about 90
 * degrees on clean depth, 34 - 43 degrees with Gaussian noise) and the turn
 * the test asks for comes down with it: DAO_SLAB_CREASE_DEG up to
 * DAO_SLAB_ROUND_FROM px (clean renders read 1 - 2 px), linearly down to
 * DAO_SLAB_CREASE_ROUNDED_DEG at DAO_SLAB_ROUND_TO px and beyond (Gaussian
 * noise reads about 5 px, structured light 14 - 16 px).  Chosen on the tune
 * split (README.md, "Thickness from the image").
 */
#define DAO_SLAB_CREASE_DEG 50.0f
#define DAO_SLAB_CREASE_ROUNDED_DEG 30.0f
#define DAO_SLAB_ROUND_FROM 2.0f
#define DAO_SLAB_ROUND_TO 5.0f
void dao_thickness_setup_rounding(struct dao_thickness_setup *t, float scale);

/*
 * Noisy input (README.md, "Noisy input"): where the prefilter's scale
 * `scale` shows noise (above DAO_SLAB_ROUND_FROM px), the face bound lets an
 * edge face's pixels lie in front of the broad face by up to
 * DAO_THICKNESS_NOISE_TOL times the frame's measured noise `sigma`
 * (dao_noise_info.sigma_area, of 1/z in 1/m: sigma z^2 m; a structured-light
 * frame reads 0.0013, its disparity bands 0.0029 apart); below, by nothing
 * (init's 0).  And the dropouts filled (fill_px, dao_thickness_fill_rows) up
 * to DAO_THICKNESS_FILL_PX px of scale.  The pipeline sets it with the crease
 * (context_frame.c).
 */
#define DAO_THICKNESS_NOISE_TOL 2.0f
void dao_thickness_setup_noise(struct dao_thickness_setup *t, float scale, float sigma);

/*
 * Dropouts inside a surface (README.md, "Noisy input"): a sensor that drops
 * single pixels at random (a Gaussian one 2 %, which the prefilter at its
 * 5 - 6 px widens to holes of 1, 3, 5 and 7 px) cuts nearly every row and
 * column of a board 100 px wide; a hole with the same surface beyond it is
 * no outline, so each piece ended at a hole and kept the bound (the chair's
 * backrest: 10 400 of its 14 500 pixels over 1.5 times 3 times their rays'
 * length through it, 700 clean).  The surface goes on across such a hole:
 * rows [y0, y1) of z into zf, each hole of at most t->fill_px pixels along
 * its row whose pixels on both sides lie on one surface (within a step, as
 * two neighbours of a run) filled linearly between them, every other pixel
 * copied.  Both passes then read zf instead of z: their runs go on across
 * dropouts, while a hole at a silhouette (something farther beyond it) and a
 * shadow stay holes.  fill_px is DAO_THICKNESS_FILL_PX (the holes face_bound
 * looks across) where the prefilter's scale is at most that many pixels, 0
 * beyond (dao_thickness_setup_noise): there the holes are the sensor's own
 * structure (structured light and active stereo read 16 px, ToF 10 - 12: lost
 * dots, patches without texture, edges), and filling them made floors and box
 * faces read as slabs (boxes with active stereo +5 -> +7 % over GTAO).  Where
 * no scale is measured (a prefilter other than the domain one, or a fixed
 * noise model: dao_thickness_setup_noise is not called) init's
 * DAO_THICKNESS_FILL_PX stays: measured there (review, 64 rays), the fill was
 * neutral to slightly better on every input.
 */
#define DAO_THICKNESS_FILL_PX 8
void dao_thickness_fill_rows(const struct dao_thickness_setup *t, const float *z, float *zf,
			     int y0, int y1);

/* Rows [y0, y1): thick = min(max, the extent of the pixel's run along its row).
 * z (and thick) hold t->width x t->height floats: the passes look at the rows
 * and columns beside the ones they write. */
void dao_thickness_rows(const struct dao_thickness_setup *t, const float *z, float *thick,
			int y0, int y1);

/*
 * Columns [x0, x1), after the rows: thick = min(thick, the extent along the
 * column), and where pl is not NULL, pl->thick the same for those columns
 * (dao_gtao_planes_fill_thickness_cols).  Swept down and up the rows over
 * blocks of DAO_THICKNESS_COL_BLOCK columns side by side (thickness_passes.c), with
 * `scratch`: dao_thickness_cols_scratch(height) floats, which no other call uses at
 * the same time.
 */
#define DAO_THICKNESS_COL_BLOCK 64
struct dao_gtao_planes;
void dao_thickness_cols(const struct dao_thickness_setup *t, const float *z, float *thick,
			float *scratch, struct dao_gtao_planes *pl, int x0, int x1);

static inline size_t dao_thickness_cols_scratch(int height)
{
	return (size_t)DAO_THICKNESS_COL_BLOCK * (size_t)height;
}

/* The references for both (the oracle of tests/kernels/test_thickness.c): each
 * line walked pixel by pixel, the columns a row stride apart.  The same
 * result, bit for bit. */
void dao_thickness_rows_ref(const struct dao_thickness_setup *t, const float *z, float *thick,
			    int y0, int y1);
void dao_thickness_cols_ref(const struct dao_thickness_setup *t, const float *z, float *thick,
			    int x0, int x1);

#endif
