// `shellfrac preview`: renders frames of a run with Blender (background mode, Cycles on the CPU). The
// library knows nothing of Blender: this command only finds the program and hands it the frame files.
#include "apps/shellfrac/preview_command.hpp"

#include "apps/shellfrac/command.hpp"
#include "core/error.hpp"
#include "output/interrupt.hpp"
#include "render_mesh/atomic_write.hpp"

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace shellfrac::app {

namespace fs = std::filesystem;

namespace {

// Frame formats Blender 3.4 (Debian) reads back from shellfrac's assimp export. Not here: FBX (Blender
// cannot parse assimp's binary FBX, and has no ASCII FBX reader) and X3D (its importer fails on Python 3.11).
const std::vector<std::string> kPreviewExtensions = {".obj", ".ply", ".stl", ".gltf", ".glb", ".dae"};

const char* kInstallHint =
    "install it with `apt-get install blender` (or `bash scripts/setup.sh`), or set SHELLFRAC_BLENDER to the "
    "blender program";

struct PreviewOptions {
  std::string run_dir;
  std::string frames = "last";
  std::string size = "480x360";
  int samples = 8;
  std::string png_dir;  // default RUN_DIR/preview
  int threads = 0;
};

// Bad input (exit code 2) and a missing or failing Blender (exit code 1).
using BadInput = core::InputError;
using BlenderError = std::runtime_error;

std::pair<int, int> parse_size(const std::string& s) {
  static const std::regex pattern(R"((\d{1,5})x(\d{1,5}))");
  std::smatch m;
  if (!std::regex_match(s, m, pattern))
    throw BadInput("--size " + s + ": expected WIDTHxHEIGHT in pixels, e.g. 480x360");
  const int w = std::stoi(m[1]), h = std::stoi(m[2]);
  if (w < 16 || h < 16 || w > 8192 || h > 8192)
    throw BadInput("--size " + s + ": width and height must be in [16, 8192]");
  return {w, h};
}

bool is_executable_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
}

// $SHELLFRAC_BLENDER if set, else the first `blender` on PATH.
fs::path find_blender() {
  if (const char* env = std::getenv("SHELLFRAC_BLENDER"); env && *env) {
    if (!is_executable_file(env))
      throw BlenderError(std::string("SHELLFRAC_BLENDER=") + env + " is not an executable file; " + kInstallHint);
    return env;
  }
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && is_executable_file(fs::path(dir) / "blender")) return fs::path(dir) / "blender";
  throw BlenderError(std::string("preview needs Blender, and `blender` is not on PATH; ") + kInstallHint);
}

struct Frame {
  int number;
  fs::path file;
};

struct Run {
  std::vector<fs::path> frames;  // every frame the run wrote, frame k at index k
  double grid_dx = 0;            // 0 when the summary has none
};

Run read_run(const fs::path& run_dir) {
  const fs::path summary_path = run_dir / "summary.json";
  std::ifstream in(summary_path);
  if (!in)
    throw BadInput(summary_path.string() + ": cannot read it (OUT_DIR must be the --out folder of `shellfrac run`)");
  nlohmann::json summary;
  try {
    in >> summary;
  } catch (const nlohmann::json::exception& e) {
    throw BadInput(summary_path.string() + ": not valid JSON: " + e.what());
  }
  const auto frames = summary.find("frames");
  if (frames == summary.end() || !frames->is_array())
    throw BadInput(summary_path.string() + ": /frames: missing or not an array of frame files");
  if (frames->empty()) throw BadInput(summary_path.string() + ": /frames: the run wrote no frames");
  Run run;
  for (std::size_t i = 0; i < frames->size(); ++i) {
    if (!(*frames)[i].is_string())
      throw BadInput(summary_path.string() + ": /frames/" + std::to_string(i) + ": expected a file name");
    run.frames.push_back(run_dir / (*frames)[i].get<std::string>());
  }
  if (const auto dx = summary.find("grid_dx"); dx != summary.end() && dx->is_number()) run.grid_dx = dx->get<double>();
  return run;
}

void check_frame_file(const fs::path& file, const fs::path& summary, int number) {
  const std::string where = summary.string() + ": /frames/" + std::to_string(number) + ": ";
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw BadInput(where + file.string() + " does not exist");
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (std::find(kPreviewExtensions.begin(), kPreviewExtensions.end(), ext) == kPreviewExtensions.end()) {
    std::string list;
    for (const auto& e : kPreviewExtensions) list += (list.empty() ? "" : ", ") + e;
    throw BadInput(where + file.string() + ": preview reads " + list +
                   " frames (output.format obj, ply, stl, gltf2, glb2 or collada); not " + ext);
  }
}

