"""The shell obstacle course as a speed-accuracy benchmark (``shellfrac bench verify``).

Runs each case of scenes/verification/course.json (Scordelis-Lo roof, pinched cylinder) over its ladder of
cells per side and spline degrees, as a sweep (shellfrac.sweep: serially, or on a Dask cluster with
``--dask``), and writes into the output folder:

- verify.csv: one row per run: case, degree, cells, degrees of freedom (3 per control point), steps,
  wall seconds, simulated seconds, whether it came to rest, measured value, reference, error in %;
- verify-error-vs-time.png, verify-error-vs-dofs.png: |error| against wall time and against degrees of
  freedom, one series per degree (the speed-accuracy front of the engineering cases);
- runs/<case>-p<degree>-c<cells>/: each run's own folder (summary.json, probes), and runs/sweep.json.

It prints the table, a preset row per case (the cheapest run within 1 %) and the course's goal (within
1 % at 16 cells and within 3 % at 8 cells, each with the best degree).

    PYTHONPATH=build/python /usr/bin/python3 -m shellfrac.verify_course --out out/verify
    ... --dask local:2               # two local worker processes
    ... --dask tcp://HOST:8786       # a running Dask scheduler (docs/benchmarks.md)
"""
import argparse
import copy
import csv
import io
import json
import math
import os
import pathlib
import sys
import uuid

from . import sweep

DEFAULT_COURSE = os.path.join("scenes", "verification", "course.json")
COMPONENTS = {"x": 0, "y": 1, "z": 2}
GOALS = ((16, 0.01), (8, 0.03))  # (cells per side, largest |error|), each with the best degree


class CourseError(Exception):
    """A course file that cannot be used; the message names the file and the JSON path."""


def load_course(path):
    path = pathlib.Path(path)
    try:
        with open(path) as f:
            course = json.load(f)
    except OSError as e:
        raise CourseError("%s: cannot read the course: %s" % (path, e.strerror)) from e
    except json.JSONDecodeError as e:
        raise CourseError("%s: not JSON: %s" % (path, e)) from e
    cases = course.get("cases")
    if not isinstance(cases, list) or not cases:
        raise CourseError("%s: /cases: a non-empty list of cases is required" % path)
    for i, c in enumerate(cases):
        where = "%s: /cases/%d" % (path, i)
        for key in ("name", "scene", "probe", "component", "reference", "cells", "degrees"):
            if key not in c:
                raise CourseError("%s: \"%s\" is required" % (where, key))
        if c["component"] not in COMPONENTS:
            raise CourseError("%s/component: one of x, y, z" % where)
        if not isinstance(c["reference"], (int, float)) or c["reference"] == 0:
            raise CourseError("%s/reference: a non-zero number" % where)
        for key in ("cells", "degrees"):
            if not c[key] or not all(isinstance(n, int) and n >= 1 for n in c[key]):
                raise CourseError("%s/%s: a list of positive integers" % (where, key))
        if c.get("measure", "displacement") not in ("displacement", "period"):
            raise CourseError("%s/measure: \"displacement\" (the probe's last value) or \"period\"" % where)
        c["scene_path"] = path.parent / c["scene"]
    return course


def plan(course, config="full", cases=None):
    """The sweep's variants: every case at every (degree, cells) of its ladder (the "tiny" ladder, and its
    shorter end time if given, with config "tiny")."""
    variants = []
    for c in course["cases"]:
        if cases and c["name"] not in cases:
            continue
        ladder = c.get("tiny", {}) if config == "tiny" else {}
        try:
            with open(c["scene_path"]) as f:
                base = json.load(f)
        except (OSError, json.JSONDecodeError) as e:
            raise CourseError("%s: case %s: %s" % (c["scene_path"], c["name"], e)) from e
        for degree in ladder.get("degrees", c["degrees"]):
            for cells in ladder.get("cells", c["cells"]):
                scene = copy.deepcopy(base)
                patch = scene["shells"][0]["patch"]
                patch["degree"] = [degree, degree]
                patch["cells"] = [cells, cells]
                if "end" in ladder:
                    scene["time"]["end"] = ladder["end"]
                name = "%s-p%d-c%d" % (c["name"], degree, cells)
                variants.append(sweep.Variant(name, scene, {"case": c["name"], "degree": degree, "cells": cells}))
    if cases:
        unknown = set(cases) - {c["name"] for c in course["cases"]}
        if unknown:
            raise CourseError("no case named %s in the course" % ", ".join(sorted(unknown)))
    return variants


def crossing_period(times, values):
    """The period of an oscillation about 0: twice the mean spacing of its sign changes (each located by
    linear interpolation between samples), or None with fewer than three."""
    crossings = []
    for i in range(1, len(values)):
        a, b = values[i - 1], values[i]
        if (a < 0) != (b < 0) and a != b:
            crossings.append(times[i - 1] + (times[i] - times[i - 1]) * (-a) / (b - a))
    if len(crossings) < 3:
        return None
    return 2 * (crossings[-1] - crossings[0]) / (len(crossings) - 1)


