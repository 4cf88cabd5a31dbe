"""Many independent runs of scene variants: serially, on a Dask cluster, or on any concurrent.futures.Executor.

A sweep is a list of ``Variant`` objects (a name and a scene document). Each variant runs ``shellfrac.run``
in a worker process and publishes its run folder (frames, summary.json) as ``<out>/<name>`` only once the
run is over, so the folder of a variant either holds a whole run or does not exist. The workers must share
``<out>`` (one machine, or a network file system on a cluster). ``run_sweep`` returns one ``Outcome`` per
variant, in the order of the variants, and writes them to ``<out>/sweep.json``.

A worker that dies while it runs a variant (killed, out of memory, lost machine) costs that variant one
attempt; it is submitted again once (``retries``), then reported with status ``"lost"``. The other variants'
results are kept. A variant whose simulation fails (a NaN blow-up, say) is a result, status ``"failed"``:
the run is deterministic, so it is not repeated. Bad input is status ``"error"`` with the message.

    import shellfrac.sweep as sw
    from distributed import Client
    client = Client("tcp://scheduler:8786")       # or sw.connect("local:2"), or a ProcessPoolExecutor
    outcomes = sw.run_sweep([sw.Variant("a", scene_a), sw.Variant("b", scene_b)], "out/sweep", client)

See docs/python.md ("Sweeps") and docs/benchmarks.md for starting a scheduler and workers on several
machines.
"""
import concurrent.futures as _cf
import dataclasses as _dc
import json as _json
import os as _os
import pathlib as _pathlib
import re as _re
import shutil as _shutil
import socket as _socket
import sys as _sys
import time as _time
import uuid as _uuid

__all__ = ["Variant", "Outcome", "SweepError", "run_sweep", "run_variant", "connect", "close", "write_atomically"]

_NAME = _re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")
_PARTIAL = ".partial"  # under <out>: run folders of variants still running (or of attempts that died)


class SweepError(Exception):
    """A sweep that cannot start: bad variant names, an unreachable scheduler, an unusable executor."""


@_dc.dataclass
class Variant:
    """One run of a sweep: ``name`` is its subfolder of the sweep's output folder (letters, digits, '_', '.',
    '-'); ``scene`` a scene document (dict), a ``shellfrac.Scene`` or a scene file's path; ``info`` anything
    the caller wants back with the outcome (the swept parameters, say)."""

    name: str
    scene: object
    info: dict = _dc.field(default_factory=dict)


@_dc.dataclass
class Outcome:
    """What became of one variant.

    status: the run's own status ("completed", "failed", "interrupted"), or "error" (bad input: SceneError
        or another exception raised by the run; ``error`` says which), or "lost" (its worker died on every
        attempt).
    summary: the run's summary.json as a dict (None for "error" and "lost").
    folder: ``<out>/<name>`` (it exists only for runs that wrote a summary).
    attempts: how many times the variant was submitted.
    worker: "host:pid" of the process that ran the last attempt, when known.
    wall_seconds: wall time of the run inside the worker.
    """

    name: str
    status: str
    summary: dict = None
    error: str = None
    folder: str = None
    attempts: int = 1
    worker: str = None
    wall_seconds: float = 0.0
    info: dict = _dc.field(default_factory=dict)

    def to_dict(self):
        d = _dc.asdict(self)
        d.pop("summary")
        return d


def _scene_document(scene):
    """A picklable form of the scene for a worker: a dict, or the JSON text of a Scene, or a path string."""
    from . import Scene  # noqa: PLC0415  (the extension loads only where it is needed)

    if isinstance(scene, Scene):
        return {"json": scene.to_json(), "source": scene.source}
    if isinstance(scene, dict):
        return {"dict": scene}
    if isinstance(scene, (str, _os.PathLike)):
        return {"path": _os.path.abspath(_os.fspath(scene))}
    raise TypeError("a variant's scene must be a dict, a shellfrac.Scene or a path, not %s" % type(scene).__name__)


def _publish(run_dir, final):
    """Makes ``run_dir`` the variant's folder ``final`` by renames only: ``final`` holds the old run or the
    new one, never part of one. An older run in its place is moved aside first, then removed."""
    old = None
    if _os.path.lexists(final):
        old = run_dir.parent / ("%s.replaced.%s" % (final.name, _uuid.uuid4().hex))
        _os.replace(final, old)
    _os.replace(run_dir, final)
    if old is not None:
        _shutil.rmtree(old, ignore_errors=True)


