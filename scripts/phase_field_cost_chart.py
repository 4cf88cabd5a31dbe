"""Log-log chart of the brittle step's wall time against particle count for local Rankine damage and
the CD-MPM phase field (CG, CHOLMOD), from bench_phase_field's JSON output (docs/phase-field.md).

    build/bench/bench_phase_field --benchmark_out=pf.json --benchmark_out_format=json
    python3 scripts/phase_field_cost_chart.py pf.json docs/benchmarks/phase-field-cost.png
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main(source, png):
    series = {}
    for b in json.load(open(source))["benchmarks"]:
        series.setdefault(b["label"], []).append((b["particles"], b["ms_per_step"]))
    fig, ax = plt.subplots(figsize=(7, 5))
    for label, points in sorted(series.items()):
        points.sort()
        ax.loglog([p for p, _ in points], [t for _, t in points], "o-", label=label)
    ax.set_xlabel("particles")
    ax.set_ylabel("wall time per step [ms] (2 threads)")
    ax.set_title("Brittle step: local damage against the phase field")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    import os

    os.replace(tmp, png)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
