# SPDX-License-Identifier: MIT
"""depthao: ambient occlusion from depth frames (Python bindings of libdepthao).

    import depthao
    cam = depthao.Camera(525, 525, 319.5, 239.5, 640, 480)
    ao = depthao.AO(cam, quality="default", radius=0.4)
    vis = ao.process(depth_mm)            # numpy uint16 (H, W), unit 0.001 m
    rgb = ao.shade()                      # uint8 (H, W, 3)

    for index, depth, info in depthao.open("recordings/spheres-rolling.oni"):
        ...

The library is found through $DEPTHAO_LIBRARY (a path to libdepthao.so), else
the project's build tree (build-py/ or build/ beside python/), else the
system's library path.  Errors from the library raise ValueError (invalid
arguments, -EINVAL) or OSError with its errno, with the library's message.
"""

from . import _lib
from ._ao import AO, Camera
from ._params import TABLE as PARAMETERS, ParamInfo
from . import _source
from ._source import Source, read_png, read_png_depth, write_png

open = _source.open

__version__ = "1.0.0"

#: Version of the loaded libdepthao ("1.0.0").
library_version = _lib.text(_lib.lib.dao_version())
#: Path (or name) of the loaded libdepthao.
library_path = _lib.path

# "open" is left out of __all__ so that "from depthao import *" does not hide the built-in open
__all__ = ["AO", "Camera", "PARAMETERS", "ParamInfo", "Source", "read_png",
           "read_png_depth", "write_png", "library_version", "library_path"]