// A private folder made with mkdtemp from `pattern` (ending in XXXXXX) and removed, with everything in
// it, when it goes out of scope: also when an error or an interrupt unwinds the command.
class TempFolder {
 public:
  explicit TempFolder(const fs::path& pattern) {
    std::string name = pattern.string();
    if (!::mkdtemp(name.data()))
      throw std::runtime_error("cannot create the temporary folder " + name + ": " + std::strerror(errno));
    dir_ = name;
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

// The embedded scripts for Blender to run, in a temporary folder.
class ScriptFolder {
 public:
  ScriptFolder() : folder_(fs::temp_directory_path() / "shellfrac-preview-XXXXXX") {
    for (const auto& script : blender_preview_scripts())
      render_mesh::write_file_durably(folder_.path() / script.name, script.text);
  }
  fs::path script() const { return folder_.path() / blender_preview_scripts().front().name; }

 private:
  TempFolder folder_;
};

// Removes the staging folders (".staging-preview-*") that previews killed with SIGKILL left in png_dir.
void remove_stale_staging(const fs::path& png_dir) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(png_dir, ec))
    if (entry.path().filename().string().rfind(".staging-preview-", 0) == 0) fs::remove_all(entry.path(), ec);
}

// Runs `argv` in its own process group with stdout and stderr into `log`; lines starting with `prefix`
// also go to `out` (prefix replaced by "preview: "). Returns the exit status; keeps the last lines for an
// error message. When a signal is caught (output::InterruptHandlers), Blender's process group gets
// SIGTERM, then SIGKILL after 5 s, and output::Interrupted is thrown once it has ended.
int run_logged(const std::vector<std::string>& argv, const fs::path& log_path, std::ostream& out,
               std::deque<std::string>& tail) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    ::setpgid(0, 0);  // Ctrl-C reaches shellfrac only; it stops Blender and cleans up
    ::dup2(fds[1], STDOUT_FILENO);
    ::dup2(fds[1], STDERR_FILENO);
    ::close(fds[0]);
    ::close(fds[1]);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    std::fprintf(stderr, "cannot start %s: %s\n", args[0], std::strerror(errno));
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here, so that the group exists before any kill below
  ::close(fds[1]);
  std::ofstream log(log_path);
  const std::string prefix = "shellfrac-preview: ";
  std::string pending;
  char buf[4096];
  auto line_done = [&](const std::string& line) {
    log << line << '\n';
    if (line.compare(0, prefix.size(), prefix) == 0) out << "preview: " << line.substr(prefix.size()) << std::endl;
    tail.push_back(line);
    if (tail.size() > 15) tail.pop_front();
  };
  using Clock = std::chrono::steady_clock;
  Clock::time_point terminated{};
  bool killed = false, exited = false;
  int status = 0;
  while (!exited) {
    if (output::interrupt_signal() != 0) {
      if (terminated == Clock::time_point{}) {
        ::kill(-pid, SIGTERM);
        terminated = Clock::now();
      } else if (!killed && Clock::now() - terminated > std::chrono::seconds(5)) {
        ::kill(-pid, SIGKILL);
        killed = true;
      }
    }
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, 100);  // wakes up to notice a signal (the handler restarts reads)
    if (ready > 0) {
      const ssize_t n = ::read(fds[0], buf, sizeof buf);
      if (n > 0) {
        pending.append(buf, static_cast<std::size_t>(n));
        for (std::size_t eol; (eol = pending.find('\n')) != std::string::npos; pending.erase(0, eol + 1))
          line_done(pending.substr(0, eol));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      // End of output: Blender has closed its side (exited, or about to).
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      exited = true;
    } else if (::waitpid(pid, &status, WNOHANG) == pid) {
      exited = true;  // ended while a child it started still holds the pipe open
    }
  }
  if (!pending.empty()) line_done(pending);
  ::close(fds[0]);
  ::kill(-pid, SIGKILL);  // anything Blender left running in its group
  if (const int signal = output::interrupt_signal())
    throw output::Interrupted(std::string("preview stopped by ") + output::signal_name(signal) +
                                  "; Blender was stopped and its partial files removed (log: " + log_path.string() + ")",
                              signal);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

