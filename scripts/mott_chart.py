#!/usr/bin/python3
"""Fragment-mass distribution of brittle runs against Mott's distribution (thesis Fig. 3.31).

Usage: scripts/mott_chart.py OUT.png SUMMARY.json [SUMMARY.json ...]

Reads the "brittle" section of each summary.json that `shellfrac run` wrote, pools the counted fragments
(slivers excluded, see docs/brittle.md) of every brittle solid that broke (at least two counted
pieces), each mass divided by the mass of its solid, and plots the cumulative fraction of fragments heavier than m against Mott's law
    N(> m) / N = exp(-(m / mu)^(1/2))
(Mott's distribution as given by Elek and Jaramaz 2008). The parameter mu is the maximum-likelihood fit:
under Mott's law sqrt(m) is exponentially distributed with mean sqrt(mu), so sqrt(mu) = mean(sqrt(m)).
Prints the fitted mu, the number of fragments and the Kolmogorov-Smirnov distance of the fit.
Needs numpy and matplotlib (Debian's /usr/bin/python3 has both).
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def fragment_mass_ratios(paths):
    ratios, names = [], []
    for path in paths:
        with open(path) as f:
            summary = json.load(f)
        for solid in summary.get("brittle", []):
            if not solid.get("event"):
                continue
            pieces = solid["fragments"]
            if solid["fragment_count"] < 2:
                continue  # an unbroken solid is no fragment population
            total = sum(p["mass"] for p in pieces)
            for p in pieces:
                if not p["sliver"]:
                    ratios.append(p["mass"] / total)
            names.append(solid["solid"])
    return np.array(sorted(ratios)), names


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    out, paths = sys.argv[1], sys.argv[2:]
    m, names = fragment_mass_ratios(paths)
    if len(m) < 2:
        print("error: fewer than two counted fragments in " + ", ".join(paths), file=sys.stderr)
        return 1
    mu = np.mean(np.sqrt(m)) ** 2
    n = len(m)
    heavier = 1.0 - np.arange(n) / n  # fraction of fragments with mass >= m_k (m sorted ascending)
    grid = np.geomspace(m.min() / 2, m.max() * 1.5, 200)
    mott = np.exp(-np.sqrt(grid / mu))
    ks = np.max(np.abs(heavier - np.exp(-np.sqrt(m / mu))))
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.step(m, heavier, where="post", label=f"simulation ({n} fragments)")
    ax.plot(grid, mott, "--", label=f"Mott, fitted mu = {mu:.3g}")
    ax.set_xscale("log")
    ax.set_xlabel("fragment mass / solid mass")
    ax.set_ylabel("fraction of fragments heavier")
    ax.set_title("Fragment masses against Mott's distribution\n" + ", ".join(names), fontsize=8)
    ax.set_ylim(0, 1.05)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"fragments {n}, fitted mu {mu:.4g} (mass ratio), KS distance {ks:.3f}; wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