def expected_cost(info):
    """A run's cost up to a constant: control points x quadrature points per cell x steps (~ cells)."""
    return info["cells"] ** 3 * (info["degree"] + 1) ** 2


def measure(course, outcome):
    """One table row from a variant's outcome."""
    case = next(c for c in course["cases"] if c["name"] == outcome.info["case"])
    row = dict(outcome.info, status=outcome.status, reference=case["reference"], measured=float("nan"),
               error_pct=float("nan"), dofs=0, steps=0, wall_seconds=float("nan"), simulated_seconds=float("nan"),
               at_rest="", attempts=outcome.attempts, worker=outcome.worker or "")
    s = outcome.summary
    if s is None:
        return row
    probe = next((p for p in s.get("probes", []) if p["name"] == case["probe"]), None)
    if probe is None or not probe["displacement"]:
        row["status"] = "no probe %s" % case["probe"]
        return row
    component = [d[COMPONENTS[case["component"]]] for d in probe["displacement"]]
    if case.get("measure", "displacement") == "period":
        value = crossing_period(probe["time"], component)
        if value is None:
            row["status"] = "no oscillation at %s" % case["probe"]
            return row
    else:
        value = case.get("sign", 1) * component[-1]
    row.update(measured=value, error_pct=100.0 * (value / case["reference"] - 1.0),
               dofs=3 * s["particle_counts"]["control_points"], steps=s["steps"], wall_seconds=s["wall_seconds"],
               simulated_seconds=s["simulated_seconds"],
               at_rest=str(s["until_rest"]["reached"]).lower() if "until_rest" in s else "")
    return row


FIELDS = ["case", "degree", "cells", "dofs", "steps", "wall_seconds", "simulated_seconds", "at_rest", "measured",
          "reference", "error_pct", "status", "attempts", "worker"]


def table_csv(rows):
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=FIELDS, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("%.6g" % r[k] if isinstance(r[k], float) else r[k]) for k in FIELDS})
    return buf.getvalue()


def ok(r):
    return r["status"] == "completed" and math.isfinite(r["error_pct"])


def presets(rows):
    """Per case: the completed run with the least wall time among those within 1 % (None when none is)."""
    out = {}
    for case in dict.fromkeys(r["case"] for r in rows):
        within = [r for r in rows if r["case"] == case and ok(r) and abs(r["error_pct"]) <= 1.0]
        out[case] = min(within, key=lambda r: r["wall_seconds"]) if within else None
    return out


def goals(rows):
    """Per case and goal (cells, limit): the best |error| over the degrees at those cells, and whether it
    meets the limit (None when the ladder has no such run)."""
    out = []
    for case in dict.fromkeys(r["case"] for r in rows):
        for cells, limit in GOALS:
            errs = [abs(r["error_pct"]) for r in rows if r["case"] == case and r["cells"] == cells and ok(r)]
            best = min(errs) if errs else None
            out.append((case, cells, limit, best, None if best is None else best <= 100 * limit))
    return out


def report(rows):
    lines = ["| case | degree | cells | dofs | steps | wall s | at rest | error % | status |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %d | %d | %d | %d | %.2f | %s | %+.2f | %s |" % (
            r["case"], r["degree"], r["cells"], r["dofs"], r["steps"], r["wall_seconds"], r["at_rest"],
            r["error_pct"], r["status"]))
    lines.append("")
    for case, r in presets(rows).items():
        lines.append("preset %s: %s" % (case, "degree %d, %d cells (%+.2f %%, %.2f s)" % (
            r["degree"], r["cells"], r["error_pct"], r["wall_seconds"]) if r else "no run within 1 %"))
    for case, cells, limit, best, met in goals(rows):
        lines.append("goal %s at %d cells within %g %%: %s" % (
            case, cells, 100 * limit, "no run" if best is None else "%.2f %% (%s)" % (best, "met" if met else "NOT met")))
    return "\n".join(lines) + "\n"


