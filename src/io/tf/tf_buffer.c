/* SPDX-License-Identifier: MIT */
/* A tf buffer: frames, their parents, static and dynamic transforms (tf_buffer.h). */
#include "tf/tf_buffer.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error_internal.h"

/* A stamp within this of the time asked is taken as it is. */
#define EXACT_NS 1000u

struct sample {
	uint64_t stamp_ns;
	struct dao_rigid tr;
};

struct frame {
	char *name;
	int parent;                 /* -1: a root */
	int has_static;
	int strict;                 /* a DAO_TF_DYNAMIC sample came: never made static */
	struct dao_rigid fixed;     /* the static transform to the parent */
	struct sample *samples;     /* dynamic, sorted by dao_tf_buffer_finish */
	uint64_t count, cap;
};

struct dao_tf_buffer {
	struct frame *frames;
	uint32_t count, max_frames;
	int *slots;                 /* hash of names: frame index + 1, 0 empty */
	uint32_t slot_mask;
	uint64_t samples, max_samples;
	int *chain;                 /* a lookup's ancestors of its target */
};

int dao_tf_buffer_create(struct dao_tf_buffer **out, uint32_t max_frames, uint64_t max_samples,
			 struct dao_error *err)
{
	struct dao_tf_buffer *b = calloc(1, sizeof(*b));
	uint32_t slots = 16;
	while (slots < 2u * max_frames && slots < (1u << 30))
		slots <<= 1;
	if (b) {
		b->frames = calloc(max_frames ? max_frames : 1, sizeof(*b->frames));
		b->chain = calloc(max_frames ? max_frames : 1, sizeof(*b->chain));
		b->slots = calloc(slots, sizeof(*b->slots));
	}
	if (!b || !b->frames || !b->chain || !b->slots) {
		dao_tf_buffer_free(b);
		return dao_error_set(err, -ENOMEM, "out of memory for the tf buffer");
	}
	b->max_frames = max_frames;
	b->max_samples = max_samples;
	b->slot_mask = slots - 1;
	*out = b;
	return 0;
}

void dao_tf_buffer_free(struct dao_tf_buffer *b)
{
	if (!b)
		return;
	for (uint32_t i = 0; b->frames && i < b->count; i++) {
		free(b->frames[i].name);
		free(b->frames[i].samples);
	}
	free(b->frames);
	free(b->chain);
	free(b->slots);
	free(b);
}

static uint32_t hash(const char *s, size_t n)
{
	uint32_t h = 2166136261u; /* FNV-1a */
	for (size_t i = 0; i < n; i++)
		h = (h ^ (uint8_t)s[i]) * 16777619u;
	return h;
}

/* The slot of name (n bytes): a frame's (its index + 1 there) or the empty one for it. */
static uint32_t slot_of(const struct dao_tf_buffer *b, const char *s, size_t n)
{
	uint32_t k = hash(s, n) & b->slot_mask;
	while (b->slots[k]) {
		const char *name = b->frames[b->slots[k] - 1].name;
		if (strlen(name) == n && !memcmp(name, s, n))
			break;
		k = (k + 1) & b->slot_mask;
	}
	return k;
}

static void strip_slash(const char **s, size_t *n)
{
	if (*n > 0 && (*s)[0] == '/') {
		(*s)++;
		(*n)--;
	}
}

int dao_tf_buffer_find(const struct dao_tf_buffer *b, const char *name)
{
	size_t n = strlen(name);
	strip_slash(&name, &n);
	return b->slots[slot_of(b, name, n)] - 1;
}

/* The frame of that name in *idx, added if new: 0, 1 (a bad name: skipped, err) or < 0. */
static int intern(struct dao_tf_buffer *b, const char *s, size_t n, int *idx,
		  struct dao_error *err)
{
	strip_slash(&s, &n);
	if (n == 0 || n > DAO_TF_NAME_MAX || memchr(s, 0, n)) {
		dao_error_set(err, -EINVAL, "a frame name that is empty, longer than %d bytes or "
			      "holds a NUL", DAO_TF_NAME_MAX);
		return 1;
	}
	uint32_t k = slot_of(b, s, n);
	if (b->slots[k]) {
		*idx = b->slots[k] - 1;
		return 0;
	}
	if (b->count >= b->max_frames)
		return dao_error_set(err, -E2BIG, "the tf names more than %u frames (the limit)",
				     b->max_frames);
	struct frame *f = &b->frames[b->count];
	if (!(f->name = strndup(s, n)))
		return dao_error_set(err, -ENOMEM, "out of memory for the tf buffer");
	f->parent = -1;
	b->slots[k] = (int)++b->count;
	*idx = (int)b->count - 1;
	return 0;
}

