// End to end: hostile scenes refused with exit 2 and the JSON path before anything is
// allocated, output folders cleaned, SIGINT, SIGTERM and SIGHUP stopping a run with an "interrupted"
// summary, and a full disk (a 200 KiB tmpfs, or RLIMIT_FSIZE where no mount is allowed) stopping a run
// with exit 1 and no partial file under a final name.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "tests/cli/cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using shellfrac::test::Result;

Result shellfrac(const std::string& args) { return shellfrac::test::run_shellfrac(args); }

fs::path scratch(const std::string& name) { return shellfrac::test::scratch_folder("robust", name); }

// A small cloth; `time` and `extra` top-level fields and `shell` fields are spliced in.
std::string cloth(const std::string& time = R"({"end": 0.1, "frame_rate": 30})", const std::string& extra = "",
                  const std::string& shell = "") {
  return R"({"time": )" + time + R"(, "output": {"resolution": [8, 8]}, )" + extra +
         R"("shells": [{"name": "cloth", )" + shell + R"("patch": {"type": "flat", "size": [1, 1], "cells": [8, 8]},
      "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}}]})";
}

// The cloth over 1 s with its material object replaced by `material`.
std::string cloth_with_material(const std::string& material) {
  const std::string plain = R"({"E": 1e5, "nu": 0.3, "density": 300})";
  std::string text = cloth(R"({"end": 1})");
  return text.replace(text.find(plain), plain.size(), material);
}

Result validate_text(const fs::path& d, const std::string& text, const std::string& flags = "") {
  std::ofstream(d / "s.json") << text;
  return shellfrac("validate " + (d / "s.json").string() + " " + flags);
}

Result run_text(const fs::path& d, const std::string& text, const std::string& flags = "") {
  std::ofstream(d / "s.json") << text;
  return shellfrac("run " + (d / "s.json").string() + " --threads 1 --out " + (d / "out").string() + " " + flags);
}

TEST(CliRobust, ScenesThatCannotBeReadAreExitTwoWithPath) {
  const fs::path d = scratch("input");
  const Result zero = shellfrac("validate /dev/zero");
  EXPECT_EQ(zero.exit_code, 2) << zero.output;
  EXPECT_THAT(zero.output, HasSubstr("/dev/zero: the scene file is larger than the limit of 64 MiB"));
  const Result overflow = validate_text(d, cloth(R"({"end": 1e999})"));
  EXPECT_EQ(overflow.exit_code, 2) << overflow.output;
  EXPECT_THAT(overflow.output, HasSubstr("s.json: /time/end: number 1e999 is too large for a double"));
  EXPECT_THAT(overflow.output, HasSubstr("(line 1, column 18)"));
  const Result duplicate = validate_text(d, cloth().replace(cloth().find("\"nu\": 0.3"), 9, "\"nu\": 0.7, \"nu\": 0.3"));
  EXPECT_EQ(duplicate.exit_code, 2) << duplicate.output;
  EXPECT_THAT(duplicate.output, HasSubstr("/shells/0/material/nu: duplicate key \"nu\""));
  const Result injected = validate_text(d, cloth().replace(cloth().find("\"cloth\""), 7, R"("sheet\nv 9 9 9\nf 1 2 999999")"));
  EXPECT_EQ(injected.exit_code, 2) << injected.output;
  EXPECT_THAT(injected.output, HasSubstr("/shells/0/name: contains the control character 0x0a"));
  const Result dx = validate_text(d, cloth(R"({"end": 0.1})", R"("grid": {"dx": 1e-9}, )"));
  EXPECT_EQ(dx.exit_code, 2) << dx.output;
  EXPECT_THAT(dx.output, HasSubstr("/grid/dx: grid spacing 1e-09 m cannot hold the scene"));
  const Result empty_out = shellfrac("run --out \"\"");
  EXPECT_EQ(empty_out.exit_code, 2) << empty_out.output;
  EXPECT_THAT(empty_out.output, HasSubstr("--out: the output folder must not be empty"));
  EXPECT_EQ(shellfrac("validate " + (d / "s.json").string() + " --max-memory lots").exit_code, 2);
  fs::remove_all(d);
}

