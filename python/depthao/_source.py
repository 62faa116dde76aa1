# SPDX-License-Identifier: MIT
"""Recordings and PNG files: the library's sources (dao_source_*) and dao_png_*."""

import ctypes
import errno
import glob
import math
import numbers
import os
import threading
import time
import warnings

import numpy as np

from . import _camera_files, _frames, _lib
from ._ao import Camera
from ._lib import lib

# --- plugins ----------------------------------------------------------------

_registries = {}
_registries_lock = threading.Lock()


def _default_plugin_path():
    """Like the depthao command: with a library from a build tree and no
    $DEPTHAO_PLUGIN_PATH, the plugins built beside it; else the library's
    own default ($DEPTHAO_PLUGIN_PATH, then the install directory)."""
    if os.environ.get("DEPTHAO_PLUGIN_PATH") or not _lib.build_root:
        return None
    dirs = sorted(d for d in glob.glob(os.path.join(_lib.build_root, "plugins", "*"))
                  if os.path.isdir(d))
    return ":".join(dirs) if dirs else None


def _plugins(path):
    """The plugin registry for `path` (None = the default, "" = only the
    built-in plugins), loaded once."""
    if path is None:
        path = _default_plugin_path()
    with _registries_lock:
        reg = _registries.get(path)
        if reg is None:
            reg = ctypes.c_void_p()
            err = _lib.new_error()
            _lib.check(lib.dao_plugins_load(ctypes.byref(reg),
                                            os.fsencode(path) if path is not None else None,
                                            ctypes.byref(err)), err)
            # kept for the life of the process: sources refer to its plugins
            _registries[path] = reg
        return reg


# --- sources ----------------------------------------------------------------


def _f32(v):
    """A float32 from C as its shortest decimal (0.001, not 0.0010000000474974513)."""
    return float(str(np.float32(v)))


_PLAYBACK = {"manual": _lib.PLAYBACK_MANUAL, "realtime": _lib.PLAYBACK_REALTIME}


def _count(name, v, lo=0):
    if isinstance(v, bool) or not isinstance(v, numbers.Integral) or not lo <= int(v) < 2**32:
        raise ValueError("%s must be an integer >= %d, got %r" % (name, lo, v))
    return int(v)


