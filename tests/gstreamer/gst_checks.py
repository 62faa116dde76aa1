# SPDX-License-Identifier: MIT
"""What the element's Python tests share: a skip (exit 77) without the tools they run,
the failures collected as they come, gst-launch-1.0 under a time limit, and the exit
status at the end."""
import shutil
import subprocess
import sys

failures = []


def require(*tools):
    """Exit 77 (skipped) unless every tool is on PATH (gstreamer1.0-tools)."""
    for tool in tools:
        if not shutil.which(tool):
            print("SKIP: %s not installed (gstreamer1.0-tools)" % tool)
            sys.exit(77)


def check(cond, what):
    """Record a failure (and go on) unless cond holds."""
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def launch(*args, seconds=120):
    """gst-launch-1.0 ARGS, stopped after `seconds` (a hang is a failure, not a wait)."""
    return subprocess.run(["timeout", str(seconds), "gst-launch-1.0", *args],
                          capture_output=True, text=True)


def status():
    """The test's exit status: 1 with the count of failures, else 0."""
    if failures:
        print("%d failure(s)" % len(failures))
        return 1
    print("ok")
    return 0
