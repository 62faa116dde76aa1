# SPDX-License-Identifier: MIT
"""A small .oni (NI10) writer and record walker in Python, independent of
depthao's C reader: the tests write recordings with colour nodes with it and
read the JPEG bytes of real recordings with it (the layout is in
src/io/oni/oni_format.h and OpenNI2's Source/Drivers/OniFile)."""
import struct

MAGIC = 0x0052494E
NODE_ADDED, INT_PROP, GENERAL_PROP = 0x0D, 0x03, 0x06
NEW_DATA, END = 0x0A, 0x0B
DEPTH, IMAGE = 2, 3


def _string(s):
    b = s.encode() + b"\0"
    return struct.pack("<I", len(b)) + b


def _record(rtype, node, fields, payload=b""):
    return struct.pack("<IIIIIQ", MAGIC, rtype, node, 28 + len(fields), len(payload), 0) + \
        fields + payload


class Writer:
    """Nodes and frames in memory; save() writes a finished 1.0.1.0 file."""

    def __init__(self):
        self.records = []
        self.max_ts = 0
        self.max_node = 0

    def node(self, nid, name, ntype, codec, width, height, fps=30, props=None):
        self.max_node = max(self.max_node, nid)
        fields = _string(name) + struct.pack("<I", ntype) + codec.encode() + bytes(28)
        self.records.append(_record(NODE_ADDED, nid, fields))
        self.general(nid, "xnMapOutputMode", struct.pack("<III", width, height, fps))
        self.general(nid, "xnCropping", bytes(12))
        for k, v in (props or {}).items():
            self.int_prop(nid, k, v)

    def general(self, nid, name, data):
        self.records.append(_record(GENERAL_PROP, nid,
                                    _string(name) + struct.pack("<I", len(data)) + data))

    def int_prop(self, nid, name, value):
        self.records.append(_record(INT_PROP, nid,
                                    _string(name) + struct.pack("<IQ", 8, value)))

    def frame(self, nid, timestamp_us, number, payload):
        self.max_ts = max(self.max_ts, timestamp_us)
        self.records.append(_record(NEW_DATA, nid, struct.pack("<QI", timestamp_us, number),
                                    payload))

    def save(self, path):
        head = b"NI10" + struct.pack("<BBHI", 1, 0, 1, 0) + struct.pack("<QI", self.max_ts,
                                                                          self.max_node)
        with open(path, "wb") as f:
            f.write(head)
            for r in self.records:
                f.write(r)
            f.write(_record(END, 0, b""))


def frames(path):
    """{node id: [(timestamp_us, number, payload bytes)]} and {node id: (name, type, codec)}."""
    data = open(path, "rb").read()
    assert data[:4] == b"NI10"
    pos, out, nodes = 24, {}, {}
    while pos < len(data):
        magic, rtype, nid, fsize, psize = struct.unpack_from("<IIIII", data, pos)
        assert magic == MAGIC, "bad record at %d" % pos
        fields = data[pos + 28:pos + fsize]
        if rtype in (0x02, 0x0C, 0x0D):
            n = struct.unpack_from("<I", fields)[0]
            name = fields[4:4 + n - 1].decode()
            ntype = struct.unpack_from("<I", fields, 4 + n)[0]
            nodes[nid] = (name, ntype, fields[8 + n:12 + n].decode("latin-1"))
        elif rtype == NEW_DATA:
            ts, num = struct.unpack_from("<QI", fields)
            out.setdefault(nid, []).append((ts, num, data[pos + fsize:pos + fsize + psize]))
        elif rtype == END:
            break
        pos += fsize + psize
    return out, nodes


def nearest(timestamps, t):
    """Index of the timestamp nearest to t, the earlier one on a tie."""
    best = 0
    for i, ts in enumerate(timestamps):
        if abs(ts - t) < abs(timestamps[best] - t):
            best = i
    return best
