# SPDX-License-Identifier: MIT
"""Camera and AO: struct dao_camera and struct dao_context."""

import ctypes
import errno
import math
import numbers
import os
import threading
import weakref

import numpy as np

from . import _camera_files, _frames, _lib, _params
from ._lib import lib


def _dimension(name, v):
    if isinstance(v, bool) or not isinstance(v, numbers.Integral):
        raise ValueError("%s must be an integer number of pixels, got %r" % (name, v))
    v = int(v)
    if v <= 0 or v > 0xFFFFFFFF:
        raise ValueError("%s must be a positive number of pixels, got %d" % (name, v))
    return v


class Camera:
    """A pinhole depth camera: Camera(fx, fy, cx, cy, width, height).

    Intrinsics in pixels, pixel centres at integer coordinates (the optical
    frame: x right, y down, z forward).  Camera.from_fov(width, height, hfov,
    vfov) takes the field of view in radians, as .oni recordings store it.
    Bad values raise ValueError with the library's message.
    """

    __slots__ = ("_c",)

    def __init__(self, fx, fy, cx, cy, width, height):
        c = _lib.dao_camera()
        err = _lib.new_error()
        _lib.check(lib.dao_camera_from_intrinsics_sized(
            ctypes.byref(c), ctypes.sizeof(c),
            _dimension("width", width), _dimension("height", height),
            float(fx), float(fy), float(cx), float(cy), ctypes.byref(err)), err)
        self._c = c

    @classmethod
    def from_fov(cls, width, height, hfov, vfov):
        """A camera from its field of view (radians, in (0, pi)): fx = (w/2) / tan(hfov/2),
        cx = (w-1)/2, and the same for y (dao_camera_from_fov)."""
        self = cls.__new__(cls)
        c = _lib.dao_camera()
        err = _lib.new_error()
        _lib.check(lib.dao_camera_from_fov_sized(
            ctypes.byref(c), ctypes.sizeof(c),
            _dimension("width", width), _dimension("height", height),
            float(hfov), float(vfov), ctypes.byref(err)), err)
        self._c = c
        return self

    @classmethod
    def from_matrix(cls, K, width, height):
        """A camera from its 3x3 intrinsic matrix K = [[fx, 0, cx], [0, fy, cy],
        [0, 0, 1]] (a numpy array, nested lists, or 9 numbers row-major as in
        a ROS CameraInfo); ValueError for anything else."""
        fx, fy, cx, cy = _camera_files.matrix_intrinsics(K)
        return cls(fx, fy, cx, cy, width, height)

    @classmethod
    def from_camera_info(cls, info):
        """A camera from a ROS CameraInfo: a path to a YAML file in
        camera_info_manager's format (needs PyYAML), its contents as a dict,
        or a sensor_msgs/CameraInfo message (ROS 1 K/D/P or ROS 2 k/d/p, or
        any object with width, height and those fields).  A CameraInfo with
        distortion gives a RuntimeWarning (the depth must be rectified) and
        the projection matrix's intrinsics, those of the rectified image."""
        if isinstance(info, (str, bytes, os.PathLike)):
            path = os.fsdecode(info)
            w, h, fx, fy, cx, cy = _camera_files.camera_info_intrinsics(
                _camera_files.load_yaml(path), "camera file '%s'" % path)
        else:
            w, h, fx, fy, cx, cy = _camera_files.camera_info_intrinsics(info)
        return cls(fx, fy, cx, cy, w, h)

    @classmethod
    def from_file(cls, path):
        """A camera from a file as `depthao process --intrinsics-file` reads it:
        Open3D JSON (width, height, intrinsic_matrix) or ROS CameraInfo YAML."""
        w, h, fx, fy, cx, cy = _camera_files.file_intrinsics(path)
        return cls(fx, fy, cx, cy, w, h)

    width = property(lambda self: self._c.width, doc="image width, pixels")
    height = property(lambda self: self._c.height, doc="image height, pixels")
    fx = property(lambda self: self._c.fx)
    fy = property(lambda self: self._c.fy)
    cx = property(lambda self: self._c.cx)
    cy = property(lambda self: self._c.cy)

    @property
    def shape(self):
        """(height, width), as numpy arrays of this camera's frames have it."""
        return (self._c.height, self._c.width)

    @property
    def fov(self):
        """(hfov, vfov) in radians."""
        h, v = ctypes.c_double(), ctypes.c_double()
        lib.dao_camera_fov(ctypes.byref(self._c), ctypes.byref(h), ctypes.byref(v))
        return (h.value, v.value)

    def __eq__(self, other):
        if not isinstance(other, Camera):
            return NotImplemented
        return (self.width, self.height, self.fx, self.fy, self.cx, self.cy) == \
            (other.width, other.height, other.fx, other.fy, other.cx, other.cy)

    def __hash__(self):
        return hash((self.width, self.height, self.fx, self.fy, self.cx, self.cy))

    def __repr__(self):
        return "depthao.Camera(fx=%r, fy=%r, cx=%r, cy=%r, width=%d, height=%d)" % (
            self.fx, self.fy, self.cx, self.cy, self.width, self.height)


