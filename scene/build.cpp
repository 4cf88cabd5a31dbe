#include "scene/build.hpp"

#include "scene/build_context.hpp"
#include "scene/json_io.hpp"
#include "scene/quality.hpp"
#include "scene/validate.hpp"

namespace shellfrac::scene {

namespace {

std::string stem_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t dot = base.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
}

model::TimeSettings build_time(const Time& t) {
  model::TimeSettings out;
  out.end = t.end.value_or(out.end);
  out.frame_rate = t.frame_rate.value_or(out.frame_rate);
  out.dt = t.dt;
  out.cfl = t.cfl.value_or(out.cfl);
  out.allow_substepping = t.allow_substepping.value_or(out.allow_substepping);
  out.enforce_stability_bound = t.enforce_stability_bound.value_or(out.enforce_stability_bound);
  if (t.until_rest) out.until_rest = model::RestCriterion{*t.until_rest->kinetic_energy, *t.until_rest->speed, *t.until_rest->duration};
  return out;
}

model::OutputSettings build_output(const Output& o) {
  model::OutputSettings out;
  out.format = o.format.value_or(out.format);
  if (o.resolution) {
    out.resolution_u = (*o.resolution)[0];
    out.resolution_v = (*o.resolution)[1];
  }
  out.triangulate = o.triangulate.value_or(false);
  out.double_precision = o.precision == "double";
  out.control_points = o.control_points.value_or(false);
  return out;
}

model::CrackSettings build_cracks(const Cracks& c) {
  model::CrackSettings out;
  out.extraction_interval = c.extraction_interval.value_or(out.extraction_interval);
  out.phantom_nodes = c.phantom_nodes.value_or(out.phantom_nodes);
  out.contact_friction = c.contact_friction.value_or(out.contact_friction);
  out.max_support = c.max_support.value_or(out.max_support);
  out.shadow_offset = c.shadow_offset.value_or(out.shadow_offset);
  out.tip_diffraction = c.tip_weights.value_or("diffraction") == "diffraction";
  out.continuous_support = c.support.value_or("continuous") == "continuous";
  out.support_margin = c.support_margin.value_or(out.support_margin);
  out.mass_scaling = c.mass_scaling.value_or(out.mass_scaling);
  return out;
}

}  // namespace

Model build(const Scene& input) {
  validate(input);
  Scene scene = input;
  apply_quality(scene);
  const detail::Builder b{scene};

  Model m;
  m.source = scene.source;
  m.name = scene.name.value_or(stem_of(scene.source));
  m.time = build_time(scene.time);
  m.output = build_output(scene.output);
  for (size_t i = 0; i < scene.shells.size(); ++i) m.shells.push_back(detail::build_shell(b, scene.shells[i], i));
  m.gravity = detail::vec3_or(scene.gravity, {0.0, -9.81, 0.0});
  m.damping = scene.damping.value_or(0.0);
  m.grid.dx = scene.grid.dx;
  // "adaptive" is the default: energy-conserving affine-FLIP on intact elastic material, APIC where damage,
  // plastic flow, cracks or seams act; on a shell that can crack the particles beside damage run PIC
  // (cracking_shells, docs/shell-model.md, "Transfer").
  const std::string transfer = scene.grid.transfer.value_or("adaptive");
  m.grid.apic = transfer == "apic" || transfer == "aflip" || transfer == "adaptive";
  if (transfer == "flip" || transfer == "aflip") m.grid.flip = scene.grid.flip_ratio.value_or(model::kDefaultFlipRatio);
  if (transfer == "adaptive") {
    m.grid.adaptive = true;
    m.grid.flip = scene.grid.flip_ratio.value_or(model::kDefaultIntactFlipRatio);
    m.grid.flip_active = scene.grid.flip_ratio_active.value_or(model::kDefaultActiveFlipRatio);
    using Cracking = model::GridSettings::CrackingShells;
    const std::string cracking = scene.grid.cracking_shells.value_or("pic_where_damaged");
    m.grid.cracking = cracking == "pic"                  ? Cracking::Pic
                      : cracking == "adaptive"           ? Cracking::Adaptive
                      : cracking == "adaptive_then_apic" ? Cracking::AdaptiveThenApic
                      : cracking == "adaptive_then_pic"  ? Cracking::AdaptiveThenPic
                      : cracking == "rpic_while_damaged" ? Cracking::RpicWhileDamaged
                      : cracking == "pic_while_damaged"  ? Cracking::PicWhileDamaged
                                                         : Cracking::PicWhereDamaged;
    // With cracking_shells "pic" and every shell able to crack, the whole scene is PIC, exactly as
    // "transfer": "pic".
    bool any = false;
    for (const model::Shell& s : m.shells) any = any || m.grid.adaptive_shell(s);
    if (!any) m.grid = model::GridSettings{m.grid.dx};
  }
  m.cracks = build_cracks(scene.cracks);
  for (size_t i = 0; i < scene.solids.size(); ++i) {
    if (scene.solids[i].fracture) {
      m.brittle_solids.push_back(detail::build_brittle_solid(b, scene.solids[i], i));
      if (!m.brittle_solids.back().mesh_repair.empty()) m.warnings.push_back(m.brittle_solids.back().mesh_repair);
    } else {
      m.solids.push_back(detail::build_solid(b, scene.solids[i], i));
    }
  }
  for (const model::BrittleBody& body : m.brittle_solids)
    if (body.rigid && !m.rigid) m.rigid = detail::build_rigid_world(b, scene.rigid);
  // Projectiles without breakable bodies strike the MPM material only (sim/shatter_system.hpp).
  if (!m.rigid && scene.rigid && !scene.rigid->projectiles.empty()) m.rigid = detail::build_rigid_world(b, scene.rigid);
  for (size_t i = 0; i < scene.colliders.size(); ++i)
    m.colliders.push_back(detail::build_collider(b, scene.colliders[i], i));
  for (size_t i = 0; i < scene.pins.size(); ++i) m.pins.push_back(detail::build_pin(b, scene.pins[i], i, m.shells));
  detail::check_pin_conflicts(b, m.pins, m.shells);
  for (size_t i = 0; i < scene.loads.size(); ++i) m.loads.push_back(detail::build_load(b, scene.loads[i], i, m.shells));
  for (size_t i = 0; i < scene.output.probes.size(); ++i)
    m.output.probes.push_back(detail::build_probe(b, scene.output.probes[i], i, m.shells));
  for (size_t i = 0; i < scene.interfaces.size(); ++i) {
    model::InterfaceSpec spec = detail::build_interface(b, scene.interfaces[i], i, m.shells);
    (spec.coupled ? m.interfaces : m.uncoupled_seams).push_back(std::move(spec));
  }
  detail::check_exact_closures(b, m);
  return m;
}

Model build_model(const std::string& json_text, const std::string& source) { return build(read_scene(json_text, source)); }

Model load_model(const std::string& path) { return build(load_scene(path)); }

}  // namespace shellfrac::scene
