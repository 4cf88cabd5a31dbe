"""Parameter sweep: failure stress sigma_f of a notched sheet against the pieces it tears into.

Loads scenes/tear-mode-one.json (a notched sheet pulled apart), changes the failure stress of the
material, runs each variant like `shellfrac run` and plots the number of pieces of the last frame (the
render mesh's connected components, metrics.pieces) and the crack length against sigma_f.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sweep_failure_stress.py --out out/sweep
    ... --tiny      # a coarse sheet and three values (seconds; what the tests run)
"""
import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import shellfrac  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]


def crack_length(summary):
    """Total length of the crack graphs in the parameter plane."""
    total = 0.0
    for g in summary.get("crack_graphs", []):
        v = np.array(g["vertices"], dtype=float).reshape(-1, 2)
        e = np.array(g["edges"], dtype=int).reshape(-1, 2)
        total += np.linalg.norm(v[e[:, 1]] - v[e[:, 0]], axis=1).sum() if len(e) else 0.0
    return total


def make_scene(base, sigma_f, tiny):
    d = json.loads(json.dumps(base))
    sheet = d["shells"][0]
    fracture = sheet["material"]["fracture"]
    fracture["failure_stress"] = sigma_f
    # A fracture energy that every sigma_f of the sweep allows on the grid (the damage law needs
    # G_f > sigma_f^2 l_ch / (2 E), l_ch = sqrt(3) dx: SceneError otherwise).
    fracture["fracture_energy"] = 100
    if tiny:  # coarse cells, a short pull, one frame per 0.1 s
        sheet["patch"]["cells"] = [12, 12]
        d["output"]["resolution"] = [16, 16]
        d["time"].update({"end": 0.3, "frame_rate": 10})
        d["pins"][1]["motion"]["keyframes"][1] = {"time": 0.3, "translation": [0, 0.3, 0]}
    return d


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/sweep", help="folder for the runs, sweep.json and sweep.png")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--tiny", action="store_true", help="a coarse, short variant (for tests)")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    base = json.loads((REPO / "scenes" / "tear-mode-one.json").read_text())
    values = [1e4, 1.5e4, 2e4] if args.tiny else [5e3, 1e4, 1.5e4, 2e4, 2.5e4, 3e4, 3.5e4]

    rows = []
    for sigma_f in values:
        summary = shellfrac.run(make_scene(base, sigma_f, args.tiny), out=out / ("sigma_%g" % sigma_f),
                                threads=args.threads)
        m = summary["metrics"]
        rows.append({"failure_stress": sigma_f, "pieces": m["pieces"], "crack_length": crack_length(summary),
                     "max_damage": m["cracks"]["max_damage"], "status": summary["status"]})
        print("sigma_f = %-8g pieces = %d  crack length = %.3f" % (sigma_f, rows[-1]["pieces"], rows[-1]["crack_length"]))
    (out / "sweep.json").write_text(json.dumps(rows, indent=2) + "\n")

    fig, ax = plt.subplots(figsize=(5, 3.5))
    s = [r["failure_stress"] for r in rows]
    ax.plot(s, [r["pieces"] for r in rows], "o-", color="C0")
    ax.set_xlabel("failure stress $\\sigma_f$ [Pa]")
    ax.set_ylabel("pieces in the last frame", color="C0")
    ax.set_yticks(range(0, max(r["pieces"] for r in rows) + 2))
    ax2 = ax.twinx()
    ax2.plot(s, [r["crack_length"] for r in rows], "s--", color="C1")
    ax2.set_ylabel("crack length (parameter plane)", color="C1")
    ax.set_title("notched sheet: fragments against failure stress")
    fig.tight_layout()
    fig.savefig(out / "sweep.png", dpi=100)
    print("wrote", out / "sweep.png")


if __name__ == "__main__":
    main()