class Source:
    """A recording or device opened with depthao.open(); iterating yields
    (index, depth, info) per frame: index is the 0-based position in the
    recording, depth a copy of the frame (uint16 counts of info["depth_unit"]
    metres, or float32 metres if the source delivers those), info a dict with
    sequence, timestamp_ns, depth_unit, and color: with open(..., color=True)
    on a source with colour (.info["has_color"]: an .oni recording with a
    colour stream, a bag with a colour topic, OpenNI2 devices), a uint8 RGB (h, w, 3) copy of the colour
    frame paired with the depth (the one recorded nearest in time), else None;
    with open(..., poses=True), pose: the camera's pose the source carries for
    the frame (a ROS recording's tf or odometry, docs/sources.md), a tuple
    (rotation, translation) as AO.set_pose() takes it, or None for a frame
    without one (then pose_missing says why).  Iteration ends at the end of the
    recording; a live source that delivers nothing for `timeout` seconds
    raises TimeoutError.

    .info describes the stream (width, height, depth_unit, fov, fps,
    frame_count, live, ...); .camera() is the Camera from its field of view.
    Use it as a context manager, or call close().  One thread at a time.
    """

    def __init__(self, uri, playback="manual", loop=False, start=0, step=1, unit=None,
                 timeout=5.0, plugin_path=None, color=False, poses=False):
        if playback not in _PLAYBACK:
            raise ValueError("playback must be 'manual' or 'realtime', got %r" % (playback,))
        if timeout is not None and not (isinstance(timeout, numbers.Real) and timeout > 0):
            raise ValueError("timeout must be a positive number of seconds or None, got %r"
                             % (timeout,))
        opts = _lib.dao_source_options()
        opts.size = ctypes.sizeof(opts)
        opts.playback = _PLAYBACK[playback]
        opts.loop = 1 if loop else 0
        opts.start_frame = _count("start", start)
        opts.step = _count("step", step, 1)
        opts.want_color = 1 if color else 0
        if unit is not None:
            unit = float(unit)
            if not (math.isfinite(unit) and unit > 0):
                raise ValueError("unit must be a positive number of metres per count, got %r"
                                 % unit)
            opts.depth_unit = unit
        self._timeout = timeout
        self._poses = bool(poses)
        self.pose_description = None
        self._lock = threading.Lock()
        self._src = None
        self._done = False
        self.uri = os.fspath(uri)
        src = ctypes.c_void_p()
        err = _lib.new_error()
        # The built-in sources (oni, images) first, so that opening a file does
        # not load every plugin module (OpenNI2, OpenCV's GUI) into Python; the
        # modules only when those do not know the URI.  Built-ins win the probe
        # for the files they read in the full registry too (oni 60 > openni2 40).
        r = -errno.ENOENT
        if plugin_path is None:
            r = lib.dao_source_open(_plugins(""), os.fsencode(self.uri), ctypes.byref(opts),
                                    ctypes.byref(src), ctypes.byref(err))
        if r == -errno.ENOENT:
            r = lib.dao_source_open(_plugins(plugin_path), os.fsencode(self.uri),
                                    ctypes.byref(opts), ctypes.byref(src), ctypes.byref(err))
        _lib.check(r, err)
        self._src = src
        info = _lib.dao_source_info()
        lib.dao_source_get_info_sized(src, ctypes.byref(info), ctypes.sizeof(info))
        self.info = {
            "width": info.width, "height": info.height,
            "format": _lib.text(lib.dao_pixfmt_name(info.format)),
            "depth_unit": _f32(info.depth_unit),
            "has_fov": bool(info.has_fov),
            "hfov": info.hfov if info.has_fov else None,
            "vfov": info.vfov if info.has_fov else None,
            "fps": info.fps,
            "frame_count": info.frame_count,
            "live": bool(info.live),
            "mirrored": bool(info.mirrored),
            "registered": bool(info.registered),
            # colour delivered with each frame (open(..., color=True) on a source with colour)
            "has_color": bool(info.has_color),
            "color_width": info.color_width if info.has_color else None,
            "color_height": info.color_height if info.has_color else None,
            "description": _lib.text(info.description),
            "warning": _lib.text(info.warning) or None,
            # (fx, fy, cx, cy) in pixels when the source knows them (a bag's CameraInfo)
            "intrinsics": ((info.fx, info.fy, info.cx, info.cy) if info.has_intrinsics
                           else None),
        }
        # PNG images: the camera.json (Open3D) or camera.yaml (ROS CameraInfo) beside them,
        # as the depthao command reads it
        self.info["camera_file"] = None
        if self.info["intrinsics"] is None and not self.info["has_fov"]:
            try:
                self._camera_file()
            except BaseException:
                self.close()
                raise
        if self.info["warning"]:
            # e.g. a recording whose writer crashed, recovered up to its last frame
            warnings.warn(self.info["warning"], RuntimeWarning, stacklevel=3)
        try:
            _lib.check(lib.dao_source_start(src, ctypes.byref(err)), err)
        except BaseException:
            self.close()
            raise

    def _camera_file(self):
        path = self.uri[7:] if self.uri.startswith("images:") else self.uri
        if ":" in path.split(os.sep)[0] and not os.path.exists(path):
            return  # another plugin's URI
        f = _camera_files.beside(path)
        if f is None:
            return
        w, h, fx, fy, cx, cy = _camera_files.file_intrinsics(f)
        if (w, h) != (self.info["width"], self.info["height"]):
            raise ValueError("camera file '%s' is for %dx%d images, '%s' is %dx%d" % (
                f, w, h, self.uri, self.info["width"], self.info["height"]))
        self.info["intrinsics"] = (fx, fy, cx, cy)
        self.info["camera_file"] = f

    def camera(self, hfov=None, vfov=None):
        """The Camera of this stream: its intrinsics when the source has them
        (a bag's CameraInfo; PNG images: the camera.json or camera.yaml beside
        them, info["camera_file"]) and no field of view is given, else from its
        field of view (or the one given, radians); ValueError if it knows
        neither."""
        k = self.info["intrinsics"]
        if k is not None and hfov is None and vfov is None:
            return Camera(k[0], k[1], k[2], k[3], self.info["width"], self.info["height"])
        hfov = self.info["hfov"] if hfov is None else hfov
        vfov = self.info["vfov"] if vfov is None else vfov
        if hfov is None or vfov is None:
            raise ValueError("'%s' has no field of view; build a depthao.Camera from the "
                             "sensor's intrinsics instead" % self.uri)
        return Camera.from_fov(self.info["width"], self.info["height"], hfov, vfov)

    @property
    def frame_count(self):
        """Frames in the recording, -1 for a live source."""
        return self.info["frame_count"]

    def seek(self, index):
        """The next frame delivered is `index` of the recording."""
        err = _lib.new_error()
        with self._lock:
            _lib.check(lib.dao_source_seek(self._handle(), _count("index", index, 0),
                                           ctypes.byref(err)), err)
            self._done = False

    def _handle(self):
        if self._src is None:
            raise ValueError("this depthao source is closed")
        return self._src

    def __iter__(self):
        return self

    def __next__(self):
        with self._lock:
            src = self._handle()
            if self._done:
                raise StopIteration
            frame = _lib.dao_source_frame()
            err = _lib.new_error()
            deadline = None if self._timeout is None else time.monotonic() + self._timeout
            while True:
                wait = 1000 if deadline is None else \
                    max(1, min(1000, int((deadline - time.monotonic()) * 1000)))
                r = lib.dao_source_read(src, ctypes.byref(frame), wait, ctypes.byref(err))
                if r == _lib.DAO_SOURCE_EOS:
                    self._done = True
                    raise StopIteration
                if r != -errno.EAGAIN:
                    break
                if deadline is not None and time.monotonic() >= deadline:
                    raise TimeoutError("no frame from '%s' within %g s" % (self.uri,
                                                                          self._timeout))
            _lib.check(r, err)
            try:
                d = frame.depth
                depth = _frames.array_from_frame(d)
                info = {"sequence": d.sequence, "timestamp_ns": d.timestamp_ns,
                        "depth_unit": _f32(d.depth_unit) if d.format == _lib.PIXFMT_DEPTH16
                        else None,
                        "color": (_frames.array_from_frame(frame.color)
                                  if frame.color.format == _lib.PIXFMT_RGB24 else None)}
                if self._poses:
                    self._frame_pose(src, frame, info)
                index = frame.index
            finally:
                lib.dao_source_release(src, ctypes.byref(frame))
            return index, depth, info

    def _frame_pose(self, src, frame, info):
        """info["pose"] (and "pose_missing") of the frame just read, before its release.
        A source that carries no poses, or cannot give any, raises its error."""
        pose = _lib.dao_source_pose()
        pose.size = ctypes.sizeof(pose)
        err = _lib.new_error()
        r = lib.dao_source_frame_pose_sized(src, ctypes.byref(frame), ctypes.byref(pose),
                                            ctypes.sizeof(pose), ctypes.byref(err))
        if r == -errno.ENOENT:  # a gap in the poses: this frame has none
            info["pose"] = None
            info["pose_missing"] = _lib.text(err.message)
            return
        if r == -errno.ENOTSUP:
            raise OSError(errno.ENOTSUP, "'%s' carries no camera poses (poses=True): a ROS "
                          "recording with tf or odometry does (bag, mcap, db3 sources)"
                          % self.uri)
        _lib.check(r, err)
        info["pose"] = (np.array(pose.rotation[:], np.float64),
                        np.array(pose.translation[:], np.float64))
        info["pose_missing"] = None
        if self.pose_description is None:
            self.pose_description = _lib.text(pose.description)
            if pose.warning:
                warnings.warn(_lib.text(pose.warning), RuntimeWarning, stacklevel=3)

    def close(self):
        """Stops and closes the source (also when collected)."""
        src, self._src = self._src, None
        if src is not None:
            lib.dao_source_close(src)

    def __del__(self):
        try:
            self.close()
        except Exception:
            pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        return "<depthao.Source %r%s>" % (self.uri, "" if self._src else " closed")


