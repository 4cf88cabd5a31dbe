// The brittle scenes through the product: `shellfrac validate` and `shellfrac run` on scenes/brittle/*.json,
// the files a fracture event writes and the numbers of summary.json; bad brittle input refused with exit
// code 2 and the JSON path.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include "tests/cli/cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Json = nlohmann::json;

using shellfrac::test::Result;

Result shellfrac(const std::string& args) { return shellfrac::test::run_shellfrac(args); }

fs::path scratch(const std::string& name) { return shellfrac::test::scratch_folder("brittle", name); }

fs::path scene_file(const std::string& name) { return fs::path(SHELLFRAC_SOURCE_DIR) / "scenes" / "brittle" / (name + ".json"); }

// Runs a shipped brittle scene and returns its summary.json (the run folder stays for the caller).
Json run_scene(const std::string& name, const fs::path& out) {
  const Result r = shellfrac("run " + scene_file(name).string() + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out / "summary.json");
  return Json::parse(in);
}

// The fragment OBJ read back on its own, without the program's numbers: its objects ("o <name>") with
// their faces as position triples. The writer never merges vertices (each face corner has its own
// normal and UV), so vertices are matched by their printed position: two corners are the same point
// exactly when their "v" lines print the same coordinates.
struct ObjObject {
  std::string name;
  std::vector<std::vector<size_t>> faces;  // indices into ObjFile::points (one per distinct printed position)
};
struct ObjFile {
  std::vector<std::array<double, 3>> points;  // per distinct printed position
  std::vector<ObjObject> objects;
};

ObjFile read_obj(const fs::path& path) {
  ObjFile file;
  std::map<std::string, size_t> by_text;
  std::vector<size_t> vertex_point;  // OBJ vertex (1-based in the file) -> distinct position
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "o") {
      file.objects.emplace_back();
      ls >> file.objects.back().name;
    } else if (tag == "v") {
      std::string x, y, z;
      ls >> x >> y >> z;
      const auto [it, added] = by_text.emplace(x + " " + y + " " + z, file.points.size());
      if (added) file.points.push_back({std::stod(x), std::stod(y), std::stod(z)});
      vertex_point.push_back(it->second);
    } else if (tag == "f") {
      if (file.objects.empty()) file.objects.emplace_back();  // faces before any "o": an unnamed object
      std::vector<size_t> face;
      std::string corner;
      while (ls >> corner) {
        const long i = std::stol(corner.substr(0, corner.find('/')));  // "v/vt/vn": the position index
        const long k = i > 0 ? i - 1 : static_cast<long>(vertex_point.size()) + i;
        if (k < 0 || k >= static_cast<long>(vertex_point.size())) throw std::runtime_error(path.string() + ": bad index " + corner);
        face.push_back(vertex_point[static_cast<size_t>(k)]);
      }
      file.objects.back().faces.push_back(face);
    }
  }
  return file;
}

// Independent check of the fragment file against summary.json: one object per listed fragment, in
// order and by name, with the listed triangle count; every object a closed, consistently oriented
// surface (every directed edge between two positions used once, and its reverse once); and its volume
// by the divergence theorem (sum over the fan triangles of a . (b x c) / 6) positive, equal to the
// listed fragment volume, and all of them summing to the input volume. Tolerance 1e-6 of the input
// volume: the file prints single-precision coordinates (the output default; each rounded by at most 6e-8
// of its size), and the volumes read back differ from the program's by at most 2e-9 of the input in
// these scenes (measured: the dropped torus and sphere; 1e-16 where the cuts are planes).
void check_fragment_file(const Json& solid, const fs::path& out) {
  const fs::path path = out / solid["files"]["fragments"].get<std::string>();
  ASSERT_EQ(path.extension(), ".obj") << path;
  const ObjFile file = read_obj(path);
  const Json& listed = solid["fragments"];
  ASSERT_EQ(file.objects.size(), listed.size()) << path;
  const double input = solid["input_volume"].get<double>();
  double total = 0, worst = 0;
  for (size_t k = 0; k < file.objects.size(); ++k) {
    const ObjObject& o = file.objects[k];
    SCOPED_TRACE(o.name);
    EXPECT_EQ(o.name, listed[k]["name"].get<std::string>());
    std::map<std::pair<size_t, size_t>, int> directed;
    size_t triangles = 0;
    double volume = 0;
    for (const std::vector<size_t>& f : o.faces) {
      ASSERT_GE(f.size(), 3u);
      for (size_t i = 0; i < f.size(); ++i) ++directed[{f[i], f[(i + 1) % f.size()]}];
      const auto& a = file.points[f[0]];
      for (size_t i = 1; i + 1 < f.size(); ++i, ++triangles) {
        const auto &b = file.points[f[i]], &c = file.points[f[i + 1]];
        volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
      }
    }
    size_t unmatched = 0;
    for (const auto& [edge, count] : directed) {
      const auto reverse = directed.find({edge.second, edge.first});
      if (count != 1 || reverse == directed.end() || reverse->second != 1) ++unmatched;
    }
    EXPECT_EQ(unmatched, 0u) << "edges of " << path << " not matched once by a reversed edge";
    EXPECT_EQ(triangles, listed[k]["triangles"].get<size_t>());
    EXPECT_GT(volume, 0.0);
    EXPECT_NEAR(volume, listed[k]["volume"].get<double>(), 1e-6 * input);
    worst = std::max(worst, std::abs(volume - listed[k]["volume"].get<double>()) / input);
    total += volume;
  }
  std::printf("MEASURE %s: %zu objects, |sum of OBJ volumes - input| / input = %.2g, worst fragment %.2g\n",
              path.filename().string().c_str(), file.objects.size(), std::abs(total - input) / input, worst);
  EXPECT_NEAR(total, input, 1e-6 * input);
}

