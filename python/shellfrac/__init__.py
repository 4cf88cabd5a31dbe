"""shellfrac: tearing thin shells with the material point method, from Python.

Kirchhoff-Love shells on NURBS patches, simulated with MPM (L. Fan's thesis, chapter 4). Build a scene
(``Scene.load``, ``Scene.from_dict``), step it (``Simulation``) and read its particles as NumPy arrays, or
run it like the command-line tool (``run``). See docs/python.md.
"""
import os as _os

from ._shellfrac import (  # noqa: F401  (re-exported)
    Error,
    NumericalError,
    Scene,
    SceneError,
    Simulation,
    __version__,
    run_interruptible,
)
from . import _shellfrac

__all__ = ["Error", "NumericalError", "Scene", "SceneError", "Simulation", "run", "run_interruptible", "__version__"]


def _as_scene(scene):
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, dict):
        return Scene.from_dict(scene)
    if isinstance(scene, (str, _os.PathLike)):
        return Scene.load(_os.fspath(scene))
    raise TypeError("scene must be a shellfrac.Scene, a dict or a path, not %s" % type(scene).__name__)


def run(scene, out="out", threads=0, log=False):
    """Runs a scene the way ``shellfrac run`` does and returns its summary.json as a dict.

    scene: a Scene, a scene dict, or the path of a scene file.
    out: the run folder; frames go to out/frames/, the record to out/summary.json (both written
        atomically, exactly as the command-line tool writes them).
    threads: TBB threads (0: all cores). Positions are deterministic for a thread count.
    log: print the run's progress lines and warnings to stderr.

    Raises SceneError for bad input (before any output) and NumericalError on a numerical failure (after
    writing a summary with "status": "failed"). The GIL is released while it runs. Ctrl-C stops the run
    between steps (KeyboardInterrupt, after the summary with "status": "interrupted" is written) when
    ``run_interruptible`` is True, i.e. when the run driver offers the hook; otherwise it is seen only
    when the run ends.
    """
    return _shellfrac._run(_as_scene(scene), _os.fspath(out), int(threads), bool(log))
