// A small driver that runs the brittle scenes (scenes/brittle/*.json) through the brittle library with
// the scene keys proposed in docs/brittle.md, until the scene parser and run driver of sim/ read them.
// Not a test and not the product: it measures how long each scene takes and writes what an event
// produces (fragments and crack as OBJ, particles as .vdb, the summary as JSON).
//
//   brittle_scene_driver SCENE.json [OUT_DIR]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <map>
#include <sstream>

#include "brittle/errors.hpp"
#include "brittle/fracture_event.hpp"
#include "brittle/particles_vdb.hpp"
#include "brittle/primitives.hpp"
#include "brittle/solver.hpp"

using namespace shellfrac::brittle;
using nlohmann::json;
namespace mpm = shellfrac::mpm;
namespace fs = std::filesystem;

namespace {

Vec3 vec(const json& j) { return Vec3(j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()); }

// OBJ positions, UVs and faces (fans), vertices split per (position, uv) pair.
TriMesh read_obj(const fs::path& file, double scale, const Vec3& translate) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open the mesh");
  std::vector<Vec3> v;
  std::vector<Vec2> vt;
  TriMesh m;
  m.name = file.stem().string();
  std::map<std::pair<int, int>, int> corner;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Vec3 p;
      s >> p.x() >> p.y() >> p.z();
      v.push_back(scale * p + translate);
    } else if (tag == "vt") {
      Vec2 t;
      s >> t.x() >> t.y();
      vt.push_back(t);
    } else if (tag == "f") {
      std::vector<int> ids;
      std::string c;
      while (s >> c) {
        const int pi = std::stoi(c.substr(0, c.find('/'))) - 1;
        int ti = -1;
        const size_t slash = c.find('/');
        if (slash != std::string::npos && slash + 1 < c.size() && c[slash + 1] != '/') ti = std::stoi(c.substr(slash + 1)) - 1;
        auto it = corner.find({pi, ti});
        if (it == corner.end()) {
          it = corner.emplace(std::make_pair(pi, ti), static_cast<int>(m.positions.size())).first;
          m.positions.push_back(v.at(static_cast<size_t>(pi)));
          m.uvs.push_back(ti >= 0 ? vt.at(static_cast<size_t>(ti)) : Vec2(0, 0));
        }
        ids.push_back(it->second);
      }
      for (size_t k = 1; k + 1 < ids.size(); ++k) m.triangles.emplace_back(ids[0], ids[k], ids[k + 1]);
    }
  }
  compute_vertex_normals(m);
  return m;
}

void write_obj(const std::vector<const TriMesh*>& meshes, const fs::path& file) {
  std::ofstream out(file);
  size_t base = 1;
  for (const TriMesh* m : meshes) {
    out << "o " << (m->name.empty() ? "mesh" : m->name) << "\n";
    for (const Vec3& p : m->positions) out << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
    for (const Tri& t : m->triangles) out << "f " << base + t[0] << " " << base + t[1] << " " << base + t[2] << "\n";
    base += m->positions.size();
  }
}

TriMesh solid_mesh(const json& s, const fs::path& dir) {
  const std::string shape = s.at("shape");
  TriMesh m;
  if (shape == "box") m = box_mesh(vec(s.at("center")), vec(s.at("half_extents")), s.value("subdivisions", 2));
  else if (shape == "sphere") m = sphere_mesh(vec(s.at("center")), s.at("radius"), 48, 24);
  else if (shape == "cylinder") m = cylinder_mesh(vec(s.at("center")), s.at("radius"), s.at("height"), 48);
  else if (shape == "torus") m = torus_mesh(vec(s.at("center")), s.at("major_radius"), s.at("minor_radius"), 48, 24);
  else if (shape == "mesh") m = read_obj(dir / s.at("file").get<std::string>(), s.value("scale", 1.0), s.contains("translate") ? vec(s["translate"]) : Vec3::Zero());
  else throw InputError("unknown shape " + shape);
  m.name = s.value("name", shape);
  return m;
}

