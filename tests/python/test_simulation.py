"""Stepping from Python: views, quadrature-point data, errors, threads and Ctrl-C."""
import _thread
import copy
import threading
import time

import numpy as np
import pytest

import shellfrac


def sim_of(d, threads=1):
    return shellfrac.Simulation(shellfrac.Scene.from_dict(d), threads=threads)


def test_views_follow_the_state_and_refuse_writes(tiny_drape):
    # PIC: control points move by dt v. Under the default adaptive transfer they move with the grid's
    # velocity, v minus the FLIP part, which the views do not show (docs/shell-model.md, "Transfer").
    tiny_drape["grid"] = {"transfer": "pic"}
    sim = sim_of(tiny_drape)
    x = sim.positions("cloth")
    v = sim.velocities(0)
    assert x.shape == (64, 3) and v.shape == (64, 3)  # (6 + 2)^2 control points of the flat layout
    assert not x.flags.writeable and not x.flags.owndata
    with pytest.raises(ValueError):
        x[0, 0] = 1.0
    with pytest.raises(ValueError):
        x.setflags(write=True)  # the base is the Simulation, which lends no writable buffer
    for _ in range(3):
        x_before = np.array(x)
        dt = sim.step()
        # The same arrays now show the new state: x^{n+1} = x^n + dt v^{n+1} (thesis Eq. 4.9) for every
        # control point the sphere has not projected (all of them this early: the sheet starts above it).
        np.testing.assert_allclose(x - x_before, dt * v, rtol=0, atol=1e-15)
        assert np.array_equal(x, sim.positions(0))
    assert sim.steps == 3
    assert sim.time == sim.metrics()["time"]


def test_views_outlive_their_python_simulation_name(tiny_drape):
    x = sim_of(tiny_drape).positions(0)  # the view keeps the simulation alive
    assert np.isfinite(x).all()


def test_masses_add_up_to_the_sheet(tiny_drape):
    sim = sim_of(tiny_drape)
    shear = sim.shear_particles(0)
    total = sim.masses(0).sum() + shear["mass"].sum()
    # rho * tau * area of the flat sheet; the lumped masses sum the quadrature volumes exactly.
    assert total == pytest.approx(300 * 0.001 * 0.4 * 0.4, rel=1e-12)
    assert shear["x"].shape == (36, 3)


def test_kinetic_energy_matches_the_arrays(tiny_drape):
    sim = sim_of(tiny_drape)
    sim.advance_to(0.02)
    sh = sim.shear_particles(0)
    ke = 0.5 * (sim.masses(0) @ (sim.velocities(0) ** 2).sum(1)) + 0.5 * (sh["mass"] @ (sh["v"] ** 2).sum(1))
    m = sim.metrics()
    assert m["kinetic_energy"] == pytest.approx(ke, rel=1e-12)
    assert sim.kinetic_energy == m["kinetic_energy"]
    assert m["steps"] == sim.steps and m["time"] == pytest.approx(0.02, abs=1e-15)


def test_deformation_gradient_is_identity_under_translation(tiny_drape):
    d = tiny_drape
    d["gravity"] = [0, 0, 0]
    d["colliders"] = []
    d["shells"][0]["initial_velocity"] = [0.5, 0, 0]
    sim = sim_of(d)
    x0 = np.array(sim.positions(0))
    F = sim.deformation_gradients(0)
    assert F.shape == (36 * 16, 3, 3, 3)  # 4 x 4 Gauss points per cell (the default rule), 3 layers
    assert len(sim.quadrature_parameters(0)) == 36 * 16
    np.testing.assert_allclose(F, np.broadcast_to(np.eye(3), F.shape), atol=1e-12)
    sim.advance_to(0.02)
    # A uniform velocity survives the grid transfers exactly (partition of unity): a rigid translation,
    # so every point moved by t v and F^KL stays the identity.
    np.testing.assert_allclose(sim.positions(0) - x0, np.tile([0.5 * sim.time, 0, 0], (64, 1)), atol=1e-12)
    np.testing.assert_allclose(sim.deformation_gradients(0), np.broadcast_to(np.eye(3), F.shape), atol=1e-9)
    assert sim.damage(0) is None and sim.crack_graph(0) is None


def test_deformation_gradient_against_the_render_mesh_area(tiny_drape):
    tiny_drape["output"]["resolution"] = [64, 64]
    sim = sim_of(tiny_drape)
    sim.advance_to(0.2)  # draped over the ball: J from 0.96 to 1.11
    J = np.linalg.det(sim.deformation_gradients(0)[:, 1])  # mid-surface layer
    # On the mid-surface det F^KL is the area ratio da/dA (the rest normal maps to the unit normal), so
    # its quadrature sum over the rest sheet is the current area: 4 x 4 Gauss-Legendre points per cell,
    # grouped by cell, on 6 x 6 cells of (0.4 / 6)^2.
    _, w = np.polynomial.legendre.leggauss(4)
    weights = np.tile(np.outer(w, w).ravel() / 4, 36) * (0.4 / 6) ** 2
    assert weights.sum() == pytest.approx(0.16, rel=1e-12)
    area_from_F = (weights * J).sum()
    # The render mesh's area (64 x 64 flat faces on the surface) is an independent estimate; its faceting
    # error falls as h^2 (measured: 2.3e-3 at 8 x 8, 1.7e-4 at 32 x 32, 4.4e-5 at 64 x 64).
    mesh = sim.render_mesh(0)
    v, t = mesh["vertices"], mesh["triangles"]
    area = 0.5 * np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]), axis=1).sum()
    assert area_from_F == pytest.approx(area, rel=2e-4)
    assert area_from_F > 0.16 * 1.01  # it did stretch
    assert (J > 0).all()


