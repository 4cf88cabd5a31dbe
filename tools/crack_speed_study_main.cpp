// shellfrac_crack_speed_study: resolution dependence of local and non-local damage (tools/crack_speed.hpp).
// Runs a notched specimen at several grid spacings with Rankine damage and with the phase field, and writes
// crack_speed.csv, crack_speed_summary.csv and crack-tip-<specimen>.png into the output folder.
//   shellfrac_crack_speed_study [--out DIR] [--specimen bar,beam] [--dx 0.005,0.0033333,0.0025] [--end 0.012]
//                               [--l0 0.0025] [--no-chart]
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/charts.hpp"
#include "tools/crack_speed.hpp"

namespace {

std::vector<double> numbers(const std::string& s) {
  std::vector<double> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(std::stod(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shellfrac::tools;
  std::filesystem::path out = "out/crack-speed";
  CrackSpeedOptions o;
  std::vector<std::string> specimens{"bar"};
  bool chart = true;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string key = argv[i];
      if (key == "--no-chart") {
        chart = false;
        continue;
      }
      if (i + 1 >= argc) throw std::invalid_argument(key + " needs a value");
      const std::string value = argv[++i];
      if (key == "--out") out = value;
      else if (key == "--specimen") {
        specimens.clear();
        std::stringstream ss(value);
        for (std::string item; std::getline(ss, item, ',');) specimens.push_back(item);
      }
      else if (key == "--dx") o.spacings = numbers(value);
      else if (key == "--end") o.end = std::stod(value);
      else if (key == "--l0") o.length_scale = std::stod(value);
      else throw std::invalid_argument("unknown option " + key);
    }
    for (double dx : o.spacings)
      if (!(dx > 0)) throw std::invalid_argument("--dx: every spacing must be > 0");
    if (!(o.end > 0) || !(o.length_scale > 0)) throw std::invalid_argument("--end and --l0 must be > 0");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shellfrac_crack_speed_study: %s\n", e.what());
    return 2;
  }
  try {
    std::vector<CrackSpeedRun> runs;
    for (const std::string& specimen : specimens) {
      o.specimen = specimen;
      for (CrackSpeedRun& r : run_crack_speed_study(o, std::cout)) runs.push_back(std::move(r));
    }
    write_crack_speed(out, runs, chart && charts::gnuplot_available());
    std::printf("wrote %s\n", (out / "crack_speed.csv").c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shellfrac_crack_speed_study: %s\n", e.what());
    return 1;
  }
  return 0;
}