int run_preview(const PreviewOptions& o) {
  const fs::path run_dir = o.run_dir;
  const auto [width, height] = parse_size(o.size);
  const Run run = read_run(run_dir);
  std::vector<int> numbers;
  try {
    numbers = select_frames(o.frames, run.frames.size());
  } catch (const std::invalid_argument& e) {
    throw BadInput(std::string("--frames ") + o.frames + ": " + e.what());
  }
  std::vector<Frame> frames;
  for (const int k : numbers) {
    check_frame_file(run.frames[static_cast<std::size_t>(k)], run_dir / "summary.json", k);
    frames.push_back({k, run.frames[static_cast<std::size_t>(k)]});
  }
  const fs::path blender = find_blender();
  const fs::path png_dir = o.png_dir.empty() ? run_dir / "preview" : fs::path(o.png_dir);
  std::error_code ec;
  fs::create_directories(png_dir, ec);
  if (!fs::is_directory(png_dir)) throw std::runtime_error("cannot create the PNG folder " + png_dir.string());

  remove_stale_staging(png_dir);

  const output::InterruptHandlers handlers;  // stop Blender and clean up on SIGINT, SIGTERM, SIGHUP
  const ScriptFolder scripts;
  // Blender renders into a staging folder; the script moves each finished PNG into png_dir, so an
  // interrupted or failed render leaves no partial image under a final name.
  const TempFolder staging(png_dir / ".staging-preview-XXXXXX");
  std::vector<std::string> argv = {blender.string(), "-b", "--factory-startup", "-noaudio", "--python-exit-code",
                                   "1", "-P", scripts.script().string(), "--", "--out", png_dir.string(),
                                   "--staging", staging.path().string(), "--size",
                                   std::to_string(width), std::to_string(height), "--samples",
                                   std::to_string(o.samples), "--threads", std::to_string(o.threads)};
  // Frame 0 is the rest state: the script measures edge stretch against it.
  bool rest_ok = true;
  try {
    check_frame_file(run.frames.front(), run_dir / "summary.json", 0);
  } catch (const BadInput&) {
    rest_ok = false;
  }
  if (rest_ok) argv.insert(argv.end(), {"--rest", run.frames.front().string()});
  if (run.grid_dx > 0) argv.insert(argv.end(), {"--sliver-area", std::to_string(run.grid_dx * run.grid_dx)});
  for (const auto& f : frames) argv.insert(argv.end(), {"--frame", std::to_string(f.number), f.file.string()});

  std::cerr << "preview: rendering " << frames.size() << " frame(s) of " << run_dir.string() << " with "
            << blender.string() << " into " << png_dir.string() << " (" << width << "x" << height << ", "
            << o.samples << " samples)\n";
  const auto start = std::chrono::steady_clock::now();
  std::deque<std::string> tail;
  const fs::path log = png_dir / "blender.log";
  const int status = run_logged(argv, log, std::cout, tail);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0) {
    std::string last;
    for (const auto& l : tail) last += "  " + l + "\n";
    throw BlenderError(blender.string() + " failed (exit status " + std::to_string(status) + "); full log in " +
                       log.string() + ", its last lines:\n" + last);
  }
  std::cerr << "done: " << frames.size() << " PNG(s) and contact_sheet.png in " << png_dir.string() << " ("
            << seconds << " s with Blender's start-up; per-frame numbers in " << (png_dir / "preview.json").string()
            << ")\n";
  return core::to_int(core::ExitCode::ok);
}

}  // namespace

std::vector<int> select_frames(const std::string& spec, std::size_t frame_count) {
  const int last = static_cast<int>(frame_count) - 1;
  const std::string range = frame_count ? "the run has frames 0.." + std::to_string(last) : "the run has no frames";
  if (frame_count == 0) throw std::invalid_argument(range);
  if (spec == "last") return {last};
  std::vector<int> out;
  if (spec == "all") {
    for (int k = 0; k <= last; ++k) out.push_back(k);
    return out;
  }
  static const std::regex item(R"((\d{1,9})(?:-(\d{1,9}))?)");
  std::set<int> chosen;
  std::stringstream items(spec);
  for (std::string s; std::getline(items, s, ',');) {
    std::smatch m;
    if (!std::regex_match(s, m, item))
      throw std::invalid_argument("\"" + s + "\" is not a frame number or range A-B (use e.g. 0,12,20-24, last or all)");
    const int a = std::stoi(m[1]), b = m[2].matched ? std::stoi(m[2]) : a;
    if (b < a) throw std::invalid_argument("range \"" + s + "\" is empty (write the smaller number first)");
    if (b > last) throw std::invalid_argument("frame " + std::to_string(b) + " is out of range: " + range);
    for (int k = a; k <= b; ++k) chosen.insert(k);
  }
  if (chosen.empty()) throw std::invalid_argument("no frames named (use e.g. 0,12,20-24, last or all)");
  return {chosen.begin(), chosen.end()};
}

Command add_preview_command(CLI::App& app) {
  auto options = std::make_shared<PreviewOptions>();
  auto* preview = app.add_subcommand(
      "preview", "Render frames of a finished run (OUT_DIR of `run`) to PNG with Blender in background mode "
                 "(Cycles on the CPU), plus a contact sheet; colours show the loose parts, red the strands.");
  preview->add_option("out_dir", options->run_dir, "Output directory of a run (holds summary.json)")->required();
  preview->add_option("--frames", options->frames, "Frames: last, all, or a list like 0,12,20-24")
      ->capture_default_str();
  preview->add_option("--size", options->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  preview->add_option("--samples", options->samples, "Cycles samples per pixel")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  preview->add_option("--out,-o", options->png_dir, "Folder for the PNGs (default OUT_DIR/preview)");
  preview->add_option("--threads,-j", options->threads, "Render threads (0: all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  return [options, preview]() -> std::optional<int> {
    if (!preview->parsed()) return std::nullopt;
    return run_guarded([&] { return run_preview(*options); });
  };
}

}  // namespace shellfrac::app
