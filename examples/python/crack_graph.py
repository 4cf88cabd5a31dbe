"""Reading a torn sheet's crack graph and drawing it over the parameter plane.

Tears the notched sheet of scenes/tear-mode-one.json, then draws, in the patch's parameter plane
(xi_1, xi_2): the damage history c_his of the quadrature points (colour), the prescribed notch and the
crack graph the consistent extraction found (thesis sec. 4.4.2), and the render mesh's pieces.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/crack_graph.py --out out/crack-graph
    ... --tiny
"""
import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
import numpy as np  # noqa: E402

import shellfrac  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/crack-graph")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--tiny", action="store_true")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    d = json.loads((REPO / "scenes" / "tear-mode-one.json").read_text())
    end = d["time"]["end"]
    if args.tiny:
        d["shells"][0]["patch"]["cells"] = [12, 12]
        d["shells"][0]["material"]["fracture"]["fracture_energy"] = 100  # the coarse grid needs more (SceneError)
        d["output"]["resolution"] = [16, 16]
        d["pins"][1]["motion"]["keyframes"][1] = {"time": 0.3, "translation": [0, 0.3, 0]}
        end = 0.3
    sim = shellfrac.Simulation(shellfrac.Scene.from_dict(d), threads=args.threads)
    sim.advance_to(end)

    uv = sim.quadrature_parameters("sheet")
    c_his = sim.damage_history("sheet").max(axis=1)  # over the layers
    vertices, edges = sim.crack_graph("sheet")
    mesh = sim.render_mesh("sheet")
    pieces = sim.metrics(mesh=True)["pieces"]
    print("t = %.3f s: %d crack vertices, %d edges, %d piece(s), max c_his %.3f" %
          (sim.time, len(vertices), len(edges), pieces, c_his.max()))
    np.savez(out / "crack_graph.npz", vertices=vertices, edges=edges)

    fig, ax = plt.subplots(figsize=(5.5, 5))
    sc = ax.scatter(uv[:, 0], uv[:, 1], c=c_his, s=6, cmap="magma_r", vmin=0, vmax=1)
    fig.colorbar(sc, ax=ax, label="damage history $c^{his}$")
    # Render faces in the parameter plane, coloured by piece (faint).
    t = mesh["triangles"]
    labels = mesh["labels"][mesh["triangle_faces"]]
    ax.tripcolor(mesh["uvs"][:, 0], mesh["uvs"][:, 1], t, facecolors=labels.astype(float), cmap="tab10",
                 alpha=0.15, edgecolors="none")
    if len(edges):
        ax.add_collection(LineCollection(vertices[edges], colors="C0", linewidths=2, label="crack graph"))
    for cut in d["shells"][0].get("cuts", []):
        p = np.array(cut["points"])
        ax.plot(p[:, 0], p[:, 1], "k-", lw=3, label="notch (prescribed cut)")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_aspect("equal")
    ax.set_xlabel("$\\xi_1$")
    ax.set_ylabel("$\\xi_2$")
    ax.set_title("crack graph at t = %.2f s (%d piece%s)" % (sim.time, pieces, "" if pieces == 1 else "s"))
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "crack_graph.png", dpi=100)
    print("wrote", out / "crack_graph.png")


if __name__ == "__main__":
    main()
