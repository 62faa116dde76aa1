/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is one message of a rosbag2 bag compressed
 * message by message (compression_mode message), decompressed by
 * dao_db3_unzstd_message() (src/io/db3/db3_zstd.c) with a limit of 1 MiB
 * into a buffer reused across inputs.  Any outcome is fine except a crash, a
 * sanitizer report, an error without a message, or a result over the limit
 * or beyond the buffer.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "db3/db3_reader.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static uint8_t *buf;
	static uint64_t cap;
	struct dao_error err = {0};
	uint64_t out = 0;
	if (dao_db3_unzstd_message(data, size, 1u << 20, &buf, &cap, &out, &err) < 0) {
		if (!err.message[0])
			abort();
		return 0;
	}
	if (out > (1u << 20) || out > cap || (out && !buf))
		abort();
	if (out)
		buf[out - 1] ^= 1; /* ASan: the whole result is inside the buffer */
	return 0;
}
