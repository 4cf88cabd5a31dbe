#pragma once
// The scene format's declarations for brittle solids (thesis ch. 3: regions, strength, impacts, the
// fracture run) and for the rigid-body world of the shatter loop (sec. 3.6). Part of scene/describe.hpp,
// which declares the rest and explains the visitors.
#include <string>

#include "scene/describe_common.hpp"

namespace shellfrac::scene {

// A box or sphere in material space: a removed region, or (in "strength") one with its failure stress.
template <class V>
void describe(V& v, SolidRegion& r) {
  v.choice("shape", r.shape, {"box", "sphere"}, kRequired);
  v.numbers("center", r.center, Range::any(), kRequired);
  if (r.shape == "box") v.numbers("half_extents", r.half_extents, Range::positive(), kRequired);
  if (r.shape == "sphere") v.number("radius", r.radius, Range::positive(), kRequired);
  v.number("failure_stress", r.failure_stress, Range::positive());
}

template <class V>
void describe(V& v, WeibullSpec& w) {
  v.number("modulus", w.modulus, Range::positive(), kRequired);
  v.boolean("scale_is_mean", w.scale_is_mean);
  v.integer("seed", w.seed, Range::closed(0, 2147483647));
}

template <class V>
void describe(V& v, SolidStrength& s) {
  v.objects("regions", s.regions, 0);
  for (size_t i = 0; i < s.regions.size(); ++i)
    v.check("regions/" + std::to_string(i), [&s, i] {
      return s.regions[i].failure_stress ? "" : "a strength region needs \"failure_stress\"";
    });
  v.object("weibull", s.weibull);
}

template <class V>
void describe(V& v, HertzSpec& h) {
  v.number("E", h.youngs_modulus, Range::positive(), kRequired);
  v.number("nu", h.poisson_ratio, Range::open(-1.0, 0.5), kRequired);
  v.number("radius", h.radius, Range::positive(), kRequired);
  v.number("mass", h.mass, Range::positive(), kRequired);
  v.number("speed", h.speed, Range::positive(), kRequired);
}

template <class V>
void describe(V& v, ImpactSpec& i) {
  v.numbers("point", i.point, Range::any(), kRequired);
  v.numbers("direction", i.direction, Range::any(), kRequired);
  v.check("direction", [&] { return detail::nonzero_direction(i.direction); });
  v.number("impulse", i.impulse, Range::positive(), kRequired);
  v.number("duration", i.duration, Range::positive());
  v.object("hertz", i.hertz);
  v.check("duration", [&] {
    return i.duration.has_value() == i.hertz.has_value()
               ? "an impact needs exactly one of \"duration\" or \"hertz\" (the projectile of Eq. 3.11)"
               : "";
  });
  v.number("start_time", i.start_time, Range::non_negative());
  v.number("radius", i.radius, Range::positive());
}

template <class V>
void describe(V& v, FractureStop& s) {
  v.number("damaged_fraction", s.damaged_fraction, Range::left_open(0.0, 1.0));
  v.integer("max_steps", s.max_steps, Range::closed(1, 100000000));
  v.number("max_time", s.max_time, Range::positive());
}

template <class V>
void describe(V& v, BreakageOrder& b) {
  v.number("dynamics", b.dynamics, Range::closed(0.0, 1.0));
  v.number("min_share", b.min_share, Range::closed(0.0, 0.5));
  v.integer("smoothing_steps", b.smoothing_steps, Range::closed(0, 1000));
}

template <class V>
void describe(V& v, FractureDetail& d) {
  v.number("height", d.height, Range::positive(), kRequired);
  v.number("edge", d.edge, Range::positive());
  v.number("step", d.step, Range::positive());
  v.integer("max_steps", d.max_steps, Range::closed(1, 100000));
  v.number("radius", d.radius, Range::non_negative());
  v.number("grid", d.grid, Range::positive());
  v.number("enhanced", d.enhanced, Range::closed(0.0, 1.0));
}

template <class V>
void describe(V& v, PhaseFieldMaterial& m) {
  v.number("length_scale", m.length_scale, Range::positive());
  v.number("mobility", m.mobility, Range::positive(), kRequired);
  v.number("residual", m.residual, Range::open(0.0, 1.0));
  v.number("broken_below", m.broken_below, Range::closed(0.0, 0.99));
}

template <class V>
void describe(V& v, NaccMaterial& m) {
  v.number("alpha0", m.alpha0, Range::open(-20.0, 0.0));
  v.number("beta", m.beta, Range::closed(0.0, 1e3));
  v.number("xi", m.xi, Range::left_open(0.0, 1e3));
  v.number("friction", m.friction, Range::left_open(0.0, 1e3));
  v.boolean("hardening", m.hardening);
}

template <class V>
void describe(V& v, PhaseFieldSolve& s) {
  v.choice("solver", s.solver, {"cg", "cholmod"});
  v.choice("gradient", s.gradient, {"spline", "mls"});
  v.integer("interval", s.interval, Range::closed(1, 1000000));
  v.number("tolerance", s.tolerance, Range::open(0.0, 1.0));
  v.integer("max_iterations", s.max_iterations, Range::closed(1, 100000000));
}

template <class V>
void describe(V& v, SolidFracture& f) {
  v.object("phase_field", f.phase_field);
  v.number("grid_spacing", f.grid_spacing, Range::positive());
  v.number("crack_grid_spacing", f.crack_grid_spacing, Range::positive());
  v.number("cfl", f.cfl, Range::left_open(0.0, 1.0));
  v.boolean("two_fields", f.two_fields);
  v.boolean("field_contact", f.field_contact);
  v.integer("crack_interval", f.crack_interval, Range::closed(1, 1000000));
  v.object("stop", f.stop);
  v.check("stop", [&] {
    return f.stop && !f.stop->damaged_fraction && !f.stop->max_time && !f.stop->max_steps
               ? "a fracture run needs a stopping criterion: \"stop\" with damaged_fraction, max_steps or max_time"
               : "";
  });
  v.choice("cutter", f.cutter, {"exact", "level_set"});
  v.number("voxel", f.voxel, Range::positive());
  v.number("gap_width", f.gap_width, Range::non_negative());
  v.number("sliver_volume", f.sliver_volume, Range::non_negative());
  v.object("breakage_order", f.breakage_order);
  v.object("detail", f.detail);
}

template <class V>
void describe(V& v, RigidBodySpec& r) {
  v.number("impulse_threshold", r.impulse_threshold, Range::positive(), kRequired);
  v.numbers("angular_velocity", r.angular_velocity, Range::any());
  v.integer("collision_faces", r.collision_faces, Range::closed(4, 10000000));
  v.number("friction", r.friction, Range::non_negative());
  v.number("restitution", r.restitution, Range::closed(0.0, 1.0));
  v.number("impact_radius", r.impact_radius, Range::positive());
  v.number("contact_times", r.contact_times, Range::positive());
}

// Bullet's surface of a static thing (ground, prop) and its material for the Hertz contact time.
template <class V>
void describe_static_surface(V& v, Opt<double>& friction, Opt<double>& restitution, Opt<double>& E, Opt<double>& nu) {
  v.number("friction", friction, Range::non_negative());
  v.number("restitution", restitution, Range::closed(0.0, 1.0));
  v.number("E", E, Range::positive());
  v.number("nu", nu, Range::open(-1.0, 0.5));
}

template <class V>
void describe(V& v, RigidGround& g) {
  v.numbers("point", g.point, Range::any());
  v.numbers("normal", g.normal, Range::any());
  v.check("normal", [&] { return detail::nonzero_direction(g.normal); });
  describe_static_surface(v, g.friction, g.restitution, g.youngs_modulus, g.poisson_ratio);
}

template <class V>
void describe(V& v, Projectile& p) {
  v.string("name", p.name);
  v.numbers("center", p.center, Range::any(), kRequired);
  v.number("radius", p.radius, Range::positive(), kRequired);
  v.numbers("velocity", p.velocity, Range::any());
  v.numbers("angular_velocity", p.angular_velocity, Range::any());
  v.number("density", p.density, Range::positive(), kRequired);
  v.number("E", p.youngs_modulus, Range::positive(), kRequired);
  v.number("nu", p.poisson_ratio, Range::open(-1.0, 0.5), kRequired);
  v.number("friction", p.friction, Range::non_negative());
  v.number("restitution", p.restitution, Range::closed(0.0, 1.0));
  v.boolean("kinematic", p.kinematic);
}

template <class V>
void describe(V& v, RigidProp& p) {
  v.string("name", p.name);
  v.choice("shape", p.shape, {"box", "mesh"});
  if (p.shape == "mesh") {
    v.string("file", p.mesh.file, kRequired);
    v.number("scale", p.mesh.scale, Range::positive());
    v.numbers("translate", p.mesh.translate, Range::any());
  } else {
    v.numbers("center", p.center, Range::any(), kRequired);
    v.numbers("half_extents", p.half_extents, Range::positive(), kRequired);
  }
  describe_static_surface(v, p.friction, p.restitution, p.youngs_modulus, p.poisson_ratio);
}

// The rigid-body world of the shatter loop (docs/brittle.md, "The shatter loop").
template <class V>
void describe(V& v, RigidWorldSpec& r) {
  v.number("dt", r.dt, Range::positive());
  v.integer("solver_iterations", r.solver_iterations, Range::closed(1, 1000));
  v.numbers("volume_ratios", r.volume_ratios, Range::left_open(0.0, 1.0));
  v.check("volume_ratios", [&] {
    const Opt<Vec3>& q = r.volume_ratios;
    return q && !((*q)[0] < (*q)[1] && (*q)[1] < (*q)[2])
               ? "volume ratios [VR_t, VR_s, VR_l] must increase: 0 < VR_t < VR_s < VR_l <= 1"
               : "";
  });
  v.object("ground", r.ground);
  v.objects("projectiles", r.projectiles, 0);
  v.objects("props", r.props, 0);
}

}  // namespace shellfrac::scene