// The other hostile scenes, each through `run`: exit code 2 and a message with the JSON pointer of
// the value to change, before anything is written. (The library tests check the same refusals in more
// detail: tests/scene/estimate_test.cpp, strict_input_test.cpp.)
TEST(CliRobust, HostileScenesExitTwoWithTheirPath) {
  const fs::path d = scratch("hostile");
  const std::string material = R"({"E": 1e5, "nu": 0.3, "density": 300})";
  std::string knots = "[0", net;
  for (int i = 0; i < 10; ++i) knots += ", 0";
  for (int i = 0; i < 11; ++i) knots += ", 1";
  knots += "]";
  for (int j = 0; j <= 10; ++j)
    for (int i = 0; i <= 10; ++i) net += std::string(net.empty() ? "" : ", ") + "[" + std::to_string(i) + ", " + std::to_string(j) + ", 0]";
  std::ofstream(d / "nan.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  std::ofstream(d / "triangle.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(d / "tet.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  auto mesh_solid = [&](const std::string& file, const std::string& extra) {
    return R"({"time": {"end": 0.1}, "solids": [{"shape": "mesh", "file": ")" + (d / file).string() + R"(", )" + extra +
           R"("spacing": 0.05, "material": )" + material + "}]}";
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {cloth(R"({"end": 1, "cfl": 1e-300})"), "/time/cfl: the run would take about"},
      {cloth_with_material(R"({"E": 1e300, "nu": 0.3, "density": 300})"), "/shells/0/material/E: the run would take about"},
      {cloth_with_material(R"({"E": 1e5, "nu": 0.3, "density": 1e-300})"), "/shells/0/material/density: the run would take about"},
      {cloth(R"({"end": 1})", "", R"("initial_velocity": [0, 1e30, 0], )"), "/shells/0/initial_velocity: the run would take about"},
      {cloth(R"({"end": 1e300})"), "/time/end: the run would write 2.4e+301 frames, more than any run can"},
      {R"({"time": {"end": 0.1}, "shells": [{"patch": {"type": "control_net", "degree": [10, 10], "knots_u": )" + knots +
           R"(, "knots_v": )" + knots + R"(, "control_points": [)" + net + R"(]}, "thickness": 0.001, "material": )" + material + "}]}",
       "/shells/0/patch/degree/0: value 10 is out of range: must be in [1, 7]"},
      {cloth().replace(cloth().find(R"("shells": [)"), 11, R"("shells": [{"name": "cloth", "patch": {"type": "flat", "size": [1, 1], "cells": [2, 2]}, "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 300}}, )"),
       "/shells/1/name: shell name \"cloth\" is already used by /shells/0"},
      {mesh_solid("nan.obj", ""), "/solids/0/file: " + (d / "nan.obj").string() + ": mesh has 1 vertices with NaN"},
      {mesh_solid("triangle.obj", ""), "/solids/0/file: " + (d / "triangle.obj").string() + ": mesh is not closed: 3 boundary edge(s)"},
      {mesh_solid("tet.obj", R"("voxel_size": 1e-6, )"), "/solids/0/voxel_size: the scene needs about"},
  };
  for (const auto& [text, message] : cases) {
    const Result r = run_text(d, text, "--max-memory 8G");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_THAT(r.output, HasSubstr("s.json: " + message)) << text;
    EXPECT_FALSE(fs::exists(d / "out")) << text;
  }
  fs::remove_all(d);
}

TEST(CliRobust, ValidatePrintsTheEstimateAndRunRefusesOverBudget) {
  const fs::path d = scratch("budget");
  const Result ok = validate_text(d, cloth());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_THAT(ok.output, HasSubstr("estimate: memory"));
  EXPECT_THAT(ok.output, HasSubstr("shell \"cloth\" quadrature points: 3072"));  // 8 x 8 cells x 4 x 4 x 3
  // A memory bomb: refused by validate and run alike, in no time.
  const std::string bomb = cloth().replace(cloth().find("\"cells\": [8, 8]"), 15, "\"cells\": [10000, 10000]");
  for (const std::string& command : std::vector<std::string>{"validate", "run --out " + (d / "out").string()}) {
    std::ofstream(d / "bomb.json") << bomb;
    const Result r = shellfrac(command + " " + (d / "bomb.json").string() + " --max-memory 8G");
    EXPECT_EQ(r.exit_code, 2) << command << r.output;
    EXPECT_THAT(r.output, HasSubstr("bomb.json: /shells/0/patch/cells: the scene needs about"));
    EXPECT_THAT(r.output, HasSubstr("more than the budget of 8.0 GiB"));
  }
  EXPECT_FALSE(fs::exists(d / "out"));
  // A run of a billion frames: run and validate refuse it without --force; validate --force warns.
  const std::string many = cloth(R"({"end": 1, "frame_rate": 1e9})");
  const Result refused = run_text(d, many);
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("/time/frame_rate: the run would write 1000000001 frames"));
  EXPECT_THAT(refused.output, HasSubstr("--force runs it anyway"));
  const Result warned = validate_text(d, many, "--force");
  EXPECT_EQ(warned.exit_code, 0) << warned.output;
  EXPECT_THAT(warned.output, HasSubstr("warning: /time/frame_rate"));
  const Result steps = run_text(d, cloth(R"({"end": 1, "dt": 1e-300})"));
  EXPECT_EQ(steps.exit_code, 2) << steps.output;
  EXPECT_THAT(steps.output, HasSubstr("/time/dt: the run would take about"));
  fs::remove_all(d);
}

