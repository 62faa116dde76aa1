# SPDX-License-Identifier: MIT
"""Loading libdepthao and libdepthao-io and declaring their C API for ctypes.

libdepthao is the AO core; libdepthao-io (files, recordings, sources) is found
through $DEPTHAO_IO_LIBRARY, else beside libdepthao (BUILD/src/io/ in a build
tree, the same directory when installed), else the system's library path.  The
package installed with pip carries both in one file.  Every function is
reached as an attribute of `lib`, whichever library exports it.

The structures below mirror include/depthao/*.h field for field (the test
suite compiles a C program that prints their sizes and offsets and compares
them with these declarations).  struct dao_params is the exception: its
layout is read at import from the library's own parameter table
(dao_param_table), so parameters added to the library appear here without a
change to this package.
"""

import ctypes
import ctypes.util
import errno as _errno
import importlib.machinery
import os

__all__ = ["lib", "path", "io_path", "build_root", "check", "error_from", "new_error", "text"]

# --- locating the library ---------------------------------------------------

_HERE = os.path.dirname(os.path.abspath(__file__))
# python/depthao/ -> the project root (where build-py/ or build/ live)
_SOURCE_ROOT = os.path.dirname(os.path.dirname(_HERE))
_BUILD_DIRS = ("build-py", "build")


def _candidates():
    """(description, path or name) in the order they are tried."""
    env = os.environ.get("DEPTHAO_LIBRARY")
    if env:
        # An explicit choice is never second-guessed: it loads or it fails.
        return [("$DEPTHAO_LIBRARY", env)]
    out = []
    # installed with pip (pyproject.toml): the package's own copy, _libdepthao.<suffix>
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        p = os.path.join(_HERE, "_libdepthao" + suffix)
        if os.path.exists(p):
            out.append(("the package", p))
            break
    for d in _BUILD_DIRS:
        p = os.path.join(_SOURCE_ROOT, d, "src", "libdepthao.so")
        if os.path.exists(p):
            out.append(("build tree", p))
    name = ctypes.util.find_library("depthao")
    if name:
        out.append(("ctypes.util.find_library('depthao')", name))
    return out


def _build_root_of(where):
    """The meson build directory a BUILD/src/libdepthao.so* lives in, or None."""
    if os.sep not in where:
        return None  # a bare name from find_library: an installed library
    src = os.path.dirname(os.path.abspath(where))
    root = os.path.dirname(src)
    if os.path.basename(src) == "src" and os.path.isdir(os.path.join(root, "meson-private")):
        return root
    return None


def _first_loadable(cands, env):
    """The first of cands that loads: (CDLL, path), or (None, what was tried).  A
    candidate from the environment variable env is never second-guessed."""
    tried = []
    for what, where in cands:
        try:
            return ctypes.CDLL(where), where
        except OSError as e:
            tried.append("%s (%s): %s" % (where, what, e))
            if what == "$" + env:
                break
    return None, tried


def _load():
    found, tried = _first_loadable(_candidates(), "DEPTHAO_LIBRARY")
    if found is not None:
        return found, tried, _build_root_of(tried)
    if not tried:
        tried.append("no DEPTHAO_LIBRARY, no %s under %s, and find_library('depthao') "
                     "found nothing" % (" or ".join(d + "/src/libdepthao.so" for d in _BUILD_DIRS),
                                        _SOURCE_ROOT))
    raise ImportError(
        "depthao: cannot load libdepthao: " + "; ".join(tried) +
        ". Build it (meson setup build && ninja -C build), install it, or set "
        "DEPTHAO_LIBRARY to the path of libdepthao.so")


lib, path, build_root = _load()


def _io_candidates():
    """(description, path or name) of libdepthao-io, in the order they are tried."""
    env = os.environ.get("DEPTHAO_IO_LIBRARY")
    if env:
        return [("$DEPTHAO_IO_LIBRARY", env)]
    out = []
    if os.sep in path:
        d = os.path.dirname(os.path.abspath(path))
        for p in (os.path.join(d, "io", "libdepthao-io.so"),  # build tree: BUILD/src/io/
                  os.path.join(d, "libdepthao-io.so.1"), os.path.join(d, "libdepthao-io.so")):
            if os.path.exists(p):
                out.append(("beside %s" % path, p))
    name = ctypes.util.find_library("depthao-io")
    if name:
        out.append(("ctypes.util.find_library('depthao-io')", name))
    return out


