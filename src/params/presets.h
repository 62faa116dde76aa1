/* SPDX-License-Identifier: MIT */
#ifndef DAO_PARAMS_PRESETS_H
#define DAO_PARAMS_PRESETS_H

#include <depthao/params.h>

/* Fills `p` with quality preset `q` (a valid enum dao_quality). */
void dao_preset_fill(struct dao_params *p, enum dao_quality q);

#endif
