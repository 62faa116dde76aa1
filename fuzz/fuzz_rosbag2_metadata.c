/* SPDX-License-Identifier: MIT */
/*
 * libFuzzer target: the input is a rosbag2 directory's metadata.yaml
 * (src/io/db3/rosbag2_metadata.c: libyaml's document API, the storage, the
 * compression and the list of files of a split bag).  Any outcome is fine
 * except a crash, a sanitizer report, an error without a message, or a
 * success whose files are not names inside the directory.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db3/db3_reader.h"
#include "harness.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *dir = fuzz_temp_dir(); /* one directory for the whole run */
	char name[96];
	snprintf(name, sizeof name, "%s/metadata.yaml", dir);
	fuzz_write_file(name, data, size);
	struct dao_rosbag2_meta m;
	struct dao_error err = {0};
	if (dao_rosbag2_metadata(dir, &m, &err) < 0) {
		if (!err.message[0] || m.files || m.file_count)
			abort();
		return 0;
	}
	const size_t n = strlen(dir);
	if (m.file_count == 0 || m.file_count > DAO_ROSBAG2_MAX_FILES || !m.storage[0])
		abort();
	for (uint32_t i = 0; i < m.file_count; i++)
		if (strncmp(m.files[i], dir, n) || m.files[i][n] != '/' || m.files[i][n + 1] == '/' ||
		    strstr(m.files[i], ".."))
			abort();
	dao_rosbag2_meta_free(&m);
	return 0;
}
