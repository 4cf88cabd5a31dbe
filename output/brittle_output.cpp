#include "output/brittle_output.hpp"

#include <cmath>

#include "brittle/particles_vdb.hpp"
#include "render_mesh/atomic_write.hpp"
#include "render_mesh/exporter.hpp"

namespace shellfrac::output {

namespace fs = std::filesystem;
using Json = nlohmann::json;

render_mesh::PolyMesh poly_mesh(const brittle::TriMesh& m) {
  render_mesh::PolyMesh out;
  out.name = m.name;
  out.positions = m.positions;
  if (m.normals.size() == m.positions.size()) out.normals = m.normals;
  if (m.uvs.size() == m.positions.size()) out.uvs = m.uvs;
  for (const brittle::Tri& t : m.triangles) out.add_face({t[0], t[1], t[2]});
  return out;
}

namespace {

const char* stop_reason(const sim::BrittleSystem::Body& b) {
  return b.solver->should_stop() ? brittle::to_string(b.solver->stop_reason()) : "scene_end";
}

}  // namespace

BrittleWriter::BrittleWriter(const scene::Model& model, fs::path out_dir)
    : model_(model), out_dir_(std::move(out_dir)), written_(model.brittle_solids.size(), false),
      files_(model.brittle_solids.size()) {}

void BrittleWriter::write_new_events(const sim::Simulation& sim) {
  const sim::BrittleSystem& system = sim.brittle();
  for (size_t i = 0; i < system.size(); ++i) {
    const sim::BrittleSystem::Body& b = system.body(i);
    if (written_[i] || !b.event) continue;
    const brittle::FractureEvent& ev = *b.event;
    const fs::path dir = out_dir_ / "brittle";
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create output directory " + dir.string() + ": " + ec.message());
    const render_mesh::ExportOptions options{model_.output.triangulate, model_.output.double_precision};
    const std::string stem = b.spec->name + "_event_0";
    std::vector<render_mesh::PolyMesh> pieces;
    for (const brittle::Fragment& f : ev.fragments.fragments) pieces.push_back(poly_mesh(f.mesh));
    const fs::path fragments = render_mesh::export_meshes(pieces, dir, stem + "_fragments", model_.output.format, options);
    brittle::TriMesh crack = ev.crack_surface_clipped;
    crack.name = b.spec->name + "_crack";
    const fs::path crack_file = render_mesh::export_meshes({poly_mesh(crack)}, dir, stem + "_crack", model_.output.format, options);
    // Particles at their material positions, where the fragments are.
    const fs::path particles = dir / (stem + "_particles.vdb");
    render_mesh::write_file_atomically(particles, brittle::particles_vdb_bytes(*b.solid, true));
    files_[i] = {fs::relative(fragments, out_dir_).string(), fs::relative(crack_file, out_dir_).string(),
                 fs::relative(particles, out_dir_).string()};
    written_[i] = true;
  }
}

std::vector<BrittleSolidReport> BrittleWriter::reports(const sim::Simulation& sim) const {
  std::vector<BrittleSolidReport> out;
  const sim::BrittleSystem& system = sim.brittle();
  for (size_t i = 0; i < system.size(); ++i) {
    const sim::BrittleSystem::Body& b = system.body(i);
    BrittleSolidReport r;
    r.solid = b.spec->name;
    r.json_path = b.spec->json_path;
    r.particles = b.solid->size();
    r.steps = static_cast<long>(b.solver->steps());
    r.simulated_seconds = b.solver->time();
    r.stop_reason = stop_reason(b);
    r.damaged_fraction = b.solver->damaged_fraction();
    r.crack_updates = b.crack_updates;
    const brittle::StageTimes& t = b.solver->times();
    r.stage_seconds = {{"p2g", t.p2g}, {"forces", t.forces}, {"grid_update", t.grid_update},
                       {"g2p", t.g2p}, {"damage", t.damage}, {"cracks", t.cracks}};
    if (b.solver->phase_field()) {
      const brittle::PhaseFieldTotals& pf = b.solver->phase_field_totals();
      r.stage_seconds.emplace_back("phase_field", t.phase_field);
      r.damage_model = "phase_field";
      r.pf_solves = pf.solves;
      r.pf_iterations = pf.iterations;
      r.pf_max_iterations = pf.max_iterations;
      r.pf_unconverged = pf.unconverged;
      r.pf_analyses = pf.analyses;
      r.pf_worst_residual = pf.worst_residual;
    }
    if (b.solid->material.model == brittle::DamageModel::Nacc) {
      r.damage_model = "nacc";
      r.nacc_branches = b.solver->nacc_totals().branch;
    }
    r.sliver_volume_threshold = b.spec->sliver_volume;
    if (b.event) {
      const brittle::FractureEvent& ev = *b.event;
      r.event = true;
      r.stage_seconds.emplace_back("event_extract", ev.seconds_extract);
      r.stage_seconds.emplace_back("event_cut", ev.seconds_cut);
      r.stage_seconds.emplace_back("event_detail", ev.detail.seconds);
      if (written_[i]) {
        r.fragments_file = files_[i][0];
        r.crack_file = files_[i][1];
        r.particles_file = files_[i][2];
      }
      const brittle::FragmentSet& set = ev.fragments;
      r.cutter = brittle::to_string(set.cutter);
      r.input_volume = set.input_volume;
      r.total_volume = set.total_volume();
      r.volume_change = set.volume_change();
      r.crack_faces = ev.crack_surface.triangles.size();
      r.crack_area = brittle::surface_area(ev.crack_surface_clipped);
      r.regions = static_cast<size_t>(ev.regions.count);
      r.breakage_order = ev.breakage_order;
      r.merged_regions = static_cast<size_t>(ev.merged_regions);
      r.detail = ev.detail.crack_vertices > 0;
      r.detail_lines = ev.detail.lines;
      r.detail_moved_vertices = ev.detail.moved_vertices;
      r.detail_max_displacement = ev.detail.max_displacement;
      r.detail_folded_triangles = ev.detail.folded_triangles;
      for (const brittle::Fragment& f : set.fragments) {
        BrittleFragmentReport fr;
        fr.name = f.mesh.name;
        fr.volume = f.properties.volume;
        fr.mass = f.properties.mass;
        for (int a = 0; a < 3; ++a) fr.centroid[static_cast<size_t>(a)] = f.properties.centroid[a];
        for (int a = 0; a < 9; ++a) fr.inertia[static_cast<size_t>(a)] = f.properties.inertia(a / 3, a % 3);
        fr.triangles = f.mesh.triangles.size();
        fr.crack_triangles = f.crack_triangles;
        fr.sliver = fr.volume < r.sliver_volume_threshold;
        (fr.sliver ? r.sliver_count : r.fragment_count) += 1;
        if (fr.sliver) r.sliver_volume += fr.volume;
        r.fragments.push_back(std::move(fr));
      }
    }
    out.push_back(std::move(r));
  }
  return out;
}

Json brittle_json(const std::vector<BrittleSolidReport>& reports) {
  Json list = Json::array();
  for (const BrittleSolidReport& r : reports) {
    Json j = {{"solid", r.solid},
              {"json_path", r.json_path},
              {"particles", r.particles},
              {"steps", r.steps},
              {"simulated_seconds", r.simulated_seconds},
              {"stop_reason", r.stop_reason},
              {"damaged_fraction", r.damaged_fraction},
              {"crack_updates", r.crack_updates},
              {"event", r.event}};
    Json stages = Json::object();
    for (const auto& [name, seconds] : r.stage_seconds) stages[name] = seconds;
    j["stage_seconds"] = stages;
    j["damage_model"] = r.damage_model;
    if (r.damage_model == "phase_field")
      j["phase_field"] = {{"solves", r.pf_solves},           {"iterations", r.pf_iterations},
                          {"max_iterations", r.pf_max_iterations}, {"unconverged", r.pf_unconverged},
                          {"analyses", r.pf_analyses},       {"worst_residual", r.pf_worst_residual}};
    if (r.damage_model == "nacc")
      j["nacc"] = {{"particle_steps",
                    {{"elastic", r.nacc_branches[0]}, {"compression", r.nacc_branches[1]},
                     {"tension", r.nacc_branches[2]}, {"shear", r.nacc_branches[3]}}}};
    if (r.event) {
      j["files"] = {{"fragments", r.fragments_file}, {"crack", r.crack_file}, {"particles", r.particles_file}};
      j["cutter"] = r.cutter;
      j["fragment_count"] = r.fragment_count;
      j["slivers"] = {{"count", r.sliver_count}, {"volume", r.sliver_volume}, {"threshold", r.sliver_volume_threshold}};
      j["input_volume"] = r.input_volume;
      j["total_volume"] = r.total_volume;
      j["volume_change"] = r.volume_change;
      j["crack_faces"] = r.crack_faces;
      j["crack_area"] = r.crack_area;
      j["regions"] = r.regions;
      if (r.breakage_order) j["breakage_order"] = {{"merged_regions", r.merged_regions}};
      if (r.detail)
        j["detail"] = {{"lines", r.detail_lines},
                       {"moved_vertices", r.detail_moved_vertices},
                       {"max_displacement", r.detail_max_displacement},
                       {"folded_triangles", r.detail_folded_triangles}};
      Json pieces = Json::array();
      for (const BrittleFragmentReport& f : r.fragments)
        pieces.push_back({{"name", f.name},
                          {"volume", f.volume},
                          {"mass", f.mass},
                          {"centroid", f.centroid},
                          {"inertia", f.inertia},
                          {"triangles", f.triangles},
                          {"crack_triangles", f.crack_triangles},
                          {"sliver", f.sliver}});
      j["fragments"] = std::move(pieces);
    }
    list.push_back(std::move(j));
  }
  return list;
}

std::vector<BrittleSolidReport> brittle_reports_from_json(const Json& list) {
  std::vector<BrittleSolidReport> out;
  try {
    for (const Json& j : list) {
      BrittleSolidReport r;
      r.solid = j.at("solid").get<std::string>();
      r.json_path = j.at("json_path").get<std::string>();
      r.particles = j.at("particles").get<size_t>();
      r.steps = j.at("steps").get<long>();
      r.simulated_seconds = j.at("simulated_seconds").get<double>();
      r.stop_reason = j.at("stop_reason").get<std::string>();
      r.damaged_fraction = j.at("damaged_fraction").get<double>();
      r.crack_updates = j.at("crack_updates").get<size_t>();
      r.event = j.at("event").get<bool>();
      for (const auto& [name, seconds] : j.at("stage_seconds").items()) r.stage_seconds.emplace_back(name, seconds.get<double>());
      r.damage_model = j.value("damage_model", std::string("rankine"));
      if (j.contains("phase_field")) {
        const Json& pf = j.at("phase_field");
        r.pf_solves = pf.at("solves").get<size_t>();
        r.pf_iterations = pf.at("iterations").get<size_t>();
        r.pf_max_iterations = pf.at("max_iterations").get<size_t>();
        r.pf_unconverged = pf.at("unconverged").get<size_t>();
        r.pf_analyses = pf.at("analyses").get<size_t>();
        r.pf_worst_residual = pf.at("worst_residual").get<double>();
      }
      if (j.contains("nacc")) {
        const Json& n = j.at("nacc").at("particle_steps");
        r.nacc_branches = {n.at("elastic").get<size_t>(), n.at("compression").get<size_t>(), n.at("tension").get<size_t>(),
                           n.at("shear").get<size_t>()};
      }
      if (r.event) {
        r.fragments_file = j.at("files").at("fragments").get<std::string>();
        r.crack_file = j.at("files").at("crack").get<std::string>();
        r.particles_file = j.at("files").at("particles").get<std::string>();
        r.cutter = j.at("cutter").get<std::string>();
        r.fragment_count = j.at("fragment_count").get<size_t>();
        r.sliver_count = j.at("slivers").at("count").get<size_t>();
        r.sliver_volume = j.at("slivers").at("volume").get<double>();
        r.sliver_volume_threshold = j.at("slivers").at("threshold").get<double>();
        r.input_volume = j.at("input_volume").get<double>();
        r.total_volume = j.at("total_volume").get<double>();
        r.volume_change = j.at("volume_change").get<double>();
        r.crack_faces = j.at("crack_faces").get<size_t>();
        r.crack_area = j.at("crack_area").get<double>();
        r.regions = j.at("regions").get<size_t>();
        if (j.contains("breakage_order")) {
          r.breakage_order = true;
          r.merged_regions = j.at("breakage_order").at("merged_regions").get<size_t>();
        }
        if (j.contains("detail")) {
          const Json& d = j.at("detail");
          r.detail = true;
          r.detail_lines = d.at("lines").get<size_t>();
          r.detail_moved_vertices = d.at("moved_vertices").get<size_t>();
          r.detail_max_displacement = d.at("max_displacement").get<double>();
          r.detail_folded_triangles = d.at("folded_triangles").get<size_t>();
        }
        for (const Json& f : j.at("fragments")) {
          BrittleFragmentReport fr;
          fr.name = f.at("name").get<std::string>();
          fr.volume = f.at("volume").get<double>();
          fr.mass = f.at("mass").get<double>();
          fr.centroid = f.at("centroid").get<std::array<double, 3>>();
          fr.inertia = f.at("inertia").get<std::array<double, 9>>();
          fr.triangles = f.at("triangles").get<size_t>();
          fr.crack_triangles = f.at("crack_triangles").get<size_t>();
          fr.sliver = f.at("sliver").get<bool>();
          r.fragments.push_back(std::move(fr));
        }
      }
      out.push_back(std::move(r));
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("summary.json: field \"brittle\": ") + e.what());
  }
  return out;
}

}  // namespace shellfrac::output
