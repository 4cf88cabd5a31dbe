#include "output/summary.hpp"

#include <fstream>
#include <stdexcept>

namespace shellfrac::output {

namespace {

using Json = nlohmann::json;

template <class T>
Json optional(const std::optional<T>& v) {
  return v ? Json(*v) : Json(nullptr);
}

Json check_json(const SeamCheck& c) {
  return {{"max", optional(c.max)}, {"frame", optional(c.frame)}, {"time", optional(c.time)},
          {"limit", optional(c.limit)}, {"result", c.result}};
}

Json interface_json(const InterfaceReport& r) {
  Json frames = Json::array();
  for (const SeamSample& s : r.frames)
    frames.push_back({{"frame", s.frame},
                      {"time", s.time},
                      {"gap", s.gap},
                      {"angle_degrees", s.angle_degrees},
                      {"stress_ratio", optional(s.stress_ratio)}});
  Json j = {{"interface", r.interface},   {"leader", r.leader},         {"follower", r.follower},
            {"reversed", r.reversed},     {"continuity", r.continuity}, {"momentum_correction", r.momentum_correction}};
  j["checks"] = {{"gap", check_json(r.gap)}, {"angle_degrees", check_json(r.angle_degrees)},
                 {"stress_ratio", check_json(r.stress_ratio)}};
  j["pass"] = r.pass;
  j["frames"] = std::move(frames);
  return j;
}

Json cracks_json(const CrackReport& c) {
  Json j = Json::object();
  sim::CrackCounters::visit([&](const char* name, auto counter) { j[name] = c.*counter; });
  j["max_damage"] = c.max_damage;
  if (c.first_mls_failure) j["first_mls_failure"] = *c.first_mls_failure;
  Json points = Json::object(), shear = Json::object();
  for (const auto& [level, n] : c.basis_points) points[level] = n;
  for (const auto& [level, n] : c.basis_shear) shear[level] = n;
  j["basis"] = {{"points", points},           {"shear_particles", shear},    {"nudged", c.nudged},
                {"membrane_only", c.membrane_only}, {"slivers", c.slivers}, {"rigid_area", c.rigid_area},
                {"rigid_mass", c.rigid_mass},   {"removed_area", c.removed_area}, {"removed_mass", c.removed_mass}};
  if (c.first_sliver) j["basis"]["first_sliver"] = *c.first_sliver;
  j["basis"]["added_mass"] = c.added_mass;
  j["basis"]["added_mass_share"] = c.added_mass_share;
  return j;
}

// Reading back: every accessor names the field it wanted.
const Json& field(const Json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) throw std::runtime_error(std::string("summary.json: missing field \"") + key + "\"");
  return j.at(key);
}

template <class T>
T get(const Json& j, const char* key) {
  try {
    return field(j, key).get<T>();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("summary.json: field \"") + key + "\": " + e.what());
  }
}

template <class T>
std::optional<T> get_optional(const Json& j, const char* key) {
  if (!j.contains(key) || j.at(key).is_null()) return std::nullopt;
  return get<T>(j, key);
}

SeamCheck check_from(const Json& j) {
  return {get_optional<double>(j, "max"), get_optional<int>(j, "frame"), get_optional<double>(j, "time"),
          get_optional<double>(j, "limit"), get<std::string>(j, "result")};
}

InterfaceReport interface_from(const Json& j) {
  InterfaceReport r;
  r.interface = get<std::string>(j, "interface");
  r.leader = get<std::string>(j, "leader");
  r.follower = get<std::string>(j, "follower");
  r.continuity = get<std::string>(j, "continuity");
  r.reversed = get<bool>(j, "reversed");
  r.momentum_correction = get<bool>(j, "momentum_correction");
  const Json& checks = field(j, "checks");
  r.gap = check_from(field(checks, "gap"));
  r.angle_degrees = check_from(field(checks, "angle_degrees"));
  r.stress_ratio = check_from(field(checks, "stress_ratio"));
  r.pass = get<bool>(j, "pass");
  for (const Json& f : field(j, "frames"))
    r.frames.push_back({get<int>(f, "frame"), get<double>(f, "time"), get<double>(f, "gap"), get<double>(f, "angle_degrees"),
                        get_optional<double>(f, "stress_ratio")});
  return r;
}

