# SPDX-License-Identifier: MIT
"""The AO parameters, described by the library's own table (dao_param_table).

Nothing here lists parameters by hand: names, types, ranges, units and help
come from the library at import, and values are parsed and range-checked by
dao_params_set, so errors carry the library's message.
"""

import collections
import ctypes
import numbers

import numpy as np

from . import _lib
from ._lib import lib

ParamInfo = collections.namedtuple(
    "ParamInfo", "name attr help unit type min max choices runtime shading offset")
ParamInfo.__doc__ = """One row of the library's parameter table.

name: as the library and the CLI spell it ("depth-min"); attr: the Python
attribute / keyword ("depth_min"); type: "float", "int", "enum" or "color";
min, max: inclusive range (float, int); choices: the names of an enum;
runtime: may change between frames; shading: affects only shade()."""

_TYPE_NAMES = {_lib.PARAM_FLOAT: "float", _lib.PARAM_INT: "int",
               _lib.PARAM_ENUM: "enum", _lib.PARAM_COLOR: "color"}
_CTYPES = {_lib.PARAM_FLOAT: ctypes.c_float, _lib.PARAM_INT: ctypes.c_int,
           _lib.PARAM_ENUM: ctypes.c_int, _lib.PARAM_COLOR: ctypes.c_uint32}


def _read_table():
    n = ctypes.c_size_t()
    rows = lib.dao_param_table(ctypes.byref(n))
    out = []
    end = 0
    for i in range(n.value):
        r = rows[i]
        if r.type not in _TYPE_NAMES:
            raise ImportError("depthao: parameter %r has type %d, which this package does not "
                              "know; update the Python package" % (_lib.text(r.name), r.type))
        choices = None
        if r.type == _lib.PARAM_ENUM:
            choices = []
            k = 0
            while r.enum_names[k] is not None:
                choices.append(_lib.text(r.enum_names[k]))
                k += 1
            choices = tuple(choices)
        name = _lib.text(r.name)
        out.append(ParamInfo(name=name, attr=name.replace("-", "_"), help=_lib.text(r.help),
                             unit=_lib.text(r.unit), type=_TYPE_NAMES[r.type],
                             min=r.min, max=r.max, choices=choices,
                             runtime=bool(r.flags & _lib.PARAM_RUNTIME),
                             shading=bool(r.flags & _lib.PARAM_SHADING),
                             offset=r.offset))
        end = max(end, r.offset + ctypes.sizeof(_CTYPES[r.type]))
    return tuple(out), end


TABLE, _END = _read_table()
BY_ATTR = {p.attr: p for p in TABLE}

# sizeof(struct dao_params) of the library loaded: the buffer holds every
# field it has, and the library writes no more than the size it is given
# (struct dao_params begins with its size; params.h).
PARAMS_BUFFER_SIZE = lib.dao_params_size()
if PARAMS_BUFFER_SIZE < _END:
    raise ImportError("libdepthao reports struct dao_params of %d bytes but its table reaches "
                      "%d: a broken library" % (PARAMS_BUFFER_SIZE, _END))


def find(name):
    """The ParamInfo called `name` (dashes or underscores), or None."""
    if not isinstance(name, str):
        return None
    return BY_ATTR.get(name.replace("-", "_"))


def names():
    """Every parameter's Python name, in the library's order."""
    return [p.attr for p in TABLE]


def parse_quality(quality):
    if quality is None:
        quality = "default"
    if not isinstance(quality, str):
        raise ValueError("quality must be one of 'low', 'medium', 'high', 'ultra', 'default', "
                         "got %r" % (quality,))
    q = ctypes.c_int()
    err = _lib.new_error()
    _lib.check(lib.dao_quality_parse(quality.encode(), ctypes.byref(q), ctypes.byref(err)), err)
    return q.value


def _to_text(info, value):
    """A Python value as the text dao_params_set parses."""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return str(value)  # rejected by the library with its own message
    if info.type == "float" and isinstance(value, numbers.Real):
        return repr(float(value))  # round-trips exactly through strtod
    if info.type == "int" and isinstance(value, numbers.Integral):
        return str(int(value))
    if info.type == "enum" and isinstance(value, numbers.Integral):
        v = int(value)
        return info.choices[v] if 0 <= v < len(info.choices) else str(v)
    if info.type == "color" and isinstance(value, numbers.Integral):
        v = int(value)
        return "%06x" % v if 0 <= v <= 0xFFFFFF else str(v)
    return str(value)


class Params:
    """A struct dao_params in a buffer, read and written through the table."""

    __slots__ = ("buf",)

    def __init__(self, quality=None):
        self.buf = ctypes.create_string_buffer(PARAMS_BUFFER_SIZE)
        lib.dao_params_init_sized(self.buf, PARAMS_BUFFER_SIZE, parse_quality(quality))

    def copy(self):
        p = Params.__new__(Params)
        p.buf = ctypes.create_string_buffer(self.buf.raw, PARAMS_BUFFER_SIZE)
        return p

    def set(self, name, value):
        """Sets one parameter; ValueError with the library's message if it is
        unknown or the value is not valid (nothing changes then)."""
        info = find(name)
        key = info.name if info else str(name)
        text = _to_text(info, value) if info else str(value)
        err = _lib.new_error()
        _lib.check(lib.dao_params_set(self.buf, key.encode(), text.encode(),
                                      ctypes.byref(err)), err)

    def get(self, name):
        info = find(name)
        if info is None:
            raise ValueError("unknown parameter '%s'" % (name,))
        v = _CTYPES[{"float": _lib.PARAM_FLOAT, "int": _lib.PARAM_INT, "enum": _lib.PARAM_ENUM,
                     "color": _lib.PARAM_COLOR}[info.type]].from_buffer(self.buf, info.offset).value
        if info.type == "enum":
            return info.choices[v] if 0 <= v < len(info.choices) else v
        if info.type == "float":
            # the shortest decimal that is this float32 (0.3, not 0.30000001192092896);
            # it parses back to the same float32
            return float(str(np.float32(v)))
        return v

    def validate(self):
        err = _lib.new_error()
        _lib.check(lib.dao_params_validate(self.buf, ctypes.byref(err)), err)

    def as_dict(self):
        return {p.attr: self.get(p.attr) for p in TABLE}
