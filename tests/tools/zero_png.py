#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes a 16-bit gray PNG of zeros without holding the image in memory.

usage: zero_png.py WIDTH HEIGHT OUT.png [ROWS]
With ROWS < HEIGHT the file ends after ROWS rows (no IEND): a header that
declares more than the file holds, as in a truncated or malicious download.
"""
import struct
import sys
import zlib


def chunk(kind, data):
    return (struct.pack(">I", len(data)) + kind + data +
            struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__)
    width, height = int(sys.argv[1]), int(sys.argv[2])
    rows = int(sys.argv[4]) if len(sys.argv) == 5 else height
    z = zlib.compressobj(9)
    line = bytes(1 + 2 * width)  # filter byte 0, then the samples
    idat = b"".join(z.compress(line) for _ in range(rows))
    idat += z.flush() if rows == height else z.flush(zlib.Z_SYNC_FLUSH)
    with open(sys.argv[3], "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", idat))
        if rows == height:
            f.write(chunk(b"IEND", b""))


if __name__ == "__main__":
    main()
