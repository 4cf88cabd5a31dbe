"""Stepping a drape from Python and plotting its kinetic energy per step.

Loads scenes/cloth-drape-sphere.json, steps it with Simulation.step() and reads the control points'
velocities and masses as NumPy views after every step: E_kin = 1/2 sum m_i |v_i|^2 (the shear particles
carry the rest of the mass and are added from their own views).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/drape_energy.py --out out/drape-energy
    ... --tiny      # a coarse cloth for a short time (what the tests run)
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/drape-energy")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--tiny", action="store_true")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    d = json.loads((REPO / "scenes" / "cloth-drape-sphere.json").read_text())
    end = d["time"]["end"]
    if args.tiny:
        # A coarse cloth dropped from higher up: its grid cells are 4x larger, and the grid nodes it
        # touches reach the ball sooner (the fall is free until they do).
        d["shells"][0]["patch"]["cells"] = [8, 8]
        d["shells"][0]["patch"]["origin"][1] = 0.7
        end = 0.5
    sim = shellfrac.Simulation(shellfrac.Scene.from_dict(d), threads=args.threads)
    m, v = sim.masses(0), sim.velocities(0)  # views: they follow the simulation
    shear = sim.shear_particles(0)

    times, energy = [0.0], [0.0]
    while sim.time < end:
        sim.step()
        e = 0.5 * m @ (v ** 2).sum(axis=1) + 0.5 * shear["mass"] @ (shear["v"] ** 2).sum(axis=1)
        times.append(sim.time)
        energy.append(e)
    print("%d steps to t = %.3f s; peak kinetic energy %.4g J at t = %.3f s" %
          (sim.steps, sim.time, max(energy), times[int(np.argmax(energy))]))
    np.savetxt(out / "energy.csv", np.column_stack([times, energy]), delimiter=",", header="time,kinetic_energy",
               comments="")

    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(range(len(energy)), energy, lw=1)
    ax.set_xlabel("step")
    ax.set_ylabel("kinetic energy [J]")
    ax.set_title("cloth draped over a sphere")
    fig.tight_layout()
    fig.savefig(out / "energy.png", dpi=100)
    print("wrote", out / "energy.png")


if __name__ == "__main__":
    main()
