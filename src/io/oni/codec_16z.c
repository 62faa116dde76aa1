/* SPDX-License-Identifier: MIT */
#include "oni/codec_16z.h"

#include <errno.h>
#include <string.h>

size_t dao_16z_bound(size_t n, int with_table)
{
	/* 2 bytes for the first value, at most 3 per further value, 1 to close */
	size_t b = 2 + 3 * n + 1;
	if (with_table)
		b += 2 + 2 * 65536;
	return b;
}

struct enc {
	uint8_t *out;
	size_t cap, pos;
	int half;       /* a nibble is pending in `ch` */
	uint8_t ch;
	unsigned zeros; /* pending 0x66 bytes */
};

static int put(struct enc *e, uint8_t b)
{
	if (e->pos >= e->cap)
		return -ENOSPC;
	e->out[e->pos++] = b;
	return 0;
}

static int flush_zeros(struct enc *e)
{
	int r = 0;
	if (e->zeros)
		r = put(e, (uint8_t)(0xE0 + e->zeros));
	e->zeros = 0;
	return r;
}

/* One value of the stream after the first; `prev`, `cur` < 32768. */
static int enc_value(struct enc *e, uint16_t prev, uint16_t cur)
{
	int d = (int)prev - (int)cur;
	int ad = d < 0 ? -d : d;
	int r;

	if (ad <= 6) {
		if (!e->half) {
			e->ch = (uint8_t)((d + 6) << 4);
			e->half = 1;
			return 0;
		}
		e->ch = (uint8_t)(e->ch + d + 6);
		e->half = 0;
		if (e->ch == 0x66) {
			if (++e->zeros == 15)
				return flush_zeros(e);
			return 0;
		}
		if ((r = flush_zeros(e)) < 0)
			return r;
		return put(e, e->ch);
	}
	if ((r = flush_zeros(e)) < 0)
		return r;
	if ((r = put(e, e->half ? (uint8_t)(e->ch + 0x0F) : 0xFF)) < 0)
		return r;
	e->half = 0;
	if (ad <= 63)
		return put(e, (uint8_t)(d + 192));
	if ((r = put(e, (uint8_t)(cur >> 8))) < 0)
		return r;
	return put(e, (uint8_t)(cur & 0xFF));
}

/*
 * The closing order differs from OpenNI's own encoder, which writes a pending
 * half byte before a pending run of unchanged pairs and so swaps the last
 * values of a frame that ends that way; the run came first, so it goes first.
 */
static int enc_finish(struct enc *e)
{
	int r;
	if ((r = flush_zeros(e)) < 0)
		return r;
	if (e->half)
		return put(e, (uint8_t)(e->ch + 0x0D));
	return 0;
}

static long enc_stream(const uint16_t *v, size_t n, const uint16_t *map, uint8_t *out,
		       size_t cap)
{
	struct enc e = {out, cap, 0, 0, 0, 0};
	uint16_t prev = map ? map[v[0]] : v[0];
	int r;

	if (prev >= 0x8000)
		return -ERANGE;
	if ((r = put(&e, (uint8_t)(prev & 0xFF))) < 0 || (r = put(&e, (uint8_t)(prev >> 8))) < 0)
		return r;
	for (size_t i = 1; i < n; i++) {
		uint16_t cur = map ? map[v[i]] : v[i];
		if (cur >= 0x8000)
			return -ERANGE;
		if ((r = enc_value(&e, prev, cur)) < 0)
			return r;
		prev = cur;
	}
	if ((r = enc_finish(&e)) < 0)
		return r;
	return (long)e.pos;
}

long dao_16z_encode(const uint16_t *in, size_t n, uint8_t *out, size_t cap)
{
	if (n == 0)
		return -EINVAL;
	return enc_stream(in, n, NULL, out, cap);
}