CrackReport cracks_from(const Json& j) {
  CrackReport c;
  sim::CrackCounters::visit([&](const char* name, auto counter) {
    c.*counter = get<std::remove_reference_t<decltype(c.*counter)>>(j, name);
  });
  c.max_damage = get<double>(j, "max_damage");
  c.first_mls_failure = get_optional<std::string>(j, "first_mls_failure");
  const Json& basis = field(j, "basis");
  for (const auto& [level, n] : field(basis, "points").items()) c.basis_points.emplace_back(level, n.get<size_t>());
  for (const auto& [level, n] : field(basis, "shear_particles").items()) c.basis_shear.emplace_back(level, n.get<size_t>());
  c.nudged = get<size_t>(basis, "nudged");
  c.membrane_only = get<size_t>(basis, "membrane_only");
  c.slivers = get<size_t>(basis, "slivers");
  c.rigid_area = get<double>(basis, "rigid_area");
  c.rigid_mass = get<double>(basis, "rigid_mass");
  c.removed_area = get<double>(basis, "removed_area");
  c.removed_mass = get<double>(basis, "removed_mass");
  c.first_sliver = get_optional<std::string>(basis, "first_sliver");
  c.added_mass = get_optional<double>(basis, "added_mass").value_or(0.0);
  c.added_mass_share = get_optional<double>(basis, "added_mass_share").value_or(0.0);
  return c;
}

}  // namespace

nlohmann::json to_json(const Summary& s) {
  Json j;
  j["shellfrac_version"] = s.shellfrac_version;
  j["scene"] = s.scene;
  j["scene_source"] = s.scene_source;
  j["threads"] = s.threads;
  j["status"] = s.status;
  if (s.error) j["error"] = *s.error;
  j["steps"] = s.steps;
  j["dt"] = optional(s.dt);
  j["dt_min"] = optional(s.dt_min);
  j["stable_dt_bound"] = s.stable_dt_bound;
  j["grid_dx"] = s.grid_dx;
  j["simulated_seconds"] = s.simulated_seconds;
  j["frames"] = s.frames;
  j["particle_counts"] = {{"solid_particles", s.particle_counts.solid_particles},
                          {"control_points", s.particle_counts.control_points},
                          {"shear_particles", s.particle_counts.shear_particles},
                          {"quadrature_points", s.particle_counts.quadrature_points}};
  Json stages = Json::object();
  for (const auto& [name, seconds] : s.stage_seconds) stages[name] = seconds;
  j["stage_seconds"] = stages;
  const Metrics& m = s.metrics;
  Json metrics = Json::object();
  metrics["pieces"] = m.mesh.pieces;
  metrics["slivers"] = {{"count", m.mesh.sliver_count}, {"area", m.mesh.sliver_area}};
  metrics["piece_areas"] = m.mesh.piece_areas;
  metrics["max_edge_stretch"] = m.mesh.max_edge_stretch;
  metrics["strand_area"] = m.mesh.strand_area;
  metrics["strand_faces"] = m.mesh.strand_faces;
  metrics["peak_edge_stretch"] = {{"value", m.mesh.peak_edge_stretch}, {"frame", m.mesh.peak_edge_stretch_frame}};
  metrics["peak_strand_area"] = m.mesh.peak_strand_area;
  metrics["max_collider_penetration"] = m.max_collider_penetration;
  metrics["max_collider_penetration_cells"] = m.max_collider_penetration_cells;
  metrics["peak_kinetic_energy"] = m.peak_kinetic_energy;
  metrics["final_kinetic_energy"] = m.final_kinetic_energy;
  metrics["max_plastic_strain"] = m.max_plastic_strain;
  if (m.interfaces) {
    Json list = Json::array();
    for (const InterfaceReport& r : *m.interfaces) list.push_back(interface_json(r));
    metrics["interfaces"] = std::move(list);
  }
  if (m.cracks) metrics["cracks"] = cracks_json(*m.cracks);
  if (m.quadrature_point_steps_per_second) metrics["quadrature_point_steps_per_second"] = *m.quadrature_point_steps_per_second;
  if (m.quadrature_point_steps_per_second_per_core)
    metrics["quadrature_point_steps_per_second_per_core"] = *m.quadrature_point_steps_per_second_per_core;
  j["metrics"] = std::move(metrics);
  if (s.crack_graphs) {
    Json graphs = Json::array();
    for (const CrackGraphReport& g : *s.crack_graphs) graphs.push_back({{"shell", g.shell}, {"vertices", g.vertices}, {"edges", g.edges}});
    j["crack_graphs"] = std::move(graphs);
  }
  if (s.brittle) j["brittle"] = brittle_json(*s.brittle);
  if (s.shatter) j["shatter"] = *s.shatter;
  write_verification(s, j);
  j["wall_seconds"] = s.wall_seconds;
  return j;
}

