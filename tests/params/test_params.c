/* SPDX-License-Identifier: MIT */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "common/cmocka_all.h"
#include "common/test_common.h"

static void test_presets_valid(void **state)
{
	(void)state;
	struct dao_params p;
	for (int q = 0; q < DAO_QUALITY_COUNT; q++) {
		dao_params_init(&p, (enum dao_quality)q);
		struct dao_error err;
		if (dao_params_validate(&p, &err))
			fail_msg("preset %s invalid: %s", dao_quality_name((enum dao_quality)q), err.message);
	}
	/* more quality means more samples */
	struct dao_params lo, hi;
	dao_params_init(&lo, DAO_QUALITY_LOW);
	dao_params_init(&hi, DAO_QUALITY_ULTRA);
	assert_true(hi.slices * hi.steps > lo.slices * lo.steps);
	enum dao_quality q;
	assert_int_equal(dao_quality_parse("default", &q, NULL), 0);
	assert_int_equal(q, DAO_QUALITY_DEFAULT);
	assert_int_equal(dao_quality_parse("ultra", &q, NULL), 0);
	assert_int_equal(q, DAO_QUALITY_ULTRA);
	struct dao_error err;
	assert_int_equal(dao_quality_parse("best", &q, &err), -EINVAL);
	assert_non_null(strstr(err.message, "best"));
	assert_null(dao_quality_name(DAO_QUALITY_COUNT));
}

/* Every table entry: get -> set -> get gives the same text; the field changes. */
static void test_table_round_trip(void **state)
{
	(void)state;
	size_t n;
	const struct dao_param_info *t = dao_param_table(&n);
	assert_true(n >= 20);
	for (size_t k = 0; k < n; k++) {
		struct dao_params p;
		dao_params_init(&p, DAO_QUALITY_DEFAULT);
		char before[64], after[64], value[64];
		assert_int_equal(dao_params_get(&p, t[k].name, before, sizeof before, NULL), 0);
		/* a different valid value */
		switch (t[k].type) {
		case DAO_PARAM_FLOAT:
		case DAO_PARAM_INT:
			snprintf(value, sizeof value, "%g", t[k].max);
			if (strcmp(value, before) == 0)
				snprintf(value, sizeof value, "%g", t[k].min);
			break;
		case DAO_PARAM_ENUM:
			snprintf(value, sizeof value, "%s",
				 strcmp(before, t[k].enum_names[0]) ? t[k].enum_names[0] : t[k].enum_names[1]);
			break;
		case DAO_PARAM_COLOR:
			snprintf(value, sizeof value, "#%s", strcmp(before, "123abc") ? "123abc" : "000000");
			break;
		}
		struct dao_error err;
		if (dao_params_set(&p, t[k].name, value, &err))
			fail_msg("%s = %s: %s", t[k].name, value, err.message);
		assert_int_equal(dao_params_get(&p, t[k].name, after, sizeof after, NULL), 0);
		if (strcmp(after, before) == 0)
			fail_msg("%s did not change from %s with '%s'", t[k].name, before, value);
		const char *expect = value[0] == '#' ? value + 1 : value;
		if (strcmp(after, expect) != 0)
			fail_msg("%s: set '%s', got back '%s'", t[k].name, expect, after);
		/* the table's name is found with underscores too */
		char us[64];
		snprintf(us, sizeof us, "%s", t[k].name);
		for (char *c = us; *c; c++)
			if (*c == '-')
				*c = '_';
		assert_ptr_equal(dao_param_find(us), &t[k]);
	}
}

static void expect_set_error(const char *name, const char *value, const char *needle)
{
	struct dao_params p, orig;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	orig = p;
	struct dao_error err = { 0 };
	assert_int_equal(dao_params_set(&p, name, value, &err), -EINVAL);
	assert_memory_equal(&p, &orig, sizeof p); /* nothing changed */
	if (!strstr(err.message, needle))
		fail_msg("%s=%s: message '%s' lacks '%s'", name, value ? value : "(null)", err.message,
			 needle);
}

static void test_set_errors(void **state)
{
	(void)state;
	expect_set_error("radius", "-1", "radius");
	expect_set_error("radius", "nan", "radius");
	expect_set_error("radius", "0.5m", "not a number");
	expect_set_error("radius", "", "needs a value");
	expect_set_error("radius", NULL, "needs a value");
	expect_set_error("slices", "0", "out of range");
	expect_set_error("slices", "2.5", "not an integer");
	expect_set_error("steps", "1000", "out of range");
	expect_set_error("denoise", "fancy", "none, plane, bilateral");
	expect_set_error("occlusion-color", "red", "RRGGBB");
	expect_set_error("occlusion-color", "1234567", "RRGGBB");
	expect_set_error("no-such-thing", "1", "unknown parameter");
	char buf[4];
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	struct dao_error err;
	assert_int_equal(dao_params_get(&p, "denoise", buf, sizeof buf, &err), -EOVERFLOW);
	assert_int_equal(dao_params_get(&p, "nope", buf, sizeof buf, &err), -EINVAL);
}

static void expect_invalid(const struct dao_params *p, const char *needle)
{
	struct dao_error err;
	assert_int_equal(dao_params_validate(p, &err), -EINVAL);
	if (!strstr(err.message, needle))
		fail_msg("message '%s' lacks '%s'", err.message, needle);
}

static void test_validate(void **state)
{
	(void)state;
	struct dao_params p;
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.radius = NAN;
	expect_invalid(&p, "radius");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.radius = -0.5f;
	expect_invalid(&p, "radius");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.slices = 0;
	expect_invalid(&p, "slices");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.denoise = 7;
	expect_invalid(&p, "denoise");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.occlusion_color = 0x1000000;
	expect_invalid(&p, "occlusion-color");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.depth_min = 5, p.depth_max = 1;
	expect_invalid(&p, "depth-min");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.near_m = 3, p.far_m = 2;
	expect_invalid(&p, "near");
	dao_params_init(&p, DAO_QUALITY_DEFAULT);
	p.min_screen_radius = 50, p.max_screen_radius = 10;
	expect_invalid(&p, "min-screen-radius");
	expect_invalid(NULL, "NULL");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_presets_valid),
		cmocka_unit_test(test_table_round_trip),
		cmocka_unit_test(test_set_errors),
		cmocka_unit_test(test_validate),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
