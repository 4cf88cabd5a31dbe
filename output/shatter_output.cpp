#include "output/shatter_output.hpp"

#include <cstdio>

#include "output/brittle_output.hpp"
#include "render_mesh/atomic_write.hpp"
#include "render_mesh/exporter.hpp"
#include "render_mesh/gltf_writer.hpp"

namespace shellfrac::output {

namespace fs = std::filesystem;
using Json = nlohmann::json;

ShatterWriter::ShatterWriter(const scene::Model& model, fs::path out_dir) : model_(model), out_dir_(std::move(out_dir)) {}

void ShatterWriter::write_frame(const sim::Simulation& sim, int frame) {
  if (sim.shatter().empty()) return;
  const shatter::ShatterLoop& loop = sim.shatter().loop();
  std::vector<render_mesh::PolyMesh> pieces;
  std::vector<std::optional<rigid::Pose>> poses(loop.pieces().size());
  for (size_t i = 0; i < loop.pieces().size(); ++i)
    if (loop.alive(i)) {
      pieces.push_back(poly_mesh(loop.world_mesh(i)));
      poses[i] = loop.world().state(loop.pieces()[i].body).pose;
    }
  // The static props stand in every frame, so that a frame is the whole shot.
  for (const brittle::TriMesh& prop : loop.prop_meshes()) pieces.push_back(poly_mesh(prop));
  times_.push_back(static_cast<float>(sim.time()));
  poses_.push_back(std::move(poses));
  const fs::path dir = out_dir_ / "rigid";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + dir.string() + ": " + ec.message());
  char stem[32];
  std::snprintf(stem, sizeof stem, "frame_%05d", frame);
  const render_mesh::ExportOptions options{model_.output.triangulate, model_.output.double_precision};
  const fs::path file = render_mesh::export_meshes(pieces, dir, stem, model_.output.format, options);
  frames_.push_back(fs::relative(file, out_dir_).string());
}

std::string ShatterWriter::write_animation(const sim::Simulation& sim) {
  if (sim.shatter().empty() || times_.empty()) return "";
  const shatter::ShatterLoop& loop = sim.shatter().loop();
  const size_t n = loop.pieces().size();
  std::vector<render_mesh::PolyMesh> meshes;
  std::vector<render_mesh::NodeTrack> tracks(n);
  for (size_t i = 0; i < n; ++i) {
    const shatter::Piece& p = loop.pieces()[i];
    meshes.push_back(poly_mesh(rigid::transformed(p.mesh, p.material_to_body)));
    meshes.back().name = p.name;
    // A piece holds its first pose before it exists and its last after it broke, hidden by scale 0.
    std::optional<rigid::Pose> held;
    for (const auto& frame : poses_)
      if (i < frame.size() && frame[i]) {
        held = frame[i];
        break;
      }
    render_mesh::NodeTrack& t = tracks[i];
    for (size_t f = 0; f < poses_.size(); ++f) {
      const bool alive = i < poses_[f].size() && poses_[f][i].has_value();
      if (alive) held = poses_[f][i];
      t.times.push_back(times_[f]);
      t.translations.push_back(held ? held->translation : Eigen::Vector3d::Zero());
      t.rotations.push_back(held ? held->rotation : Eigen::Quaterniond::Identity());
      t.scales.push_back(alive ? 1.0f : 0.0f);
    }
  }
  // Static props: their meshes where they stand, one constant key per frame.
  for (const brittle::TriMesh& prop : loop.prop_meshes()) {
    meshes.push_back(poly_mesh(prop));
    render_mesh::NodeTrack t;
    for (float time : times_) {
      t.times.push_back(time);
      t.translations.push_back(Eigen::Vector3d::Zero());
      t.rotations.push_back(Eigen::Quaterniond::Identity());
      t.scales.push_back(1.0f);
    }
    tracks.push_back(std::move(t));
  }
  const fs::path dir = out_dir_ / "rigid";
  const render_mesh::GltfDocument doc = render_mesh::gltf_document(meshes, "shatter.bin", tracks);
  render_mesh::write_file_atomically(dir / "shatter.bin", doc.binary);  // the buffer before the file naming it
  render_mesh::write_file_atomically(dir / "shatter.gltf", doc.json);
  return "rigid/shatter.gltf";
}

namespace {

Json vec(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

}  // namespace

Json shatter_json(const shatter::ShatterLoop& loop, const std::vector<std::string>& frames, const std::string& animation) {
  Json events = Json::array();
  for (const shatter::EventRecord& e : loop.events()) {
    Json j = {{"time", e.time}, {"body", e.body}, {"partner", e.partner}, {"generation", e.generation}, {"outcome", e.outcome},
              {"impulse", e.impulse}, {"contact_time", e.contact_time}, {"approach_speed", e.approach_speed},
              {"point", vec(e.point)}, {"particles", e.particles}, {"mpm_steps", e.mpm_steps},
              {"damaged_particles", e.damaged_particles}, {"rubble_particles", e.rubble_particles},
              {"breakage_order", e.breakage_order},
              {"fragments", e.fragments},
              {"fragments_by_class", {{"tiny", e.by_class[0]}, {"small", e.by_class[1]}, {"large", e.by_class[2]},
                                      {"nearly_whole", e.by_class[3]}}},
              {"seconds", {{"mpm", e.seconds_mpm}, {"mpm_crack_updates", e.seconds_mpm_cracks}, {"extract", e.seconds_extract}, {"cut", e.seconds_cut},
                           {"spawn", e.seconds_spawn}}},
              {"conservation", {{"mass", e.mass_error}, {"momentum", e.momentum_error},
                                {"angular_momentum", e.angular_momentum_error}, {"kinetic_energy_ratio", e.energy_ratio},
                                {"volume_change", e.volume_change}}}};
    if (!e.message.empty()) j["message"] = e.message;
    events.push_back(j);
  }
  size_t by_class[4] = {0, 0, 0, 0};
  size_t alive = 0;
  for (size_t i = 0; i < loop.pieces().size(); ++i) {
    if (!loop.alive(i)) continue;
    ++alive;
    const shatter::Piece& p = loop.pieces()[i];
    if (p.root >= 0 && p.generation > 0) ++by_class[static_cast<int>(p.fragment_class)];  // fragments only
  }
  const shatter::ShatterTotals& t = loop.totals();
  return {{"events", events},
          {"pieces", alive},
          {"fragments_by_class", {{"tiny", by_class[0]}, {"small", by_class[1]}, {"large", by_class[2]},
                                  {"nearly_whole", by_class[3]}}},
          {"totals", {{"rigid_steps", t.rigid_steps}, {"rigid_seconds", t.seconds_rigid}, {"mpm_steps", t.mpm_steps},
                      {"mpm_seconds", t.seconds_mpm}, {"extract_seconds", t.seconds_extract},
                      {"cut_seconds", t.seconds_cut}, {"spawn_seconds", t.seconds_spawn}, {"events", t.events},
                      {"broken", t.broken}, {"failed", t.failed}}},
          {"frames", frames},
          {"animation", animation}};
}

}  // namespace shellfrac::output