// `validate` once said OK (with a warning) to six scenes `run` then refused. Both now apply the
// same check (scene::check_budget): exit 2 at the same JSON path, saying --force would run it; with
// --force validate accepts them and warns.
TEST(CliRobust, ValidateRefusesWhatRunRefuses) {
  const fs::path d = scratch("agree");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {cloth_with_material(R"({"E": 1e300, "nu": 0.3, "density": 300})"), "/shells/0/material/E"},
      {cloth_with_material(R"({"E": 1e5, "nu": 0.3, "density": 1e-300})"), "/shells/0/material/density"},
      {cloth(R"({"end": 1, "dt": 1e-300})"), "/time/dt"},
      {cloth(R"({"end": 1, "cfl": 1e-300})"), "/time/cfl"},
      {cloth(R"({"end": 1, "frame_rate": 1e9})"), "/time/frame_rate"},
      {cloth(R"({"end": 1})", "", R"("initial_velocity": [0, 1e30, 0], )"), "/shells/0/initial_velocity"},
  };
  for (const auto& [text, path] : cases) {
    SCOPED_TRACE(path);
    const Result run = run_text(d, text);
    const Result validate = validate_text(d, text);
    for (const Result* r : {&run, &validate}) {
      EXPECT_EQ(r->exit_code, 2) << r->output;
      EXPECT_THAT(r->output, HasSubstr("s.json: " + path + ": the run would"));
      EXPECT_THAT(r->output, HasSubstr("--force runs it anyway"));
    }
    const Result forced = validate_text(d, text, "--force");
    EXPECT_EQ(forced.exit_code, 0) << forced.output;
    EXPECT_THAT(forced.output, HasSubstr("warning: " + path));
    EXPECT_FALSE(fs::exists(d / "out"));
  }
  fs::remove_all(d);
}

// Under an address-space cap (`prlimit --as`, as `ulimit -v` or a batch system sets one) the
// memory budget is what is left under the cap. Each scene below fits the machine's RAM but not 4 GiB;
// validate and run refuse it with exit 2 and the value to change, from the estimate alone, instead of
// being killed while sampling particles, building a level set or writing a frame.
TEST(CliRobust, ScenesOverAnAddressSpaceCapAreRefusedNotKilled) {
  if (std::system("prlimit --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "prlimit is not installed";
  const fs::path d = scratch("cap");
  const std::string mesh = std::string(SHELLFRAC_SOURCE_DIR) + "/scenes/meshes/ellipsoid.obj";
  const std::string material = R"("material": {"E": 1e5, "nu": 0.3, "density": 300})";
  // The ellipsoid is 0.6 m long; scaled by 1/3 it is 0.2 m long.
  const std::string small_mesh = R"("file": ")" + mesh + R"(", "scale": 0.3333333, "voxel_size": 3e-5)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      // 1 m^3 at 0.002752 m: 4.8e7 particles, just under the 5e7 cap of the build.
      {R"({"time": {"end": 0.01}, "solids": [{"shape": "box", "center": [0, 0, 0], "half_extents": [0.5, 0.5, 0.5],
          "spacing": 0.002752, )" + material + "}]}",
       "/solids/0/spacing"},
      {R"({"time": {"end": 0.01}, "solids": [{"shape": "mesh", )" + small_mesh + R"(, "spacing": 0.01, )" + material + "}]}",
       "/solids/0/voxel_size"},
      {cloth(R"({"end": 0.1})", R"("colliders": [{"shape": "mesh", )" + small_mesh + "}], "), "/colliders/0/voxel_size"},
      {R"({"time": {"end": 0}, "output": {"resolution": [4096, 4096]}, "shells": [{"name": "cloth",
          "patch": {"type": "flat", "size": [1, 1], "cells": [8, 8]}, "thickness": 0.0005, )" + material + "}]}",
       "/output/resolution"},
  };
  for (const auto& [text, path] : cases) {
    SCOPED_TRACE(path);
    std::ofstream(d / "s.json") << text;
    for (const std::string& command : std::vector<std::string>{"validate", "run --threads 1 --out " + (d / "out").string()}) {
      const Result r = shellfrac::test::run_shellfrac_under("prlimit --as=4294967296", command + " " + (d / "s.json").string());
      EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
      EXPECT_THAT(r.output, HasSubstr("s.json: " + path + ": the scene needs about")) << command;
      EXPECT_THAT(r.output, HasSubstr("RLIMIT_AS")) << command;
    }
    EXPECT_FALSE(fs::exists(d / "out"));
  }
  fs::remove_all(d);
}