def open(uri, playback="manual", loop=False, start=0, step=1, unit=None, timeout=5.0,
         plugin_path=None, color=False, poses=False):
    """Opens a recording or device through the library's sources:
    "FILE.oni" or "oni:FILE" (depthao's reader), "FILE.bag" or "bag:FILE.bag?topic=..."
    (ROS 1 bags and RealSense recordings), "images:DIR", "images:FILE.png", a
    directory or a PNG (16-bit depth PNGs in name order; `unit` metres per count,
    default 0.001; the camera from the camera.json or camera.yaml beside them),
    "openni2:any" and other plugins' URIs.  Returns a Source: iterate it for
    (index, depth, info).  Plugin modules are loaded (once) only for URIs the
    built-in sources do not take.

    playback: "manual" (every frame once, as fast as you read) or "realtime"
    (paced by the timestamps); loop: at the end, start again (at `start`)
    instead of stopping; start: first frame (0-based); step: every step-th
    frame.
    color: also deliver the colour frame of each depth frame, in info["color"]
    (sources with colour: .oni recordings with a colour stream, bags with a
    colour topic (FILE.bag?color=TOPIC when there are several), OpenNI2; the
    others deliver None; .info["has_color"] says which).
    poses: also deliver the camera's pose of each frame from the recording's tf
    or odometry, in info["pose"] (bag, mcap and db3 sources; the fixed frame in
    the URI, e.g. "FILE.bag?pose_frame=odom", docs/sources.md); the first
    frame's read then loads the recording's transforms.  A source without
    poses raises OSError (ENOTSUP) on the first frame.  Hand each pose to
    AO.set_pose() before AO.process() with depth_temporal_motion="source" or
    "source+icp".
    plugin_path: directories (colon-separated) to load plugin modules from,
    instead of $DEPTHAO_PLUGIN_PATH / the install directory.
    """
    return Source(uri, playback=playback, loop=loop, start=start, step=step, unit=unit,
                  timeout=timeout, plugin_path=plugin_path, color=color, poses=poses)