def unstable(d):
    # An explicit step 200 times the stability bound: the sheet blows up within a few steps.
    d["time"]["enforce_stability_bound"] = False
    d["time"]["dt"] = 0.01
    d["shells"][0]["material"]["E"] = 1e9
    return d


def test_numerical_error_carries_particle_shell_and_step(tiny_drape):
    sim = sim_of(unstable(tiny_drape))
    with pytest.raises(shellfrac.NumericalError) as e:
        sim.advance_to(1.0)
    err = e.value
    assert isinstance(err, ArithmeticError) and isinstance(err, shellfrac.Error)
    assert err.shell == "cloth" and err.solid is None
    assert err.particle_kind in ("control point", "shear particle", "quadrature point")
    assert isinstance(err.particle, int) and err.particle >= 0
    assert err.step == sim.steps  # the failing step did not complete
    assert 'shell "cloth"' in str(err) and "at step %d" % err.step in str(err)
    assert sim.error == str(err)
    # The object stays usable for reading.
    m = sim.metrics()
    assert m["steps"] == err.step
    assert sim.positions(0).shape == (64, 3)
    assert isinstance(sim.metrics(mesh=True), dict)


def test_two_simulations_in_two_threads(tiny_drape):
    reference = []
    for _ in range(2):
        sim = sim_of(tiny_drape)
        sim.advance_to(0.04)
        reference.append(np.array(sim.positions(0)))
    sims = [sim_of(tiny_drape), sim_of(tiny_drape)]
    errors = []

    def work(s):
        try:
            s.advance_to(0.04)
        except Exception as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=work, args=(s,)) for s in sims]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for s, ref in zip(sims, reference):
        assert np.array_equal(s.positions(0), ref)  # bit-identical to stepping alone


def test_gil_is_released_while_stepping(tiny_drape):
    sim = sim_of(tiny_drape)
    seen = []
    done = threading.Event()

    def watch():
        while not done.is_set():
            seen.append(sim.steps)
            time.sleep(0.0005)

    watcher = threading.Thread(target=watch)
    watcher.start()
    # Long enough (about 160 steps) that the watcher samples many times even when a step takes well under a
    # millisecond: 16 steps (0.06 s) once finished before its first wake-up.
    sim.advance_to(0.6)
    done.set()
    watcher.join()
    # The watcher ran during the advance and saw steps in progress.
    assert any(0 < s < sim.steps for s in seen), (seen[:5], sim.steps)


def test_keyboard_interrupt_stops_between_steps(tiny_drape):
    sim = sim_of(tiny_drape)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.advance_to(1000.0)  # hours of stepping unless interrupted
    finally:
        timer.cancel()
    assert 0 < sim.steps and sim.time < 1000.0
    steps = sim.steps
    sim.step()  # still usable
    assert sim.steps == steps + 1
    assert np.isfinite(sim.positions(0)).all()


def test_shell_by_bad_name_or_index(tiny_drape):
    sim = sim_of(tiny_drape)
    with pytest.raises(KeyError):
        sim.positions("nope")
    with pytest.raises(IndexError):
        sim.positions(3)


def test_solid_particle_views(tiny_drape):
    d = tiny_drape
    d["solids"] = [{"name": "ball", "shape": "sphere", "center": [0, 0.4, 0], "radius": 0.05, "spacing": 0.02,
                    "material": {"E": 3e4, "nu": 0.3, "density": 600}}]
    sim = sim_of(d)
    assert sim.solid_names == ["ball"]
    p = sim.solid_particles("ball")
    n = len(p["x"])
    assert n > 20 and p["F"].shape == (n, 3, 3) and not p["F"].flags.writeable
    assert p["mass"] == pytest.approx(600 * p["volume"], rel=1e-12)  # m_p = rho V_p^0
    np.testing.assert_array_equal(p["F"], np.broadcast_to(np.eye(3), (n, 3, 3)))  # undeformed at the start
    assert (np.linalg.norm(p["x"] - [0, 0.4, 0], axis=1) <= 0.05).all()  # sampled inside the sphere
    x0 = np.array(p["x"])
    dt = sim.step()
    assert np.allclose(p["x"] - x0, dt * p["v"], atol=1e-15)  # the view moved with the step