static int push_sample(struct dao_tf_buffer *b, struct frame *f, uint64_t stamp_ns,
		       const struct dao_rigid *tr, struct dao_error *err)
{
	if (b->samples >= b->max_samples)
		return dao_error_set(err, -E2BIG, "the tf holds more than %llu dynamic transforms "
				     "(the limit)", (unsigned long long)b->max_samples);
	if (f->count == f->cap) {
		uint64_t cap = f->cap ? 2 * f->cap : 64;
		struct sample *s = realloc(f->samples, cap * sizeof(*s));
		if (!s)
			return dao_error_set(err, -ENOMEM, "out of memory for the tf buffer");
		f->samples = s;
		f->cap = cap;
	}
	f->samples[f->count++] = (struct sample){ stamp_ns, *tr };
	b->samples++;
	return 0;
}

int dao_tf_buffer_add(struct dao_tf_buffer *b, const char *parent, size_t plen,
		      const char *child, size_t clen, uint64_t stamp_ns,
		      const struct dao_rigid *tr, int time, struct dao_error *err)
{
	struct dao_rigid t = *tr;
	const char *why;
	if (dao_rigid_check(&t, 1e-3, &why) < 0) {
		dao_error_set(err, -EINVAL, "%s", why);
		return 1;
	}
	int p = -1, c = -1, r;
	if ((r = intern(b, parent, plen, &p, err)) != 0 || (r = intern(b, child, clen, &c, err)) != 0)
		return r;
	if (p == c) {
		dao_error_set(err, -EINVAL, "frame '%s' given as its own parent", b->frames[c].name);
		return 1;
	}
	struct frame *f = &b->frames[c];
	if (f->parent >= 0 && f->parent != p)
		return dao_error_set(err, -EINVAL, "frame '%s' has two parents in the tf, '%s' and "
				     "'%s' (a tf tree gives each frame one)", f->name,
				     b->frames[f->parent].name, b->frames[p].name);
	f->parent = p;
	if (time != DAO_TF_STATIC) {
		f->strict |= time == DAO_TF_DYNAMIC;
		return push_sample(b, f, stamp_ns, &t, err);
	}
	f->has_static = 1;
	f->fixed = t;
	return 0;
}

/*
 * Sorted by stamp, stable (of equal stamps the one added last stays last):
 * a bottom-up merge sort; messages mostly come in order, so it is skipped then.
 */
static int sort_samples(struct frame *f, struct dao_error *err)
{
	struct sample *s = f->samples, *tmp;
	const uint64_t n = f->count;
	int sorted = 1;
	for (uint64_t i = 1; i < n && sorted; i++)
		sorted = s[i - 1].stamp_ns <= s[i].stamp_ns;
	if (sorted)
		return 0;
	if (!(tmp = malloc(n * sizeof(*tmp))))
		return dao_error_set(err, -ENOMEM, "out of memory for the tf buffer");
	for (uint64_t w = 1; w < n; w *= 2) {
		for (uint64_t lo = 0; lo < n; lo += 2 * w) {
			uint64_t mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n;
			uint64_t i = lo, j = mid, k = lo;
			while (i < mid && j < hi)
				tmp[k++] = s[j].stamp_ns < s[i].stamp_ns ? s[j++] : s[i++];
			while (i < mid)
				tmp[k++] = s[i++];
			while (j < hi)
				tmp[k++] = s[j++];
		}
		memcpy(s, tmp, n * sizeof(*s));
	}
	free(tmp);
	return 0;
}

int dao_tf_buffer_finish(struct dao_tf_buffer *b, struct dao_error *err)
{
	for (uint32_t i = 0; i < b->count; i++) {
		struct frame *f = &b->frames[i];
		int rc = sort_samples(f, err);
		if (rc < 0)
			return rc;
		uint64_t w = 0; /* equal stamps: the last one */
		for (uint64_t r = 0; r < f->count; r++) {
			if (w > 0 && f->samples[w - 1].stamp_ns == f->samples[r].stamp_ns)
				w--;
			f->samples[w++] = f->samples[r];
		}
		b->samples -= f->count - w;
		f->count = w;
		if (w == 1 && !f->strict) { /* a lone DAO_TF_STATIC_IF_ALONE: static */
			f->fixed = f->samples[0].tr;
			f->has_static = 1;
			f->count = 0;
			b->samples--;
		}
	}
	return 0;
}

uint32_t dao_tf_buffer_frame_count(const struct dao_tf_buffer *b)
{
	return b->count;
}

const char *dao_tf_buffer_frame_name(const struct dao_tf_buffer *b, uint32_t i)
{
	return i < b->count ? b->frames[i].name : NULL;
}

uint64_t dao_tf_buffer_samples(const struct dao_tf_buffer *b)
{
	return b->samples;
}

void dao_tf_buffer_list(const struct dao_tf_buffer *b, char *buf, size_t cap)
{
	size_t len = 0;
	if (cap)
		buf[0] = 0;
	for (uint32_t i = 0; i < b->count && len + 8 < cap; i++) {
		int n = snprintf(buf + len, cap - len, "%s'%s'", i ? ", " : "", b->frames[i].name);
		if (n < 0 || (size_t)n >= cap - len) {
			snprintf(buf + len, cap - len, "%s...", i ? ", " : "");
			break;
		}
		len += (size_t)n;
	}
}

