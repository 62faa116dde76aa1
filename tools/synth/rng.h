/* SPDX-License-Identifier: MIT */
/* A small deterministic random generator for the synthetic scenes. */
#ifndef DAO_SYNTH_RNG_H
#define DAO_SYNTH_RNG_H

#include <stdint.h>

/* splitmix64 (Steele, Lea, Flood 2014): a 64-bit state, one output per step. */
static inline uint64_t synth_rng_next(uint64_t *state)
{
	uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	return z ^ (z >> 31);
}

/* Uniform in (0, 1): never exactly 0, so log() of it is finite. */
static inline double synth_rng_uniform(uint64_t *state)
{
	return ((double)(synth_rng_next(state) >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

#endif
