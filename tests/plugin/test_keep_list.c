/* SPDX-License-Identifier: MIT */
/*
 * The images sink's list of files to keep, against a plain array that does
 * the same thing slowly: random touches (new numbers and rewrites of ones
 * held) and removals of the oldest must give the same order and count.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "plugin/keep_list.h"

struct model {
	uint64_t *v; /* oldest first */
	size_t n;
};

static void model_touch(struct model *m, uint64_t num)
{
	for (size_t i = 0; i < m->n; i++) {
		if (m->v[i] == num) {
			memmove(m->v + i, m->v + i + 1, (m->n - i - 1) * sizeof(*m->v));
			m->n--;
			break;
		}
	}
	m->v[m->n++] = num;
}

static uint64_t rng(uint64_t *s)
{
	*s ^= *s << 13;
	*s ^= *s >> 7;
	*s ^= *s << 17;
	return *s;
}

static void run(uint64_t seed, uint64_t range, size_t keep, int ops)
{
	struct keep_list k;
	struct model m = {calloc(keep + 2, sizeof(uint64_t)), 0};
	assert_non_null(m.v);
	keep_list_init(&k);
	for (int i = 0; i < ops; i++) {
		uint64_t x = rng(&seed);
		/* mostly increasing numbers, as frames are, with rewrites and far jumps */
		uint64_t num = x % 8 == 0 ? x % range : (uint64_t)i % range;
		assert_int_equal(keep_list_touch(&k, num), 0);
		model_touch(&m, num);
		while (m.n > keep) {
			uint64_t got;
			assert_int_equal(keep_list_pop_oldest(&k, &got), 1);
			assert_true(got == m.v[0]);
			memmove(m.v, m.v + 1, (m.n - 1) * sizeof(*m.v));
			m.n--;
		}
		assert_int_equal(keep_list_count(&k), m.n);
	}
	/* drained in the model's order */
	for (size_t i = 0; i < m.n; i++) {
		uint64_t got;
		assert_int_equal(keep_list_pop_oldest(&k, &got), 1);
		assert_true(got == m.v[i]);
	}
	uint64_t none;
	assert_int_equal(keep_list_pop_oldest(&k, &none), 0);
	assert_int_equal(keep_list_count(&k), 0);
	keep_list_free(&k);
	free(m.v);
}

static void test_against_model(void **state)
{
	(void)state;
	run(1, 50, 10, 20000);       /* few numbers: rewrites all the time */
	run(2, 1000, 300, 20000);    /* the list grows past several reallocations */
	run(3, 1ull << 40, 5, 5000); /* huge numbers, tiny keep */
	run(4, 400, 1000, 5000);     /* keep above the range: nothing is ever removed */
}

static void test_rewrite_becomes_newest(void **state)
{
	(void)state;
	struct keep_list k;
	keep_list_init(&k);
	const uint64_t seq[] = {1, 2, 3, 1, 2, 3, 4};
	for (size_t i = 0; i < 7; i++)
		assert_int_equal(keep_list_touch(&k, seq[i]), 0);
	assert_int_equal(keep_list_count(&k), 4);
	uint64_t n;
	const uint64_t want[] = {1, 2, 3, 4};
	for (size_t i = 0; i < 4; i++) {
		assert_int_equal(keep_list_pop_oldest(&k, &n), 1);
		assert_true(n == want[i]);
	}
	keep_list_free(&k);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_against_model),
		cmocka_unit_test(test_rewrite_becomes_newest),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