def _load_io():
    if hasattr(lib, "dao_source_open") and not os.environ.get("DEPTHAO_IO_LIBRARY"):
        return lib, path  # both libraries in one file (the pip package)
    found, tried = _first_loadable(_io_candidates(), "DEPTHAO_IO_LIBRARY")
    if found is not None:
        return found, tried
    if not tried:
        tried.append("no DEPTHAO_IO_LIBRARY, no libdepthao-io beside %s, and "
                     "find_library('depthao-io') found nothing" % path)
    raise ImportError(
        "depthao: cannot load libdepthao-io (files, recordings, sources): " + "; ".join(tried) +
        ". Build or install it beside libdepthao, or set DEPTHAO_IO_LIBRARY to the path of "
        "libdepthao-io.so")


_io, io_path = _load_io()

# --- structures -------------------------------------------------------------

DAO_ERROR_MESSAGE_MAX = 256


class dao_error(ctypes.Structure):
    _fields_ = [("code", ctypes.c_int), ("message", ctypes.c_char * DAO_ERROR_MESSAGE_MAX)]


class dao_camera(ctypes.Structure):
    # `size` first, set by dao_camera_from_*_sized from the size passed (docs/abi.md)
    _fields_ = [("size", ctypes.c_uint32),
                ("width", ctypes.c_uint32), ("height", ctypes.c_uint32),
                ("fx", ctypes.c_double), ("fy", ctypes.c_double),
                ("cx", ctypes.c_double), ("cy", ctypes.c_double),
                ("ax", ctypes.c_float), ("ay", ctypes.c_float),
                ("bx", ctypes.c_float), ("by", ctypes.c_float)]


# enum dao_pixfmt
PIXFMT_NONE = 0
PIXFMT_DEPTH16 = 1
PIXFMT_DEPTH_F32 = 2
PIXFMT_GRAY8 = 3
PIXFMT_GRAY16 = 4
PIXFMT_GRAY_F32 = 5
PIXFMT_RGB24 = 6
PIXFMT_NORMAL_F32 = 7


class dao_frame(ctypes.Structure):
    _fields_ = [("format", ctypes.c_int),
                ("width", ctypes.c_uint32), ("height", ctypes.c_uint32),
                ("stride", ctypes.c_int32),
                ("data", ctypes.c_void_p),
                ("depth_unit", ctypes.c_float),
                ("timestamp_ns", ctypes.c_uint64),
                ("sequence", ctypes.c_uint64),
                # frame.h: sizeof never changes, `size` says which fields it holds
                ("size", ctypes.c_uint32), ("reserved0", ctypes.c_uint32),
                ("reserved", ctypes.c_uint64 * 4)]


DAO_FRAME_SIZE = dao_frame.reserved0.offset


# enum dao_param_type
PARAM_FLOAT = 0
PARAM_INT = 1
PARAM_ENUM = 2
PARAM_COLOR = 3
PARAM_RUNTIME = 1 << 0
PARAM_SHADING = 1 << 1


class dao_param_info(ctypes.Structure):
    _fields_ = [("name", ctypes.c_char_p), ("help", ctypes.c_char_p),
                ("unit", ctypes.c_char_p),
                ("type", ctypes.c_int),
                ("offset", ctypes.c_size_t),
                ("min", ctypes.c_double), ("max", ctypes.c_double),
                ("enum_names", ctypes.POINTER(ctypes.c_char_p)),
                ("flags", ctypes.c_uint)]


# Structs the library fills begin with `size`: it writes no more than the size this
# package passes (ctypes.sizeof) and says in `size` how much it filled (docs/abi.md).
class dao_timings(ctypes.Structure):
    _fields_ = [("size", ctypes.c_uint32)] + [(n, ctypes.c_double) for n in (
        "decode_ms", "prefilter_ms", "normals_ms", "gtao_ms", "denoise_ms", "output_ms",
        "process_ms", "shade_ms", "noise_ms")]


class dao_noise_info(ctypes.Structure):
    _fields_ = [("size", ctypes.c_uint32),
                ("measured", ctypes.c_int), ("sigma_area", ctypes.c_float),
                ("sigma_link", ctypes.c_float), ("prefilter_scale", ctypes.c_float),
                ("normal_radius", ctypes.c_int), ("denoise_noise", ctypes.c_float),
                ("sigma_slope", ctypes.c_float), ("age", ctypes.c_int),
                ("cells_measured", ctypes.c_int)]


class dao_motion_info(ctypes.Structure):
    _fields_ = [("size", ctypes.c_uint32), ("state", ctypes.c_int),
                ("rotation", ctypes.c_double * 9), ("translation", ctypes.c_double * 3),
                ("reason", ctypes.c_int), ("points", ctypes.c_int), ("pairs", ctypes.c_int),
                ("rms", ctypes.c_float), ("condition", ctypes.c_float),
                ("iterations", ctypes.c_int), ("origin", ctypes.c_int),
                ("reserved", ctypes.c_uint32)]