std::set<std::string> frame_files(const fs::path& frames) {
  std::set<std::string> out;
  for (const auto& e : fs::directory_iterator(frames)) out.insert(e.path().filename().string());
  return out;
}

TEST(CliRobust, OutputFolderHoldsOnlyThisRunsFrames) {
  const fs::path d = scratch("folder");
  ASSERT_EQ(run_text(d, cloth(R"({"end": 0.1, "frame_rate": 30})")).exit_code, 0);
  EXPECT_EQ(frame_files(d / "out" / "frames").size(), 8u);  // frames 0..3, .obj and .mtl
  // A stale staging folder of a killed run, and a second, shorter run into the same folder.
  fs::create_directories(d / "out" / "frames" / ".staging-12345-1");
  std::ofstream(d / "out" / "frames" / ".staging-12345-1" / "frame_00009.obj") << "v 0 0 0\n";
  const Result second = run_text(d, cloth(R"({"end": 0.05, "frame_rate": 30})"));
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_THAT(second.output, HasSubstr("removed 1 staging folder(s)"));
  EXPECT_THAT(second.output, HasSubstr("removed 8 file(s) of an earlier run"));
  // 0.05 s ends between two frames at 30 frames/s: frames at 0, 1/30 and 0.05 s.
  EXPECT_EQ(frame_files(d / "out" / "frames"),
            (std::set<std::string>{"frame_00000.mtl", "frame_00000.obj", "frame_00001.mtl", "frame_00001.obj",
                                   "frame_00002.mtl", "frame_00002.obj"}));
  std::ifstream in(d / "out" / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(in)["frames"].size(), 3u);
  // --keep-old-frames leaves them.
  std::ofstream(d / "out" / "frames" / "frame_00042.obj") << "v 0 0 0\n";
  ASSERT_EQ(run_text(d, cloth(R"({"end": 0.05, "frame_rate": 30})"), "--keep-old-frames").exit_code, 0);
  EXPECT_TRUE(fs::exists(d / "out" / "frames" / "frame_00042.obj"));
  fs::remove_all(d);
}

// Starts `shellfrac args...` with stdout and stderr to `log`; `limit_file_size` > 0 sets RLIMIT_FSIZE
// (with SIGXFSZ ignored, so a write past it fails with EFBIG like a full disk).
pid_t spawn(const std::vector<std::string>& args, const fs::path& log, long limit_file_size = 0) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  if (limit_file_size > 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{static_cast<rlim_t>(limit_file_size), static_cast<rlim_t>(limit_file_size)};
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  FILE* out = std::fopen(log.c_str(), "w");
  ::dup2(fileno(out), 1);
  ::dup2(fileno(out), 2);
  std::vector<char*> argv;
  std::string bin = SHELLFRAC_BIN;
  argv.push_back(bin.data());
  std::vector<std::string> copy = args;
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  ::execv(bin.c_str(), argv.data());
  ::_exit(127);
}

