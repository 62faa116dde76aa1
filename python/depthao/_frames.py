# SPDX-License-Identifier: MIT
"""numpy arrays <-> struct dao_frame, without copying where the layout allows."""

import ctypes

import numpy as np

from . import _lib

INT32_MAX = 2**31 - 1

# format -> (numpy dtype, components per pixel)
LAYOUT = {
    _lib.PIXFMT_DEPTH16: (np.uint16, 1),
    _lib.PIXFMT_DEPTH_F32: (np.float32, 1),
    _lib.PIXFMT_GRAY8: (np.uint8, 1),
    _lib.PIXFMT_GRAY16: (np.uint16, 1),
    _lib.PIXFMT_GRAY_F32: (np.float32, 1),
    _lib.PIXFMT_RGB24: (np.uint8, 3),
    _lib.PIXFMT_NORMAL_F32: (np.float32, 3),
}


def row_stride(arr, comps):
    """The byte stride to hand the library for `arr` ((H, W) or (H, W, C)),
    or None when its rows are not runs of tightly packed pixels at a positive
    stride that is a multiple of the sample size (then the caller copies)."""
    if not arr.flags.aligned or not arr.dtype.isnative:
        return None
    item = arr.dtype.itemsize
    h, w = arr.shape[0], arr.shape[1]
    row = w * comps * item
    if comps > 1 and arr.strides[2] != item:
        return None
    if w > 1 and arr.strides[1] != comps * item:
        return None
    if h == 1:
        return row  # only one row is read: its stride does not matter
    s = arr.strides[0]
    if s < row or s % item or s > INT32_MAX:
        return None  # negative, overlapping, odd or too large
    return s


def make_frame(arr, fmt, stride, unit=0.0):
    f = _lib.dao_frame()
    f.size = _lib.DAO_FRAME_SIZE
    f.format = fmt
    f.height, f.width = arr.shape[0], arr.shape[1]
    f.stride = stride
    f.data = arr.ctypes.data
    f.depth_unit = unit
    return f


def packed(arr, dtype):
    """A C-contiguous native-order copy of `arr` (only if needed)."""
    return np.ascontiguousarray(arr, dtype=np.dtype(dtype).newbyteorder("="))


def array_from_frame(f):
    """A copy of the pixels of a library-owned frame as a numpy array."""
    if f.format not in LAYOUT:
        raise ValueError("frame format %s has no numpy layout"
                         % _lib.text(_lib.lib.dao_pixfmt_name(f.format)))
    dtype, comps = LAYOUT[f.format]
    item = np.dtype(dtype).itemsize
    h, w, stride = f.height, f.width, f.stride
    if not f.data or h == 0 or w == 0:
        raise ValueError("empty frame from the library")
    size = stride * (h - 1) + w * comps * item
    buf = (ctypes.c_char * size).from_address(f.data)
    shape = (h, w) if comps == 1 else (h, w, comps)
    strides = (stride, comps * item) if comps == 1 else (stride, comps * item, item)
    return np.ndarray(shape, dtype=dtype, buffer=buf, strides=strides).copy()
