"""A parameter sweep of one scene from the command line, serially or on a Dask cluster.

    python3 -m shellfrac.sweep_cli SCENE.json --vary shells.0.material.E=1e4,2e4,4e4 \\
        [--vary time.cfl=0.25,0.5] [--out DIR] [--dask tcp://HOST:8786 | --dask local:2] [--threads N]

Every combination of the --vary values is one variant (their Cartesian product), run with shellfrac.run
as shellfrac.sweep does (each run folder published whole, a variant whose worker dies retried once). A
path is the scene's keys joined by dots, list positions as numbers; a value is JSON (1e4, "apic", true,
[1, 2]); values are separated by commas outside brackets and quotes. Writes DIR/sweep.csv (one row per
variant: the values, status, steps, wall and simulated seconds, pieces, peak edge stretch, final kinetic
energy), DIR/sweep.json and DIR/<variant>/. Exit codes: 0 every run completed, 1 some did not, 2 bad input
(the scene, a path, a value, every variant is checked before any runs) or an unreachable scheduler,
130 after Ctrl-C.
"""
import argparse
import copy
import csv
import io
import itertools
import json
import os
import sys

from . import sweep


class SweepInputError(Exception):
    """A --vary argument or a variant that cannot be used."""


def split_values(text):
    """Splits "1,[2, 3],\"a,b\"" at the commas outside brackets and quotes."""
    parts, depth, quoted, start = [], 0, False, 0
    for i, ch in enumerate(text):
        if ch == '"' and (i == 0 or text[i - 1] != "\\"):
            quoted = not quoted
        elif not quoted and ch in "[{":
            depth += 1
        elif not quoted and ch in "]}":
            depth -= 1
        elif not quoted and depth == 0 and ch == ",":
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return parts


def parse_vary(arg):
    """"a.b.0.c=v1,v2" -> (["a", "b", 0, "c"], [v1, v2])."""
    path, sep, values = arg.partition("=")
    if not sep or not path or not values:
        raise SweepInputError("--vary %r: write PATH=VALUE[,VALUE...], e.g. shells.0.material.E=1e4,2e4" % arg)
    keys = [int(k) if k.isdigit() else k for k in path.split(".")]
    parsed = []
    for v in split_values(values):
        try:
            parsed.append(json.loads(v))
        except json.JSONDecodeError as e:
            raise SweepInputError("--vary %s: value %r is not JSON (%s); quote strings: '\"apic\"'" % (path, v, e)) from e
    return path, keys, parsed


def set_path(document, keys, value, path):
    """Sets document[k0][k1]... = value; dict keys along the way are created, list positions must exist."""
    node = document
    for depth, k in enumerate(keys):
        last = depth == len(keys) - 1
        if isinstance(k, int):
            if not isinstance(node, list) or k >= len(node):
                raise SweepInputError("--vary %s: %s has no element %d" % (path, ".".join(map(str, keys[:depth])) or
                                                                         "the scene", k))
            if last:
                node[k] = value
            else:
                node = node[k]
        else:
            if not isinstance(node, dict):
                raise SweepInputError("--vary %s: %s is not an object" % (path, ".".join(map(str, keys[:depth]))))
            if last:
                node[k] = value
            else:
                node = node.setdefault(k, {})


def variants_of(base, varies):
    """One Variant per combination of the values, with the values in its info."""
    out = []
    for i, combo in enumerate(itertools.product(*[values for _, _, values in varies])):
        doc = copy.deepcopy(base)
        info = {}
        for (path, keys, _), value in zip(varies, combo):
            set_path(doc, keys, value, path)
            info[path] = value
        out.append(sweep.Variant("v%03d" % i, doc, info))
    return out


def check(variants, source):
    """Reads every variant as the run will (types, ranges, unknown keys) before anything runs, and makes it
    a Scene whose source is the scene file, so that relative mesh paths resolve against its folder."""
    from . import Scene, SceneError  # noqa: PLC0415

    for v in variants:
        try:
            v.scene = Scene.from_dict(v.scene, source)
        except SceneError as e:
            raise SweepInputError("variant %s (%s): %s" % (v.name, ", ".join("%s=%s" % (k, json.dumps(x))
                                                                             for k, x in v.info.items()), e)) from e


FIELDS = ["status", "steps", "wall_seconds", "simulated_seconds", "pieces", "peak_edge_stretch",
          "final_kinetic_energy", "error"]


def table(outcomes, paths):
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["variant"] + paths + FIELDS)
    for o in outcomes:
        s = o.summary or {}
        m = s.get("metrics", {})
        peak = m.get("peak_edge_stretch")
        w.writerow([o.name] + [json.dumps(o.info[p]) for p in paths] + [
            o.status, s.get("steps", ""), "%.4g" % s["wall_seconds"] if "wall_seconds" in s else "",
            s.get("simulated_seconds", ""), m.get("pieces", ""), "%.6g" % peak["value"] if peak else "",
            m.get("final_kinetic_energy", ""), o.error or ""])
    return buf.getvalue()


def main(argv=None):
    p = argparse.ArgumentParser(prog="python3 -m shellfrac.sweep_cli", description=__doc__.split("\n\n")[0])
    p.add_argument("scene", help="the scene file every variant starts from")
    p.add_argument("--vary", action="append", default=[], metavar="PATH=V1,V2",
                   help="a scene key and its values (repeat for more keys: every combination runs)")
    p.add_argument("--out", "-o", default="out/sweep", help="output folder (default out/sweep)")
    p.add_argument("--dask", default="", metavar="ADDRESS",
                   help="run on a Dask cluster: tcp://HOST:PORT, or local:N for N local worker processes")
    p.add_argument("--threads", "-j", type=int, default=1, help="threads of each run (default 1)")
    a = p.parse_args(argv)
    client = None
    try:
        if not a.vary:
            raise SweepInputError("give at least one --vary PATH=VALUE[,VALUE...]")
        try:
            with open(a.scene) as f:
                base = json.load(f)
        except OSError as e:
            raise SweepInputError("%s: %s" % (a.scene, e.strerror)) from e
        except json.JSONDecodeError as e:
            raise SweepInputError("%s: not JSON: %s" % (a.scene, e)) from e
        varies = [parse_vary(v) for v in a.vary]
        variants = variants_of(base, varies)
        check(variants, os.path.abspath(a.scene))
        if a.dask:
            client = sweep.connect(a.dask)
        outcomes = sweep.run_sweep(variants, a.out, client, threads=a.threads,
                                   log=lambda line: print(line, file=sys.stderr, flush=True))
    except (SweepInputError, sweep.SweepError) as e:
        print("shellfrac sweep: %s" % e, file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("shellfrac sweep: interrupted; finished runs stay in %s" % a.out, file=sys.stderr)
        return 130
    finally:
        if client is not None:
            sweep.close(client)
    text = table(outcomes, [path for path, _, _ in varies])
    sweep.write_atomically(os.path.join(a.out, "sweep.csv"), text)
    sys.stdout.write(text)
    return 0 if all(o.status == "completed" for o in outcomes) else 1


if __name__ == "__main__":
    sys.exit(main())