int wait_exit(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Parses an OBJ frame of the 8 x 8 cloth completely: every line is a known statement with the right
// number of finite values, faces refer to existing v/vt/vn, and the file holds the 81 vertices and 64
// quads of resolution 8 x 8 and ends with a newline. Returns "" or what is wrong.
std::string check_cloth_obj(const std::string& text) {
  if (text.empty() || text.back() != '\n') return "empty or not ending with a newline";
  std::istringstream in(text);
  size_t v = 0, vt = 0, vn = 0, faces = 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag.empty() || tag[0] == '#' || tag == "o" || tag == "g" || tag == "usemtl" || tag == "mtllib") continue;
    if (tag == "v" || tag == "vt" || tag == "vn") {
      const int n = tag == "vt" ? 2 : 3;
      double x;
      for (int k = 0; k < n; ++k)
        if (!(ls >> x) || !std::isfinite(x)) return "bad " + tag + " line: " + line;
      (tag == "v" ? v : tag == "vt" ? vt : vn) += 1;
    } else if (tag == "f") {
      static const std::regex corner(R"((\d+)/(\d+)/(\d+))");
      int corners = 0;
      for (std::string c; ls >> c; ++corners) {
        std::smatch m;
        if (!std::regex_match(c, m, corner)) return "bad face corner: " + line;
        if (std::stoul(m[1]) > v || std::stoul(m[2]) > vt || std::stoul(m[3]) > vn) return "face index out of range: " + line;
      }
      if (corners < 3) return "face with fewer than 3 corners: " + line;
      ++faces;
    } else {
      return "unknown statement: " + line;
    }
  }
  if (v != 81 || vt != 81 || vn != 81 || faces != 64)
    return std::to_string(v) + " v, " + std::to_string(vt) + " vt, " + std::to_string(vn) + " vn, " +
           std::to_string(faces) + " f (expected 81, 81, 81, 64)";
  return "";
}

// Every frame named in the summary is on disk and complete, every file on disk is listed (or is its
// .mtl, with the material text), no file is empty, and no staging folder or temporary file remains.
void expect_complete_frames(const fs::path& out, const nlohmann::json& summary, bool summary_written = true) {
  std::set<std::string> listed;
  for (const auto& f : summary["frames"]) {
    EXPECT_EQ(check_cloth_obj(read_text(out / f.get<std::string>())), "") << f;
    listed.insert(fs::path(f.get<std::string>()).filename().string());
  }
  for (const fs::path& dir : {out, out / "frames"})
    for (const std::string& name : frame_files(dir)) EXPECT_NE(name[0], '.') << "left behind: " << (dir / name);
  for (const std::string& name : frame_files(out / "frames")) {
    EXPECT_GT(fs::file_size(out / "frames" / name), 0u) << name;
    const fs::path ext = fs::path(name).extension();
    if (ext == ".mtl") {
      EXPECT_THAT(read_text(out / "frames" / name), HasSubstr("newmtl shell\n")) << name;
      EXPECT_EQ(read_text(out / "frames" / name).back(), '\n') << name;
      EXPECT_TRUE(fs::exists(out / "frames" / fs::path(name).replace_extension(".obj"))) << "an .mtl without its frame: " << name;
      continue;
    }
    EXPECT_EQ(ext, ".obj") << name;
    if (summary_written) {
      EXPECT_TRUE(listed.count(name)) << name;
    }
    EXPECT_EQ(check_cloth_obj(read_text(out / "frames" / name)), "") << name;
    EXPECT_TRUE(fs::exists(out / "frames" / fs::path(name).replace_extension(".mtl"))) << name;
  }
}

// A run long enough to interrupt: 200 frames of a small cloth (it is stopped after frame 2).
std::string long_cloth() { return cloth(R"({"end": 10, "frame_rate": 20})"); }

