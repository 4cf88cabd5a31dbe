// The shatter loop through the product (docs/brittle.md, "The shatter loop"): the shipped shatter scenes
// run by `shellfrac run`, their frames, glTF and summary checked from the files; props from the scene;
// bad rigid-body input refused with exit code 2 and the JSON path.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
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