def run_variant(name, scene, out, threads=1):
    """Runs one variant in this process and publishes its folder; the task a sweep submits to a worker.

    Returns a dict: status, summary, error, worker ("host:pid"), wall_seconds. Raises nothing for a bad
    scene or a failed run (they are results); an exception here (a full disk, say) is an infrastructure
    failure, which the sweep retries like a dead worker.
    """
    import shellfrac  # noqa: PLC0415  (imported in the worker process)

    out = _pathlib.Path(out)
    worker = "%s:%d" % (_socket.gethostname(), _os.getpid())
    run_dir = out / _PARTIAL / ("%s.%s" % (name, _uuid.uuid4().hex))
    run_dir.mkdir(parents=True)
    (run_dir / "worker.txt").write_text(worker + "\n")
    if "dict" in scene:
        doc = scene["dict"]
    elif "json" in scene:
        doc = shellfrac.Scene.from_json(scene["json"], scene["source"])
    else:
        doc = scene["path"]
    result = {"status": None, "summary": None, "error": None, "worker": worker, "wall_seconds": 0.0}
    start = _time.perf_counter()
    try:
        result["summary"] = shellfrac.run(doc, out=str(run_dir), threads=int(threads))
    except shellfrac.NumericalError as e:  # the summary says "failed"; keep it
        result["error"] = str(e)
        with open(run_dir / "summary.json") as f:
            result["summary"] = _json.load(f)
    except KeyboardInterrupt:  # the summary says "interrupted"
        _shutil.rmtree(run_dir, ignore_errors=True)
        raise
    except shellfrac.Error as e:  # bad input: nothing was written
        _shutil.rmtree(run_dir, ignore_errors=True)
        result.update(status="error", error=str(e))
        return result
    result["wall_seconds"] = _time.perf_counter() - start
    result["status"] = result["summary"]["status"]
    (run_dir / "worker.txt").unlink()
    _publish(run_dir, out / name)
    return result


class _Serial:
    """The executor of a sweep without one: each variant runs in this process when it is submitted."""

    def submit(self, fn, *args):
        f = _cf.Future()
        try:
            f.set_result(fn(*args))
        except KeyboardInterrupt:
            raise
        except BaseException as e:  # noqa: BLE001  (reported as the attempt's failure)
            f.set_exception(e)
        return f


def _executor_of(executor):
    """(an object with submit() returning concurrent.futures.Future, how many extra attempts a dead worker
    already gets from the executor itself)."""
    if executor is None:
        return _Serial(), 0
    if hasattr(executor, "get_executor") and hasattr(executor, "run_on_scheduler"):  # a Dask Client
        try:  # a lambda travels by value: the scheduler need not import shellfrac
            scheduler_retries = int(executor.run_on_scheduler(lambda dask_scheduler: dask_scheduler.allowed_failures))
        except Exception:  # noqa: BLE001  (a scheduler that refuses to run functions: assume Dask's default)
            scheduler_retries = 3
        return executor.get_executor(pure=False), scheduler_retries
    if hasattr(executor, "submit"):
        return executor, 0
    raise SweepError("the executor must be a Dask Client or a concurrent.futures.Executor, not %s"
                     % type(executor).__name__)


def _failure_text(exc):
    """The exception's kind and the first line of its message."""
    return ("%s: %s" % (type(exc).__name__, exc)).splitlines()[0]