void interrupt_run(int signal, int expected_exit) {
  const fs::path d = scratch("signal" + std::to_string(signal));
  std::ofstream(d / "s.json") << long_cloth();
  const pid_t pid = spawn({"run", (d / "s.json").string(), "--threads", "1", "--out", (d / "out").string()}, d / "log");
  // Wait for frame 2, then stop the run (at most 60 s).
  for (int i = 0; i < 600 && !fs::exists(d / "out" / "frames" / "frame_00002.obj"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(fs::exists(d / "out" / "frames" / "frame_00002.obj")) << read_text(d / "log");
  ::kill(pid, signal);
  EXPECT_EQ(wait_exit(pid), expected_exit) << read_text(d / "log");
  const std::string log = read_text(d / "log");
  EXPECT_THAT(log, HasSubstr("interrupted"));
  std::ifstream in(d / "out" / "summary.json");
  ASSERT_TRUE(in) << log;
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_THAT(s["error"].get<std::string>(), HasSubstr(signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP"));
  const size_t frames = s["frames"].size();
  EXPECT_GE(frames, 3u);
  EXPECT_LT(frames, 201u);
  // The time reached lies between the last frame written and the next one.
  const double t = s["simulated_seconds"].get<double>();
  EXPECT_GE(t, (frames - 1) / 20.0 - 1e-9);
  EXPECT_LT(t, frames / 20.0 + 1e-9);
  expect_complete_frames(d / "out", s);
  fs::remove_all(d);
}

TEST(CliRobust, SigintStopsBetweenStepsWithAnInterruptedSummary) { interrupt_run(SIGINT, 130); }
TEST(CliRobust, SigtermExitsWith143) { interrupt_run(SIGTERM, 143); }
TEST(CliRobust, SighupExitsWith129) { interrupt_run(SIGHUP, 129); }

TEST(CliRobust, SecondSigintKillsAtOnce) {
  // A step of this 96 x 96-cell cloth takes about a second; the second SIGINT is sent as soon as the run
  // says it will stop after the current step, so it arrives while that step still runs, and the default
  // action ends the process (killed by SIGINT, no summary).
  const fs::path d = scratch("twice");
  std::string text = cloth(R"({"end": 10, "frame_rate": 1})");
  text.replace(text.find("\"cells\": [8, 8]"), 15, "\"cells\": [96, 96]");
  std::ofstream(d / "s.json") << text;
  const pid_t pid = spawn({"run", (d / "s.json").string(), "--threads", "1", "--out", (d / "out").string()}, d / "log");
  for (int i = 0; i < 600 && !fs::exists(d / "out" / "frames" / "frame_00000.obj"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(fs::exists(d / "out" / "frames" / "frame_00000.obj")) << read_text(d / "log");
  // Frame 0 is written just before the first step: a SIGINT in between stops the run before it steps, and it
  // exits normally before the second one arrives (seen once under a loaded ctest -j 2). A third of the
  // step's second later it is stepping.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(pid, SIGINT);
  for (int i = 0; i < 20000 && read_text(d / "log").find("stopping after the current step") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status)) << read_text(d / "log");
  EXPECT_EQ(WIFSIGNALED(status) ? WTERMSIG(status) : 0, SIGINT);
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json"));
  fs::remove_all(d);
}

// Runs `shellfrac args` (its --out inside `mount_point`) with a fresh tmpfs of `size` mounted at
// mount_point in a private mount namespace, so that nothing is seen outside the child processes and the
// mount goes away with them. The child copies the output folder to `copy_to` (sizes, hidden staging
// folders and all) before its namespace ends. Returns the run's exit code, or -1 when this machine does
// not allow the mount (no CAP_SYS_ADMIN, a seccomp filter).
int run_on_tmpfs(const std::vector<std::string>& args, const fs::path& mount_point, const std::string& size,
                 const fs::path& log, const fs::path& copy_to) {
  const fs::path status_file = log.string() + ".status";
  const pid_t child = ::fork();
  if (child == 0) {
    if (::unshare(CLONE_NEWNS) != 0) ::_exit(100);
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) ::_exit(101);  // no propagation out
    if (::mount("tmpfs", mount_point.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, ("size=" + size).c_str()) != 0) ::_exit(102);
    const int code = wait_exit(spawn(args, log));
    std::error_code ec;
    fs::copy(mount_point, copy_to, fs::copy_options::recursive, ec);
    std::ofstream(status_file) << code;
    ::_exit(ec ? 103 : 0);
  }
  const int child_code = wait_exit(child);
  if (child_code >= 100 && child_code <= 102) return -1;
  EXPECT_EQ(child_code, 0) << "the child could not copy the tmpfs out";
  std::ifstream in(status_file);
  int code = -2;
  in >> code;
  return code;
}

// A full disk: a 200 KiB tmpfs that fills up after some frames of a 61-frame run (each frame
// takes three 4 KiB pages: a 5-6 kB OBJ and its .mtl). The run must stop at the first failed write with
// exit code 1 and a message naming the file and "No space left on device"; every frame written before
// stays complete and parseable, nothing partial or empty sits under a final name, and no staging folder
// is left. --force: the estimate already says the frames will not fit. Where the machine allows no
// mount, the same assertions run on a file size limit (RLIMIT_FSIZE, "File too large") instead.
TEST(CliRobust, FullTmpfsStopsTheRunAtTheFirstFailedWrite) {
  const fs::path d = scratch("tmpfs");
  fs::create_directories(d / "mnt");
  std::ofstream(d / "s.json") << cloth(R"({"end": 2, "frame_rate": 30})");
  const std::vector<std::string> args = {"run", (d / "s.json").string(), "--threads", "1", "--force",
                                         "--out", (d / "mnt" / "out").string()};
  int code = run_on_tmpfs(args, d / "mnt", "200k", d / "log", d / "copy");
  fs::path out = d / "copy" / "out";
  std::string reason = "No space left on device";
  if (code == -1) {
    // The fallback, asserted in full: frame 0 (5337 bytes) fits under a 5800-byte limit, frame 1 does not.
    std::cerr << "note: mounting a tmpfs is not allowed here; simulating the full disk with RLIMIT_FSIZE\n";
    out = d / "out";
    reason = "File too large";
    code = wait_exit(spawn({"run", (d / "s.json").string(), "--threads", "1", "--force", "--out", out.string()}, d / "log", 5800));
  }
  const std::string log = read_text(d / "log");
  EXPECT_EQ(code, 1) << log;
  const std::regex message("cannot write \\S*/out/frames/frame_\\d{5}\\.(obj|mtl): " + reason);
  EXPECT_TRUE(std::regex_search(log, message)) << log;
  ASSERT_TRUE(fs::exists(out / "summary.json")) << log;  // the failed frame's staging space is freed for it
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(s["status"], "failed");
  EXPECT_THAT(s["error"].get<std::string>(), HasSubstr(reason));
  // It stopped at the failure: at least frame 0 kept, far from all 61 frames.
  EXPECT_GE(s["frames"].size(), 1u);
  EXPECT_LT(s["frames"].size(), 61u);
  EXPECT_LT(s["simulated_seconds"].get<double>(), 2.0);
  expect_complete_frames(out, s);
  EXPECT_EQ(frame_files(out / "frames").size(), 2 * s["frames"].size());  // each frame's .obj and .mtl
  fs::remove_all(d);
}

TEST(CliRobust, FullDiskStopsTheRunWithExitOneAndNoPartialFile) {
  // Files may not grow past 3000 bytes: frame 0 of this cloth takes 5337 bytes, so its write fails and
  // no frame is kept; with 5800 bytes frame 0 fits and frame 1 (6094 bytes) fails. The summary (about
  // 2.5 kB) still fits and says "failed".
  for (const long limit : {3000L, 5800L}) {
    const fs::path d = scratch("full" + std::to_string(limit));
    std::ofstream(d / "s.json") << cloth(R"({"end": 1, "frame_rate": 30})", "", "");
    const pid_t pid = spawn({"run", (d / "s.json").string(), "--threads", "1", "--out", (d / "out").string()}, d / "log", limit);
    EXPECT_EQ(wait_exit(pid), 1) << read_text(d / "log");
    const std::string log = read_text(d / "log");
    EXPECT_THAT(log, HasSubstr("File too large")) << log;
    EXPECT_THAT(log, HasSubstr("frame_")) << log;
    nlohmann::json s = {{"frames", nlohmann::json::array()}};
    const bool summary_written = fs::exists(d / "out" / "summary.json");
    if (summary_written) {
      std::ifstream in(d / "out" / "summary.json");
      s = nlohmann::json::parse(in);
      EXPECT_EQ(s["status"], "failed");
      EXPECT_THAT(s["error"].get<std::string>(), HasSubstr("File too large"));
      EXPECT_EQ(s["frames"].size(), limit == 3000L ? 0u : 1u);
    }
    EXPECT_TRUE(summary_written);
    expect_complete_frames(d / "out", s, summary_written);
    fs::remove_all(d);
  }
}

// A stand-in for Blender that records its arguments and pid, leaves a partial PNG in the staging folder
// shellfrac gives it, says it started, and then renders "forever" (until it is stopped).
void write_fake_blender(const fs::path& d) {
  std::ofstream(d / "blender") << "#!/bin/sh\n"
                                  "echo \"$@\" > " << (d / "args").string() << "\n"
                                  "echo $$ > " << (d / "pid.tmp").string() << " && mv " << (d / "pid.tmp").string() << " " << (d / "pid").string() << "\n"
                                  "while [ $# -gt 0 ]; do [ \"$1\" = --staging ] && staging=$2; shift; done\n"
                                  "printf partial > \"$staging/.frame_00001.partial.png\"\n"
                                  "echo 'shellfrac-preview: fake render started'\n"
                                  "exec sleep 600\n";
  fs::permissions(d / "blender", fs::perms::owner_all);
}

// `preview` stopped by a signal while Blender renders: exit 128 + the signal, Blender's process ended,
// and no temporary file left (the script folder in TMP, the staging folder with its partial PNG).
void interrupt_preview(int signal) {
  const fs::path d = scratch("preview" + std::to_string(signal));
  ASSERT_EQ(run_text(d, cloth(R"({"end": 0.05, "frame_rate": 20})")).exit_code, 0);
  write_fake_blender(d);
  ::setenv("SHELLFRAC_BLENDER", (d / "blender").c_str(), 1);
  const pid_t pid = spawn({"preview", (d / "out").string(), "--out", (d / "png").string()}, d / "log");
  ::unsetenv("SHELLFRAC_BLENDER");
  for (int i = 0; i < 600 && read_text(d / "log").find("fake render started") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_THAT(read_text(d / "log"), HasSubstr("fake render started"));
  ::kill(pid, signal);
  EXPECT_EQ(wait_exit(pid), 128 + signal) << read_text(d / "log");
  const std::string log = read_text(d / "log");
  EXPECT_THAT(log, HasSubstr(std::string("interrupted: preview stopped by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM")));
  // Blender is gone (shellfrac reaped it), and so are its script folder and the staging folder.
  std::ifstream pid_in(d / "pid");
  pid_t blender = 0;
  pid_in >> blender;
  ASSERT_GT(blender, 0);
  EXPECT_EQ(::kill(blender, 0), -1);
  EXPECT_EQ(errno, ESRCH);
  std::istringstream args(read_text(d / "args"));
  std::string arg, script, staging;
  for (std::string previous; args >> arg; previous = arg) {
    if (previous == "-P") script = arg;
    if (previous == "--staging") staging = arg;
  }
  ASSERT_FALSE(script.empty());
  ASSERT_FALSE(staging.empty());
  EXPECT_EQ(fs::path(staging).parent_path(), d / "png");
  EXPECT_FALSE(fs::exists(fs::path(script).parent_path())) << script;
  EXPECT_FALSE(fs::exists(staging)) << staging;
  for (const std::string& name : frame_files(d / "png")) EXPECT_EQ(name, "blender.log");
  fs::remove_all(d);
}

TEST(CliRobust, PreviewStopsBlenderAndCleansUpOnSigint) { interrupt_preview(SIGINT); }
TEST(CliRobust, PreviewStopsBlenderAndCleansUpOnSigterm) { interrupt_preview(SIGTERM); }

// `bench` checks every scene against the budget before building it, and stops between steps on a signal
// without writing a CSV or chart that would look complete.
TEST(CliRobust, BenchHonoursTheMemoryBudget) {
  const fs::path d = scratch("bench-budget");
  const Result r = shellfrac("bench sweep --no-charts --max-memory 16M --out " + (d / "bench").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("the scene needs about"));
  EXPECT_THAT(r.output, HasSubstr("more than the budget of 16.0 MiB"));
  fs::remove_all(d);
}

TEST(CliRobust, BenchStopsOnSigterm) {
  const fs::path d = scratch("bench-signal");
  const pid_t pid = spawn({"bench", "stability", "--no-charts", "--threads", "1", "--out", (d / "bench").string()}, d / "log");
  // The output folder is made after the handlers are installed, before the first scene runs.
  for (int i = 0; i < 600 && !fs::exists(d / "bench"); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(d / "bench")) << read_text(d / "log");
  ::kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid), 143) << read_text(d / "log");
  EXPECT_THAT(read_text(d / "log"), HasSubstr("interrupted: bench stability"));
  EXPECT_THAT(read_text(d / "log"), HasSubstr("stopped by SIGTERM"));
  EXPECT_TRUE(fs::is_empty(d / "bench"));
  fs::remove_all(d);
}

}  // namespace
