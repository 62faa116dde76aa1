/* SPDX-License-Identifier: MIT */
/*
 * The parameter table, one row per field of struct dao_params:
 *   ROW(name, help, unit, type, field, min, max, enum names, flags, default)
 * The only place a parameter and its default are written down: params.c
 * includes this file twice, once to build the public table
 * (dao_param_table()), once to build the defaults (dao_param_defaults),
 * which the quality presets (presets.c) start from and override.  min and
 * max are inclusive (FLOAT, INT, COLOR); the enum names are NULL-terminated
 * arrays of params.c; flags are RT (runtime) or SH (runtime, shading only).
 *
 * No include guard: the includer defines ROW.
 */
ROW("depth-min", "nearest valid depth; nearer pixels count as no data", "m",
    FLOAT, depth_min, 0.0, 1000.0, NULL, RT, 0.05f)
ROW("depth-max", "farthest valid depth; farther pixels count as no data", "m",
    FLOAT, depth_max, 0.001, 1000.0, NULL, RT, 20.0f)
ROW("prefilter", "depth prefilter before normals and AO", NULL,
    ENUM, prefilter, 0, 0, prefilter_names, RT, DAO_PREFILTER_DOMAIN)
ROW("depth-noise", "sensor noise model sigma(z) = k z^2 with noise-model=fixed; k in 1/m (Kinect v1 ~0.0012)", "1/m",
    FLOAT, depth_noise, 0.0, 0.1, NULL, RT, 0.0012f)
ROW("prefilter-radius", "footprint of the bilateral prefilter", "px",
    INT, prefilter_radius, 1, 8, NULL, RT, 3)
ROW("prefilter-scale", "domain prefilter: spatial scale sigma_s with noise-model=fixed (its cost does not depend on it)", "px",
    FLOAT, prefilter_scale, 0.5, 64.0, NULL, RT, 4.0f)
ROW("prefilter-range", "domain prefilter: neighbours differing by more than about this many noise sigmas are not averaged", NULL,
    FLOAT, prefilter_range, 0.5, 20.0, NULL, RT, 3.0f)
ROW("prefilter-iterations", "domain prefilter: iterations of a vertical and a horizontal pass", NULL,
    INT, prefilter_iterations, 1, 5, NULL, RT, 2)
ROW("noise-model", "depth noise: fixed (depth-noise), auto (measured per frame and region; drives prefilter, normals and denoise), auto-prefilter (drives the prefilter only)", NULL,
    ENUM, noise_model, 0, 0, noise_model_names, RT, DAO_NOISE_MODEL_AUTO)
ROW("normals", "how normals are derived from depth", NULL,
    ENUM, normals, 0, 0, normals_names, RT, DAO_NORMALS_WIDE)
ROW("normal-radius", "footprint of wide normals (noise-model=auto: from the measured noise)", "px",
    INT, normal_radius, 1, 8, NULL, RT, 4)
ROW("algorithm", "gtao (ground-truth AO), vbao (visibility bitmask: finite thickness), hbao, ssao, edl (eye-dome lighting, not AO), or none (the filtered depth only: no normals, AO or shading)", NULL,
    ENUM, algorithm, 0, 5, algorithm_names, RT, DAO_ALGORITHM_GTAO)
ROW("radius", "world-space AO radius", "m",
    FLOAT, radius, 0.01, 100.0, NULL, RT, 0.5f)
ROW("falloff", "fraction of the radius over which occluders fade out", NULL,
    FLOAT, falloff, 0.0, 1.0, NULL, RT, 0.2f)
ROW("slices", "slice directions per pixel", NULL,
    INT, slices, 1, DAO_MAX_SLICES, NULL, RT, 2)
ROW("steps", "horizon samples per side of each slice", NULL,
    INT, steps, 1, DAO_MAX_STEPS, NULL, RT, 6)
ROW("thickness", "thin-occluder heuristic: pull of later, lower samples on the horizon (0 = surfaces infinitely thick)", NULL,
    FLOAT, thickness, 0.0, 1.0, NULL, RT, 0.0f)
ROW("max-screen-radius", "cap of the radius projected on screen", "px",
    FLOAT, max_screen_radius, 1.0, 4096.0, NULL, RT, 160.0f)
ROW("min-screen-radius", "below this projected radius the pixel is left open", "px",
    FLOAT, min_screen_radius, 0.0, 64.0, NULL, RT, 0.0f)
ROW("distribution-power", "sample spacing t^power; > 1 packs samples near the pixel", NULL,
    FLOAT, distribution_power, 1.0, 4.0, NULL, RT, 1.0f)
ROW("noise", "rotation of slices and jitter of steps: tile (4x4, the fast kernel), or per pixel ign, r2; none", NULL,
    ENUM, noise, 0, 0, noise_names, RT, DAO_NOISE_TILE)
ROW("final-power", "visibility is raised to this power", NULL,
    FLOAT, final_power, 0.1, 8.0, NULL, RT, 1.0f)
ROW("albedo", "multi-bounce fit (Jimenez 2016) for this albedo; 0 = off", NULL,
    FLOAT, albedo, 0.0, 0.95, NULL, RT, 0.0f)
ROW("invalid-value", "visibility written where there is no depth", NULL,
    FLOAT, invalid_value, 0.0, 1.0, NULL, RT, 1.0f)
ROW("strength", "hbao, ssao, edl: visibility = 1 - strength x occlusion", NULL,
    FLOAT, strength, 0.0, 10.0, NULL, RT, 1.0f)