long dao_16zt_encode(const uint16_t *in, size_t n, uint8_t *out, size_t cap, uint16_t *map)
{
	size_t pos = 2;
	uint32_t count = 0;

	if (n == 0)
		return -EINVAL;
	memset(map, 0, 65536 * sizeof(*map));
	for (size_t i = 0; i < n; i++)
		map[in[i]] = 1;
	for (uint32_t v = 0; v < 65536; v++) {
		if (!map[v])
			continue;
		if (count == 0x8000)
			return -ERANGE; /* indices must stay below 32768 */
		if (pos + 2 > cap)
			return -ENOSPC;
		out[pos++] = (uint8_t)(v & 0xFF);
		out[pos++] = (uint8_t)(v >> 8);
		map[v] = (uint16_t)count++;
	}
	if (cap < 2)
		return -ENOSPC;
	out[0] = (uint8_t)(count & 0xFF);
	out[1] = (uint8_t)(count >> 8);
	long r = enc_stream(in, n, map, out + pos, cap - pos);
	return r < 0 ? r : (long)pos + r;
}

/* ---- decoding -------------------------------------------------------- */

struct dec {
	uint16_t *out;
	size_t n, k;
	const uint16_t *table; /* 16zT: table[idx], bytes little-endian */
	size_t table_len;
	const uint8_t *table_bytes;
};

static int emit(struct dec *d, uint16_t v, const char **why)
{
	if (d->k >= d->n) {
		*why = "the stream holds more values than the frame has pixels";
		return -EINVAL;
	}
	if (d->table_bytes) {
		if (v >= d->table_len) {
			*why = "a value refers past the end of the 16zT table";
			return -EINVAL;
		}
		v = (uint16_t)(d->table_bytes[2 * v] | (d->table_bytes[2 * v + 1] << 8));
	}
	d->out[d->k++] = v;
	return 0;
}

static int dec_stream(struct dec *d, const uint8_t *p, const uint8_t *end, const char **why)
{
	uint16_t last;
	int r;

	if (end - p < 2) {
		*why = "the stream is shorter than its first value";
		return -EINVAL;
	}
	last = (uint16_t)(p[0] | (p[1] << 8));
	p += 2;
	if ((r = emit(d, last, why)) < 0)
		return r;
	while (p != end) {
		uint8_t c = *p;
		int escape = 0;
		if (c < 0xE0) {
			int hi = c >> 4, lo = c & 0x0F;
			last = (uint16_t)(last - (hi - 6));
			if ((r = emit(d, last, why)) < 0)
				return r;
			p++;
			if (lo == 0x0F)
				escape = 1;
			else if (lo != 0x0D) {
				last = (uint16_t)(last - (lo - 6));
				if ((r = emit(d, last, why)) < 0)
					return r;
			}
		} else if (c == 0xFF) {
			p++;
			escape = 1;
		} else {
			for (int z = c - 0xE0; z > 0; z--) {
				if ((r = emit(d, last, why)) < 0 || (r = emit(d, last, why)) < 0)
					return r;
			}
			p++;
		}
		if (!escape)
			continue;
		if (p == end) {
			*why = "the stream ends inside an escape";
			return -EINVAL;
		}
		if (*p & 0x80) {
			last = (uint16_t)(last - (*p - 192));
			p++;
		} else {
			if (end - p < 2) {
				*why = "the stream ends inside a full value";
				return -EINVAL;
			}
			last = (uint16_t)((p[0] << 8) + p[1]);
			p += 2;
		}
		if ((r = emit(d, last, why)) < 0)
			return r;
	}
	if (d->k != d->n) {
		*why = "the stream holds fewer values than the frame has pixels";
		return -EINVAL;
	}
	return 0;
}

int dao_16z_decode(const uint8_t *in, size_t len, uint16_t *out, size_t n, const char **why)
{
	struct dec d = {out, n, 0, NULL, 0, NULL};
	if (len < 2) { /* also keeps `in + len` away from a NULL `in` */
		*why = "the stream is shorter than its first value";
		return -EINVAL;
	}
	return dec_stream(&d, in, in + len, why);
}

int dao_16zt_decode(const uint8_t *in, size_t len, uint16_t *out, size_t n, const char **why)
{
	struct dec d = {out, n, 0, NULL, 0, NULL};
	size_t count;

	if (len < 2) {
		*why = "the stream is shorter than its table header";
		return -EINVAL;
	}
	count = (size_t)(in[0] | (in[1] << 8));
	if (len - 2 < 2 * count) {
		*why = "the stream is shorter than its value table";
		return -EINVAL;
	}
	d.table_bytes = in + 2;
	d.table_len = count;
	return dec_stream(&d, in + 2 + 2 * count, in + len, why);
}