// What every fracture event must satisfy: files written, the exact cutter's volumes summing to the
// input's to 1e-9, fragment masses summing to the solid's mass (density x volume), counts consistent,
// and the fragment file agreeing with all that on its own (check_fragment_file).
void check_event(const Json& solid, const fs::path& out, double density) {
  SCOPED_TRACE(solid["solid"].get<std::string>());
  ASSERT_TRUE(solid["event"].get<bool>());
  for (const char* f : {"fragments", "crack", "particles"}) EXPECT_TRUE(fs::exists(out / solid["files"][f].get<std::string>())) << f;
  EXPECT_EQ(solid["cutter"], "exact");
  const double input = solid["input_volume"], total = solid["total_volume"];
  EXPECT_LT(std::abs(total - input) / input, 1e-9);
  EXPECT_LT(std::abs(solid["volume_change"].get<double>()), 1e-9);
  double volume = 0, mass = 0;
  size_t counted = 0;
  for (const Json& f : solid["fragments"]) {
    volume += f["volume"].get<double>();
    mass += f["mass"].get<double>();
    counted += f["sliver"].get<bool>() ? 0 : 1;
    EXPECT_EQ(f["sliver"].get<bool>(), f["volume"].get<double>() < solid["slivers"]["threshold"].get<double>());
  }
  EXPECT_NEAR(volume, input, 1e-9 * input);
  EXPECT_NEAR(mass, density * input, 1e-9 * density * input);
  EXPECT_EQ(solid["fragment_count"].get<size_t>(), counted);
  EXPECT_EQ(solid["slivers"]["count"].get<size_t>() + counted, solid["fragments"].size());
  check_fragment_file(solid, out);
}

// The fragment file holds one object per fragment ("o <solid>_fragment_<k>" in OBJ).
size_t objects_in(const fs::path& obj) {
  std::ifstream in(obj);
  std::string line;
  size_t n = 0;
  while (std::getline(in, line)) n += line.rfind("o ", 0) == 0;
  return n;
}

