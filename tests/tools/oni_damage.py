#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Damages the first JPEG colour frame of an .oni recording, in place of a copy:
   oni_damage.py IN OUT zero    the second half of its entropy-coded data zeroed
   oni_damage.py IN OUT arith   its SOF0 marker made SOF9 (arithmetic coding)
The record sizes stay, so only the JPEG decoder can tell."""
import struct
import sys

src, dst, mode = sys.argv[1:4]
d = bytearray(open(src, "rb").read())
pos, color = 24, None
nodes = {}
while pos + 28 <= len(d):
    magic, rtype, nid, fsize, psize = struct.unpack_from("<5I", d, pos)
    if magic != 0x0052494E or rtype == 0x0B:
        break
    if rtype in (0x02, 0x0C, 0x0D):  # node added: name, type
        n = struct.unpack_from("<I", d, pos + 28)[0]
        nodes[nid] = struct.unpack_from("<I", d, pos + 32 + n)[0]
    if rtype == 0x0A and nodes.get(nid) == 3 and color is None:  # an image node's frame
        color = (pos + fsize, psize)
    pos += fsize + psize
assert color, "no colour frame"
p, n = color
j = bytes(d[p:p + n])
assert j[:2] == b"\xff\xd8", "not a JPEG frame"
if mode == "zero":
    sos = j.index(b"\xff\xda")
    start = sos + 2 + struct.unpack(">H", j[sos + 2:sos + 4])[0]
    end = j.rindex(b"\xff\xd9")
    d[p + (start + end) // 2:p + end] = bytes(end - (start + end) // 2)
elif mode == "arith":
    d[p + j.index(b"\xff\xc0") + 1] = 0xC9
else:
    sys.exit("mode: zero or arith")
open(dst, "wb").write(d)