class dao_pose_track(ctypes.Structure):
    _fields_ = [("size", ctypes.c_uint32), ("current", ctypes.c_int),
                ("frames", ctypes.c_uint64), ("accepted", ctypes.c_uint64),
                ("refused", ctypes.c_uint64), ("rotation", ctypes.c_double * 9),
                ("translation", ctypes.c_double * 3), ("frame_index", ctypes.c_uint64),
                ("timestamp_ns", ctypes.c_uint64)]


# enum dao_motion_state, enum dao_motion_origin
MOTION_STATES = ("none", "refused", "still", "applied")
MOTION_ORIGINS = ("depth", "source", "source+icp")


class dao_source_pose(ctypes.Structure):
    _fields_ = [("size", ctypes.c_uint32), ("reserved", ctypes.c_uint32),
                ("rotation", ctypes.c_double * 4), ("translation", ctypes.c_double * 3),
                ("description", ctypes.c_char * 160), ("warning", ctypes.c_char * 256)]


DAO_SOURCE_EOS = 1
PLAYBACK_MANUAL = 0
PLAYBACK_REALTIME = 1


class dao_source_info(ctypes.Structure):
    # `size` first: the library fills what fits (plugin.h, "Growing the interface")
    _fields_ = [("size", ctypes.c_uint32),
                ("width", ctypes.c_uint32), ("height", ctypes.c_uint32),
                ("format", ctypes.c_int),
                ("depth_unit", ctypes.c_float),
                ("has_fov", ctypes.c_int),
                ("hfov", ctypes.c_double), ("vfov", ctypes.c_double),
                ("fps", ctypes.c_double),
                ("frame_count", ctypes.c_int64),
                ("live", ctypes.c_int), ("mirrored", ctypes.c_int),
                ("registered", ctypes.c_int), ("has_color", ctypes.c_int),
                ("color_width", ctypes.c_uint32), ("color_height", ctypes.c_uint32),
                ("description", ctypes.c_char * 160),
                ("warning", ctypes.c_char * 256),
                ("has_intrinsics", ctypes.c_int),
                ("fx", ctypes.c_double), ("fy", ctypes.c_double),
                ("cx", ctypes.c_double), ("cy", ctypes.c_double)]


class dao_source_options(ctypes.Structure):
    _fields_ = [("size", ctypes.c_uint32),
                ("playback", ctypes.c_int), ("loop", ctypes.c_int),
                ("start_frame", ctypes.c_uint32), ("step", ctypes.c_uint32),
                ("want_color", ctypes.c_int), ("depth_unit", ctypes.c_float)]


class dao_source_frame(ctypes.Structure):
    _fields_ = [("depth", dao_frame), ("color", dao_frame), ("index", ctypes.c_uint64)]


# --- functions --------------------------------------------------------------

_E = ctypes.POINTER(dao_error)
_int, _u32, _u64, _dbl, _flt = ctypes.c_int, ctypes.c_uint32, ctypes.c_uint64, ctypes.c_double, ctypes.c_float
_vp, _cp = ctypes.c_void_p, ctypes.c_char_p
_P = ctypes.POINTER

