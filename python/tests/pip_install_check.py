#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""pip install of the depthao package into a fresh virtual environment, offline
as on a Debian machine without PyPI:

    python3 -m venv --system-site-packages V
    V/bin/pip install --no-build-isolation --no-index <a copy of the project>

then `import depthao` from another directory with no DEPTHAO_LIBRARY or
PYTHONPATH: the package and its bundled library come from the venv, the AO of
a frame opened with depthao.open() (camera from the camera.json beside it)
equals `depthao process` bit for bit.  SKIP (77) without venv, pip or
meson-python (Debian: python3-venv, python3-mesonpy).

usage: pip_install_check.py  (DEPTHAO_CLI, DAO_SOURCE_ROOT from meson's test)
"""

import os
import shutil
import subprocess
import sys
import tempfile
import time

PY = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
ROOT = os.environ.get("DAO_SOURCE_ROOT") or \
    os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLI = os.environ.get("DEPTHAO_CLI")

USE = r'''
import os, sys
import numpy as np
import depthao
venv = sys.argv[1]
images, cli_ao = sys.argv[2], sys.argv[3]
assert depthao.__file__.startswith(venv), depthao.__file__
assert depthao.library_path.startswith(os.path.join(os.path.dirname(depthao.__file__), "_libdepthao")), \
    depthao.library_path
assert os.path.exists(os.path.join(os.path.dirname(depthao.__file__), "py.typed"))
assert os.path.exists(os.path.join(os.path.dirname(depthao.__file__), "__init__.pyi"))
src = depthao.open(images)
cam = src.camera()
assert src.info["camera_file"] == os.path.join(images, "camera.json"), src.info["camera_file"]
assert cam == depthao.Camera.from_matrix([[525, 0, 319.5], [0, 525, 239.5], [0, 0, 1]], 640, 480)
ao = depthao.AO(cam)
index, depth, info = next(src)
vis = ao.process(depth, unit=info["depth_unit"], frame_index=index)
got = np.rint(vis * np.float32(65535.0)).astype(np.uint16)  # lrintf(v * 65535.0f)
want = depthao.read_png(cli_ao)
assert np.array_equal(got, want), np.abs(got.astype(int) - want).max()
metres = depth.astype(np.float64) * info["depth_unit"]
assert ao.process(metres).shape == (480, 640)  # float64 depth
print("ok: %s, %s" % (depthao.__file__, depthao.library_path))
'''


def main():
    try:
        subprocess.run([PY, "-c", "import venv, ensurepip, mesonpy"], check=True,
                       capture_output=True)
    except subprocess.CalledProcessError as e:
        print("SKIP: %s cannot make a venv with meson-python (Debian: python3-venv "
              "python3-mesonpy): %s" % (PY, e.stderr.decode().strip().splitlines()[-1]))
        return 77
    if not CLI:
        print("SKIP: DEPTHAO_CLI is not set (run through meson test)")
        return 77
    env = {k: v for k, v in os.environ.items()
           if k not in ("DEPTHAO_LIBRARY", "PYTHONPATH", "DEPTHAO_PLUGIN_PATH",
                        "PYTHONHOME", "VIRTUAL_ENV")}
    env.update(PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INPUT="1")
    with tempfile.TemporaryDirectory() as tmp:
        # a copy of the project as a fresh checkout has it (no build directories)
        src = os.path.join(tmp, "depthao")
        shutil.copytree(ROOT, src, ignore=lambda d, names: [
            n for n in names if d == ROOT and (n.startswith("build") or n.startswith(".mesonpy")
                                               or n in (".git", "out"))])
        venv = os.path.join(tmp, "venv")
        subprocess.run([PY, "-m", "venv", "--system-site-packages", venv], check=True, env=env)
        t0 = time.monotonic()
        p = subprocess.run([os.path.join(venv, "bin", "pip"), "install", "--no-build-isolation",
                            "--no-index", "--no-cache-dir", src], capture_output=True,
                           text=True, env=env)
        took = time.monotonic() - t0
        if p.returncode:
            print(p.stdout, p.stderr)
            print("FAIL: pip install exit %d" % p.returncode)
            return 1
        print("pip install (builds libdepthao) took %.0f s" % took)

        cli_ao = os.path.join(tmp, "cli-ao")
        images = os.path.join(ROOT, "recordings", "spheres-noisy")
        subprocess.run([CLI, "process", "--quiet", "--input", os.path.join(images, "0000.png"),
                        "--ao-out", cli_ao + ".png"], check=True)
        elsewhere = os.path.join(tmp, "elsewhere")
        os.mkdir(elsewhere)
        p = subprocess.run([os.path.join(venv, "bin", "python"), "-c", USE, venv, images,
                            cli_ao + ".png"], cwd=elsewhere, env=env, capture_output=True,
                           text=True)
        print(p.stdout + p.stderr)
        if p.returncode:
            print("FAIL: using the installed package")
            return 1
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