ROW("hbao-bias", "hbao: tangent bias angle; hides self-occlusion of flat surfaces", "deg",
    FLOAT, hbao_bias, 0.0, 60.0, NULL, RT, 20.0f)
ROW("ssao-min", "ssao: a sample is occluded when the surface is in front of it by more than this", "m",
    FLOAT, ssao_min, 0.0, 1.0, NULL, RT, 0.02f)
ROW("ssao-max", "ssao: ... and by less than this (farther surfaces are not its occluders)", "m",
    FLOAT, ssao_max, 0.001, 100.0, NULL, RT, 0.5f)
ROW("edl-radius", "edl: distance of the neighbours compared", "px",
    FLOAT, edl_radius, 0.5, 16.0, NULL, RT, 1.5f)
ROW("vbao-thickness", "vbao: thickness assumed behind every visible surface", "m",
    FLOAT, vbao_thickness, 0.001, 10.0, NULL, RT, 0.2f)
ROW("vbao-thickness-mode", "vbao: constant (vbao-thickness behind every surface) or image (each surface's visible extent, at most vbao-thickness-max)", NULL,
    ENUM, vbao_thickness_mode, 0, 0, vbao_thickness_names, RT, DAO_VBAO_THICKNESS_IMAGE)
ROW("vbao-thickness-max", "vbao, vbao-thickness-mode=image: upper bound of the thickness estimated from the image", "m",
    FLOAT, vbao_thickness_max, 0.001, 10.0, NULL, RT, 0.5f)
ROW("temporal", "streams: share of the per-pixel AO history in each output (0 = off; 0.8 settles in ~5 frames)", NULL,
    FLOAT, temporal, 0.0, 0.98, NULL, RT, 0.0f)
ROW("temporal-reject", "streams: the AO history of a pixel is dropped where its depth changed by more than this share", NULL,
    FLOAT, temporal_reject, 0.001, 1.0, NULL, RT, 0.02f)
ROW("depth-temporal", "streams: share of the per-pixel 1/z history in the depth, before the prefilter (0 = off; streams of the CLI and daemon: 0.8)", NULL,
    FLOAT, depth_temporal, 0.0, 0.98, NULL, RT, 0.0f)
ROW("depth-temporal-reject", "streams: the depth history of a pixel restarts where a sample differs from it by more than this many sigma of the noise model", NULL,
    FLOAT, depth_temporal_reject, 0.5, 100.0, NULL, RT, 3.0f)
ROW("depth-temporal-persist", "streams: frames a pixel that lost its depth keeps the filtered value (0 = never invent depth)", "frames",
    INT, depth_temporal_persist, 0, 30, NULL, RT, 0)
ROW("depth-temporal-motion", "streams: follow the camera's motion with the 1/z history: off, icp (the motion estimated from the depth; where refused, as off), source (the motion between the poses given with the frames), or source+icp (ICP seeded with it)", NULL,
    ENUM, depth_temporal_motion, 0, 0, depth_motion_names, RT, DAO_DEPTH_MOTION_OFF)
ROW("depth-fill", "filtered depth output only (dao_context_get_depth, algorithm none): holes of at most this many pixels along a row filled linearly where the depths on both sides lie on one surface, within 3 %; the normals and AO never read them (0 = off)", "px",
    INT, depth_fill, 0, 64, NULL, RT, 0)
ROW("noise-interval", "noise-model=auto: frames between full measurements of the noise, with a check of every frame that measures the cells the scene moved in, and all after a cut (1 = every frame; streams of the CLI and daemon: 15)", "frames",
    INT, noise_interval, 1, 3600, NULL, RT, 1)
ROW("threads", "threads per context (0 = one per available CPU)", NULL,
    INT, threads, 0, 256, NULL, RT, 0)
ROW("simd", "kernels: auto (best for this CPU), reference (scalar oracle) or an instruction set", NULL,
    ENUM, simd, 0, 0, dao_simd_names, RT, DAO_SIMD_AUTO)
ROW("denoise", "spatial filter of the AO", NULL,
    ENUM, denoise, 0, 0, denoise_names, RT, DAO_DENOISE_PLANE)
ROW("denoise-radius", "radius of the bilateral denoise", "px",
    INT, denoise_radius, 1, 16, NULL, RT, 4)
ROW("denoise-sharpness", "depth tolerance of the denoise in units of the depth noise", NULL,
    FLOAT, denoise_sharpness, 0.1, 100.0, NULL, RT, 4.0f)
ROW("shade", "shaded image: lambert head light, depth colormap, or AO alone", NULL,
    ENUM, shade, 0, 0, shade_names, SH, DAO_SHADE_LAMBERT)
ROW("near", "colormap near depth; 0 = nearest depth in the frame", "m",
    FLOAT, near_m, 0.0, 1000.0, NULL, SH, 0.0f)
ROW("far", "colormap far depth; 0 = farthest depth in the frame", "m",
    FLOAT, far_m, 0.0, 1000.0, NULL, SH, 0.0f)
ROW("shade-power", "shaded = mix(occlusion colour, colour, AO^power)", NULL,
    FLOAT, shade_power, 0.0, 8.0, NULL, SH, 1.0f)
ROW("occlusion-color", "colour of full occlusion, RRGGBB", NULL,
    COLOR, occlusion_color, 0, 0xffffff, NULL, SH, 0x000000)
