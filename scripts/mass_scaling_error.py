#!/usr/bin/env python3
"""Measures what selective mass scaling (cracks.mass_scaling) changes in a run: the steps it saves, and
the energy and momentum it moves, against the same scene at the small (unscaled) step.

    PYTHONPATH=build/python python3 scripts/mass_scaling_error.py [--scene scenes/benchmark-tear.json]
                                                                  [--end 0.3] [--every 0.02] [--budget 0.01]

Both runs are sampled at the same times. Energy is kinetic + elastic + gravitational (control points and
shear particles with their physical masses: the added mass is numerical and left out); momentum is their
linear momentum. Errors are the largest differences over the samples, relative to the reference's
largest kinetic energy and its largest momentum (the total energy is dominated by the potential's
arbitrary zero).
"""
import argparse
import json
import os
import sys
import time

import numpy as np

try:
    import shellfrac
except ImportError:
    sys.exit("mass_scaling_error: import shellfrac failed; build first and set PYTHONPATH=build/python")


def energy(sim, gravity):
    """Kinetic + elastic + gravitational energy and linear momentum of the material: physical masses only,
    without the added mass (which the solver's own kinetic energy and momentum include)."""
    m = sim.metrics()
    e, p, kinetic = m["elastic_energy"], np.zeros(3), 0.0
    g = np.asarray(gravity)
    for s in range(len(sim.shell_names)):
        sp = sim.shear_particles(s)
        for mass, x, v in ((sim.masses(s), sim.positions(s), sim.velocities(s)), (sp["mass"], sp["x"], sp["v"])):
            k = float(np.sum(0.5 * mass * np.sum(v * v, axis=1)))
            kinetic += k
            e += k - float(np.sum(mass * (x @ g)))
            p += mass @ v
    return e, p, kinetic


def run(scene_dict, budget, end, every, threads):
    d = json.loads(json.dumps(scene_dict))
    d.setdefault("cracks", {})["mass_scaling"] = budget
    sim = shellfrac.Simulation(shellfrac.Scene.from_dict(d), threads=threads)
    gravity = d.get("gravity", [0, -9.81, 0])
    samples = []
    t0 = time.time()
    t = 0.0
    while t < end - 1e-12:
        t = min(end, t + every)
        sim.advance_to(t)
        samples.append((t,) + energy(sim, gravity))
    return samples, sim.steps, time.time() - t0, sim.metrics(mesh=True)


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=os.path.join(root, "scenes", "benchmark-tear.json"))
    ap.add_argument("--end", type=float, default=0.3)
    ap.add_argument("--every", type=float, default=0.02)
    ap.add_argument("--budget", type=float, default=0.01)
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    scene = json.load(open(args.scene))
    ref, ref_steps, ref_wall, ref_m = run(scene, 0.0, args.end, args.every, args.threads)
    sca, sca_steps, sca_wall, sca_m = run(scene, args.budget, args.end, args.every, args.threads)
    e_scale = max(k for _, _, _, k in ref)
    p_scale = max(np.linalg.norm(p) for _, _, p, _ in ref)
    print("%8s %14s %14s %12s %12s" % ("t", "E ref [J]", "E scaled [J]", "|dE|/max K", "|dp|/max|p|"))
    worst_e = worst_p = 0.0
    for (t, e0, p0, _), (_, e1, p1, _) in zip(ref, sca):
        de, dp = abs(e1 - e0) / e_scale, np.linalg.norm(p1 - p0) / p_scale
        worst_e, worst_p = max(worst_e, de), max(worst_p, dp)
        print("%8.3f %14.6g %14.6g %12.2e %12.2e" % (t, e0, e1, de, dp))
    print("steps: %d unscaled, %d with mass_scaling %g (%.2fx fewer); wall %.1f s and %.1f s" %
          (ref_steps, sca_steps, args.budget, ref_steps / max(sca_steps, 1), ref_wall, sca_wall))
    print("largest energy difference %.2e (of the largest kinetic energy), momentum difference %.2e (of the largest |p|)" %
          (worst_e, worst_p))
    print("pieces %s / %s, max edge stretch %.3f / %.3f" % (ref_m.get("pieces"), sca_m.get("pieces"),
                                                          ref_m.get("max_edge_stretch", float("nan")),
                                                          sca_m.get("max_edge_stretch", float("nan"))))


if __name__ == "__main__":
    main()
