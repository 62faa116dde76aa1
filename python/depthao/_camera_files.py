# SPDX-License-Identifier: MIT
"""Camera intrinsics from a 3x3 matrix, a ROS CameraInfo (a dict, a YAML
file in camera_info_manager's format, or a message object) and Open3D's
PinholeCameraIntrinsic JSON; the same rules as the depthao command's
--intrinsics-file (tools/depthao/camera_file.c)."""

import json
import numbers
import os
import sys
import warnings

import numpy as np

# a CameraInfo is a few hundred bytes: larger files are not read
MAX_FILE_BYTES = 1 << 20


def _warn(msg):
    """A RuntimeWarning shown at the first caller outside this package."""
    here = os.path.dirname(os.path.abspath(__file__))
    level, f = 1, sys._getframe(0)
    while f is not None and os.path.dirname(os.path.abspath(f.f_code.co_filename)) == here:
        f, level = f.f_back, level + 1
    warnings.warn(msg, RuntimeWarning, stacklevel=level)


def _fail(where, what):
    return ValueError("%s: %s" % (where, what))


def _numbers(where, name, values, count):
    try:
        a = np.asarray(values, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        raise _fail(where, "%s must be %d numbers" % (name, count)) from None
    if a.size != count:
        raise _fail(where, "%s has %d numbers, it needs %d" % (name, a.size, count))
    if not np.all(np.isfinite(a)):
        raise _fail(where, "%s holds a number that is not finite" % name)
    return a


def _size(where, name, v):
    if isinstance(v, bool) or not isinstance(v, numbers.Integral) or not 1 <= int(v) <= 16384:
        raise _fail(where, "%s must be an integer number of pixels in 1..16384, got %r"
                    % (name, v))
    return int(v)


def matrix_intrinsics(k, where="K"):
    """(fx, fy, cx, cy) of a pinhole K: 3x3, or 9 numbers row-major (ROS's K)."""
    a = _numbers(where, "K", k, 9).reshape(3, 3)
    if a[1, 0] != 0 or a[2, 0] != 0 or a[2, 1] != 0 or a[2, 2] != 1:
        raise _fail(where, "K must be [[fx, s, cx], [0, fy, cy], [0, 0, 1]], got %s"
                    % a.tolist())
    if a[0, 1] != 0:
        _warn("%s: K has skew %g, which depthao's pinhole model ignores" % (where, a[0, 1]))
    return float(a[0, 0]), float(a[1, 1]), float(a[0, 2]), float(a[1, 2])


def _field(info, *names):
    """The first of `names` that `info` (a dict or an object) has, else None."""
    for n in names:
        if isinstance(info, dict):
            if n in info:
                return info[n]
        elif hasattr(info, n):
            return getattr(info, n)
    return None


def _matrix_data(where, name, m):
    """camera_info_manager's {rows, cols, data}, or a plain list of numbers."""
    if isinstance(m, dict):
        if "data" not in m:
            raise _fail(where, "%s needs rows, cols and data" % name)
        rows, cols, data = m.get("rows"), m.get("cols"), m["data"]
        if rows is not None and cols is not None:
            _numbers(where, name + ".data", data, int(rows) * int(cols))
        return data
    return m


def camera_info_intrinsics(info, where="CameraInfo"):
    """(width, height, fx, fy, cx, cy) of a ROS CameraInfo given as a dict
    (camera_info_manager's YAML keys image_width, camera_matrix, ... or the
    message's width, K, D, P), or a message object (ROS 1: K, D, P; ROS 2:
    k, d, p).  With distortion, a RuntimeWarning says that the depth must be
    rectified, and the projection matrix P (the rectified image's camera) is
    used."""
    if isinstance(info, dict) and "image_width" in info:
        w, h = info.get("image_width"), info.get("image_height")
        k = info.get("camera_matrix")
        if k is None:
            raise _fail(where, "camera_matrix is missing")
        k = _matrix_data(where, "camera_matrix", k)
        d = _matrix_data(where, "distortion_coefficients", info.get("distortion_coefficients"))
        p = _matrix_data(where, "projection_matrix", info.get("projection_matrix"))
        model = info.get("distortion_model")
    else:
        w, h = _field(info, "width"), _field(info, "height")
        k = _field(info, "K", "k")
        if k is None:
            raise _fail(where, "has no K (k): not a CameraInfo")
        d, p = _field(info, "D", "d"), _field(info, "P", "p")
        model = _field(info, "distortion_model")
    w, h = _size(where, "width", w), _size(where, "height", h)
    fx, fy, cx, cy = matrix_intrinsics(k, where)
    d = np.zeros(0) if d is None or len(d) == 0 else \
        _numbers(where, "the distortion coefficients", d, len(d))
    if np.any(d != 0):
        used = "camera_matrix"
        if p is not None and len(p) != 0:
            pm = _numbers(where, "the projection matrix", p, 12).reshape(3, 4)
            if pm[0, 0] > 0 and pm[1, 1] > 0:
                fx, fy, cx, cy = float(pm[0, 0]), float(pm[1, 1]), float(pm[0, 2]), \
                    float(pm[1, 2])
                used = "projection_matrix (the rectified image's)"
        _warn("%s has distortion (%s, %d coefficients): depthao does not undistort, so the "
              "depth must be rectified (a ROS image_rect topic); using the intrinsics of its "
              "%s: fx %.3f fy %.3f cx %.3f cy %.3f"
              % (where, model or "no model", d.size, used, fx, fy, cx, cy))
    return w, h, fx, fy, cx, cy


def _read_text(path):
    size = os.path.getsize(path)
    if size > MAX_FILE_BYTES:
        raise ValueError("camera file '%s' is larger than %d bytes: not a camera file"
                         % (path, MAX_FILE_BYTES))
    with open(path, "rb") as f:
        return f.read().decode("utf-8", "replace")


def _is_yaml(path, text):
    ext = os.path.splitext(path)[1].lower()
    if ext in (".yaml", ".yml"):
        return True
    if ext == ".json":
        return False
    return not text.lstrip().startswith("{")


def load_yaml(path):
    """A CameraInfo YAML file as a dict (PyYAML's safe loader)."""
    try:
        import yaml
    except ImportError:
        raise ImportError("reading the CameraInfo YAML '%s' needs PyYAML (Debian: python3-yaml; "
                          "pip: PyYAML), or pass the CameraInfo as a dict" % path) from None
    try:
        doc = yaml.safe_load(_read_text(path))
    except yaml.YAMLError as e:
        raise ValueError("camera file '%s': not valid YAML: %s" % (path, e)) from None
    if not isinstance(doc, dict):
        raise ValueError("camera file '%s' is not a ROS CameraInfo (a YAML mapping with "
                         "image_width, image_height, camera_matrix, ...)" % path)
    return doc


def open3d_intrinsics(path, text=None):
    """(width, height, fx, fy, cx, cy) of Open3D's PinholeCameraIntrinsic JSON
    (intrinsic_matrix column-major: [fx, 0, 0, 0, fy, 0, cx, cy, 1])."""
    where = "camera file '%s'" % path
    try:
        doc = json.loads(_read_text(path) if text is None else text)
    except ValueError as e:
        raise _fail(where, "not valid JSON: %s" % e) from None
    if not isinstance(doc, dict) or "intrinsic_matrix" not in doc:
        raise _fail(where, 'needs "width", "height" and "intrinsic_matrix" (Open3D)')
    m = _numbers(where, "intrinsic_matrix", doc["intrinsic_matrix"], 9)
    w, h = _size(where, "width", doc.get("width")), _size(where, "height", doc.get("height"))
    return w, h, float(m[0]), float(m[4]), float(m[6]), float(m[7])


def file_intrinsics(path):
    """(width, height, fx, fy, cx, cy) of a camera file: ROS CameraInfo YAML
    or Open3D JSON, told apart as the depthao command does (.yaml/.yml,
    .json, else '{' first is JSON)."""
    path = os.fspath(path)
    text = _read_text(path)
    if _is_yaml(path, text):
        return camera_info_intrinsics(load_yaml(path), "camera file '%s'" % path)
    return open3d_intrinsics(path, text)


def beside(path):
    """camera.json, else camera.yaml, readable, in a directory of images or
    beside a .png file (the rule of the depthao command and depthaod:
    tools/common/camera_file.c, camera_file_beside); None if there is neither
    or `path` is not PNG input."""
    if os.path.isdir(path):
        d = path
    elif os.path.isfile(path) and path.lower().endswith(".png"):
        d = os.path.dirname(path) or "."
    else:
        return None
    for name in ("camera.json", "camera.yaml"):
        f = os.path.join(d, name)
        if os.access(f, os.R_OK):
            return f
    return None