static int cycle(const struct dao_tf_buffer *b, int frame, struct dao_error *err)
{
	return dao_error_set(err, -ELOOP, "the tf has a cycle: frame '%s' is its own ancestor "
			     "(through '%s')", b->frames[frame].name,
			     b->frames[b->frames[frame].parent].name);
}

int dao_tf_buffer_root(const struct dao_tf_buffer *b, int frame, int *root, struct dao_error *err)
{
	int cur = frame;
	for (uint32_t steps = 0; b->frames[cur].parent >= 0; steps++) {
		if (steps > b->count)
			return cycle(b, frame, err);
		cur = b->frames[cur].parent;
	}
	*root = cur;
	return 0;
}

int dao_tf_buffer_connected(const struct dao_tf_buffer *b, int a, int c, struct dao_error *err)
{
	int ra = -1, rc = -1, r;
	if ((r = dao_tf_buffer_root(b, a, &ra, err)) < 0 ||
	    (r = dao_tf_buffer_root(b, c, &rc, err)) < 0)
		return r;
	return ra == rc;
}

static double seconds(uint64_t ns)
{
	return (double)ns * 1e-9;
}

/* The transform of frame f to its parent at t_ns (tf_buffer.h's rules). */
static int edge_at(const struct dao_tf_buffer *b, int fi, uint64_t t_ns, uint64_t max_gap_ns,
		   struct dao_rigid *out, struct dao_error *err)
{
	const struct frame *f = &b->frames[fi];
	const char *pn = b->frames[f->parent].name;
	if (f->count == 0) {
		*out = f->fixed; /* only static ones */
		return 0;
	}
	uint64_t lo = 0, hi = f->count;
	while (lo < hi) { /* the first sample at or after t */
		uint64_t mid = lo + (hi - lo) / 2;
		if (f->samples[mid].stamp_ns < t_ns)
			lo = mid + 1;
		else
			hi = mid;
	}
	if (lo < f->count && f->samples[lo].stamp_ns - t_ns <= EXACT_NS) {
		*out = f->samples[lo].tr;
		return 0;
	}
	if (lo > 0 && t_ns - f->samples[lo - 1].stamp_ns <= EXACT_NS) {
		*out = f->samples[lo - 1].tr;
		return 0;
	}
	if (lo == 0 || lo == f->count)
		return dao_error_set(err, -ENOENT, "no transform '%s' -> '%s' at %.6f s: it is %s "
				     "its %s (%.6f s)", pn, f->name, seconds(t_ns),
				     lo ? "after" : "before", lo ? "last" : "first",
				     seconds(f->samples[lo ? lo - 1 : 0].stamp_ns));
	const struct sample *a = &f->samples[lo - 1], *c = &f->samples[lo];
	if (c->stamp_ns - a->stamp_ns > max_gap_ns)
		return dao_error_set(err, -ENOENT, "no transform '%s' -> '%s' at %.6f s: the "
				     "nearest are at %.6f and %.6f s, farther apart than %.3f s",
				     pn, f->name, seconds(t_ns), seconds(a->stamp_ns),
				     seconds(c->stamp_ns), seconds(max_gap_ns));
	dao_rigid_interpolate(&a->tr, &c->tr,
			      (double)(t_ns - a->stamp_ns) / (double)(c->stamp_ns - a->stamp_ns), out);
	return 0;
}

/* The transform of `from` into its ancestor `to` at t_ns. */
static int up_to(const struct dao_tf_buffer *b, int from, int to, uint64_t t_ns,
		 uint64_t max_gap_ns, struct dao_rigid *out, struct dao_error *err)
{
	dao_rigid_identity(out);
	for (int cur = from; cur != to; cur = b->frames[cur].parent) {
		struct dao_rigid e;
		int r = edge_at(b, cur, t_ns, max_gap_ns, &e, err);
		if (r < 0)
			return r;
		dao_rigid_compose(&e, out, out);
	}
	return 0;
}

int dao_tf_buffer_lookup(struct dao_tf_buffer *b, int target, int source, uint64_t t_ns,
			 uint64_t max_gap_ns, struct dao_rigid *out, struct dao_error *err)
{
	int r = dao_tf_buffer_connected(b, target, source, err);
	if (r <= 0)
		return r < 0 ? r : dao_error_set(err, -ENOTCONN, "frames '%s' and '%s' are not "
						 "connected in the tf", b->frames[source].name,
						 b->frames[target].name);
	uint32_t n = 0; /* target's ancestors, itself first (acyclic: checked above) */
	for (int cur = target; cur >= 0; cur = b->frames[cur].parent)
		b->chain[n++] = cur;
	int lca = -1;
	for (int cur = source; lca < 0 && cur >= 0; cur = b->frames[cur].parent)
		for (uint32_t i = 0; i < n && lca < 0; i++)
			lca = b->chain[i] == cur ? cur : -1;
	struct dao_rigid s, t;
	if ((r = up_to(b, source, lca, t_ns, max_gap_ns, &s, err)) < 0 ||
	    (r = up_to(b, target, lca, t_ns, max_gap_ns, &t, err)) < 0)
		return r;
	dao_rigid_inverse(&t, &t);
	dao_rigid_compose(&t, &s, out);
	return 0;
}
