# SPDX-License-Identifier: MIT
"""What the CLI tests share: run depthao and check what it did."""

import subprocess
import sys


def run(cli, *args, expect=0):
    """depthao ARGS; its stdout and stderr, or the test fails on another exit status."""
    p = subprocess.run([cli, *args], capture_output=True, text=True, timeout=300)
    if p.returncode != expect:
        sys.exit("FAIL: depthao %s: exit %d, want %d\n%s%s" % (" ".join(args), p.returncode, expect,
                                                               p.stdout, p.stderr))
    return p.stdout + p.stderr


def check(cond, what):
    if not cond:
        sys.exit("FAIL: " + what)
