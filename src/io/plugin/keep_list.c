/* SPDX-License-Identifier: MIT */
#include "plugin/keep_list.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

void keep_list_init(struct keep_list *k)
{
	memset(k, 0, sizeof(*k));
	k->free_head = k->head = k->tail = KEEP_NONE;
}

void keep_list_free(struct keep_list *k)
{
	free(k->nodes);
	free(k->slots);
	keep_list_init(k);
}

/* Fibonacci hashing of the number into nslots (a power of two). */
static uint32_t home(const struct keep_list *k, uint64_t num)
{
	return (uint32_t)((num * 0x9E3779B97F4A7C15ull) >> 32) & (k->nslots - 1);
}

/* The slot holding `num`, or the empty slot where it would go. */
static uint32_t find_slot(const struct keep_list *k, uint64_t num)
{
	uint32_t i = home(k, num);
	while (k->slots[i] && k->nodes[k->slots[i] - 1].num != num)
		i = (i + 1) & (k->nslots - 1);
	return i;
}

/* Empties slot i and moves later entries of its probe run back (no tombstones). */
static void clear_slot(struct keep_list *k, uint32_t i)
{
	const uint32_t mask = k->nslots - 1;
	uint32_t j = i;
	k->slots[i] = 0;
	for (;;) {
		j = (j + 1) & mask;
		if (!k->slots[j])
			return;
		uint32_t h = home(k, k->nodes[k->slots[j] - 1].num);
		/* move j to i if its home is not cyclically within (i, j] */
		if ((i <= j) ? (h <= i || h > j) : (h <= i && h > j)) {
			k->slots[i] = k->slots[j];
			k->slots[j] = 0;
			i = j;
		}
	}
}

static int grow(struct keep_list *k)
{
	uint32_t cap = k->cap ? 2 * k->cap : 64;
	if (cap > UINT32_MAX / 4)
		return -ENOMEM;
	struct keep_node *nodes = realloc(k->nodes, (size_t)cap * sizeof(*nodes));
	if (!nodes)
		return -ENOMEM;
	k->nodes = nodes;
	uint32_t nslots = 4 * cap; /* load factor at most 1/4 */
	uint32_t *slots = calloc(nslots, sizeof(*slots));
	if (!slots)
		return -ENOMEM; /* nodes grew, which is harmless */
	free(k->slots);
	k->slots = slots;
	k->nslots = nslots;
	k->cap = cap;
	for (uint32_t n = k->head; n != KEEP_NONE; n = k->nodes[n].next)
		k->slots[find_slot(k, k->nodes[n].num)] = n + 1;
	return 0;
}

static void unlink_node(struct keep_list *k, uint32_t n)
{
	struct keep_node *x = &k->nodes[n];
	if (x->prev != KEEP_NONE)
		k->nodes[x->prev].next = x->next;
	else
		k->head = x->next;
	if (x->next != KEEP_NONE)
		k->nodes[x->next].prev = x->prev;
	else
		k->tail = x->prev;
}

static void append_node(struct keep_list *k, uint32_t n)
{
	k->nodes[n].prev = k->tail;
	k->nodes[n].next = KEEP_NONE;
	if (k->tail != KEEP_NONE)
		k->nodes[k->tail].next = n;
	else
		k->head = n;
	k->tail = n;
}

int keep_list_touch(struct keep_list *k, uint64_t num)
{
	if (k->nslots) {
		uint32_t s = find_slot(k, num);
		if (k->slots[s]) { /* rewritten: the newest now */
			uint32_t n = k->slots[s] - 1;
			unlink_node(k, n);
			append_node(k, n);
			return 0;
		}
	}
	uint32_t n;
	if (k->free_head != KEEP_NONE) {
		n = k->free_head;
		k->free_head = k->nodes[n].next;
	} else {
		if (k->used == k->cap && grow(k) < 0)
			return -ENOMEM;
		n = k->used++;
	}
	k->nodes[n].num = num;
	append_node(k, n);
	k->slots[find_slot(k, num)] = n + 1;
	k->count++;
	return 0;
}

int keep_list_pop_oldest(struct keep_list *k, uint64_t *num)
{
	if (k->head == KEEP_NONE)
		return 0;
	uint32_t n = k->head;
	*num = k->nodes[n].num;
	clear_slot(k, find_slot(k, *num));
	unlink_node(k, n);
	k->nodes[n].next = k->free_head;
	k->free_head = n;
	k->count--;
	return 1;
}
