/* SPDX-License-Identifier: MIT */
/*
 * libdepthao-io: frames in and out of files, recordings and devices.  PNG and
 * PLY files, output files written whole, OpenNI recordings (.oni), ROS bags,
 * colour decoding, and the plugin interface with its built-in sources and
 * sinks.  Built on libdepthao (<depthao/depthao.h>, the AO core, which needs
 * none of this); link both with `pkg-config --cflags --libs depthao-io`.
 *
 *   struct dao_frame depth = { 0 };
 *   dao_png_read_depth("depth.png", 0.001f, &depth, &err);
 *   ... dao_context_process(ctx, &depth, NULL, 0, &ao, &err) (libdepthao) ...
 *   dao_png_write("ao.png", &ao, &err);
 */
#ifndef DEPTHAO_IO_H
#define DEPTHAO_IO_H

#include <depthao/png.h>
#include <depthao/ply.h>
#include <depthao/oni.h>
#include <depthao/plugin.h>
#include <depthao/uri.h>
#include <depthao/output_file.h>

#endif