_PROTOTYPES = {
    "dao_version": (_cp, []),
    "dao_strerror": (_cp, [_int]),
    "dao_pixfmt_name": (_cp, [_int]),
    "dao_camera_from_intrinsics_sized": (_int, [_P(dao_camera), ctypes.c_size_t, _u32, _u32,
                                                _dbl, _dbl, _dbl, _dbl, _E]),
    "dao_camera_from_fov_sized": (_int, [_P(dao_camera), ctypes.c_size_t, _u32, _u32, _dbl, _dbl,
                                         _E]),
    "dao_camera_fov": (None, [_P(dao_camera), _P(_dbl), _P(_dbl)]),
    "dao_param_table": (_P(dao_param_info), [_P(ctypes.c_size_t)]),
    "dao_quality_parse": (_int, [_cp, _P(_int), _E]),
    "dao_quality_name": (_cp, [_int]),
    "dao_params_size": (ctypes.c_size_t, []),
    "dao_params_init_sized": (_int, [_vp, ctypes.c_size_t, _int]),
    "dao_params_set": (_int, [_vp, _cp, _cp, _E]),
    "dao_params_get": (_int, [_vp, _cp, _cp, ctypes.c_size_t, _E]),
    "dao_params_validate": (_int, [_vp, _E]),
    "dao_params_stream_defaults": (None, [_vp]),
    "dao_context_create": (_int, [_P(_vp), _P(dao_camera), _vp, _E]),
    "dao_context_destroy": (None, [_vp]),
    "dao_context_reset": (None, [_vp]),
    "dao_context_set_params": (_int, [_vp, _vp, _E]),
    "dao_context_get_params_sized": (_int, [_vp, _vp, ctypes.c_size_t]),
    "dao_context_process": (_int, [_vp, _P(dao_frame), _P(dao_frame), _u64, _P(dao_frame), _E]),
    "dao_context_shade": (_int, [_vp, _P(dao_frame), _E]),
    "dao_context_process_shaded": (_int, [_vp, _P(dao_frame), _P(dao_frame), _u64,
                                          _P(dao_frame), _P(dao_frame), _E]),
    "dao_overlay": (_int, [_P(dao_frame), _P(dao_frame), _P(dao_frame), _E]),
    "dao_context_get_depth": (_int, [_vp, _P(dao_frame), _E]),
    "dao_context_get_normals": (_int, [_vp, _P(dao_frame), _E]),
    "dao_context_timings_sized": (_int, [_vp, _P(dao_timings), ctypes.c_size_t]),
    "dao_context_noise_sized": (_int, [_vp, _P(dao_noise_info), ctypes.c_size_t]),
    "dao_context_simd": (_int, [_vp]),
    "dao_context_motion_sized": (_int, [_vp, _P(dao_motion_info), ctypes.c_size_t]),
    "dao_context_set_pose": (_int, [_vp, _P(_dbl), _P(_dbl), _E]),
    "dao_motion_accumulate": (_int, [_P(dao_motion_info), _P(_dbl), _P(_dbl)]),
    "dao_context_pose_track_sized": (_int, [_vp, _P(dao_pose_track), ctypes.c_size_t]),
    "dao_pose_matrix_to_quat": (None, [_P(_dbl), _P(_dbl)]),
    "dao_pose_quat_to_matrix": (None, [_P(_dbl), _P(_dbl)]),
    "dao_simd_name": (_cp, [_int]),
    "dao_frame_free": (None, [_P(dao_frame)]),
    "dao_png_read": (_int, [_cp, _P(dao_frame), _E]),
    "dao_png_read_depth": (_int, [_cp, _flt, _P(dao_frame), _E]),
    "dao_png_write": (_int, [_cp, _P(dao_frame), _E]),
    "dao_plugins_load": (_int, [_P(_vp), _cp, _E]),
    "dao_plugins_free": (None, [_vp]),
    "dao_source_open": (_int, [_vp, _cp, _P(dao_source_options), _P(_vp), _E]),
    "dao_source_get_info_sized": (_int, [_vp, _P(dao_source_info), ctypes.c_size_t]),
    "dao_source_start": (_int, [_vp, _E]),
    "dao_source_read": (_int, [_vp, _P(dao_source_frame), _int, _E]),
    "dao_source_release": (None, [_vp, _P(dao_source_frame)]),
    "dao_source_seek": (_int, [_vp, _u64, _E]),
    "dao_source_frame_pose_sized": (_int, [_vp, _P(dao_source_frame), _P(dao_source_pose),
                                           ctypes.c_size_t, _E]),
    "dao_source_close": (None, [_vp]),
}

for _name, (_res, _args) in _PROTOTYPES.items():
    # the core's functions from libdepthao, the io ones from libdepthao-io (one copy of
    # the core: libdepthao-io links the libdepthao loaded above), all as lib.<name>
    _fn = None
    for _l in (lib, _io):
        try:
            _fn = getattr(_l, _name)
            break
        except AttributeError:
            pass
    if _fn is None:
        raise ImportError("depthao: neither %s nor %s exports %s(): the libraries are older "
                          "than this package or not libdepthao" % (path, io_path, _name))
    _fn.restype = _res
    _fn.argtypes = _args
    setattr(lib, _name, _fn)



def filled_fields(st):
    """(name, value) of the fields of a sized struct the library filled (those
    within st.size; an older library fills fewer), without `size` itself."""
    return [(name, getattr(st, name)) for name, _ in st._fields_
            if name != "size" and getattr(type(st), name).offset
            + getattr(type(st), name).size <= st.size]


# --- errors -----------------------------------------------------------------


def new_error():
    return dao_error()


def error_from(code, err=None):
    """The Python exception for a negative libdepthao code and its message."""
    msg = err.message.decode("utf-8", "replace") if err is not None else ""
    if not msg:
        msg = lib.dao_strerror(code).decode()
    if code == -_errno.EINVAL:
        return ValueError(msg)
    # OSError(errno, text) picks the subclass (FileNotFoundError for ENOENT, ...)
    return OSError(-code, msg)


def check(code, err):
    if code < 0:
        raise error_from(code, err)
    return code


def text(s):
    return s.decode("utf-8", "replace") if s is not None else None