TEST(BrittleCli, EveryBrittleSceneValidates) {
  int count = 0;
  for (const auto& e : fs::directory_iterator(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes" / "brittle")) {
    if (e.path().extension() != ".json") continue;
    ++count;
    const Result r = shellfrac("validate " + e.path().string());
    EXPECT_EQ(r.exit_code, 0) << e.path() << "\n" << r.output;
  }
  EXPECT_EQ(count, 9);
}

// Three-point bending of a notched beam: the crack runs from the notch through the height, so the beam
// ends in exactly two pieces, one on each side of the notch (x = 0), of about half the volume each.
TEST(BrittleCli, NotchedBeamBreaksInTwoAtTheNotch) {
  const fs::path d = scratch("beam");
  const Json s = run_scene("notched-beam", d);
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& beam = s["brittle"][0];
  check_event(beam, d, 1000);
  ASSERT_EQ(beam["fragment_count"].get<size_t>(), 2u);
  const Json& a = beam["fragments"][0];
  const Json& b = beam["fragments"][1];
  EXPECT_LT(a["centroid"][0].get<double>() * b["centroid"][0].get<double>(), 0.0);  // opposite sides
  EXPECT_NEAR(a["volume"].get<double>() / beam["input_volume"].get<double>(), 0.5, 0.1);
  EXPECT_EQ(objects_in(d / beam["files"]["fragments"].get<std::string>()), beam["fragments"].size());
  fs::remove_all(d);
}

// A notched bar pulled apart by sticky grips, broken by the CD-MPM phase field (scenes/brittle/
// pulled-bar-phase-field.json): the crack runs from the notch across the section, so the bar ends in
// two pieces, one each side of x = 0, of half the volume each (symmetry). Every CG solve converged to
// the tolerance 1e-10 (the solver reports unconverged solves).
TEST(BrittleCli, PulledBarBreaksAtTheNotchUnderThePhaseField) {
  const fs::path d = scratch("pulled_bar");
  const Json s = run_scene("pulled-bar-phase-field", d);
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& bar = s["brittle"][0];
  check_event(bar, d, 1000);
  EXPECT_EQ(bar["damage_model"], "phase_field");
  EXPECT_GT(bar["phase_field"]["solves"].get<size_t>(), 100u);
  EXPECT_EQ(bar["phase_field"]["unconverged"].get<size_t>(), 0u);
  EXPECT_LE(bar["phase_field"]["worst_residual"].get<double>(), 1e-10);
  ASSERT_EQ(bar["fragment_count"].get<size_t>(), 2u);
  const Json& a = bar["fragments"][0];
  const Json& b = bar["fragments"][1];
  EXPECT_LT(a["centroid"][0].get<double>() * b["centroid"][0].get<double>(), 0.0);
  EXPECT_NEAR(a["volume"].get<double>() / bar["input_volume"].get<double>(), 0.5, 0.02);
  fs::remove_all(d);
}

// The same bar broken by CD-MPM's NACC plasticity (scenes/brittle/pulled-bar-nacc.json): the yield
// ellipse's tensile tip softens the ligament until it carries nothing, and the crack extracted from the
// broken particles cuts the bar at the notch plane into two halves. Every branch of the return mapping
// is taken (the grips compress, the notch shears and pulls).
TEST(BrittleCli, PulledBarBreaksAtTheNotchUnderNacc) {
  const fs::path d = scratch("pulled_bar_nacc");
  const Json s = run_scene("pulled-bar-nacc", d);
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& bar = s["brittle"][0];
  check_event(bar, d, 1000);
  EXPECT_EQ(bar["damage_model"], "nacc");
  const Json& steps = bar["nacc"]["particle_steps"];
  size_t total = 0;
  for (const char* branch : {"elastic", "compression", "tension", "shear"}) {
    EXPECT_GT(steps[branch].get<size_t>(), 0u) << branch;
    total += steps[branch].get<size_t>();
  }
  EXPECT_EQ(total, bar["steps"].get<size_t>() * bar["particles"].get<size_t>());
  ASSERT_EQ(bar["fragment_count"].get<size_t>(), 2u);
  const Json& a = bar["fragments"][0];
  const Json& b = bar["fragments"][1];
  EXPECT_LT(a["centroid"][0].get<double>() * b["centroid"][0].get<double>(), 0.0);
  EXPECT_NEAR(a["volume"].get<double>() / bar["input_volume"].get<double>(), 0.5, 0.02);
  // The crack surface lies within one grid cell (5 mm) of the notch plane x = 0.
  std::ifstream crack(d / bar["files"]["crack"].get<std::string>());
  std::string tag;
  double x = 0, y = 0, z = 0, worst = 0;
  size_t vertices = 0;
  for (std::string line; std::getline(crack, line);) {
    std::istringstream in(line);
    if (in >> tag && tag == "v" && in >> x >> y >> z) {
      worst = std::max(worst, std::abs(x));
      ++vertices;
    }
  }
  EXPECT_GT(vertices, 0u);
  EXPECT_LE(worst, 0.005);
  fs::remove_all(d);
}

// Share of the solid's input volume held by each fragment (largest first, as listed).
std::vector<double> volume_shares(const Json& solid) {
  std::vector<double> shares;
  for (const Json& f : solid["fragments"]) shares.push_back(f["volume"].get<double>() / solid["input_volume"].get<double>());
  return shares;
}

size_t pieces_of_at_least(const std::vector<double>& shares, double share) {
  return static_cast<size_t>(std::count_if(shares.begin(), shares.end(), [&](double s) { return s >= share; }));
}

// Four shapes dropped on the ground at 4 m/s (thesis Fig. 3.29), a brittle material (fracture energy 15
// J/m^2: Irwin length E G_f / sigma_f^2 = 1.3 cm, 1.7 cells), run through the impact to 10 ms, the crack
// following the damage time (breakage_order). Every shape shatters: at least 4 pieces, every counted
// piece at least 1 % of its shape's volume, no sliver. Physics bound: at most 12 counted pieces each (no
// shape is pulverised at this speed). Measured: 8 / 10 / 7 / 10 (sphere / box / cylinder / torus), 35 in
// all, the smallest 1.3 / 1.4 / 2.1 / 3.3 % (3 / 2 / 2 / 3 pieces with G_f 30; the box had two
// more pieces of 0.9 and 0.7 % before the merge was checked on the cut volumes, the torus a chip of 0.2 %
// before regions were split at cells without particles). The totals of at least 30 and of at least 5
// pieces for the sphere and box are regression checks just below those values.
TEST(BrittleCli, ShapesDropShatterEveryShape) {
  const fs::path d = scratch("shapes");
  const Json s = run_scene("shapes-drop", d);
  ASSERT_EQ(s["brittle"].size(), 4u);
  size_t total = 0;
  for (const Json& solid : s["brittle"]) {
    SCOPED_TRACE(solid["solid"].get<std::string>());
    check_event(solid, d, 2400);
    const size_t n = solid["fragment_count"].get<size_t>();
    total += n;
    const std::vector<double> shares = volume_shares(solid);
    EXPECT_EQ(solid["slivers"]["count"].get<size_t>(), 0u);
    EXPECT_GE(n, 4u);
    EXPECT_EQ(pieces_of_at_least(shares, 0.01), n);  // every counted piece (and no sliver) >= 1 %
    EXPECT_LE(n, 12u);
    if (solid["solid"] == "sphere" || solid["solid"] == "box") {
      EXPECT_GE(pieces_of_at_least(shares, 0.01), 5u);  // regression check
    }
  }
  EXPECT_GE(total, 30u);  // regression check (measured 35)
  fs::remove_all(d);
}

// A shipped scene with its end time (and time stop) cut to `end` seconds, written into `dir`; a mesh
// file path is made absolute. The shipped scenes run in 30-60 s of CPU; these checks take seconds.
fs::path shortened_scene(const std::string& name, double end, const fs::path& dir) {
  std::ifstream in(scene_file(name));
  Json scene = Json::parse(in);
  scene["time"]["end"] = end;
  for (Json& solid : scene["solids"]) {
    solid["fracture"]["stop"]["max_time"] = end;
    if (solid.contains("file")) solid["file"] = (scene_file(name).parent_path() / solid["file"].get<std::string>()).lexically_normal().string();
  }
  const fs::path out = dir / (name + ".json");
  std::ofstream(out) << scene.dump(2);
  return out;
}

// slab-sphere for its first 3 ms (the ball has touched the slab): the run writes its event with the
// volumes and masses conserved (check_event), and the slab, a box of 0.2 x 0.2 x 0.02 m, keeps its
// volume exactly in the input.
TEST(BrittleCli, SlabSphereShortRunWritesAConservingEvent) {
  const fs::path d = scratch("slab");
  const Result r = shellfrac("run " + shortened_scene("slab-sphere", 0.003, d).string() + " --out " + (d / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(d / "out" / "summary.json");
  const Json s = Json::parse(in);
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& slab = s["brittle"][0];
  check_event(slab, d / "out", 2500);
  EXPECT_NEAR(slab["input_volume"].get<double>(), 0.2 * 0.2 * 0.02, 1e-12);
  EXPECT_NEAR(slab["simulated_seconds"].get<double>(), 0.003, 1e-4);  // stopped by the time criterion
  EXPECT_EQ(slab["stop_reason"], "max_time");
  fs::remove_all(d);
}

// Crack triangles of an OBJ file (centroid and area), for the orientation measure below.
struct CrackTriangle {
  Eigen::Vector3d centroid;
  double area;
};
std::vector<CrackTriangle> crack_triangles(const fs::path& obj) {
  std::ifstream in(obj);
  std::string line;
  std::vector<Eigen::Vector3d> v;
  std::vector<CrackTriangle> out;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      Eigen::Vector3d p;
      ls >> p.x() >> p.y() >> p.z();
      v.push_back(p);
    } else if (tag == "f") {
      std::vector<int> ids;
      std::string w;
      while (ls >> w) ids.push_back(std::stoi(w.substr(0, w.find('/'))) - 1);
      for (size_t i = 1; i + 1 < ids.size(); ++i) {
        const Eigen::Vector3d &a = v[ids[0]], &b = v[ids[i]], &c = v[ids[i + 1]];
        const double area = 0.5 * (b - a).cross(c - a).norm();
        if (area > 0) out.push_back({(a + b + c) / 3.0, area});
      }
    }
  }
  return out;
}

// The slab of slab-sphere (0.2 x 0.2 x 0.02 m, glass-like brittle, on four frictionless edge supports)
// struck at its centre by a ball: a simply supported plate under a central load bends, its lower face
// is in biaxial tension, and it breaks along radial cracks that start under the load and run out
// through the thickness (for a square plate along the diagonals, the yield-line pattern), into pie
// pieces. The run of the shipped scene (30 ms, about 50 CPU s) must give:
//  - at least 3 counted fragments, each at least 5 % of the slab (a sector of 18 degrees; the sliver
//    rule only drops pieces under one MPM cell, 0.04 %), volumes and masses summing to the slab's;
//  - radial crack faces. Measure: for each crack triangle (the crack surface clipped to the slab) at
//    least 2 h_v from the impact axis, the plane fitted (least squares, area-weighted centroids) to the
//    crack within 1.5 h_v of it; its normal n against the hoop direction t = e_z x r / |r|. A radial
//    crack contains e_z and r, so |n . t| = 1; a ring or cone crack has |n . t| ~ 0, and so has a
//    horizontal (delamination) crack. The fit is needed because Voronoi faces of grid sites are nearly
//    axis-aligned: a diagonal crack is a staircase whose single faces are 45 degrees off either way.
//    At least 70 % of that crack area must have |n . t| >= cos 30 degrees (vertical planes of uniformly
//    random azimuth would give 1/6; the scene on sticky supports measured 0.08; on slip supports 0.88).
TEST(BrittleCli, SlabSphereBreaksIntoRadialPieces) {
  const fs::path d = scratch("slab_radial");
  const Json s = run_scene("slab-sphere", d);
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& slab = s["brittle"][0];
  check_event(slab, d, 2500);
  const double input = slab["input_volume"];
  size_t large = 0;
  for (const Json& f : slab["fragments"]) {
    if (f["sliver"].get<bool>()) continue;
    EXPECT_GE(f["volume"].get<double>(), 0.05 * input) << f["name"];
    large += f["volume"].get<double>() >= 0.05 * input ? 1 : 0;
  }
  std::printf("MEASURE slab-sphere: %zu fragments (%zu of at least 5 %%), damaged %.4f, stop %s\n",
              slab["fragment_count"].get<size_t>(), large, slab["damaged_fraction"].get<double>(),
              slab["stop_reason"].get<std::string>().c_str());
  EXPECT_GE(large, 3u);

  const double h_v = 0.00667;  // the scene's crack grid spacing (its MPM grid_spacing)
  const std::vector<CrackTriangle> tris = crack_triangles(d / slab["files"]["crack"].get<std::string>());
  const double fit = 1.5 * h_v;
  double considered = 0, radial = 0;
  for (const CrackTriangle& t : tris) {
    const Eigen::Vector3d r(t.centroid.x(), t.centroid.y(), 0.0);
    if (r.norm() < 2 * h_v) continue;
    double w = 0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    for (const CrackTriangle& u : tris) {
      if ((u.centroid - t.centroid).squaredNorm() > fit * fit) continue;
      w += u.area;
      mean += u.area * u.centroid;
      second += u.area * u.centroid * u.centroid.transpose();
    }
    mean /= w;
    const Eigen::Matrix3d cov = second / w - mean * mean.transpose();
    const Eigen::Vector3d n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
    const Eigen::Vector3d hoop = Eigen::Vector3d::UnitZ().cross(r).normalized();
    considered += t.area;
    if (std::abs(n.dot(hoop)) >= std::cos(M_PI / 6)) radial += t.area;
  }
  std::printf("MEASURE slab-sphere crack: %.5f m^2 beyond 2 h_v of the axis, radial fraction %.3f\n", considered,
              considered > 0 ? radial / considered : 0.0);
  ASSERT_GT(considered, 0.0);
  EXPECT_GE(radial / considered, 0.7);
  fs::remove_all(d);
}

// spot-impact for its first 1 ms (the impact starts at t = 0): the scanned mesh is sampled, broken and cut with the volumes and masses conserved.
TEST(BrittleCli, SpotImpactShortRunWritesAConservingEvent) {
  const fs::path d = scratch("spot");
  const Result r = shellfrac("run " + shortened_scene("spot-impact", 0.001, d).string() + " --out " + (d / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(d / "out" / "summary.json");
  const Json s = Json::parse(in);
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& spot = s["brittle"][0];
  check_event(spot, d / "out", 1800);
  EXPECT_EQ(spot["stop_reason"], "max_time");
  fs::remove_all(d);
}

// spot-impact, the scanned cow struck on its flank by a 70 g steel ball at 86 m/s (impulse 12 N s, Hertz
// contact time), with the crack following the damage time, in a copy cut to 8 ms (the shipped scene runs
// to 15 ms in about 20 s; the pieces are the same at 8, 10 and 15 ms: 50.9 / 32.4 / 14.7 / 2.0-2.1 %).
// It must come apart in a substantial break: at least 2 pieces of at least 5 % of its volume each, the
// largest at most 90 %, one of them at the head end (centroid z < -0.02 m; the mesh spans z -0.134..0.21
// m, the head at -z) and one at the hind end (centroid z > 0.05 m), volumes and masses summing to the
// input's to 1e-9, no sliver. Measured at 8 ms: 4 pieces 50.9 / 32.4 / 14.7 / 2.0 % (hind body, head
// and neck with centroid z -0.051 m, chest and front legs, a chip), 49.9 % of the particles broken;
// before (impulse 6 N s from a 5 m/s ball, stop at 30 % broken, no breakage order): 1 piece. "At least
// 3 pieces of >= 10 %" is a regression check below the measured 3.
TEST(BrittleCli, SpotImpactKnocksTheHeadOff) {
  const fs::path d = scratch("spot-break");
  const Result r = shellfrac("run " + shortened_scene("spot-impact", 0.008, d).string() + " --out " + (d / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(d / "out" / "summary.json");
  const Json s = Json::parse(in);
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& spot = s["brittle"][0];
  check_event(spot, d / "out", 1800);
  const std::vector<double> shares = volume_shares(spot);
  EXPECT_GE(pieces_of_at_least(shares, 0.05), 2u);
  EXPECT_GE(pieces_of_at_least(shares, 0.10), 3u);  // regression check
  ASSERT_FALSE(shares.empty());
  EXPECT_LE(shares.front(), 0.9);
  bool head = false, hind = false;
  for (const Json& f : spot["fragments"]) {
    if (f["volume"].get<double>() < 0.05 * spot["input_volume"].get<double>()) continue;
    head = head || f["centroid"][2].get<double>() < -0.02;
    hind = hind || f["centroid"][2].get<double>() > 0.05;
  }
  EXPECT_TRUE(head);
  EXPECT_TRUE(hind);
  EXPECT_EQ(spot["slivers"]["count"].get<size_t>(), 0u);
  fs::remove_all(d);
}

// The ball drop below: 14,022 particles at 8 m/s onto the ground, stopped at 95 % damaged; `fracture_extra`
// is appended to its "fracture" object. Runs `shellfrac run` in d and returns summary.json.
Json run_ball_drop(const fs::path& d, const std::string& fracture_extra) {
  std::ofstream(d / "ball.json") << R"({"name": "ball-drop", "time": {"end": 0.02, "frame_rate": 1000},
    "gravity": [0, 0, -9.81],
    "solids": [{"name": "ball", "shape": "sphere", "center": [0, 0, 0.0605], "radius": 0.06,
      "spacing": 0.004, "sampling": "jittered", "seed": 4, "initial_velocity": [0, 0, -8.0],
      "material": {"E": 2e7, "nu": 0.22, "density": 2400, "failure_stress": 1e5, "fracture_energy": 15},
      "strength": {"weibull": {"modulus": 6, "scale_is_mean": true, "seed": 21}},
      "fracture": {"grid_spacing": 0.008, "two_fields": true, "crack_interval": 20,
                   "stop": {"max_time": 0.02, "damaged_fraction": 0.95}, "cutter": "exact")" + fracture_extra + R"(}}],
    "colliders": [{"name": "ground", "shape": "half_space", "point": [0, 0, 0], "normal": [0, 0, 1],
                   "boundary": "friction", "friction": 0.5}]})";
  const Result r = shellfrac("run " + (d / "ball.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(d / "out" / "summary.json");
  return in ? Json::parse(in) : Json::object();
}

// A denser ball drop (14,022 particles, 8 m/s onto the ground, weak Weibull material,
// stopped at 95 % damaged particles after about 2.4 ms): its crushed contact zone reaches most of the
// surface, which once let the Voronoi container miss part of the ball, and the exact cutter lost 10 %
// of the volume (15 % at 6 m/s). Conservation: the fragment volumes sum to the ball's to 1e-9 relative
// (check_event), whatever the number of pieces.
TEST(BrittleCli, DenserBallDropKeepsItsVolumeInTheExactCutter) {
  const fs::path d = scratch("ball");
  const Json s = run_ball_drop(d, "");
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& ball = s["brittle"][0];
  EXPECT_EQ(ball["stop_reason"], "damaged_fraction");
  EXPECT_GE(ball["damaged_fraction"].get<double>(), 0.95);
  check_event(ball, d / "out", 2400);
  fs::remove_all(d);
}

// The same ball with the crack following the damage time: the medial surface of a 95 % broken ball is
// empty (one piece, above), the valleys of the damage time cut it into pieces. At least 4 counted pieces,
// each at least 1 % of the ball, no sliver, volumes and masses summing to the input's to 1e-9. Measured:
// 6 pieces, 78.1 / 7.6 / 6.6 / 3.3 / 3.0 / 1.45 %.
TEST(BrittleCli, PulverisedBallBreaksAlongItsDamageTime) {
  const fs::path d = scratch("ball-order");
  const Json s = run_ball_drop(d, R"(, "breakage_order": {"dynamics": 0.1, "min_share": 0.01})");
  ASSERT_EQ(s["brittle"].size(), 1u);
  const Json& ball = s["brittle"][0];
  EXPECT_GE(ball["damaged_fraction"].get<double>(), 0.95);
  check_event(ball, d / "out", 2400);
  EXPECT_GE(ball["fragment_count"].get<size_t>(), 4u);
  EXPECT_EQ(ball["slivers"]["count"].get<size_t>(), 0u);
  for (const Json& f : ball["fragments"])
    EXPECT_GE(f["volume"].get<double>(), 0.01 * ball["input_volume"].get<double>()) << f["name"];
  fs::remove_all(d);
}

// Bad brittle input: exit code 2, the file and JSON path in the message, nothing run.
struct BadCase {
  std::string name, solid_extra, fragment, expected_path;
};

std::string brittle_scene(const std::string& solid_fields, const std::string& fracture = R"("stop": {"max_steps": 5})") {
  return R"({"gravity": [0, 0, 0], "solids": [{"name": "block", "spacing": 0.01,
    "material": {"E": 1e7, "nu": 0.2, "density": 1000, "failure_stress": 1e5, "fracture_energy": 100},
    "fracture": {)" + fracture + "}, " + solid_fields + "}]}";
}

TEST(BrittleCli, BadBrittleInputIsRefusedWithItsPath) {
  const fs::path d = scratch("bad");
  const std::string box = R"("shape": "box", "center": [0, 0, 0], "half_extents": [0.05, 0.05, 0.05])";
  const std::string impact = R"(, "impacts": [{"point": )";
  const std::vector<BadCase> cases = {
      {"outside", box + impact + R"([0.4, 0, 0], "direction": [-1, 0, 0], "impulse": 1, "duration": 1e-4}])",
       "impacts must touch the object", "/solids/0/impacts/0"},
      {"impulse", box + impact + R"([0.05, 0, 0], "direction": [-1, 0, 0], "impulse": 0, "duration": 1e-4}])", "> 0",
       "/solids/0/impacts/0/impulse"},
      {"duration", box + impact + R"([0.05, 0, 0], "direction": [-1, 0, 0], "impulse": 1, "duration": -1}])", "> 0",
       "/solids/0/impacts/0/duration"},
      {"outward", box + impact + R"([0.05, 0, 0], "direction": [1, 0, 0], "impulse": 1, "duration": 1e-4}])", "out of",
       "/solids/0/impacts/0"},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    std::ofstream(d / (c.name + ".json")) << brittle_scene(c.solid_extra);
    const Result r = shellfrac("validate " + (d / (c.name + ".json")).string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr(c.expected_path));
    EXPECT_THAT(r.output, HasSubstr(c.fragment));
  }
  // A crack grid too fine for memory: refused with the estimate and the smallest spacing that fits.
  std::ofstream(d / "memory.json") << brittle_scene(box, R"("stop": {"max_steps": 5}, "crack_grid_spacing": 1e-5)");
  const Result mem = shellfrac("run " + (d / "memory.json").string() + " --out " + (d / "out").string());
  EXPECT_EQ(mem.exit_code, 2) << mem.output;
  EXPECT_THAT(mem.output, HasSubstr("/solids/0/fracture/crack_grid_spacing"));
  EXPECT_THAT(mem.output, HasSubstr("GB"));
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
  // No stopping criterion.
  std::ofstream(d / "nostop.json") << brittle_scene(box, R"("cfl": 0.3)");
  const Result nostop = shellfrac("validate " + (d / "nostop.json").string());
  EXPECT_EQ(nostop.exit_code, 2);
  EXPECT_THAT(nostop.output, HasSubstr("/solids/0/fracture/stop"));
  // Brittle keys on a solid without "fracture".
  std::ofstream(d / "nofracture.json") << R"({"solids": [{"shape": "torus", "center": [0, 0, 0], "major_radius": 0.1,
    "minor_radius": 0.02, "spacing": 0.01, "material": {"E": 1e7, "nu": 0.2, "density": 1000}}]})";
  const Result nf = shellfrac("validate " + (d / "nofracture.json").string());
  EXPECT_EQ(nf.exit_code, 2);
  EXPECT_THAT(nf.output, HasSubstr("/solids/0/shape"));
  fs::remove_all(d);
}

