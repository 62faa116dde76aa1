/* SPDX-License-Identifier: MIT */
/*
 * The numbered files a sink keeps, oldest first: a list in the order the
 * files were (re)written, with an index by number, so rewriting file n
 * (a looped recording numbers its frames again) makes n the newest instead
 * of leaving a stale entry that would later remove the fresh file.  All
 * operations are O(1) on average; memory grows to the largest count held
 * and is reused after that.
 */
#ifndef DAO_PLUGIN_KEEP_LIST_H
#define DAO_PLUGIN_KEEP_LIST_H

#include <stddef.h>
#include <stdint.h>

struct keep_node {
	uint64_t num;
	uint32_t prev, next;     /* KEEP_NONE at the ends */
};

struct keep_list {
	struct keep_node *nodes;
	uint32_t cap, used;      /* nodes allocated, nodes ever handed out */
	uint32_t free_head;      /* a list of released nodes through next */
	uint32_t head, tail;     /* oldest, newest */
	uint32_t count;
	uint32_t *slots;         /* open addressing: node index + 1, 0 = empty */
	uint32_t nslots;         /* a power of two, > 2 x cap */
};

#define KEEP_NONE UINT32_MAX

void keep_list_init(struct keep_list *k);
void keep_list_free(struct keep_list *k);

/* Makes `num` the newest (adding it if new); 0 or -ENOMEM. */
int keep_list_touch(struct keep_list *k, uint64_t num);

/* Removes and returns the oldest in *num: 1, or 0 if the list is empty. */
int keep_list_pop_oldest(struct keep_list *k, uint64_t *num);

static inline uint32_t keep_list_count(const struct keep_list *k)
{
	return k->count;
}

#endif
