/* SPDX-License-Identifier: MIT */
/*
 * The thickness plane split by column phase (kernels/gtao_planes.h) a block
 * of columns at a time, as the pipeline does after the column pass, against
 * the split of whole rows: the same entries, bit for bit, for blocks that
 * start on any column phase; and the entries outside the block untouched.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "core/half.h"
#include "kernels/gtao_planes.h"

static size_t plane_floats(const struct dao_gtao_planes *pl)
{
	return ((size_t)pl->height + 2) * 4 * (size_t)pl->stride4;
}

static void expect_cols_as_rows(int w, int h, const int *cuts, int ncuts)
{
	struct dao_gtao_planes a, b;
	assert_int_equal(dao_gtao_planes_init(&a, w, h, 20.0f), 0);
	assert_int_equal(dao_gtao_planes_init(&b, w, h, 20.0f), 0);
	assert_int_equal(dao_gtao_planes_init_thickness(&a), 0);
	assert_int_equal(dao_gtao_planes_init_thickness(&b), 0);
	float *t = malloc((size_t)w * h * sizeof(float));
	assert_non_null(t);
	for (int i = 0; i < w * h; i++)
		t[i] = 0.001f * (float)(i + 1); /* every pixel its own value */
	dao_gtao_planes_fill_thickness(&a, t, 0, h);
	for (int c = 0; c + 1 < ncuts; c++) {
		/* before its block: the columns of the block are still 0 (fresh plane) */
		const int x = cuts[c];
		assert_true(dao_gtao_thick_row(&b, h - 1, x & 3)[x >> 2] == 0);
		dao_gtao_planes_fill_thickness_cols(&b, t, 0, h, cuts[c], cuts[c + 1]);
		assert_true(dao_gtao_thick_row(&b, h - 1, x & 3)[x >> 2] ==
			    dao_half_from_float(t[(size_t)(h - 1) * w + x]));
		/* ... and the next block's first column not yet */
		const int xn = cuts[c + 1];
		if (xn < w)
			assert_true(dao_gtao_thick_row(&b, 0, xn & 3)[xn >> 2] == 0);
	}
	assert_memory_equal(a.thick, b.thick, plane_floats(&a) * sizeof(uint16_t));
	free(t);
	dao_gtao_planes_free(&b);
	dao_gtao_planes_free(&a);
}

static void test_thickness_by_column_blocks(void **state)
{
	(void)state;
	/* the pipeline's blocks of 64 on 640 columns */
	const int c640[] = { 0, 64, 128, 192, 256, 320, 384, 448, 512, 576, 640 };
	expect_cols_as_rows(640, 48, c640, (int)(sizeof c640 / sizeof c640[0]));
	/* blocks starting on every phase, a width no multiple of 4 or of a block */
	const int c203[] = { 0, 1, 2, 3, 6, 13, 64, 101, 130, 202, 203 };
	expect_cols_as_rows(203, 37, c203, (int)(sizeof c203 / sizeof c203[0]));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_thickness_by_column_blocks),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