mpm::Collider collider(const json& c) {
  mpm::Collider col;
  const std::string shape = c.at("shape");
  if (shape == "half_space") col.shape = std::make_shared<mpm::HalfSpace>(vec(c.at("point")), vec(c.at("normal")));
  else if (shape == "sphere") col.shape = std::make_shared<mpm::Sphere>(vec(c.at("center")), c.at("radius").get<double>());
  else col.shape = std::make_shared<mpm::Box>(vec(c.at("center")), vec(c.at("half_extents")));
  const std::string b = c.value("boundary", "friction");
  col.boundary = b == "sticky" ? mpm::Boundary::Sticky : b == "slip" ? mpm::Boundary::Slip : mpm::Boundary::Friction;
  col.friction = c.value("friction", 0.3);
  if (c.contains("motion") && c["motion"].contains("linear_velocity")) col.motion.linear_velocity = vec(c["motion"]["linear_velocity"]);
  return col;
}

bool removed(const json& regions, const Vec3& x) {
  for (const json& r : regions) {
    const Vec3 c = vec(r.at("center"));
    if (r.at("shape") == "sphere" ? (x - c).norm() < r.at("radius").get<double>()
                                  : ((x - c).cwiseAbs() - vec(r.at("half_extents"))).maxCoeff() < 0)
      return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: brittle_scene_driver SCENE.json [OUT_DIR]\n";
    return 2;
  }
  try {
    const fs::path scene_file = argv[1];
    std::ifstream in(scene_file);
    const json scene = json::parse(in);
    const fs::path dir = scene_file.parent_path();
    json report = {{"scene", scene.value("name", scene_file.stem().string())}, {"solids", json::array()}};
    const auto t_scene = std::chrono::steady_clock::now();
    const Vec3 gravity = scene.contains("gravity") ? vec(scene["gravity"]) : Vec3(0, 0, 0);
    size_t index = 0;
    for (const json& s : scene.at("solids")) {
      const std::string where = scene_file.string() + "#/solids/" + std::to_string(index++);
      const auto t0 = std::chrono::steady_clock::now();
      TriMesh mesh = solid_mesh(s, dir);
      const json& mj = s.at("material");
      BrittleMaterial mat;
      mat.youngs_modulus = mj.at("E");
      mat.poisson_ratio = mj.at("nu");
      mat.density = mj.at("density");
      mat.failure_stress = mj.at("failure_stress");
      mat.fracture_energy = mj.at("fracture_energy");
      mat.rule = mj.value("damage_rule", "healing") == "monotone" ? DamageRule::Monotone : DamageRule::Healing;
      mat.characteristic_length = mj.value("characteristic_length", 0.0);
      const std::string sampling = s.value("sampling", "jittered");
      const double spacing = s.at("spacing");
      BrittleSolid solid;
      solid.material = mat;
      solid.spacing = spacing;
      {
        const Sampling method = sampling == "regular" ? Sampling::Regular : sampling == "poisson_disk" ? Sampling::PoissonDisk : Sampling::Jittered;
        std::vector<Vec3> pts = sample_mesh(mesh, spacing, method, s.value("seed", 1u), where);
        const double volume = mass_properties(mesh, 1.0).volume / static_cast<double>(pts.size());
        std::vector<Vec3> kept;
        for (const Vec3& p : pts)
          if (!s.contains("remove") || !removed(s["remove"], p)) kept.push_back(p);
        solid.add_particles(kept, volume, s.contains("initial_velocity") ? vec(s["initial_velocity"]) : Vec3::Zero());
      }
      const json fr = s.value("fracture", json::object());
      const double dx = fr.value("grid_spacing", 2 * spacing);
      std::vector<StrengthRegion> regions;
      WeibullStrength weibull;
      if (s.contains("strength")) {
        for (const json& r : s["strength"].value("regions", json::array())) {
          StrengthRegion reg;
          reg.shape = r.at("shape") == "sphere" ? StrengthRegion::Shape::Sphere : StrengthRegion::Shape::Box;
          reg.centre = vec(r.at("center"));
          if (r.contains("half_extents")) reg.half_extents = vec(r["half_extents"]);
          reg.radius = r.value("radius", 0.0);
          reg.failure_stress = r.at("failure_stress");
          regions.push_back(reg);
        }
        if (s["strength"].contains("weibull")) {
          const json& w = s["strength"]["weibull"];
          weibull = {true, w.at("modulus").get<double>(), w.value("scale_is_mean", false), w.value("seed", 1ULL)};
        }
      }
      solid.set_strength(regions, weibull, dx);
      SolverOptions o;
      o.dx = dx;
      o.cfl = fr.value("cfl", 0.3);
      o.gravity = gravity;
      o.two_fields = fr.value("two_fields", true);
      o.field_contact = fr.value("field_contact", true);
      const json st = fr.value("stop", json::object());
      o.stop.damaged_fraction = st.value("damaged_fraction", 0.0);
      o.stop.max_steps = st.value("max_steps", 0);
      o.stop.max_time = st.value("max_time", 0.0);
      BrittleSolver solver(solid, o);
      for (const json& c : scene.value("colliders", json::array())) solver.add_collider(collider(c));
      for (const json& im : s.value("impacts", json::array())) {
        Impact impact;
        impact.point = vec(im.at("point"));
        impact.direction = vec(im.at("direction"));
        impact.impulse = im.at("impulse");
        impact.start_time = im.value("start_time", 0.0);
        impact.radius = im.value("radius", 0.0);
        if (im.contains("hertz")) {
          const json& h = im["hertz"];
          impact.duration = impact_duration(HertzBody{h.at("E"), h.at("nu"), h.at("radius"), h.at("mass")}, solid, impact.point, h.at("speed"));
        } else {
          impact.duration = im.at("duration");
        }
        solver.add_ghosts(impact_ghosts(impact, mesh, solid, where + "/impacts"));
      }
      CrackExtractionOptions co;
      co.grid.spacing = fr.value("crack_grid_spacing", dx);
      const int interval = fr.value("crack_interval", 20);
      const auto t1 = std::chrono::steady_clock::now();
      while (!solver.should_stop()) {
        solver.step();
        if (o.two_fields && solver.steps() % static_cast<size_t>(interval) == 0 && solver.damaged_count() > 0) solver.update_crack(co);
      }
      const auto t2 = std::chrono::steady_clock::now();
      FractureEventOptions eo;
      eo.crack = co;
      eo.fragments.cutter = fr.value("cutter", "exact") == "level_set" ? Cutter::LevelSet : Cutter::Exact;
      eo.fragments.voxel = fr.value("voxel", 0.0);
      eo.gap_width = fr.value("gap_width", 0.0);
      const FractureEvent ev = fracture_event(solid, mesh, eo, where);
      const auto t3 = std::chrono::steady_clock::now();
      json r = fracture_summary(ev);
      r["name"] = mesh.name;
      r["particles"] = solid.size();
      r["steps"] = solver.steps();
      r["simulated_time"] = solver.time();
      r["stop_reason"] = to_string(solver.stop_reason());
      r["damaged_fraction"] = solver.damaged_fraction();
      r["stage_seconds"] = {{"p2g", solver.times().p2g},   {"forces", solver.times().forces}, {"grid_update", solver.times().grid_update},
                            {"g2p", solver.times().g2p},   {"damage", solver.times().damage}, {"cracks", solver.times().cracks}};
      r["wall_seconds"] = {{"setup", std::chrono::duration<double>(t1 - t0).count()},
                           {"mpm", std::chrono::duration<double>(t2 - t1).count()},
                           {"event", std::chrono::duration<double>(t3 - t2).count()}};
      if (argc > 2) {
        const fs::path out = fs::path(argv[2]) / r["name"].get<std::string>();
        fs::create_directories(out);
        std::vector<const TriMesh*> frags;
        for (const Fragment& f : ev.fragments.fragments) frags.push_back(&f.mesh);
        write_obj(frags, out / "fragments.obj");
        write_obj({&ev.crack_surface_clipped}, out / "crack_surface.obj");
        write_particles_vdb(solid, out / "particles.vdb", true);
        std::ofstream(out / "summary.json") << r.dump(2) << "\n";
      }
      report["solids"].push_back(r);
    }
    report["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_scene).count();
    std::cout << report.dump(1) << "\n";
    return 0;
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