Summary summary_from_json(const nlohmann::json& j) {
  Summary s;
  s.shellfrac_version = get<std::string>(j, "shellfrac_version");
  s.scene = get<std::string>(j, "scene");
  s.scene_source = get<std::string>(j, "scene_source");
  s.threads = get<int>(j, "threads");
  s.status = get<std::string>(j, "status");
  s.error = get_optional<std::string>(j, "error");
  s.steps = get<long>(j, "steps");
  s.dt = get_optional<double>(j, "dt");
  s.dt_min = get_optional<double>(j, "dt_min");
  s.stable_dt_bound = get<double>(j, "stable_dt_bound");
  s.grid_dx = get<double>(j, "grid_dx");
  s.simulated_seconds = get<double>(j, "simulated_seconds");
  s.frames = get<std::vector<std::string>>(j, "frames");
  const Json& counts = field(j, "particle_counts");
  s.particle_counts = {get<size_t>(counts, "solid_particles"), get<size_t>(counts, "control_points"),
                       get<size_t>(counts, "shear_particles"), get<size_t>(counts, "quadrature_points")};
  for (const auto& [name, seconds] : field(j, "stage_seconds").items()) s.stage_seconds.emplace_back(name, seconds.get<double>());
  const Json& m = field(j, "metrics");
  MeshReport& mesh = s.metrics.mesh;
  mesh.pieces = get<int>(m, "pieces");
  mesh.sliver_count = get<int>(field(m, "slivers"), "count");
  mesh.sliver_area = get<double>(field(m, "slivers"), "area");
  mesh.piece_areas = get<std::vector<double>>(m, "piece_areas");
  mesh.max_edge_stretch = get<double>(m, "max_edge_stretch");
  mesh.strand_area = get<double>(m, "strand_area");
  mesh.strand_faces = get<int>(m, "strand_faces");
  mesh.peak_edge_stretch = get<double>(field(m, "peak_edge_stretch"), "value");
  mesh.peak_edge_stretch_frame = get<int>(field(m, "peak_edge_stretch"), "frame");
  mesh.peak_strand_area = get<double>(m, "peak_strand_area");
  s.metrics.max_collider_penetration = get<double>(m, "max_collider_penetration");
  s.metrics.max_collider_penetration_cells = get<double>(m, "max_collider_penetration_cells");
  s.metrics.peak_kinetic_energy = get<double>(m, "peak_kinetic_energy");
  s.metrics.final_kinetic_energy = get<double>(m, "final_kinetic_energy");
  s.metrics.max_plastic_strain = get<double>(m, "max_plastic_strain");
  if (m.contains("interfaces")) {
    s.metrics.interfaces.emplace();
    for (const Json& r : m.at("interfaces")) s.metrics.interfaces->push_back(interface_from(r));
  }
  if (m.contains("cracks")) s.metrics.cracks = cracks_from(m.at("cracks"));
  s.metrics.quadrature_point_steps_per_second = get_optional<double>(m, "quadrature_point_steps_per_second");
  s.metrics.quadrature_point_steps_per_second_per_core = get_optional<double>(m, "quadrature_point_steps_per_second_per_core");
  if (j.contains("crack_graphs")) {
    s.crack_graphs.emplace();
    for (const Json& g : j.at("crack_graphs"))
      s.crack_graphs->push_back({get<std::string>(g, "shell"), get<std::vector<std::array<double, 2>>>(g, "vertices"),
                                 get<std::vector<std::array<int, 2>>>(g, "edges")});
  }
  if (j.contains("brittle")) s.brittle = brittle_reports_from_json(j.at("brittle"));
  if (j.contains("shatter")) s.shatter = j.at("shatter");
  read_verification(j, s);
  s.wall_seconds = get<double>(j, "wall_seconds");
  return s;
}

Summary read_summary(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  return summary_from_json(j);
}

}  // namespace shellfrac::output
