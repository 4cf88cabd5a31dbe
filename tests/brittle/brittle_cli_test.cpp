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

#include "tests/brittle/brittle_cli_support.hpp"

namespace {

using ::testing::HasSubstr;
using namespace shellfrac::test::brittle_cli;
using shellfrac::test::Result;
using shellfrac::test::brittle_cli::shellfrac;  // the function, ahead of the namespace of that name

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
  EXPECT_EQ(count, 10);
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
