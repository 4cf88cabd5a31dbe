// Shells of a scene: NURBS patches from the built-in shapes or an explicit control net, materials with
// their defaults, quadrature, and prescribed cuts checked against the patch's parameter domain.
#include <algorithm>
#include <cmath>

#include "core/constants.hpp"
#include "crack2d/prescribed_cut.hpp"
#include "nurbs/degree_elevation.hpp"
#include "nurbs/knot_insertion.hpp"
#include "nurbs/nurbs_error.hpp"
#include "nurbs/patch_builders.hpp"
#include "scene/build_context.hpp"

namespace shellfrac::scene::detail {

namespace {

nurbs::Frame frame_of(const Patch& p) {
  nurbs::Frame f;
  f.origin = vec3_or(p.origin, {0, 0, 0});
  f.axis_u = vec3_or(p.axis_u, {1, 0, 0}).normalized();
  f.axis_v = vec3_or(p.axis_v, {0, 1, 0}).normalized();
  return f;
}

double sweep_of(const Patch& p) { return p.sweep_degrees.value_or(360.0) * core::kPi / 180.0; }

nurbs::KnotVector knots(const Builder& b, const std::string& path, const std::vector<double>& k, int degree) {
  try {
    return nurbs::KnotVector(k, degree);
  } catch (const nurbs::NurbsError& e) {
    b.fail(path, e.what());
  }
}

nurbs::NurbsSurface control_net(const Builder& b, const Patch& p, const std::string& path) {
  const Int2 degree = *p.degree;
  nurbs::KnotVector ku = knots(b, path + "/knots_u", *p.knots_u, degree[0]);
  nurbs::KnotVector kv = knots(b, path + "/knots_v", *p.knots_v, degree[1]);
  const size_t expected = static_cast<size_t>(ku.num_basis()) * static_cast<size_t>(kv.num_basis());
  const std::vector<Vec3>& pts = *p.control_points;
  if (pts.size() != expected)
    b.fail(path + "/control_points", "control net has " + std::to_string(pts.size()) +
                                         " points but degree and knots require " + std::to_string(ku.num_basis()) +
                                         " x " + std::to_string(kv.num_basis()) + " = " + std::to_string(expected) +
                                         " (u runs fastest)");
  nurbs::Vec3List points;
  points.reserve(expected);
  for (const Vec3& x : pts) points.push_back(vec3(x));
  std::vector<double> weights = p.weights.value_or(std::vector<double>(expected, 1.0));
  if (weights.size() != expected)
    b.fail(path + "/weights", "expected one weight per control point (" + std::to_string(expected) + "), got " +
                                  std::to_string(weights.size()));
  const Int2 refine = p.refine.value_or(Int2{1, 1});
  nurbs::NurbsSurface surface = [&] {
    try {
      return nurbs::NurbsSurface(std::move(ku), std::move(kv), std::move(points), std::move(weights));
    } catch (const nurbs::NurbsError& e) {
      b.fail(path, e.what());
    }
  }();
  if (p.elevate && ((*p.elevate)[0] > 0 || (*p.elevate)[1] > 0)) {
    try {
      surface = nurbs::elevate_degree(surface, (*p.elevate)[0], (*p.elevate)[1]);
    } catch (const nurbs::NurbsError& e) {
      b.fail(path + "/elevate", e.what());
    }
  }
  if (refine[0] == 1 && refine[1] == 1) return surface;
  // Split every non-empty span into `refine` equal parts by knot insertion (geometry unchanged).
  auto splits = [](const nurbs::KnotVector& k, int parts) {
    std::vector<double> ins;
    for (int i = k.degree(); i < k.num_basis(); ++i) {
      const double a = k[i], c = k[i + 1];
      if (c <= a) continue;
      for (int s = 1; s < parts; ++s) ins.push_back(a + (c - a) * s / parts);
    }
    return ins;
  };
  return nurbs::insert_knots(surface, splits(surface.knots_u(), refine[0]), splits(surface.knots_v(), refine[1])).surface;
}


model::FractureSpec fracture_of(const Fracture& f) {
  model::FractureSpec out;
  out.enabled = true;
  out.failure_stress = *f.failure_stress;
  out.fracture_energy = *f.fracture_energy;
  out.rule = f.damage_rule == "monotone" ? shell::DamageRule::Monotone : shell::DamageRule::Healing;
  out.residual_stiffness = f.residual_stiffness.value_or(0.0);
  for (const FailureRegion& r : f.regions) {
    model::FailureRegion fr;
    fr.polygon = points2(*r.polygon);
    fr.failure_stress = *r.failure_stress;
    fr.fracture_energy = r.fracture_energy;
    out.regions.push_back(std::move(fr));
  }
  out.weibull = weibull_of(f.weibull);
  return out;
}

model::Material material_of(const Material& m) {
  model::Material out;
  out.model = m.model.value_or("neo_hookean");
  out.youngs_modulus = *m.youngs_modulus;
  out.poisson_ratio = *m.poisson_ratio;
  out.density = *m.density;
  out.shear_stiffness = m.shear_stiffness;
  out.compression_stiffness = m.compression_stiffness;
  out.shear_friction = m.shear_friction.value_or(0.0);
  out.strand_stretch = m.strand_stretch.value_or(out.strand_stretch);
  if (m.plasticity) {
    out.plasticity.enabled = true;
    out.plasticity.yield_stress = *m.plasticity->yield_stress;
    out.plasticity.hardening = m.plasticity->hardening.value_or(0.0);
  }
  out.transverse = m.transverse == "rigid" ? shell::TransverseModel::Rigid : shell::TransverseModel::Condensed;
  const std::string model = m.stress_model.value_or("kirchhoff_love");
  out.stress_model = model == "plane_strain"    ? shell::StressModel::PlaneStrain
                     : model == "2d_f"          ? shell::StressModel::MidSurface2D
                     : model == "2d_f_director" ? shell::StressModel::DirectorF2D
                                                : shell::StressModel::KirchhoffLove;
  if (m.fracture) out.fracture = fracture_of(*m.fracture);
  return out;
}

}  // namespace

nurbs::NurbsSurface patch_surface(const Builder& b, const Patch& p, const std::string& path) {
  try {
    const Int2 degree = p.type == "control_net" ? Int2{2, 2} : p.degree.value_or(Int2{2, 2});
    if (p.type == "flat")
      return nurbs::flat_patch((*p.size)[0], (*p.size)[1], (*p.cells)[0], (*p.cells)[1], frame_of(p), degree[0], degree[1]);
    if (p.type == "cylinder")
      return nurbs::cylinder_segment(*p.radius, *p.height, sweep_of(p), (*p.cells)[0], (*p.cells)[1], frame_of(p),
                                     degree[0], degree[1]);
    if (p.type == "cone")
      return nurbs::cone_segment(*p.radius_bottom, *p.radius_top, *p.height, sweep_of(p), (*p.cells)[0], (*p.cells)[1],
                                 frame_of(p), degree[0], degree[1]);
    return control_net(b, p, path);
  } catch (const nurbs::NurbsError& e) {
    b.fail(path, e.what());
  }
}

model::Shell build_shell(const Builder& b, const Shell& s, size_t index) {
  const std::string path = index_path("/shells", index);
  nurbs::NurbsSurface surface = patch_surface(b, *s.patch, path + "/patch");
  shell::QuadratureRule quadrature;
  // Gauss points per direction: 4 by default, and p + 1 for degrees above 3.
  const int degree = std::max(surface.knots_u().degree(), surface.knots_v().degree());
  quadrature.points_per_direction = s.quadrature.points.value_or(std::max(quadrature.points_per_direction, degree + 1));
  quadrature.layers = s.quadrature.layers.value_or(quadrature.layers);
  const crack2d::Box domain{{surface.knots_u().domain_begin(), surface.knots_v().domain_begin()},
                            {surface.knots_u().domain_end(), surface.knots_v().domain_end()}};
  std::vector<model::Cut> cuts;
  for (size_t i = 0; i < s.cuts.size(); ++i) {
    model::Cut cut;
    cut.closed = s.cuts[i].closed.value_or(false);
    cut.points = points2(*s.cuts[i].points);
    try {
      crack2d::validate_cut(cut.points, cut.closed, domain);
    } catch (const crack2d::CutError& e) {
      b.fail(index_path(path + "/cuts", i) + "/points",
             std::string(e.what()) + " (parameter domain [" + std::to_string(domain.lo.x()) + ", " +
                 std::to_string(domain.hi.x()) + "] x [" + std::to_string(domain.lo.y()) + ", " +
                 std::to_string(domain.hi.y()) + "])");
    }
    cuts.push_back(std::move(cut));
  }
  std::vector<Eigen::Vector3d> field;
  if (s.initial_velocity_field) field = build_velocity_field(b, *s.initial_velocity_field, surface, path + "/initial_velocity_field");
  return model::Shell{s.name.value_or("shell" + std::to_string(index)),
                      *s.patch->type,
                      std::move(surface),
                      *s.thickness,
                      material_of(*s.material),
                      quadrature,
                      vec3_or(s.initial_velocity, {0, 0, 0}),
                      std::move(cuts),
                      std::move(field)};
}

}  // namespace shellfrac::scene::detail