def _unknown_parameter_message(name):
    """The library's message for a name it does not know."""
    try:
        _params.Params().set(name, "0")
    except ValueError as e:
        return str(e)
    return "unknown parameter '%s'" % name


def _quaternion(rotation):
    """A rotation given as a quaternion (x, y, z, w) or a 3x3 rotation matrix, as the
    quaternion's 4 floats (the library checks its norm)."""
    try:
        r = np.asarray(rotation, np.float64)
    except (TypeError, ValueError):
        r = None
    if r is not None and r.shape == (4,):
        return r.tolist()
    if r is None or r.shape != (3, 3):
        raise ValueError("rotation must be a quaternion (x, y, z, w) or a 3x3 rotation "
                         "matrix, got %r" % (rotation,))
    if not np.all(np.isfinite(r)):
        raise ValueError("rotation matrix has a value that is not finite: %r" % (r.tolist(),))
    if np.abs(r @ r.T - np.eye(3)).max() > 1e-6 or abs(np.linalg.det(r) - 1.0) > 1e-6:
        raise ValueError("the 3x3 rotation matrix is not a rotation (R R^T = I and det R = +1 "
                         "within 1e-6): %r" % (r.tolist(),))
    q = (ctypes.c_double * 4)()
    lib.dao_pose_matrix_to_quat((ctypes.c_double * 9)(*r.ravel().tolist()), q)
    return q[:]


