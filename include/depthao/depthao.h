/* SPDX-License-Identifier: MIT */
/*
 * libdepthao: depth frames to ambient occlusion, on the CPU (the AO core:
 * libc, libm and pthreads only; pkg-config depthao).  Files, recordings,
 * sources and sinks are libdepthao-io's: <depthao/io.h>, pkg-config depthao-io.
 *
 *   struct dao_camera cam;
 *   dao_camera_from_intrinsics(&cam, 640, 480, 525, 525, 319.5, 239.5, &err);
 *   struct dao_context *ctx;
 *   dao_context_create(&ctx, &cam, NULL, &err);         // default preset
 *   dao_context_process(ctx, &depth, NULL, 0, &ao, &err);
 *   dao_context_shade(ctx, &rgb, &err);
 *   dao_context_destroy(ctx);
 */
#ifndef DEPTHAO_H
#define DEPTHAO_H

#include <depthao/version.h>
#include <depthao/error.h>
#include <depthao/frame.h>
#include <depthao/camera.h>
#include <depthao/params.h>
#include <depthao/cpu.h>
#include <depthao/context.h>
#include <depthao/overlay.h>
#include <depthao/pose.h>

#include <depthao/api.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Version of the library at run time ("1.0.0"); DAO_VERSION_STRING is that of the
 * headers a program was built with (version.h). */
DAO_API const char *dao_version(void);

#ifdef __cplusplus
}
#endif
#endif
