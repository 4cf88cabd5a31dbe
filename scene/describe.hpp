#pragma once
// The scene format, declared once. Each describe() lists the keys of one JSON object of a scene file with
// their field, type, allowed range and whether they are required, plus the rules that tie fields
// together. Three visitors walk these declarations: the JSON reader (json_read.cpp: type checks, ranges,
// unknown keys), the validator (validate.cpp: the same checks on a scene built in C++) and the JSON
// writer (json_write.cpp).
//
// A visitor V provides, for a key and a field:
//   number, integer, boolean, string, choice, numbers<N>, integers<N>, number_list, points2, points3,
//   index_pairs, shell_ref, choices (a list of strings from a set), limit, object (optional or plain sub-object), objects (array of objects),
//   and check(key, fn): fn() returns an error message for the key, or "" when the rule holds.
// Cross-references (shell names, pins against control nets, interface edges, prescribed cuts against the
// patch domain, mesh files) need the built geometry and are checked by scene::build().
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "scene/describe_brittle.hpp"
#include "scene/describe_common.hpp"
#include "scene/range.hpp"
#include "scene/scene.hpp"

namespace shellfrac::scene {


template <class V>
void describe_frame(V& v, Patch& p) {
  v.numbers("origin", p.origin, Range::any());
  v.numbers("axis_u", p.axis_u, Range::any());
  v.numbers("axis_v", p.axis_v, Range::any());
  v.check("axis_u", [&] { return p.axis_u && detail::norm3(*p.axis_u) < 1e-12 ? "axis must be a non-zero vector" : ""; });
  v.check("axis_v", [&] { return p.axis_v && detail::norm3(*p.axis_v) < 1e-12 ? "axis must be a non-zero vector" : ""; });
  v.check("axis_v", [&]() -> std::string {
    const Vec3 u = p.axis_u.value_or(Vec3{1, 0, 0}), w = p.axis_v.value_or(Vec3{0, 1, 0});
    const double c = (u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / (detail::norm3(u) * detail::norm3(w));
    return std::abs(c) > 1e-9 ? "axis_v must be orthogonal to axis_u (their cosine is " + std::to_string(c) + ")" : "";
  });
}

template <class V>
void describe(V& v, Patch& p) {
  v.choice("type", p.type, {"flat", "cylinder", "cone", "control_net"}, kRequired);
  if (!p.type) return;
  const std::string& type = *p.type;
  // Built-in shapes: the spline degree per direction (k-refinement, nurbs/patch_builders.hpp). The shell
  // solver keeps each point's (p+1)(q+1) basis functions on the stack, at most 64 (shell/shell_patch.cpp,
  // kMaxSupport): degree 7 in both directions; Kirchhoff-Love bending needs degree 2 at least.
  if (type != "control_net") v.integers("degree", p.degree, Range::closed(2, 7));
  if (type == "flat") {
    v.numbers("size", p.size, Range::positive(), kRequired);
    v.integers("cells", p.cells, kCells, kRequired);
    describe_frame(v, p);
  } else if (type == "cylinder" || type == "cone") {
    if (type == "cylinder") {
      v.number("radius", p.radius, Range::positive(), kRequired);
    } else {
      v.number("radius_bottom", p.radius_bottom, Range::non_negative(), kRequired);
      v.number("radius_top", p.radius_top, Range::non_negative(), kRequired);
      v.check("radius_top", [&] {
        return p.radius_bottom == 0.0 && p.radius_top == 0.0 ? "a cone needs at least one radius > 0" : "";
      });
    }
    v.number("height", p.height, Range::positive(), kRequired);
    v.number("sweep_degrees", p.sweep_degrees, Range::left_open(0.0, 360.0));
    v.integers("cells", p.cells, kCells, kRequired);
    describe_frame(v, p);
  } else {
    // The shell solver keeps each point's (p+1)(q+1) basis functions on the stack, at most 64
    // (shell/shell_patch.cpp, kMaxSupport): degree 7 in both directions.
    v.integers("degree", p.degree, Range::closed(1, 7), kRequired);
    v.number_list("knots_u", p.knots_u, 2, Range::any(), kRequired);
    v.number_list("knots_v", p.knots_v, 2, Range::any(), kRequired);
    v.points3("control_points", p.control_points, kRequired);
    v.number_list("weights", p.weights, 0, Range::positive());
    v.integers("refine", p.refine, Range::closed(1, 64));
    // Degree elevation before the refinement: elevate then refine is k-refinement.
    v.integers("elevate", p.elevate, Range::closed(0, 6));
    v.check("elevate", [&] {
      return p.degree && p.elevate && ((*p.degree)[0] + (*p.elevate)[0] > 7 || (*p.degree)[1] + (*p.elevate)[1] > 7)
                 ? "degree + elevate must stay at most 7 in each direction (the shell solver's limit)"
                 : "";
    });
  }
}

template <class V>
void describe(V& v, Plasticity& p) {
  v.number("yield_stress", p.yield_stress, Range::positive(), kRequired);
  v.number("hardening", p.hardening, Range::non_negative());
}

template <class V>
void describe(V& v, FailureRegion& r) {
  v.points2("polygon", r.polygon, 3, kRequired);
  v.number("failure_stress", r.failure_stress, Range::positive(), kRequired);
  v.number("fracture_energy", r.fracture_energy, Range::positive());
}

template <class V>
void describe(V& v, Fracture& f) {
  v.number("failure_stress", f.failure_stress, Range::positive(), kRequired);
  v.number("fracture_energy", f.fracture_energy, Range::positive(), kRequired);
  v.choice("damage_rule", f.damage_rule, {"healing", "monotone"});
  v.number("residual_stiffness", f.residual_stiffness, Range::closed(0.0, 0.1));
  v.objects("regions", f.regions, 0);
  v.object("weibull", f.weibull);
}

template <class V>
void describe(V& v, Material& m) {
  v.choice("model", m.model, {"neo_hookean"});
  v.number("E", m.youngs_modulus, Range::positive(), kRequired);
  v.number("nu", m.poisson_ratio, Range::open(-1.0, 0.5), kRequired);
  v.number("density", m.density, Range::positive(), kRequired);
  v.number("shear_stiffness", m.shear_stiffness, Range::non_negative());
  v.number("compression_stiffness", m.compression_stiffness, Range::non_negative());
  v.number("shear_friction", m.shear_friction, Range::non_negative());
  v.number("strand_stretch", m.strand_stretch, Range::left_open(1.0, 1e6));
  v.object("plasticity", m.plasticity);
  v.choice("transverse", m.transverse, {"condensed", "rigid"});
  v.choice("stress_model", m.stress_model, {"kirchhoff_love", "plane_strain", "2d_f", "2d_f_director"});
  v.check("stress_model", [&] {
    return m.stress_model && *m.stress_model != "kirchhoff_love" && m.plasticity
               ? "plasticity needs \"stress_model\": \"kirchhoff_love\" (the comparison models are elastic)"
               : "";
  });
  v.object("fracture", m.fracture);
}

template <class V>
void describe(V& v, Quadrature& q) {
  v.integer("points", q.points, Range::closed(1, 8));
  v.integer("layers", q.layers, Range::closed(1, 3));
  v.check("layers", [&] { return q.layers == 2 ? "layers must be 1 (membrane only) or 3 (lower, mid, upper)" : ""; });
}

template <class V>
void describe(V& v, Cut& c) {
  v.boolean("closed", c.closed);
  v.points2("points", c.points, c.closed.value_or(false) ? 3 : 2, kRequired);
}

template <class V>
void describe(V& v, VelocityField& f) {
  v.choice("shape", f.shape, {"sine", "linear", "list"}, kRequired);
  if (f.shape == "sine") {
    v.integers("modes", f.modes, Range::closed(1, 1000), kRequired);
    v.number("amplitude", f.amplitude, Range::any(), kRequired);
    v.numbers("direction", f.direction, Range::any(), kRequired);
    v.check("direction", [&] { return detail::nonzero_direction(f.direction); });
  } else if (f.shape == "linear") {
    v.numbers("at_origin", f.at_origin, Range::any());
    v.numbers("per_u", f.per_u, Range::any());
    v.numbers("per_v", f.per_v, Range::any());
  } else if (f.shape == "list") {
    v.points3("values", f.values, kRequired);
  }
}

template <class V>
void describe(V& v, Shell& s) {
  v.string("name", s.name);
  v.object("patch", s.patch, kRequired);
  v.number("thickness", s.thickness, Range::positive(), kRequired);
  v.object("material", s.material, kRequired);
  v.object("quadrature", s.quadrature);
  v.numbers("initial_velocity", s.initial_velocity, Range::any());
  v.object("initial_velocity_field", s.initial_velocity_field);
  v.objects("cuts", s.cuts, 0);
}

// A solid's material. The damage keys are required for brittle solids and refused for the others (the
// solid's describe() checks that, it knows whether the solid has a "fracture" object).
template <class V>
void describe(V& v, SolidMaterial& m) {
  v.choice("model", m.model, {"neo_hookean"});
  v.number("E", m.youngs_modulus, Range::positive(), kRequired);
  v.number("nu", m.poisson_ratio, Range::open(-1.0, 0.5), kRequired);
  v.number("density", m.density, Range::positive(), kRequired);
  v.choice("damage_model", m.damage_model, {"rankine", "phase_field", "nacc"});
  v.number("failure_stress", m.failure_stress, Range::positive());
  v.number("fracture_energy", m.fracture_energy, Range::positive());
  v.choice("damage_rule", m.damage_rule, {"healing", "monotone"});
  v.number("characteristic_length", m.characteristic_length, Range::positive());
  v.number("residual_stiffness", m.residual_stiffness, Range::closed(0.0, 0.1));
  v.choice("fully_damaged", m.fully_damaged, {"bounded", "rubble", "tensionless"});
  v.object("phase_field", m.phase_field);
  v.object("nacc", m.nacc);
  const bool phase_field = m.damage_model == "phase_field", nacc = m.damage_model == "nacc";
  v.check("phase_field", [&] {
    if (phase_field && !m.phase_field) return "damage_model \"phase_field\" needs a \"phase_field\" object with its \"mobility\"";
    if (!phase_field && m.phase_field) return "\"phase_field\" is only for damage_model \"phase_field\"";
    return "";
  });
  v.check("nacc", [&] { return !nacc && m.nacc ? "\"nacc\" is only for damage_model \"nacc\"" : ""; });
  v.check("damage_rule", [&] {
    return phase_field && (m.damage_rule || m.characteristic_length || m.failure_stress || m.residual_stiffness ||
                           m.fully_damaged)
               ? "failure_stress, damage_rule, characteristic_length, residual_stiffness and fully_damaged are Rankine "
                 "keys; the "
                 "phase field has none (its residual is material.phase_field.residual)"
               : "";
  });
  v.check("damage_rule", [&] {
    return nacc && (m.damage_rule || m.characteristic_length || m.failure_stress || m.fracture_energy ||
                    m.residual_stiffness || m.fully_damaged)
               ? "failure_stress, fracture_energy, damage_rule, characteristic_length, residual_stiffness and "
                 "fully_damaged are Rankine "
                 "and phase-field "
                 "keys; NACC breaks by the softening its \"nacc\" parameters set"
               : "";
  });
}

// The keys of a "mesh" solid or collider; a collider must give its voxel size. Only brittle solids
// repair their mesh (the level sets of the others take any closed surface).
template <class V>
void describe_mesh(V& v, MeshFile& m, Need voxel_size, bool brittle) {
  v.number("voxel_size", m.voxel_size, Range::positive(), voxel_size);
  v.string("file", m.file, kRequired);
  v.number("scale", m.scale, Range::positive());
  v.numbers("translate", m.translate, Range::any());
  v.number("band_voxels", m.band_voxels, Range::closed(1.0, 100.0));
  v.boolean("repair", m.repair);
  v.check("repair", [&] { return m.repair && !brittle ? "\"repair\" is only for brittle solids (solids with \"fracture\")" : ""; });
}

// A solid: Type-I particles of the shell simulation, or, with a "fracture" object, a brittle solid broken
// by the brittle solver (docs/brittle.md: its extra shapes, sampling and keys are only allowed then).
template <class V>
void describe(V& v, Solid& s) {
  v.string("name", s.name);
  v.object("fracture", s.fracture);
  const bool brittle = s.fracture.has_value();
  if (brittle) v.choice("shape", s.shape, {"sphere", "box", "mesh", "cylinder", "torus"}, kRequired);
  else v.choice("shape", s.shape, {"sphere", "box", "mesh"}, kRequired);  // cylinder, torus: brittle only
  v.number("spacing", s.spacing, Range::positive(), kRequired);
  if (s.shape == "mesh") {
    describe_mesh(v, s.mesh, kOptional, brittle);
  } else if (s.shape == "sphere") {
    v.numbers("center", s.center, Range::any(), kRequired);
    v.number("radius", s.radius, Range::positive(), kRequired);
  } else if (s.shape == "box") {
    v.numbers("center", s.center, Range::any(), kRequired);
    v.numbers("half_extents", s.half_extents, Range::positive(), kRequired);
  } else if (s.shape == "cylinder") {
    v.numbers("center", s.center, Range::any(), kRequired);
    v.number("radius", s.radius, Range::positive(), kRequired);
    v.number("height", s.height, Range::positive(), kRequired);
  } else if (s.shape == "torus") {
    v.numbers("center", s.center, Range::any(), kRequired);
    v.number("major_radius", s.major_radius, Range::positive(), kRequired);
    v.number("minor_radius", s.minor_radius, Range::positive(), kRequired);
    v.check("minor_radius", [&] {
      return s.major_radius && s.minor_radius && !(*s.minor_radius < *s.major_radius)
                 ? "minor_radius must be smaller than major_radius (a torus without a hole)"
                 : "";
    });
  }
  v.choice("sampling", s.sampling, {"jittered", "poisson_disk", "regular"});
  v.check("sampling", [&] {
    return !brittle && s.sampling == "regular" ? "sampling \"regular\" is only for brittle solids" : "";
  });
  v.integer("seed", s.seed, Range::closed(0, 2147483647));
  v.object("material", s.material, kRequired);
  v.numbers("initial_velocity", s.initial_velocity, Range::any());
  if (s.material) {
    const SolidMaterial& m = *s.material;
    if (brittle) {
      v.check("material/failure_stress", [&] {
        return m.failure_stress || m.damage_model == "phase_field" || m.damage_model == "nacc"
                   ? ""
                   : "required key is missing (a brittle solid)";
      });
      v.check("material/fracture_energy", [&] {
        return m.fracture_energy || m.damage_model == "nacc" ? "" : "required key is missing (a brittle solid)";
      });
    }
    v.check("material", [&] {
      return !brittle && (m.failure_stress || m.fracture_energy || m.damage_rule || m.characteristic_length || m.damage_model)
                 ? "damage keys of a solid need a \"fracture\" object on the solid (docs/brittle.md)"
                 : "";
    });
  }
  v.objects("remove", s.remove, 0);
  for (size_t i = 0; i < s.remove.size(); ++i)
    v.check("remove/" + std::to_string(i) + "/failure_stress", [&s, i] {
      return s.remove[i].failure_stress ? "a removed region has no failure stress (strength regions go in \"strength\")" : "";
    });
  v.object("strength", s.strength);
  v.check("strength", [&] {
    return s.strength && s.material && (s.material->damage_model == "phase_field" || s.material->damage_model == "nacc")
               ? "\"strength\" varies the Rankine failure stress; a phase-field or NACC solid has none"
               : "";
  });
  v.check("fracture/phase_field", [&] {
    return brittle && s.fracture->phase_field && !(s.material && s.material->damage_model == "phase_field")
               ? "\"fracture/phase_field\" configures the phase-field solve; the material's damage_model is not \"phase_field\""
               : "";
  });
  v.objects("impacts", s.impacts, 0);
  v.object("rigid_body", s.rigid_body);
  // A rigid body's fracture runs stop after a few contact times of their impact (contact_times).
  v.check("fracture/stop", [&] {
    return brittle && !s.rigid_body && !s.fracture->stop
               ? "a fracture run needs a stopping criterion: \"stop\" with damaged_fraction, max_steps or max_time"
               : "";
  });
  v.check("rigid_body", [&] {
    if (!s.rigid_body) return "";
    if (!brittle) return "\"rigid_body\" needs a \"fracture\" object on the solid (a breakable body)";
    return s.impacts.empty() ? "" : "a rigid body's impacts come from its contacts: remove \"impacts\"";
  });
  v.check("impacts", [&] {
    return !brittle && (!s.remove.empty() || s.strength || !s.impacts.empty())
               ? "\"remove\", \"strength\" and \"impacts\" are keys of brittle solids (give the solid a \"fracture\" object)"
               : "";
  });
}

template <class V>
void describe(V& v, Keyframe& k) {
  v.number("time", k.time, Range::non_negative(), kRequired);
  v.numbers("translation", k.translation, Range::any());
  v.numbers("rotation", k.rotation, Range::any());
}

template <class V>
void describe(V& v, Motion& m) {
  v.numbers("pivot", m.pivot, Range::any());
  v.objects("keyframes", m.keyframes, 1);
  v.numbers("linear_velocity", m.linear_velocity, Range::any());
  v.numbers("angular_velocity", m.angular_velocity, Range::any());
  v.check("keyframes", [&] {
    return m.keyframes && (m.linear_velocity || m.angular_velocity)
               ? "give either keyframes or constant velocities, not both"
               : "";
  });
  if (m.keyframes)
    for (size_t i = 1; i < m.keyframes->size(); ++i)
      v.check("keyframes/" + std::to_string(i) + "/time", [&m, i] {
        const auto& f = *m.keyframes;
        return f[i].time && f[i - 1].time && !(*f[i].time > *f[i - 1].time) ? "keyframe times must increase strictly" : "";
      });
}

template <class V>
void describe(V& v, Collider& c) {
  v.string("name", c.name);
  v.choice("shape", c.shape, {"half_space", "sphere", "box", "mesh"}, kRequired);
  if (c.shape == "mesh") {
    describe_mesh(v, c.mesh, kRequired, false);
  } else if (c.shape == "half_space") {
    v.numbers("point", c.point, Range::any(), kRequired);
    v.numbers("normal", c.normal, Range::any(), kRequired);
    v.check("normal", [&] { return detail::nonzero_direction(c.normal); });
  } else if (c.shape == "sphere") {
    v.numbers("center", c.center, Range::any(), kRequired);
    v.number("radius", c.radius, Range::positive(), kRequired);
  } else if (c.shape == "box") {
    v.numbers("center", c.center, Range::any(), kRequired);
    v.numbers("half_extents", c.half_extents, Range::positive(), kRequired);
  }
  v.choice("boundary", c.boundary, {"sticky", "slip", "friction"});
  v.number("friction", c.friction, Range::non_negative());
  v.object("motion", c.motion);
}

template <class V>
void describe(V& v, PinRegion& r) {
  v.numbers("u", r.u, Range::closed(0, 1));
  v.numbers("v", r.v, Range::closed(0, 1));
}

namespace detail {
// The components a pin may hold in its frame (scene.hpp, Pin).
inline std::vector<std::string> pin_components(const Opt<std::string>& frame) {
  if (frame == "plane") return {"normal", "tangential"};
  if (frame == "edge") return {"normal", "along", "across", "tangential"};
  return {"x", "y", "z"};
}
// Why a pin's component list holds a direction twice, or "".
inline std::string repeated_component(const std::vector<std::string>& c) {
  auto has = [&](const char* name) { return std::count(c.begin(), c.end(), name); };
  for (const std::string& name : c)
    if (has(name.c_str()) > 1) return "component \"" + name + "\" is given twice";
  if (has("tangential") && (has("along") || has("across")))
    return "\"tangential\" already holds \"along\" and \"across\": the components conflict";
  return "";
}
// Why a ramp's keyframe k does not follow keyframe k - 1 in time, or "".
inline std::string ramp_problem(const std::vector<Vec2>& ramp, size_t k) {
  return k > 0 && !(ramp[k][0] > ramp[k - 1][0]) ? "ramp times must increase strictly (keyframe " + std::to_string(k) +
                                                       " at t = " + std::to_string(ramp[k][0]) + " s follows t = " +
                                                       std::to_string(ramp[k - 1][0]) + " s)"
                                                 : "";
}
}  // namespace detail

template <class V>
void describe(V& v, Pin& p) {
  v.string("name", p.name);
  v.shell_ref("shell", p.shell, kRequired);
  v.object("region", p.region);
  v.index_pairs("control_points", p.control_points, 1);
  v.choices("edges", p.edges, {"u0", "u1", "v0", "v1"}, 1);
  v.integer("rows", p.rows, Range::closed(1, 1000));
  v.check("", [&] {
    const int given = int(p.region.has_value()) + int(p.control_points.has_value()) + int(p.edges.has_value());
    return given != 1 ? "a pin needs exactly one of \"region\", \"control_points\" or \"edges\"" : "";
  });
  v.check("rows", [&] { return p.rows && !p.edges ? "\"rows\" counts rows from \"edges\"" : ""; });
  v.check("edges", [&]() -> std::string {
    if (!p.edges) return "";
    for (size_t i = 0; i < p.edges->size(); ++i)
      for (size_t k = 0; k < i; ++k)
        if ((*p.edges)[i] == (*p.edges)[k]) return "edge \"" + (*p.edges)[i] + "\" is given twice";
    return "";
  });
  v.check("region", [&] { return p.region && p.region->u && (*p.region->u)[0] > (*p.region->u)[1] ? "u range is reversed" : ""; });
  v.check("region", [&] { return p.region && p.region->v && (*p.region->v)[0] > (*p.region->v)[1] ? "v range is reversed" : ""; });
  v.choice("frame", p.frame, {"global", "plane", "edge"});
  v.choices("components", p.components, detail::pin_components(p.frame), 1);
  v.check("components", [&] { return p.components ? detail::repeated_component(*p.components) : std::string(); });
  v.numbers("plane_normal", p.plane_normal, Range::any());
  v.check("plane_normal", [&] { return detail::nonzero_direction(p.plane_normal); });
  v.check("plane_normal", [&] {
    return (p.frame == "plane") != p.plane_normal.has_value() ? "\"plane_normal\" goes with \"frame\": \"plane\" (and only with it)" : "";
  });
  v.check("frame", [&] { return p.frame == "edge" && !p.edges ? "\"frame\": \"edge\" needs the pin's \"edges\"" : ""; });
  v.check("components", [&] {
    return p.frame && *p.frame != "global" && !p.components ? "a pin in the \"" + *p.frame + "\" frame needs its \"components\"" : std::string();
  });
  v.numbers("symmetry_normal", p.symmetry_normal, Range::any());
  v.check("symmetry_normal", [&] { return detail::nonzero_direction(p.symmetry_normal); });
  v.check("symmetry_normal", [&] {
    if (!p.symmetry_normal) return "";
    if (!p.edges) return "a symmetry pin needs \"edges\"";
    if (p.rows && *p.rows != 1) return "a symmetry pin holds one edge row and ties the next: \"rows\" must be 1";
    if (p.frame || p.components || p.motion) return "a symmetry pin takes no \"frame\", \"components\" or \"motion\"";
    return "";
  });
  v.object("motion", p.motion);
}

template <class V>
void describe(V& v, Load& l) {
  v.choice("type", l.type, {"pressure", "point", "edge", "body"}, kRequired);
  v.shell_ref("shell", l.shell, kRequired);
  if (l.type == "pressure") {
    v.number("pressure", l.pressure, Range::any(), kRequired);
  } else if (l.type == "point") {
    v.numbers("at", l.at, Range::closed(0, 1), kRequired);
    v.numbers("force", l.force, Range::any(), kRequired);
  } else if (l.type == "edge") {
    v.choice("edge", l.edge, {"u0", "u1", "v0", "v1"}, kRequired);
    v.numbers("force_per_length", l.force_per_length, Range::any(), kRequired);
  } else if (l.type == "body") {
    v.numbers("acceleration", l.acceleration, Range::any(), kRequired);
  }
  v.points2("ramp", l.ramp, 1);
  if (l.ramp)
    for (size_t k = 0; k < l.ramp->size(); ++k)
      v.check("ramp/" + std::to_string(k) + "/0", [&l, k] { return detail::ramp_problem(*l.ramp, k); });
}

template <class V>
void describe(V& v, Edge& e) {
  v.shell_ref("shell", e.shell, kRequired);
  v.choice("side", e.side, {"u0", "u1", "v0", "v1"}, kRequired);
}

template <class V>
void describe(V& v, InterfaceVerify& s) {
  v.limit("max_gap", s.max_gap, Range::non_negative());
  v.limit("max_angle_degrees", s.max_angle_degrees, Range::closed(0.0, 180.0));
  v.limit("max_stress_ratio", s.max_stress_ratio, Range::positive());
}

template <class V>
void describe(V& v, SceneVerify& s) {
  v.limit("max_edge_stretch", s.max_edge_stretch, Range::positive());
}

template <class V>
void describe(V& v, Interface& i) {
  v.object("a", i.a, kRequired);
  v.object("b", i.b, kRequired);
  v.choice("continuity", i.continuity, {"C0", "C1", "none"});
  v.number("tolerance", i.tolerance, Range::positive());
  v.boolean("reversed", i.reversed);
  v.boolean("momentum_correction", i.momentum_correction);
  v.choice("closure", i.closure, {"least_squares", "exact"});
  v.check("closure", [&] {
    return i.closure == "exact" && i.continuity == "none" ? "a seam with \"continuity\": \"none\" is never closed" : "";
  });
  v.choice("seam_velocity", i.seam_velocity, {"leader", "projected"});
  v.object("verify", i.verify);
}

template <class V>
void describe(V& v, UntilRest& r) {
  v.number("kinetic_energy", r.kinetic_energy, Range::non_negative(), kRequired);
  v.number("speed", r.speed, Range::non_negative(), kRequired);
  v.number("duration", r.duration, Range::non_negative(), kRequired);
}

template <class V>
void describe(V& v, Time& t) {
  v.number("end", t.end, Range::non_negative());
  v.number("frame_rate", t.frame_rate, Range::positive());
  v.number("dt", t.dt, Range::positive());
  v.number("cfl", t.cfl, Range::left_open(0.0, 1.0));
  v.boolean("allow_substepping", t.allow_substepping);
  v.boolean("enforce_stability_bound", t.enforce_stability_bound);
  v.check("enforce_stability_bound", [&] {
    return t.enforce_stability_bound == false && !t.dt ? "turning the stability bound off needs an explicit \"dt\"" : "";
  });
  v.object("until_rest", t.until_rest);
}

template <class V>
void describe(V& v, Probe& p) {
  v.string("name", p.name, kRequired);
  v.check("name", [&] {  // the probe's CSV is named after it
    return p.name && (p.name->empty() || p.name->find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") !=
                                             std::string::npos || (*p.name)[0] == '.')
               ? "a probe name names its CSV file: use letters, digits, '_', '-' and '.' (not first)"
               : "";
  });
  v.shell_ref("shell", p.shell, kRequired);
  // Normalised parameter coordinates: [0, 1] spans the patch, so anything outside is off the patch.
  v.numbers("at", p.at, Range::closed(0, 1), kRequired);
  v.choice("every", p.every, {"step", "frame"});
}

template <class V>
void describe(V& v, Output& o) {
  v.string("format", o.format);
  v.check("format", [&] { return o.format ? export_format_problem(*o.format) : std::string(); });
  v.integers("resolution", o.resolution, Range::closed(1, 4096));
  v.boolean("triangulate", o.triangulate);
  v.choice("precision", o.precision, {"float", "double"});
  v.objects("probes", o.probes, 0);
  for (size_t i = 0; i < o.probes.size(); ++i)
    for (size_t k = 0; k < i; ++k)
      v.check("probes/" + std::to_string(i) + "/name", [&o, i, k] {
        return o.probes[i].name && o.probes[i].name == o.probes[k].name
                   ? "probe name \"" + *o.probes[i].name + "\" is already used by /output/probes/" + std::to_string(k)
                   : std::string();
      });
  v.boolean("control_points", o.control_points);
}

template <class V>
void describe(V& v, Grid& g) {
  v.number("dx", g.dx, Range::positive());
  v.choice("transfer", g.transfer, {"adaptive", "pic", "apic", "flip", "aflip"});
  v.number("flip_ratio", g.flip_ratio, Range::closed(0.0, 1.0));
  v.number("flip_ratio_active", g.flip_ratio_active, Range::closed(0.0, 1.0));
  v.check("flip_ratio", [&] {
    return g.flip_ratio && g.transfer && (*g.transfer == "pic" || *g.transfer == "apic")
               ? "\"flip_ratio\" needs \"transfer\": \"adaptive\", \"flip\" or \"aflip\""
               : "";
  });
  v.check("flip_ratio_active", [&] {
    return g.flip_ratio_active && g.transfer && *g.transfer != "adaptive"
               ? "\"flip_ratio_active\" needs \"transfer\": \"adaptive\""
               : "";
  });
  v.choice("cracking_shells", g.cracking_shells,
           {"pic_where_damaged", "pic_while_damaged", "rpic_while_damaged", "adaptive_then_pic", "adaptive_then_apic", "adaptive", "pic"});
  v.check("cracking_shells", [&] {
    return g.cracking_shells && g.transfer && *g.transfer != "adaptive"
               ? "\"cracking_shells\" needs \"transfer\": \"adaptive\""
               : "";
  });
}

template <class V>
void describe(V& v, Cracks& c) {
  v.integer("extraction_interval", c.extraction_interval, Range::closed(1, 1000000));
  v.boolean("phantom_nodes", c.phantom_nodes);
  v.number("contact_friction", c.contact_friction, Range::non_negative());
  v.number("max_support", c.max_support, Range::closed(1.5, 10.0));
  v.number("shadow_offset", c.shadow_offset, Range::open(0.0, 0.01));
  v.choice("tip_weights", c.tip_weights, {"visibility", "diffraction"});
  v.choice("support", c.support, {"continuous", "stepped"});
  v.number("support_margin", c.support_margin, Range::closed(1.1, 3.0));
  v.number("mass_scaling", c.mass_scaling, Range::closed(0.0, 0.1));
}

template <class V>
void describe(V& v, Scene& s) {
  v.quality("quality", s.quality);
  v.string("name", s.name);
  v.object("time", s.time);
  v.object("output", s.output);
  v.objects("shells", s.shells, 0);
  v.numbers("gravity", s.gravity, Range::any());
  v.number("damping", s.damping, Range::non_negative());
  v.object("grid", s.grid);
  v.object("cracks", s.cracks);
  v.objects("solids", s.solids, 0);
  v.check("shells", [&] { return s.shells.empty() && s.solids.empty() ? "a scene needs at least one shell or solid" : ""; });
  v.objects("colliders", s.colliders, 0);
  v.objects("pins", s.pins, 0);
  v.objects("loads", s.loads, 0);
  v.objects("interfaces", s.interfaces, 0);
  v.object("verify", s.verify);
  v.object("rigid", s.rigid);
  v.check("rigid", [&] {
    bool bodies = false;
    for (const Solid& solid : s.solids) bodies = bodies || solid.rigid_body.has_value();
    const bool strikes = s.rigid && !s.rigid->projectiles.empty() && (!s.shells.empty() || !s.solids.empty());
    if (s.rigid && !bodies && !strikes)
      return "\"rigid\" sets up the shatter loop: give a brittle solid a \"rigid_body\" object, or give "
             "\"rigid\" \"projectiles\" to strike the shells";
    if (bodies && !s.colliders.empty())
      return "colliders act on MPM particles; the rigid bodies' ground is \"rigid\".\"ground\"";
    return "";
  });
}

}  // namespace shellfrac::scene