class AO:
    """Ambient occlusion for the frames of one camera (a dao_context).

        ao = depthao.AO(camera, quality="default", threads=None, radius=0.4)
        vis = ao.process(depth_mm)            # float32 (H, W), 1 = open
        rgb = ao.shade()                      # uint8 (H, W, 3) of the same frame

    quality: "low", "medium" (= "default"), "high" or "ultra", the preset the
    parameters start from.  stream: True for consecutive frames of one camera
    (a recording, a device): the temporal depth filter is on, as in
    `depthao process` on a recording and in depthaod (the preset leaves it
    off; the keyword depth_temporal=0 turns it off again).  threads: worker
    threads of this context (None or 0: one per CPU).  Every other keyword is
    a parameter of the library's table (depthao.PARAMETERS; dashes become
    underscores: depth_min).

    Parameters are also attributes: ``ao.radius = 0.3`` changes them for the
    next frame (an unknown name is AttributeError, a bad value ValueError,
    both with the library's message); ``ao.update(a=..., b=...)`` changes
    several at once (checked together), ``ao.params`` is a dict of all.  The
    parameter ``shade`` (the shading mode) shares its name with the method
    shade(): use ``ao.set("shade", "turbo")``, ``ao.update(shade="turbo")``
    or the constructor keyword.

    Threads: contexts share nothing (the library has no global state) and
    the GIL is released while a frame is processed or shaded, so separate AO
    objects run truly in parallel from several Python threads.  One AO
    object is used by one thread at a time; calls on the same object from
    several threads are serialised by a lock (safe, not parallel).
    """

    def __init__(self, camera, quality="default", threads=None, stream=False, **params):
        if not isinstance(camera, Camera):
            raise ValueError("camera must be a depthao.Camera, got %s" % type(camera).__name__)
        object.__setattr__(self, "_ctx", None)
        object.__setattr__(self, "_lock", threading.Lock())
        object.__setattr__(self, "_camera", camera)
        object.__setattr__(self, "_last_ao", None)
        p = _params.Params(quality)
        if stream:
            lib.dao_params_stream_defaults(p.buf)
        if threads is not None:
            p.set("threads", threads)
        for k, v in params.items():
            p.set(k, v)
        ctx = ctypes.c_void_p()
        err = _lib.new_error()
        _lib.check(lib.dao_context_create(ctypes.byref(ctx), ctypes.byref(camera._c), p.buf,
                                          ctypes.byref(err)), err)
        object.__setattr__(self, "_ctx", ctx)
        object.__setattr__(self, "_finalizer",
                           weakref.finalize(self, lib.dao_context_destroy, ctx.value))

    # --- lifetime ---------------------------------------------------------

    def close(self):
        """Frees the context and its worker threads now (else when collected)."""
        with self._lock:
            self._finalizer()
            object.__setattr__(self, "_ctx", None)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _handle(self):
        if self._ctx is None:
            raise ValueError("this depthao.AO is closed")
        return self._ctx

    # --- parameters -------------------------------------------------------

    @property
    def camera(self):
        return self._camera

    @property
    def shape(self):
        """(height, width) of the frames this context takes."""
        return self._camera.shape

    def _current(self):
        p = _params.Params.__new__(_params.Params)
        p.buf = ctypes.create_string_buffer(_params.PARAMS_BUFFER_SIZE)
        lib.dao_context_get_params_sized(self._handle(), p.buf, _params.PARAMS_BUFFER_SIZE)
        return p

    @property
    def params(self):
        """Every parameter as a dict {python_name: value} (enums as names,
        colours as 0xRRGGBB integers)."""
        with self._lock:
            return self._current().as_dict()

    def get(self, name):
        """One parameter's value; ValueError if there is none called `name`."""
        with self._lock:
            return self._current().get(name)

    def update(self, mapping=(), **params):
        """Sets several parameters at once: all are parsed, then the whole set
        is validated and applied (or, on any error, none)."""
        items = dict(mapping, **params)
        with self._lock:
            p = self._current()
            for k, v in items.items():
                p.set(k, v)
            err = _lib.new_error()
            _lib.check(lib.dao_context_set_params(self._handle(), p.buf, ctypes.byref(err)), err)

    def set(self, name, value):
        """Sets one parameter (by its library or Python name)."""
        self.update({name: value})

    def __getattr__(self, name):
        # only reached when normal lookup fails
        if not name.startswith("_") and _params.find(name) is not None:
            return self.get(name)
        raise AttributeError("'AO' object has no attribute '%s'" % name)

    def __setattr__(self, name, value):
        if name.startswith("_"):
            object.__setattr__(self, name, value)
            return
        cls_attr = getattr(type(self), name, None)
        if cls_attr is not None:
            if hasattr(cls_attr, "__set__"):
                object.__setattr__(self, name, value)
                return
            raise AttributeError(
                "'%s' is a method of AO; set the parameter with ao.set('%s', value)" %
                (name, name))
        if _params.find(name) is None:
            raise AttributeError(_unknown_parameter_message(name))
        self.set(name, value)

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(_params.names()))

    def __repr__(self):
        state = "closed" if self._ctx is None else "%dx%d" % (self._camera.width,
                                                             self._camera.height)
        return "<depthao.AO %s, %r>" % (state, self._camera)

    # --- frames -----------------------------------------------------------

    def _check_image(self, what, arr, dtypes, comps):
        """Checks type and shape; returns the array (not copied)."""
        if not isinstance(arr, np.ndarray):
            raise ValueError("%s must be a numpy array, got %s" % (what, type(arr).__name__))
        h, w = self._camera.shape
        want = (h, w) if comps == 1 else (h, w, comps)
        if arr.dtype.kind + str(arr.dtype.itemsize) not in dtypes:
            raise ValueError("%s must be %s, got %s" % (
                what, " or ".join(dtypes.values()), arr.dtype))
        if arr.shape != want:
            raise ValueError("%s must have shape %s (the camera is %dx%d), got %s" % (
                what, want, w, h, arr.shape))
        return arr

    def process(self, depth, unit=0.001, frame_index=0, out=None):
        """Ambient occlusion of one depth frame: float32 visibility (H, W), 1 = open.

        depth: numpy uint16 (H, W) counts of `unit` metres (0 = no data), or
        float32 or float64 (H, W) metres (0, NaN, inf = no data; `unit` is
        ignored; float64 is converted to float32 first, a copy).  Any
        strides: rows at a positive stride are passed as they are; other
        layouts (transposed, reversed, unaligned) are copied first.
        frame_index selects the noise pattern and tells the temporal filters
        (depth_temporal, temporal) whether this frame follows the last one: 1
        to 4 past it continues their histories, anything else starts them
        over (with both off the result is a pure function of depth,
        parameters and frame_index).  out: a float32 (H, W) array to write
        into (may be a strided view) instead of a new one.
        The GIL is released while the library works.
        """
        return self._process(depth, unit, frame_index, out, None)

    def process_shaded(self, depth, unit=0.001, frame_index=0, out=None, shaded_out=None):
        """process() and shade() in one call (dao_context_process_shaded): the same
        visibility and the same shaded image, byte for byte, the shading done on each
        band of rows while its AO is still in the core's cache (one pass over the
        frame fewer).  Returns (visibility, shaded): float32 (H, W) and uint8 RGB (H, W, 3);
        shaded_out may be uint8 (H, W, 3) for RGB or (H, W) for gray (also a strided
        view) to write into.  With algorithm="none" the frame is processed and OSError
        ENODATA raised, as shade() does."""
        h, w = self._camera.shape
        if shaded_out is None:
            s_result = s_target = np.empty((h, w, 3), np.uint8)
        else:
            if not isinstance(shaded_out, np.ndarray):
                raise ValueError("shaded_out must be a numpy array, got %s"
                                 % type(shaded_out).__name__)
            comps = 3 if shaded_out.ndim == 3 else 1
            s_result = self._check_image("shaded_out", shaded_out, {"u1": "uint8"}, comps)
            if not shaded_out.flags.writeable:
                raise ValueError("shaded_out is read-only")
            if out is not None and np.may_share_memory(out, shaded_out):
                raise ValueError("out and shaded_out share memory")
            s_target = shaded_out
            if _frames.row_stride(shaded_out, comps) is None or \
                    np.may_share_memory(shaded_out, depth):
                s_target = np.empty(shaded_out.shape, np.uint8)
        vis = self._process(depth, unit, frame_index, out, (s_result, s_target))
        return vis, s_result

    def _process(self, depth, unit, frame_index, out, shaded):
        """process() and process_shaded(): shaded None, or (array returned, array filled)."""
        depth = self._check_image("depth", depth, {"u2": "uint16 (with unit)",
                                                   "f4": "float32 (metres)",
                                                   "f8": "float64 (metres)"}, 1)
        if depth.dtype.kind == "f" and depth.dtype.itemsize == 8:
            depth = depth.astype(np.float32)  # what the library takes; NaN and inf stay
        fmt = _lib.PIXFMT_DEPTH16 if depth.dtype.kind == "u" else _lib.PIXFMT_DEPTH_F32
        if fmt == _lib.PIXFMT_DEPTH16:
            unit = float(unit)
            if not (math.isfinite(unit) and unit > 0):
                raise ValueError("unit must be a positive number of metres per count, got %r"
                                 % unit)
        else:
            unit = 0.0
        if isinstance(frame_index, bool) or not isinstance(frame_index, numbers.Integral) \
                or not 0 <= int(frame_index) < 2**64:
            raise ValueError("frame_index must be an integer in [0, 2^64), got %r"
                             % (frame_index,))
        stride = _frames.row_stride(depth, 1)
        if stride is None:
            depth = _frames.packed(depth, depth.dtype)
            stride = depth.strides[0] if depth.shape[0] > 1 else depth.shape[1] * depth.itemsize
        dframe = _frames.make_frame(depth, fmt, stride, unit)

        if out is None:
            result = target = np.empty(self._camera.shape, np.float32)
            ostride = target.strides[0]
        else:
            result = self._check_image("out", out, {"f4": "float32"}, 1)
            if not out.flags.writeable:
                raise ValueError("out is read-only")
            ostride = _frames.row_stride(out, 1)
            if ostride is None or np.may_share_memory(out, depth):
                target = np.empty(self._camera.shape, np.float32)
                ostride = target.strides[0]
            else:
                target = out
        aframe = _frames.make_frame(target, _lib.PIXFMT_GRAY_F32, ostride)
        err = _lib.new_error()
        sframe = None
        if shaded is not None:
            s_result, s_target = shaded
            comps = 3 if s_target.ndim == 3 else 1
            sframe = _frames.make_frame(s_target, _lib.PIXFMT_RGB24 if comps == 3 else
                                        _lib.PIXFMT_GRAY8, _frames.row_stride(s_target, comps))
        with self._lock:
            if sframe is None:
                r = lib.dao_context_process(self._handle(), ctypes.byref(dframe), None,
                                            int(frame_index), ctypes.byref(aframe),
                                            ctypes.byref(err))
            else:
                r = lib.dao_context_process_shaded(self._handle(), ctypes.byref(dframe), None,
                                                   int(frame_index), ctypes.byref(aframe),
                                                   ctypes.byref(sframe), ctypes.byref(err))
            # algorithm=none with a shaded image: processed, -ENODATA (nothing to shade)
            processed = r >= 0 or (sframe is not None and r == -errno.ENODATA)
        if processed:
            if target is not result:
                result[...] = target
            object.__setattr__(self, "_last_ao", result)
        _lib.check(r, err)
        if sframe is not None and s_target is not s_result:
            s_result[...] = s_target
        return result

    def reset(self):
        """Starts the temporal filters' histories over (a cut the frame
        indices do not show: another scene, another camera), and the camera's
        pose (AO.pose) with them."""
        with self._lock:
            lib.dao_context_reset(self._handle())

    # --- the camera's motion ----------------------------------------------

    def set_pose(self, rotation, translation=None):
        """The camera's pose for the next process() (dao_context_set_pose), from
        whatever knows it (odometry, tf, a tracker, a trajectory file; a source
        opened with poses=True gives info["pose"]).

        rotation: the rotation from the camera's optical frame (x right, y down,
        z forward) to a fixed world frame, as a unit quaternion (x, y, z, w; w
        last) or a 3x3 rotation matrix; translation: the optical centre in that
        frame, metres (x_world = R x_camera + t).  rotation None: the next frame
        has no pose.  The pose serves the next process() only.  Used with
        depth_temporal_motion "source" (the motion between consecutive frames'
        poses carries the depth history) and "source+icp" (it seeds the
        estimate); the other modes ignore it.  ValueError for a quaternion whose
        norm is not 1 within 1e-3, a matrix that is not a rotation, a value that
        is not finite, a translation beyond 1e6 m (the next frame then has no
        pose).
        """
        err = _lib.new_error()
        if rotation is None:
            with self._lock:
                _lib.check(lib.dao_context_set_pose(self._handle(), None, None,
                                                    ctypes.byref(err)), err)
            return
        try:
            q = _quaternion(rotation)
            try:
                t = np.asarray(translation, np.float64)
            except (TypeError, ValueError):
                t = None
            if translation is None or t is None or t.shape != (3,):
                raise ValueError("translation must be 3 numbers (metres), got %r"
                                 % (translation,))
        except ValueError:
            with self._lock:  # as the library does with a bad pose: none for the next frame
                lib.dao_context_set_pose(self._handle(), None, None, None)
            raise
        qc = (ctypes.c_double * 4)(*q)
        tc = (ctypes.c_double * 3)(*t.tolist())
        with self._lock:
            _lib.check(lib.dao_context_set_pose(self._handle(), qc, tc, ctypes.byref(err)), err)

    @property
    def motion(self):
        """What became of the last frame's camera-motion estimate
        (dao_context_motion): a dict with state ("none": not estimated, the
        motion not followed or no history; "refused", with its reason 1-5;
        "still"; "applied"), rotation (3x3) and translation (3,) of the motion
        from the last frame's camera to the one before (p_prev = R p + t,
        metres), reason, points, pairs, rms (m), condition, iterations, and
        origin ("depth", "source", "source+icp")."""
        mi = _lib.dao_motion_info()
        with self._lock:
            _lib.check(lib.dao_context_motion_sized(self._handle(), ctypes.byref(mi),
                                                    ctypes.sizeof(mi)), None)
        out = {}
        for name, value in _lib.filled_fields(mi):
            if name == "reserved":
                continue
            if name == "rotation":
                value = np.array(value[:], np.float64).reshape(3, 3)
            elif name == "translation":
                value = np.array(value[:], np.float64)
            elif name == "state":
                value = _lib.MOTION_STATES[value] if 0 <= value < 4 else value
            elif name == "origin":
                value = _lib.MOTION_ORIGINS[value] if 0 <= value < 3 else value
            out[name] = value
        return out

    @property
    def pose(self):
        """The camera's pose after the last process(), where the run follows the
        camera (depth_temporal > 0 and depth_temporal_motion not "off"): the
        motions accepted since the first followed frame composed (the
        library's pose track, dao_context_pose_track), as depthao process
        --pose-out gives them where this is not None (--pose-out also prints
        the pose held through a frame without one).  A
        tuple (rotation, translation): the unit quaternion x, y, z, w (w last) from
        this frame's optical frame to the first followed frame's, and the optical
        centre there, metres.  None where there is none: the motion not followed,
        or a frame whose motion estimate was refused or is unknown (after a cut,
        or without a pose in "source" mode).  A motion not known is taken as none:
        the poses after it are off by it.  It starts over with reset() and when
        the motion is followed again."""
        track = self.pose_track
        return (track["rotation"], track["translation"]) if track["current"] else None

    @property
    def pose_track(self):
        """The library's pose track as it stands (dao_context_pose_track), held
        poses included: a dict with "rotation" (unit quaternion x, y, z, w) and
        "translation" (metres), "current" (the pose is the last frame's; where
        False it was held from the frame "frame_index", with that frame's
        "timestamp_ns"), and the counts "frames" (0: no track), "accepted" and
        "refused" (the frames after the origin whose motion moved the pose, or
        whose estimate was refused).  What depthao process --pose-out prints
        for every frame; AO.pose is its current poses only."""
        pt = _lib.dao_pose_track()
        with self._lock:
            lib.dao_context_pose_track_sized(self._handle(), ctypes.byref(pt), ctypes.sizeof(pt))
        q = (ctypes.c_double * 4)()
        lib.dao_pose_matrix_to_quat(pt.rotation, q)
        return {"rotation": np.array(q[:], np.float64),
                "translation": np.array(pt.translation[:], np.float64),
                "current": bool(pt.current), "frame_index": int(pt.frame_index),
                "timestamp_ns": int(pt.timestamp_ns), "frames": int(pt.frames),
                "accepted": int(pt.accepted), "refused": int(pt.refused)}

    def shade(self, out=None):
        """The occlusion-shaded image of the last processed frame: uint8 RGB
        (H, W, 3) by default; `out` may be uint8 (H, W, 3) for RGB or (H, W)
        for gray, also a strided view.  The shading mode and colours are the
        parameters shade, near, far, shade_power, occlusion_color."""
        h, w = self._camera.shape
        if out is None:
            result = target = np.empty((h, w, 3), np.uint8)
        else:
            if not isinstance(out, np.ndarray):
                raise ValueError("out must be a numpy array, got %s" % type(out).__name__)
            comps = 3 if out.ndim == 3 else 1
            result = self._check_image("out", out, {"u1": "uint8"}, comps)
            if not out.flags.writeable:
                raise ValueError("out is read-only")
            target = out if _frames.row_stride(out, comps) is not None else \
                np.empty(out.shape, np.uint8)
        comps = 3 if target.ndim == 3 else 1
        fmt = _lib.PIXFMT_RGB24 if comps == 3 else _lib.PIXFMT_GRAY8
        frame = _frames.make_frame(target, fmt, _frames.row_stride(target, comps))
        err = _lib.new_error()
        with self._lock:
            r = lib.dao_context_shade(self._handle(), ctypes.byref(frame), ctypes.byref(err))
        _lib.check(r, err)
        if target is not result:
            result[...] = target
        return result

    def overlay(self, color, ao=None, out=None):
        """AO over colour: the colour image darkened by the AO, uint8 RGB (H, W, 3)
        at the camera's (the depth's) size, each channel round(c x a / 65535) with
        a = round(visibility x 65535) (dao_overlay; what depthaod's overlay stream
        and depthao process --overlay-out write).

        color: uint8 (h, w, 3) RGB of the frame, the depth's size or the same
        aspect ratio (then resampled bilinearly; another aspect ratio raises
        ValueError: depthao does not reproject between cameras).  ao: the
        visibility (float32 (H, W)); default the array the last process()
        returned.  out: a uint8 (H, W, 3) array to write into.
        """
        if ao is None:
            ao = self._last_ao
            if ao is None:
                raise ValueError("overlay() before process(): there is no AO yet")
        ao = self._check_image("ao", ao, {"f4": "float32"}, 1)
        if not isinstance(color, np.ndarray):
            raise ValueError("color must be a numpy array, got %s" % type(color).__name__)
        if color.dtype != np.uint8 or color.ndim != 3 or color.shape[2] != 3:
            raise ValueError("color must be uint8 RGB of shape (h, w, 3), got %s %s"
                             % (color.dtype, color.shape))
        if _frames.row_stride(color, 3) is None:
            color = _frames.packed(color, np.uint8)
        if _frames.row_stride(ao, 1) is None:
            ao = _frames.packed(ao, np.float32)
        h, w = self._camera.shape
        if out is None:
            result = target = np.empty((h, w, 3), np.uint8)
        else:
            result = self._check_image("out", out, {"u1": "uint8"}, 3)
            if not out.flags.writeable:
                raise ValueError("out is read-only")
            target = out if _frames.row_stride(out, 3) is not None else \
                np.empty((h, w, 3), np.uint8)
        cframe = _frames.make_frame(color, _lib.PIXFMT_RGB24, _frames.row_stride(color, 3))
        aframe = _frames.make_frame(ao, _lib.PIXFMT_GRAY_F32, _frames.row_stride(ao, 1))
        oframe = _frames.make_frame(target, _lib.PIXFMT_RGB24, _frames.row_stride(target, 3))
        err = _lib.new_error()
        _lib.check(lib.dao_overlay(ctypes.byref(cframe), ctypes.byref(aframe),
                                   ctypes.byref(oframe), ctypes.byref(err)), err)
        if target is not result:
            result[...] = target
        return result

    def _plane(self, fn, fmt, comps):
        h, w = self._camera.shape
        arr = np.empty((h, w) if comps == 1 else (h, w, comps), np.float32)
        frame = _frames.make_frame(arr, fmt, arr.strides[0])
        err = _lib.new_error()
        with self._lock:
            r = fn(self._handle(), ctypes.byref(frame), ctypes.byref(err))
        _lib.check(r, err)
        return arr

    def filtered_depth(self, unit=None):
        """The filtered depth of the last processed frame (dao_context_get_depth): the
        depth the normals and the AO were computed from, after depth-min/max, the
        temporal depth filter and the prefilter; 0 where there is no depth.

        unit=None: float32 (H, W) metres.  unit (metres per count, e.g. the unit
        process() was given): uint16 (H, W) counts of `unit`, rounded to the nearest
        (ties to even); a depth below half a count is 1 and one beyond 65535 counts
        65535, so a pixel with depth is never 0.  uint16 input read back in its own
        unit keeps its counts where the filters left it alone.  Works with
        algorithm="none" (depth only).  Before the first process(): OSError EAGAIN.
        """
        if unit is None:
            return self._plane(lib.dao_context_get_depth, _lib.PIXFMT_DEPTH_F32, 1)
        if isinstance(unit, bool) or not isinstance(unit, numbers.Real) or \
                not (math.isfinite(unit) and unit > 0):
            raise ValueError("unit must be a positive number of metres per count "
                             "(0.001 for millimetres), got %r" % (unit,))
        arr = np.empty(self._camera.shape, np.uint16)
        frame = _frames.make_frame(arr, _lib.PIXFMT_DEPTH16, arr.strides[0], float(unit))
        err = _lib.new_error()
        with self._lock:
            r = lib.dao_context_get_depth(self._handle(), ctypes.byref(frame), ctypes.byref(err))
        _lib.check(r, err)
        return arr

    def normals(self):
        """The last frame's unit normals: float32 (H, W, 3), optical frame."""
        return self._plane(lib.dao_context_get_normals, _lib.PIXFMT_NORMAL_F32, 3)

    @property
    def timings(self):
        """Milliseconds per stage of the last frame (dao_context_timings)."""
        t = _lib.dao_timings()
        with self._lock:
            _lib.check(lib.dao_context_timings_sized(self._handle(), ctypes.byref(t),
                                                     ctypes.sizeof(t)), None)
        return {name[:-3]: value for name, value in _lib.filled_fields(t)}

    @property
    def noise_info(self):
        """The noise the last frame was filtered for (dao_context_noise): a dict with
        measured (bool), sigma_area, sigma_link and sigma_slope (1/z, 1/m),
        prefilter_scale (px), normal_radius (px), denoise_noise (1/m), and with
        noise_interval > 1 age (frames since the full measurement) and
        cells_measured (cells measured again this frame where the scene moved)."""
        n = _lib.dao_noise_info()
        with self._lock:
            _lib.check(lib.dao_context_noise_sized(self._handle(), ctypes.byref(n),
                                                   ctypes.sizeof(n)), None)
        return {name: (bool(value) if name == "measured" else value)
                for name, value in _lib.filled_fields(n)}

    @property
    def simd(self):
        """The kernel set this context runs ("avx2", "reference", ...)."""
        with self._lock:
            return _lib.text(lib.dao_simd_name(lib.dao_context_simd(self._handle())))
