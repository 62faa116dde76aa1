# SPDX-License-Identifier: MIT
"""The GStreamer element with 16-bit big-endian depth and with colour:
pngdec linked straight to depthao (GRAY16_BE) gives the AO that GRAY16_LE
gives and that depthao process gives; hfov-deg/vfov-deg equal depthao
process --fov and the deprecated radian properties; a colour stream on the
color_sink request pad gives AO over colour, round(colour x AO16 / 65535)
with the AO of the same depth frames, colour of twice the size averaged
down; another aspect ratio, a color_sink requested but not linked, and a
colour stream without frames are errors.
usage: test_gst_color.py DEPTHAO   (GST_PLUGIN_PATH set; exit 77 without
gst-launch-1.0, PIL or numpy)"""
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
    from PIL import Image
except ImportError as e:
    print("SKIP: %s (python3-numpy, python3-pil)" % e)
    sys.exit(77)
from gst_checks import check, launch, require, status  # noqa: E402

require("gst-launch-1.0")

DEPTHAO = sys.argv[1]
CAM = ["fx=525", "fy=525", "cx=319.5", "cy=239.5"]


def raw(path, shape, dtype):
    return np.fromfile(path, dtype=dtype).reshape(shape)


def composite(color, ao16):
    return ((color.astype(np.uint32) * ao16.astype(np.uint32)[:, :, None] + 32767) // 65535)


def big_endian(tmp, depth):
    ref = os.path.join(tmp, "ref-ao.png")
    p = subprocess.run([DEPTHAO, "process", "--input", depth, "--intrinsics",
                        "525,525,319.5,239.5", "--ao-out", ref, "--quiet"], capture_output=True,
                       text=True)
    check(p.returncode == 0, "depthao process: %s" % p.stderr)
    want = np.asarray(Image.open(ref), dtype=np.uint16)
    outs = {}
    for name, chain in [("straight", []), ("forced-be", ["!", "video/x-raw,format=GRAY16_BE"]),
                        ("le", ["!", "videoconvert", "!", "video/x-raw,format=GRAY16_LE"])]:
        out = os.path.join(tmp, name + ".raw")
        p = launch("-v", "filesrc", "location=" + depth, "!", "pngdec", *chain, "!",
                   "depthao", "name=d", *CAM, "!", "video/x-raw,format=GRAY16_LE", "!",
                   "filesink", "location=" + out)
        check(p.returncode == 0, "%s pipeline: %s" % (name, p.stderr[-500:]))
        if p.returncode:
            continue
        # what the element's sink pad negotiated (gst-launch -v prints the caps)
        sink_caps = [l for l in p.stdout.splitlines() if "/GstDepthao:d.GstPad:sink:" in l]
        fmt = "GRAY16_LE" if name == "le" else "GRAY16_BE"
        check(sink_caps and "format=(string)%s" % fmt in sink_caps[0],
              "%s: the sink pad did not negotiate %s: %s" % (name, fmt, sink_caps))
        outs[name] = raw(out, (480, 640), "<u2")
        check(np.array_equal(outs[name], want),
              "%s: %d AO pixels differ from depthao process" % (
                  name, np.count_nonzero(outs[name] != want)))
    print("GRAY16_BE straight from pngdec = GRAY16_LE = depthao process (%d pipelines)"
          % len(outs))


def fov(tmp, depth):
    ref = os.path.join(tmp, "ref-fov.png")
    subprocess.run([DEPTHAO, "process", "--input", depth, "--fov", "66,50", "--ao-out", ref,
                    "--quiet"], check=True)
    want = np.asarray(Image.open(ref), dtype=np.uint16)
    rad = ["hfov=%.17g" % (66 * (3.14159265358979323846 / 180.0)),
           "vfov=%.17g" % (50 * (3.14159265358979323846 / 180.0))]
    for name, props in [("degrees", ["hfov-deg=66", "vfov-deg=50"]), ("radians", rad)]:
        out = os.path.join(tmp, "fov-%s.raw" % name)
        p = subprocess.run(["timeout", "60", "gst-launch-1.0", "filesrc", "location=" + depth,
                            "!", "pngdec", "!", "depthao", *props, "!",
                            "video/x-raw,format=GRAY16_LE", "!", "filesink",
                            "location=" + out], capture_output=True, text=True,
                           env=dict(os.environ, GST_DEBUG="depthao:2"))
        check(p.returncode == 0, "fov %s: %s" % (name, p.stderr[-400:]))
        if p.returncode == 0:
            check(np.array_equal(raw(out, (480, 640), "<u2"), want),
                  "fov in %s differs from depthao process --fov 66,50" % name)
        deprecated = "deprecated" in p.stderr
        check(deprecated == (name == "radians"),
              "fov %s: deprecation warning %s: %s" % (name, deprecated, p.stderr[-300:]))
    print("hfov-deg=66 vfov-deg=50 = depthao process --fov 66,50 = the deprecated radians")


def overlay_run(tmp, depth, colour, name, n=3, fmt="RGB"):
    out = os.path.join(tmp, name + "-%d.raw")
    return launch("filesrc", "location=" + depth, "!", "pngdec", "!", "imagefreeze",
                  "num-buffers=%d" % n, "!", "depthao", "name=d", *CAM, "!",
                  "video/x-raw,format=" + fmt, "!", "multifilesink", "location=" + out,
                  "filesrc", "location=" + colour, "!", "pngdec", "!", "videoconvert", "!",
                  "video/x-raw,format=RGB", "!", "imagefreeze", "num-buffers=%d" % n, "!",
                  "d.color_sink"), out


def overlay(tmp, depth):
    # the AO of the same three depth frames, without colour
    aos = os.path.join(tmp, "ao-%d.raw")
    p = launch("filesrc", "location=" + depth, "!", "pngdec", "!", "imagefreeze",
               "num-buffers=3", "!", "depthao", *CAM, "!", "video/x-raw,format=GRAY16_LE", "!",
               "multifilesink", "location=" + aos)
    check(p.returncode == 0, "AO frames: %s" % p.stderr[-400:])
    y, x = np.mgrid[0:960, 0:1280]
    big = np.stack([(x * 255 // 1279), (y * 255 // 959), ((x + y) * 7) % 256], -1)\
        .astype(np.uint8)
    big[::7, ::5] = 255 - big[::7, ::5]  # detail the averaging must see
    small = big[::2, ::2].copy()
    Image.fromarray(small).save(os.path.join(tmp, "colour.png"))
    Image.fromarray(big).save(os.path.join(tmp, "colour2x.png"))
    mean = np.floor(big.astype(np.float64).reshape(480, 2, 640, 2, 3).mean(axis=(1, 3)) + 0.5)
    for name, colour, want_colour in [("same", "colour.png", small),
                                      ("2x", "colour2x.png", mean)]:
        p, out = overlay_run(tmp, depth, os.path.join(tmp, colour), "ov-" + name)
        check(p.returncode == 0, "overlay %s: %s" % (name, p.stderr[-500:]))
        if p.returncode:
            continue
        for i in range(3):
            got = raw(out % i, (480, 640, 3), np.uint8)
            ao = raw(aos % i, (480, 640), "<u2")
            want = composite(want_colour, ao)
            bad = int(np.count_nonzero(np.any(got != want, axis=2)))
            check(bad == 0, "overlay %s frame %d: %d pixels are not colour x AO" % (name, i, bad))
            check(np.count_nonzero(ao < 60000) > 1000, "the AO occludes too little to test")
    # BGRx out: the same pixels repacked
    p, out = overlay_run(tmp, depth, os.path.join(tmp, "colour.png"), "ov-bgrx", n=1, fmt="BGRx")
    check(p.returncode == 0, "overlay BGRx: %s" % p.stderr[-400:])
    if p.returncode == 0:
        got = raw(out % 0, (480, 640, 4), np.uint8)
        want = composite(small, raw(aos % 0, (480, 640), "<u2"))
        check(np.array_equal(got[:, :, 2::-1], want), "overlay BGRx differs")
    print("color_sink: overlay = colour x AO (same size, 2x scaled, BGRx), 3 frames")
    # another aspect ratio
    Image.fromarray(small[:360]).save(os.path.join(tmp, "wide.png"))
    p, _ = overlay_run(tmp, depth, os.path.join(tmp, "wide.png"), "ov-wide", n=1)
    check(p.returncode != 0 and "aspect ratio" in p.stderr + p.stdout,
          "another aspect ratio: exit %d, %s" % (p.returncode, (p.stderr + p.stdout)[-400:]))


def errors(tmp, depth):
    try:
        import gi
        gi.require_version("Gst", "1.0")
        from gi.repository import Gst
    except (ImportError, ValueError) as e:
        print("SKIP part: %s (python3-gi, gir1.2-gstreamer-1.0)" % e)
        return
    Gst.init(None)

    def run(desc, request_color, link_color=None):
        pipe = Gst.parse_launch(desc)
        d = pipe.get_by_name("d")
        if request_color:
            pad = d.request_pad_simple("color_sink")
            check(pad is not None and pad.get_name() == "color_sink", "no color_sink pad")
            if link_color:
                pipe.get_by_name(link_color).get_static_pad("src").link(pad)
        pipe.set_state(Gst.State.PLAYING)
        msg = pipe.get_bus().timed_pop_filtered(20 * Gst.SECOND,
                                                Gst.MessageType.ERROR | Gst.MessageType.EOS)
        pipe.set_state(Gst.State.NULL)
        if msg is None:
            return "timeout"
        if msg.type == Gst.MessageType.EOS:
            return "eos"
        return msg.parse_error()[0].message

    base = ("filesrc location=%s ! pngdec ! depthao name=d fx=525 fy=525 ! "
            "video/x-raw,format=RGB ! fakesink" % depth)
    m = run(base, True)
    check("color_sink" in m and "nothing is linked" in m, "unlinked color_sink: %s" % m)
    # a colour stream that ends before its first frame
    m = run(base + " videotestsrc num-buffers=0 ! video/x-raw,format=RGB,width=640,height=480 "
            "! identity name=c", True, "c")
    check("ended before its first frame" in m, "colour without frames: %s" % m)
    # without color_sink: shaded output, no error
    check(run(base, False) == "eos", "depth only without color_sink")
    print("errors: color_sink requested but unlinked, colour without frames")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        p = subprocess.run([DEPTHAO, "synth", "--scene", "boxes", "--rays", "1", "--out",
                            os.path.join(tmp, "synth")], capture_output=True, text=True)
        if p.returncode:
            print("FAIL: synth: %s" % p.stderr)
            return 1
        depth = os.path.join(tmp, "synth", "boxes", "depth.png")
        big_endian(tmp, depth)
        fov(tmp, depth)
        overlay(tmp, depth)
        errors(tmp, depth)
    return status()


sys.exit(main())