// Meshes that cannot be broken: open (the boundary-edge count is named), NaN, zero volume.
TEST(BrittleCli, UnusableMeshesAreRefusedWithTheFileAndCounts) {
  const fs::path d = scratch("mesh");
  // A unit tetrahedron without one face: 3 boundary edges.
  std::ofstream(d / "open.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n";
  std::ofstream(d / "nan.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 nan 0\nv 0 0 0.1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  std::ofstream(d / "flat.obj") << "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0.1 0.1 0\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  for (const std::string name : {"open", "nan", "flat"}) {
    SCOPED_TRACE(name);
    std::ofstream(d / (name + ".json")) << brittle_scene(R"("shape": "mesh", "file": ")" + name + R"(.obj")");
    const Result r = shellfrac("validate " + (d / (name + ".json")).string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr("/solids/0/file"));
    EXPECT_THAT(r.output, HasSubstr(name + ".obj"));
    if (name == "open") {
      EXPECT_THAT(r.output, HasSubstr("3 boundary edge"));
    }
  }
  fs::remove_all(d);
}

}  // namespace

namespace {

// Volume of one OBJ object by the divergence theorem over its fan triangles.
double object_volume(const ObjFile& file, const ObjObject& o) {
  double v = 0;
  for (const std::vector<size_t>& f : o.faces)
    for (size_t k = 1; k + 1 < f.size(); ++k) {
      const auto& a = file.points[f[0]];
      const auto& b = file.points[f[k]];
      const auto& c = file.points[f[k + 1]];
      v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
  return v;
}

// The shipped shatter scene: four shapes dropped spinning onto the ground, carried by Bullet, broken by
// fracture events on impact (docs/brittle.md, "The shatter loop"). Checked from the files alone: one
// mesh per frame with one object per piece, the piece count at the end equal to 4 plus the fragments the
// broken events added, and the total volume of the last frame equal to the first frame's (1e-6: the
// file's single-precision coordinates). From summary.json: every broken event keeps mass, momentum and
// angular momentum to 1e-10 and never adds kinetic energy. Regression check at today's result: at least
// two events broke a body (measured: the torus in 2, the box in 2 along its damage time).
TEST(ShatterCli, ShatterDropBreaksBodiesAndKeepsTheirVolume) {
  const fs::path out = scratch("shatter-drop");
  const Json s = run_scene("shatter-drop", out);
  ASSERT_TRUE(s.contains("shatter")) << s.dump(1);
  const Json& sh = s["shatter"];
  size_t broken = 0, added = 0;
  for (const Json& e : sh["events"]) {
    if (e["outcome"] != "broken") continue;
    ++broken;
    added += e["fragments"].get<size_t>() - 1;
    EXPECT_LE(e["conservation"]["mass"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["momentum"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["angular_momentum"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["kinetic_energy_ratio"].get<double>(), 1 + 1e-12);
    EXPECT_GT(e["contact_time"].get<double>(), 0);
  }
  EXPECT_GE(broken, 2u) << "regression check";
  ASSERT_EQ(sh["frames"].size(), 31u);
  const ObjFile first = read_obj(out / sh["frames"][0].get<std::string>());
  const ObjFile last = read_obj(out / sh["frames"][30].get<std::string>());
  EXPECT_EQ(first.objects.size(), 4u);
  EXPECT_EQ(last.objects.size(), 4 + added);
  EXPECT_EQ(sh["pieces"].get<size_t>(), 4 + added);
  double v0 = 0, v1 = 0;
  for (const ObjObject& o : first.objects) v0 += object_volume(first, o);
  for (const ObjObject& o : last.objects) {
    const double v = object_volume(last, o);
    EXPECT_GT(v, 0) << o.name;
    v1 += v;
  }
  EXPECT_NEAR(v1, v0, 1e-6 * v0);
  // The glTF animation read back through assimp: one node per piece that ever existed, one animation
  // channel per node with a key per frame, and the last key of every piece still whole at the centre of
  // mass of its object in the last frame's OBJ (1e-5 m: both files hold single-precision numbers).
  ASSERT_EQ(sh["animation"], "rigid/shatter.gltf");
  Assimp::Importer importer;
  const aiScene* gltf = importer.ReadFile((out / "rigid" / "shatter.gltf").string(), 0);
  ASSERT_NE(gltf, nullptr) << importer.GetErrorString();
  const size_t ever = 4 + broken + added;  // originals, then every broken body's fragments
  EXPECT_EQ(gltf->mRootNode->mNumChildren, ever);
  ASSERT_EQ(gltf->mNumAnimations, 1u);
  EXPECT_EQ(gltf->mAnimations[0]->mNumChannels, ever);
  std::map<std::string, std::array<double, 3>> last_key;
  for (unsigned c = 0; c < gltf->mAnimations[0]->mNumChannels; ++c) {
    const aiNodeAnim* ch = gltf->mAnimations[0]->mChannels[c];
    EXPECT_EQ(ch->mNumPositionKeys, 31u) << ch->mNodeName.C_Str();
    EXPECT_EQ(ch->mNumRotationKeys, 31u);
    const aiVector3D& p = ch->mPositionKeys[ch->mNumPositionKeys - 1].mValue;
    last_key[ch->mNodeName.C_Str()] = {p.x, p.y, p.z};
  }
  for (const ObjObject& o : last.objects) {
    // centre of mass of the closed surface: sum over fan tetrahedra from the origin
    double vol = 0, c[3] = {0, 0, 0};
    for (const auto& f : o.faces)
      for (size_t k = 1; k + 1 < f.size(); ++k) {
        const auto &a = last.points[f[0]], &b = last.points[f[k]], &q = last.points[f[k + 1]];
        const double v = (a[0] * (b[1] * q[2] - b[2] * q[1]) - a[1] * (b[0] * q[2] - b[2] * q[0]) + a[2] * (b[0] * q[1] - b[1] * q[0])) / 6;
        vol += v;
        for (int d = 0; d < 3; ++d) c[d] += v * (a[d] + b[d] + q[d]) / 4;
      }
    ASSERT_TRUE(last_key.count(o.name)) << o.name;
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(last_key[o.name][d], c[d] / vol, 1e-5) << o.name;
  }
  // every piece rests on the ground (z = 0) at the end: its lowest point within 2 mm of it
  for (const ObjObject& o : last.objects) {
    double lowest = 1e9;
    for (const auto& f : o.faces)
      for (size_t p : f) lowest = std::min(lowest, last.points[p][2]);
    EXPECT_NEAR(lowest, 0.0, 2e-3) << o.name;
  }
  fs::remove_all(out);
}

// Two bodies thrown at each other (scenes/brittle/thrown-pair.json, thesis Fig. 3.30): a box and a torus
// at 5 m/s each meet in mid-air. Their first events are their collision with each other, at the same
// time, high above the ground (z > 0.5 m), and both break, keeping mass, momentum and angular momentum
// to 1e-10 without adding kinetic energy. Every later event either breaks a body the same way, finds it
// whole, or fails numerically: then its message is kept and the body flies on unbroken (it is still in
// the last frame). The pieces in the last frame are the two bodies plus what broken events added, and
// they hold the first frame's volume (1e-6, single-precision files).
TEST(ShatterCli, ThrownPairBreaksInMidAir) {
  const fs::path out = scratch("thrown-pair");
  const Json s = run_scene("thrown-pair", out);
  ASSERT_TRUE(s.contains("shatter")) << s.dump(1);
  const Json& ev = s["shatter"]["events"];
  ASSERT_GE(ev.size(), 2u);
  std::set<std::string> first{ev[0]["body"].get<std::string>(), ev[1]["body"].get<std::string>()};
  EXPECT_EQ(first, (std::set<std::string>{"box", "torus"}));
  EXPECT_EQ(ev[0]["time"].get<double>(), ev[1]["time"].get<double>());
  size_t added = 0;
  std::set<std::string> failed;
  for (size_t i = 0; i < ev.size(); ++i) {
    const Json& e = ev[i];
    if (i < 2) {
      EXPECT_EQ(e["outcome"], "broken") << e["body"];
      EXPECT_GT(e["point"][2].get<double>(), 0.5);
      EXPECT_GE(e["fragments"].get<size_t>(), 2u);
    }
    if (e["outcome"] == "failed") {
      EXPECT_FALSE(e["message"].get<std::string>().empty());
      failed.insert(e["body"].get<std::string>());
      continue;
    }
    if (e["outcome"] != "broken") continue;
    added += e["fragments"].get<size_t>() - 1;
    EXPECT_LE(e["conservation"]["mass"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["momentum"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["angular_momentum"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["kinetic_energy_ratio"].get<double>(), 1 + 1e-12);
  }
  const Json& frames = s["shatter"]["frames"];
  const ObjFile first_frame = read_obj(out / frames[0].get<std::string>());
  const ObjFile last = read_obj(out / frames[frames.size() - 1].get<std::string>());
  EXPECT_EQ(first_frame.objects.size(), 2u);
  EXPECT_EQ(last.objects.size(), 2 + added);
  std::set<std::string> names;
  for (const ObjObject& o : last.objects) names.insert(o.name);
  for (const std::string& body : failed) {
    // a body whose event failed was not replaced: it (or a later fragment of it) is still flying
    const bool present = std::any_of(names.begin(), names.end(), [&](const std::string& n) { return n.rfind(body, 0) == 0; });
    EXPECT_TRUE(present) << body;
  }
  double v0 = 0, v1 = 0;
  for (const ObjObject& o : first_frame.objects) v0 += object_volume(first_frame, o);
  for (const ObjObject& o : last.objects) v1 += object_volume(last, o);
  EXPECT_NEAR(v1, v0, 1e-6 * v0);
  fs::remove_all(out);
}

// The shipped statue shot (docs/brittle.md, "The statue on a column"): the ball breaks the scanned statue
// on its column, the event keeps mass, momentum and angular momentum (1e-10) and adds no kinetic energy,
// and the column stands in every frame. Regression check: the head comes off (2 pieces from the statue,
// measured 2).
TEST(ShatterCli, StatueStrikeBreaksTheStatueOnItsColumn) {
  const fs::path out = scratch("statue-strike");
  const Json s = run_scene("statue-strike", out);
  ASSERT_TRUE(s.contains("shatter")) << s.dump(1);
  const Json& sh = s["shatter"];
  size_t broken = 0;
  for (const Json& e : sh["events"]) {
    if (e["outcome"] != "broken") continue;
    ++broken;
    EXPECT_GE(e["fragments"].get<size_t>(), 2u) << "regression check";
    EXPECT_LE(e["conservation"]["mass"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["momentum"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["angular_momentum"].get<double>(), 1e-10);
    EXPECT_LE(e["conservation"]["kinetic_energy_ratio"].get<double>(), 1 + 1e-12);
  }
  EXPECT_GE(broken, 1u) << "regression check";
  ASSERT_FALSE(sh["frames"].empty());
  for (const Json& frame : sh["frames"]) {
    const ObjFile f = read_obj(out / frame.get<std::string>());
    bool column = false;
    for (const ObjObject& o : f.objects) column = column || o.name == "column";
    EXPECT_TRUE(column) << frame;
  }
}

// Static props from the scene stand in every frame and carry bodies: a box dropped onto an open mesh (a
// single quad, a table top read from an OBJ file) comes to rest on it, 0.3 m above the ground, and a box
// prop (a column) stands beside it. Each frame and the glTF hold both props where the scene put them.
TEST(ShatterCli, PropsStandInEveryFrameAndCarryBodies) {
  const fs::path out = scratch("props");
  fs::create_directories(out);
  {
    std::ofstream obj(out / "table.obj");  // 0.6 x 0.6 m at z = 0, facing +z; placed 0.3 m up by translate
    obj << "v -0.3 -0.3 0\nv 0.3 -0.3 0\nv 0.3 0.3 0\nv -0.3 0.3 0\nf 1 2 3 4\n";
  }
  const Json scene = Json::parse(R"({
    "name": "props", "time": {"end": 0.6, "frame_rate": 10}, "gravity": [0, 0, -9.81],
    "rigid": {"dt": 0.001,
      "props": [{"name": "table", "shape": "mesh", "file": "table.obj", "translate": [0, 0, 0.3]},
                {"name": "column", "center": [0.6, 0, 0.25], "half_extents": [0.05, 0.05, 0.25]}]},
    "solids": [{"name": "block", "shape": "box", "center": [0, 0, 0.45], "half_extents": [0.05, 0.05, 0.05],
      "spacing": 0.02, "sampling": "regular",
      "material": {"E": 1e9, "nu": 0.25, "density": 1000, "failure_stress": 3e5, "fracture_energy": 10},
      "fracture": {"grid_spacing": 0.02}, "rigid_body": {"impulse_threshold": 1e6}}]})");
  {
    std::ofstream f(out / "props.json");
    f << scene.dump(1);
  }
  const Result r = shellfrac("run " + (out / "props.json").string() + " --out " + (out / "run").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out / "run" / "summary.json");
  const Json sh = Json::parse(in)["shatter"];
  ASSERT_EQ(sh["frames"].size(), 7u);
  for (const Json& frame : sh["frames"]) {
    const ObjFile f = read_obj(out / "run" / frame.get<std::string>());
    std::map<std::string, const ObjObject*> by_name;
    for (const ObjObject& o : f.objects) by_name[o.name] = &o;
    ASSERT_EQ(f.objects.size(), 3u) << frame;
    ASSERT_TRUE(by_name.count("table") && by_name.count("column") && by_name.count("block")) << frame;
    // The table's corners where the file and translate put them, the column's box to its half extents.
    for (const auto& face : by_name["table"]->faces)
      for (size_t p : face) {
        EXPECT_NEAR(std::abs(f.points[p][0]), 0.3, 1e-6);
        EXPECT_NEAR(std::abs(f.points[p][1]), 0.3, 1e-6);
        EXPECT_NEAR(f.points[p][2], 0.3, 1e-6);
      }
    double top = -1;
    for (const auto& face : by_name["column"]->faces)
      for (size_t p : face) top = std::max(top, f.points[p][2]);
    EXPECT_NEAR(top, 0.5, 1e-6);
  }
  // The block at rest on the table: its lowest point at the table's height (Bullet's margin: 2 mm).
  const ObjFile last = read_obj(out / "run" / sh["frames"][6].get<std::string>());
  double lowest = 1e9;
  for (const ObjObject& o : last.objects)
    if (o.name == "block")
      for (const auto& face : o.faces)
        for (size_t p : face) lowest = std::min(lowest, last.points[p][2]);
  EXPECT_NEAR(lowest, 0.3, 2e-3);
  // The glTF: a node and a channel with a key per frame for the block and each prop.
  Assimp::Importer importer;
  const aiScene* gltf = importer.ReadFile((out / "run" / "rigid" / "shatter.gltf").string(), 0);
  ASSERT_NE(gltf, nullptr) << importer.GetErrorString();
  EXPECT_EQ(gltf->mRootNode->mNumChildren, 3u);
  ASSERT_EQ(gltf->mNumAnimations, 1u);
  EXPECT_EQ(gltf->mAnimations[0]->mNumChannels, 3u);
}

TEST(ShatterCli, BadRigidInputIsRefusedWithItsPath) {
  const fs::path d = scratch("shatter-bad");
  const std::string box = R"("shape": "box", "center": [0, 0, 0.1], "half_extents": [0.05, 0.05, 0.05])";
  struct Case {
    std::string name, scene, path, fragment;
  };
  const std::string body = R"(, "rigid_body": {"impulse_threshold": 1})";
  const std::vector<Case> cases = {
      {"threshold", brittle_scene(box + R"(, "rigid_body": {"impulse_threshold": 0})"), "/solids/0/rigid_body/impulse_threshold", "> 0"},
      {"no_fracture", R"({"solids": [{"shape": "sphere", "center": [0, 0, 1], "radius": 0.1, "spacing": 0.02,
          "material": {"E": 1e7, "nu": 0.2, "density": 1000}, "rigid_body": {"impulse_threshold": 1}}]})",
       "/solids/0/rigid_body", "needs a \"fracture\""},
      {"impacts", brittle_scene(box + body + R"(, "impacts": [{"point": [0.05, 0, 0.1], "direction": [-1, 0, 0], "impulse": 1, "duration": 1e-4}])"),
       "/solids/0/rigid_body", "remove \"impacts\""},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::ofstream(d / (c.name + ".json")) << c.scene;
    const Result r = shellfrac("validate " + (d / (c.name + ".json")).string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr(c.path));
    EXPECT_THAT(r.output, HasSubstr(c.fragment));
  }
  // Whole-scene keys: the volume ratios out of order, colliders beside rigid bodies.
  Json ratios = Json::parse(brittle_scene(box + body));
  ratios["rigid"] = {{"volume_ratios", {0.3, 0.2, 0.98}}};
  std::ofstream(d / "ratios.json") << ratios.dump();
  const Result rr = shellfrac("validate " + (d / "ratios.json").string());
  EXPECT_EQ(rr.exit_code, 2) << rr.output;
  EXPECT_THAT(rr.output, HasSubstr("/rigid/volume_ratios"));
  Json colliders = Json::parse(brittle_scene(box + body));
  colliders["colliders"] = Json::array({{{"shape", "half_space"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}}});
  std::ofstream(d / "colliders.json") << colliders.dump();
  const Result rc = shellfrac("validate " + (d / "colliders.json").string());
  EXPECT_EQ(rc.exit_code, 2) << rc.output;
  EXPECT_THAT(rc.output, HasSubstr("/rigid"));
  // A mesh prop whose file is missing, and one that also gives a box's half extents.
  Json missing = Json::parse(brittle_scene(box + body));
  missing["rigid"] = {{"props", Json::array({{{"shape", "mesh"}, {"file", "no-such-table.obj"}}})}};
  std::ofstream(d / "missing.json") << missing.dump();
  const Result rm = shellfrac("validate " + (d / "missing.json").string());
  EXPECT_EQ(rm.exit_code, 2) << rm.output;
  EXPECT_THAT(rm.output, HasSubstr("/rigid/props/0/file"));
  EXPECT_THAT(rm.output, HasSubstr("no-such-table.obj"));
  Json both = missing;
  both["rigid"]["props"][0]["half_extents"] = {0.1, 0.1, 0.1};
  std::ofstream(d / "both.json") << both.dump();
  const Result rb = shellfrac("validate " + (d / "both.json").string());
  EXPECT_EQ(rb.exit_code, 2) << rb.output;
  EXPECT_THAT(rb.output, HasSubstr("/rigid/props/0/half_extents"));
  fs::remove_all(d);
}

}  // namespace
