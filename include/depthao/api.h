/* SPDX-License-Identifier: MIT */
#ifndef DEPTHAO_API_H
#define DEPTHAO_API_H

/* Marks the functions libdepthao exports; everything else stays internal. */
#if defined(__GNUC__) || defined(__clang__)
#define DAO_API __attribute__((visibility("default")))
#else
#define DAO_API
#endif

#endif