def run_sweep(variants, out, executor=None, threads=1, retries=1, log=None):
    """Runs every variant and returns their outcomes in the order given.

    variants: Variant objects with distinct names.
    out: the sweep's folder; variant v writes to <out>/<v.name>, the outcomes go to <out>/sweep.json.
    executor: None (one after another in this process), a Dask ``distributed.Client`` or any
        ``concurrent.futures.Executor`` whose workers can import shellfrac (a ProcessPoolExecutor, say).
    threads: TBB threads of each run (parallelism comes from the variants, so 1 by default).
    retries: further attempts for a variant whose worker died. A Dask scheduler already reruns a task whose
        worker died ``distributed.scheduler.allowed-failures`` times; those count against ``retries``.
    log: a function taking one progress line (print, say), or None.
    """
    variants = list(variants)
    seen = set()
    for v in variants:
        if not isinstance(v, Variant):
            raise SweepError("a sweep takes Variant objects, not %s" % type(v).__name__)
        if not _NAME.match(v.name) or v.name == _PARTIAL:
            raise SweepError("variant name %r: use letters, digits, '_', '.' and '-' (it names a folder)" % v.name)
        if v.name in seen:
            raise SweepError("variant name %r is given twice" % v.name)
        seen.add(v.name)
    out = _pathlib.Path(out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    submitter, executor_retries = _executor_of(executor)
    own_retries = max(0, int(retries) - executor_retries)
    documents = {v.name: _scene_document(v.scene) for v in variants}
    attempts = {v.name: 0 for v in variants}
    outcomes = {}
    pending = {}

    def submit(v):
        attempts[v.name] += 1
        try:
            f = submitter.submit(run_variant, v.name, documents[v.name], str(out), int(threads))
        except Exception as e:  # noqa: BLE001  (a broken executor: the variant is lost, the rest go on)
            f = _cf.Future()
            f.set_exception(e)
        pending[f] = v

    def say(line):
        if log is not None:
            log(line)

    def settle(f):
        v = pending.pop(f)
        exc = f.exception()
        if exc is not None:
            if attempts[v.name] <= own_retries:
                say("%s: its worker failed (%s); submitting it again" % (v.name, _failure_text(exc)))
                submit(v)
                return
            outcomes[v.name] = Outcome(v.name, "lost", error=_failure_text(exc),
                                       attempts=attempts[v.name] + executor_retries, info=v.info)
        else:
            r = f.result()
            folder = str(out / v.name) if r["summary"] is not None else None
            outcomes[v.name] = Outcome(v.name, r["status"], r["summary"], r["error"], folder, attempts[v.name],
                                       r["worker"], r["wall_seconds"], v.info)
        o = outcomes[v.name]
        say("[%d/%d] %s: %s%s%s" % (len(outcomes), len(variants), v.name, o.status,
                                   " in %.1f s on %s" % (o.wall_seconds, o.worker) if o.worker else "",
                                   " (%s)" % o.error if o.error else ""))

    serial = isinstance(submitter, _Serial)
    try:
        for v in variants:  # executors start them about in this order: put the longest first
            submit(v)
            while serial and pending:  # one at a time, each reported as it ends
                settle(next(iter(pending)))
        while pending:
            done, _ = _cf.wait(list(pending), return_when=_cf.FIRST_COMPLETED)
            for f in done:
                settle(f)
    except KeyboardInterrupt:
        for f in pending:
            f.cancel()
        raise
    finally:
        # Only settled variants: after Ctrl-C a worker may still be running a pending one in its folder.
        _remove_partials(out, set(outcomes))
    result = [outcomes[v.name] for v in variants]
    write_atomically(out / "sweep.json", _json.dumps({"variants": [o.to_dict() for o in result]}, indent=1) + "\n")
    return result


def _remove_partials(out, names):
    """Removes the run folders that attempts of these variants left behind (dead workers, interruptions)."""
    partial = out / _PARTIAL
    if not partial.is_dir():
        return
    for entry in partial.iterdir():
        if entry.name.rsplit(".", 1)[0] in names or entry.name.rsplit(".", 2)[0] in names:
            _shutil.rmtree(entry, ignore_errors=True)
    try:
        partial.rmdir()
    except OSError:  # another sweep's runs are still in it
        pass


def write_atomically(path, text):
    """Writes ``text`` to ``path`` through a temporary file in the same folder and a rename: the file holds
    the old content or the new, never part of either."""
    path = _pathlib.Path(path)
    tmp = path.with_name(".%s.%s.tmp" % (path.name, _uuid.uuid4().hex))
    try:
        with open(tmp, "w") as f:
            f.write(text)
            f.flush()
            _os.fsync(f.fileno())
        _os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def connect(address, timeout=5.0):
    """A Dask client for ``address``: "tcp://HOST:PORT" (a running scheduler) or "local:N" (a LocalCluster
    of N worker processes on this machine, one thread each, which a killed worker is restarted in).

    Raises SweepError when distributed is not installed or the scheduler does not answer within ``timeout``
    seconds. Close it with ``close(client)``.
    """
    try:
        import dask  # noqa: PLC0415
        from distributed import Client, LocalCluster  # noqa: PLC0415
    except ImportError as e:
        raise SweepError("--dask needs Dask's distributed package (Debian: apt-get install python3-distributed; "
                         "scripts/setup.sh installs it): %s" % e) from e
    m = _re.match(r"^local:(\d+)$", address)
    if m:
        n = int(m.group(1))
        if n < 1:
            raise SweepError("%s: a local cluster needs at least one worker" % address)
        # A worker that dies fails its task at once (run_sweep then decides about the retry), and a worker
        # holds only the task it runs, so that its death costs no queued variant an attempt.
        dask.config.set({"distributed.scheduler.allowed-failures": 0, "distributed.scheduler.worker-saturation": 1.0})
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
        return Client(cluster, timeout=timeout)
    if not _re.match(r"^(tcp|tls|inproc|ucx)://.+", address):
        raise SweepError("--dask %r: give a scheduler address such as tcp://HOST:8786, or local:N" % address)
    try:
        return Client(address, timeout=timeout)
    except (OSError, TimeoutError) as e:
        raise SweepError("cannot reach the Dask scheduler at %s within %g s: %s" % (address, timeout, e)) from e


def close(client):
    """Closes a client made by ``connect`` (and its local cluster)."""
    cluster = getattr(client, "cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()


if __name__ == "__main__":
    _sys.exit("shellfrac.sweep is a library: sweep a scene with `python3 -m shellfrac.sweep_cli`, run the obstacle "
              "course with `python3 -m shellfrac.verify_course`")
