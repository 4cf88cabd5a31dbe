"""Helpers shared by the Blender test drivers: running shellfrac and Blender, reading their answers."""
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.dirname(os.path.dirname(HERE))
COUNT_SCRIPT = os.path.join(SOURCE_DIR, "apps", "shellfrac", "blender", "count_loose_parts.py")


class Failure(Exception):
    """A failed check; the driver prints the message and exits 1."""


def check(condition, message):
    if not condition:
        raise Failure(message)


def blender_program(given=None):
    """The blender to run: --blender, $SHELLFRAC_BLENDER, or `blender` on PATH; a clear failure otherwise."""
    program = given or os.environ.get("SHELLFRAC_BLENDER") or shutil.which("blender")
    check(program and os.path.isfile(program) and os.access(program, os.X_OK),
          "Blender not found (%r): these tests import frames into Blender; install it with "
          "`apt-get install blender` or `bash scripts/setup.sh`" % program)
    return program


def run(cmd, **kw):
    """Runs cmd; returns (exit code, stdout, stderr)."""
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw)
    return p.returncode, p.stdout, p.stderr


def shellfrac_run(shellfrac, scene, out_dir, threads=2):
    """`shellfrac run SCENE --out OUT --threads N`; returns summary.json (a failed run is a test failure)."""
    shutil.rmtree(out_dir, ignore_errors=True)
    code, out, err = run([shellfrac, "run", scene, "--out", out_dir, "--threads", str(threads)])
    check(code == 0, "shellfrac run %s exited %d:\n%s%s" % (scene, code, out, err[-3000:]))
    with open(os.path.join(out_dir, "summary.json")) as f:
        return json.load(f)


def count_loose_parts(blender, frame, extra=()):
    """Blender's loose-part record of one frame file (apps/shellfrac/blender/count_loose_parts.py)."""
    code, out, err = run([blender, "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
                          "-P", COUNT_SCRIPT, "--", frame] + list(extra))
    lines = [l for l in out.splitlines() if l.startswith("loose-parts: ")]
    check(code == 0 and len(lines) == 1,
          "Blender could not count the loose parts of %s (exit %d):\n%s%s" % (frame, code, out[-3000:], err[-3000:]))
    return json.loads(lines[0][len("loose-parts: "):])


def main_guard(fn):
    try:
        fn()
    except Failure as e:
        print("FAIL: %s" % e, file=sys.stderr)
        sys.exit(1)
