/* SPDX-License-Identifier: MIT */
#ifndef DAO_PARAMS_PRESETS_H
#define DAO_PARAMS_PRESETS_H

#include <depthao/params.h>

/* Every parameter at the default of its row in the table (param_rows.h). */
extern const struct dao_params dao_param_defaults;

/* Fills `p` with quality preset `q` (a valid enum dao_quality): the
 * defaults, with the preset's own values over them. */
void dao_preset_fill(struct dao_params *p, enum dao_quality q);

#endif