# --- PNG ----------------------------------------------------------------------


def _read(fn, path, *args):
    f = _lib.dao_frame()
    err = _lib.new_error()
    _lib.check(fn(os.fsencode(path), *args, ctypes.byref(f), ctypes.byref(err)), err)
    try:
        return _frames.array_from_frame(f)
    finally:
        lib.dao_frame_free(ctypes.byref(f))


def read_png_depth(path, unit=0.001):
    """A single-channel 16-bit PNG as a uint16 (H, W) array (dao_png_read_depth);
    pass it to AO.process with the same unit.  Any other layout is ValueError."""
    unit = float(unit)
    if not (math.isfinite(unit) and unit > 0):
        raise ValueError("unit must be a positive number of metres per count, got %r" % unit)
    return _read(lib.dao_png_read_depth, path, ctypes.c_float(unit))


def read_png(path):
    """A PNG as uint8 (H, W) (8-bit gray), uint16 (H, W) (16-bit gray) or uint8
    (H, W, 3) (RGB; palette and alpha images are converted) (dao_png_read)."""
    return _read(lib.dao_png_read, path)


def write_png(path, image):
    """Writes uint8 (H, W) gray, uint16 (H, W) 16-bit gray or uint8 (H, W, 3)
    RGB atomically (a temporary file renamed into place; dao_png_write)."""
    if not isinstance(image, np.ndarray):
        raise ValueError("image must be a numpy array, got %s" % type(image).__name__)
    key = (image.dtype.kind + str(image.dtype.itemsize), image.ndim,
           image.shape[2] if image.ndim == 3 else 1)
    fmt = {("u1", 2, 1): _lib.PIXFMT_GRAY8, ("u2", 2, 1): _lib.PIXFMT_GRAY16,
           ("u1", 3, 3): _lib.PIXFMT_RGB24}.get(key)
    if fmt is None:
        raise ValueError("image must be uint8 (H, W), uint16 (H, W) or uint8 (H, W, 3), "
                         "got %s %s" % (image.dtype, image.shape))
    comps = 3 if fmt == _lib.PIXFMT_RGB24 else 1
    stride = _frames.row_stride(image, comps)
    if stride is None:
        image = _frames.packed(image, image.dtype)
        stride = _frames.row_stride(image, comps)
    f = _frames.make_frame(image, fmt, stride)
    err = _lib.new_error()
    _lib.check(lib.dao_png_write(os.fsencode(path), ctypes.byref(f), ctypes.byref(err)), err)