def charts(rows, out):
    import matplotlib  # noqa: PLC0415  (only when charts are drawn)

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415

    cases = list(dict.fromkeys(r["case"] for r in rows))
    for x_key, x_label, stem in (("wall_seconds", "wall time of the run (s)", "verify-error-vs-time"),
                                 ("dofs", "degrees of freedom (3 per control point)", "verify-error-vs-dofs")):
        cols = min(3, len(cases))
        rows_of_axes = (len(cases) + cols - 1) // cols
        fig, axes = plt.subplots(rows_of_axes, cols, figsize=(5.2 * cols, 4.2 * rows_of_axes), squeeze=False)
        for ax in axes.flat[len(cases):]:
            ax.set_visible(False)
        for ax, case in zip(axes.flat, cases):
            for degree in sorted({r["degree"] for r in rows if r["case"] == case}):
                pts = sorted((r["cells"], r[x_key], max(abs(r["error_pct"]), 1e-3), r["at_rest"] == "false")
                             for r in rows if r["case"] == case and r["degree"] == degree and ok(r))
                if not pts:
                    continue
                line, = ax.loglog([p[1] for p in pts], [p[2] for p in pts], "-", label="degree %d" % degree)
                for cells, x, e, moving in pts:  # hollow: still moving at the end (read before rest)
                    ax.plot(x, e, "o", color=line.get_color(), mfc="white" if moving else line.get_color())
                    ax.annotate("%d" % cells, (x, e), textcoords="offset points", xytext=(4, 4), fontsize=7)
            ax.axhline(1.0, color="grey", lw=0.8, ls="--")
            # Runs without a result (diverged, lost, no oscillation): a red cross on the top edge, at their
            # cost where the summary has it.
            top = ax.get_ylim()[1]
            for r in rows:
                if r["case"] == case and not ok(r) and math.isfinite(r[x_key]) and r[x_key] > 0:
                    ax.plot(r[x_key], top, "x", color="red", ms=9, mew=2, clip_on=False)
                    ax.annotate("p%d, %d cells: %s" % (r["degree"], r["cells"], r["status"]), (r[x_key], top),
                                textcoords="offset points", xytext=(-10, -12), fontsize=7, color="red")
            ax.set_title("%s (labels: cells per side; hollow: not at rest)" % case, fontsize=9)
            ax.set_xlabel(x_label)
            ax.set_ylabel("|error| against the reference (%)")
            ax.grid(True, which="both", lw=0.3)
            ax.legend(fontsize=8)
        fig.tight_layout()
        tmp = out / (".%s.%s.png" % (stem, uuid.uuid4().hex))
        fig.savefig(tmp, dpi=110)
        plt.close(fig)
        os.replace(tmp, out / (stem + ".png"))


def run_course(out, course_path=DEFAULT_COURSE, config="full", cases=None, executor=None, threads=1,
               draw=True, log=None):
    """Runs the course and writes verify.csv (and the charts); returns the table rows."""
    course = load_course(course_path)
    variants = plan(course, config, cases)
    out = pathlib.Path(out)
    out.mkdir(parents=True, exist_ok=True)
    # Longest first, so that the last runs to end are short ones (the table keeps the ladder's order).
    longest_first = sorted(variants, key=lambda v: -expected_cost(v.info))
    outcomes = {o.name: o for o in sweep.run_sweep(longest_first, out / "runs", executor, threads=threads, log=log)}
    rows = [measure(course, outcomes[v.name]) for v in variants]
    sweep.write_atomically(out / "verify.csv", table_csv(rows))
    if draw:
        charts(rows, out)
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(prog="shellfrac bench verify", description=__doc__.split("\n\n")[0])
    p.add_argument("--out", "-o", default="out/verify", help="output folder (default out/verify)")
    p.add_argument("--course", default=DEFAULT_COURSE, help="the course file (default %(default)s)")
    p.add_argument("--config", choices=("tiny", "full"), default="full",
                   help="full: the documented ladders; tiny: the coarsest runs, short (what the tests run)")
    p.add_argument("--cases", default="", help="comma-separated case names (default: all)")
    p.add_argument("--dask", default="", metavar="ADDRESS",
                   help="run the variants on a Dask cluster: tcp://HOST:PORT, or local:N for N local worker processes")
    p.add_argument("--threads", "-j", type=int, default=1, help="threads of each run (default 1)")
    p.add_argument("--no-charts", action="store_true", help="write verify.csv only")
    a = p.parse_args(argv)
    if a.threads < 0:
        p.error("--threads: a count >= 0")
    client = None
    try:
        if a.dask:
            client = sweep.connect(a.dask)
        rows = run_course(a.out, a.course, a.config, [c for c in a.cases.split(",") if c], client, a.threads,
                          not a.no_charts, log=lambda line: print(line, file=sys.stderr, flush=True))
    except (CourseError, sweep.SweepError) as e:
        print("shellfrac bench verify: %s" % e, file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("shellfrac bench verify: interrupted; no table written (finished runs stay in %s/runs)" % a.out,
              file=sys.stderr)
        return 130
    finally:
        if client is not None:
            sweep.close(client)
    sys.stdout.write(report(rows))
    print("verify.csv%s in %s" % ("" if a.no_charts else ", verify-error-vs-time.png, verify-error-vs-dofs.png", a.out))
    return 0 if all(r["status"] == "completed" for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
