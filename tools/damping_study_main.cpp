// shellfrac_damping_study: the transfer's numerical damping against cell size / thickness.
// Runs the simply supported plate of tools/vibration.hpp for each transfer, a/t and resolution, writes
// damping.csv and the chart damping-ratio.png (gnuplot) into the output folder.
//   shellfrac_damping_study [--out DIR] [--cells 8,16,32] [--ratios 20,100] [--transfers pic,apic,aflip]
//                           [--degree 2]
// A transfer may carry its FLIP share ("aflip:1"). Two single measurements print instead of charting:
//   --free-sheet aflip:1@0.5#0.002%32   energy history of the free bent sheet (share, cfl, amplitude, cells)
//   --tear aflip:0.99                   whether the sweeps' 16-cell mode-I tear completes with this transfer
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "sim/simulation.hpp"
#include "tools/bench_scenes.hpp"
#include "tools/charts.hpp"
#include "tools/vibration.hpp"

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
  return out;
}

// --free-sheet: the energy history of the free bent sheet with this transfer
// ("aflip:1@0.5#0.002%32": transfer, FLIP share, cfl, amplitude [m], cells along u).
void print_free_sheet(const std::string& value) {
  using namespace shellfrac::tools;
  FreeSheetCase c;
  if (value.find('@') != std::string::npos) c.cfl = std::stod(value.substr(value.find('@') + 1));
  if (value.find('#') != std::string::npos) c.amplitude = std::stod(value.substr(value.find('#') + 1));
  if (value.find('%') != std::string::npos) {
    c.cells_u = std::stoi(value.substr(value.find('%') + 1));
    c.cells_v = c.cells_u / 4;
  }
  c.transfer.transfer = value.substr(0, value.find_first_of(":@"));
  if (value.find(':') != std::string::npos) c.transfer.flip = std::stod(value.substr(value.find(':') + 1));
  const EnergyHistory h = free_bent_sheet(c, 40);
  for (size_t k = 0; k < h.time.size(); ++k)
    std::cout << h.time[k] << " kinetic " << h.kinetic[k] << " consistent " << h.consistent_kinetic[k]
              << " elastic " << h.elastic[k] << " total " << h.total(k) << " consistent total " << h.consistent_total(k)
              << "\n";
}

// --tear: whether the mode-I tear of the sweeps at 16 cells completes with this transfer.
void print_tear(const std::string& value) {
  using namespace shellfrac::tools;
  shellfrac::scene::Scene scene = bench_scenes::mode_one_tear(Discretisation{16, 4, 3, 0.5, false});
  scene.grid.transfer = value.substr(0, value.find(':'));
  if (value.find(':') != std::string::npos) scene.grid.flip_ratio = std::stod(value.substr(value.find(':') + 1));
  try {
    shellfrac::sim::Simulation sim(scene);
    const double end = scene.time.end.value_or(1.0);
    for (int f = 1; f <= 40; ++f) sim.advance_to(end * f / 40);
    std::cout << value << ": tear completed, " << sim.steps() << " steps\n";
  } catch (const std::exception& e) {
    std::cout << value << ": " << e.what() << "\n";
  }
}

// The plate's damping ratio and period for every transfer ("aflip:0.95" selects a FLIP share), a/t and
// cell count: rows of damping.csv, printed lines, and one chart series per transfer and a/t.
std::vector<shellfrac::tools::charts::Series> damping_sweep(const std::vector<std::string>& transfers,
                                                            const std::vector<std::string>& ratios,
                                                            const std::vector<std::string>& cells, int degree,
                                                            shellfrac::tools::charts::CsvTable& table) {
  using namespace shellfrac::tools;
  std::vector<charts::Series> series;
  for (const std::string& name : transfers) {
    TransferChoice t;
    t.transfer = name.substr(0, name.find(':'));
    if (name.find(':') != std::string::npos) t.flip = std::stod(name.substr(name.find(':') + 1));
    for (const std::string& r : ratios) {
      charts::Series s{name + ", a/t = " + r, {}, {}};
      for (const std::string& n : cells) {
        PlateVibrationCase c;
        c.thickness = c.side / std::stod(r);
        c.cells = std::stoi(n);
        c.degree = degree;
        c.transfer = t;
        const VibrationResult v = simply_supported_plate(c);
        const double h_over_t = c.side / c.cells / c.thickness;
        const double period_error = v.period > 0 ? v.period / v.reference_period - 1 : 0.0;
        table.add({name, charts::number(t.flip), r, n, charts::number(h_over_t), charts::number(v.damping_ratio),
                   charts::number(v.period), charts::number(v.reference_period), charts::number(period_error),
                   std::to_string(v.extrema), std::to_string(v.steps)});
        std::cout << name << " a/t=" << r << " cells=" << n << " h/t=" << h_over_t << " zeta=" << v.damping_ratio
                  << " period error=" << period_error << " extrema=" << v.extrema << " steps=" << v.steps << std::endl;
        s.x.push_back(h_over_t);
        s.y.push_back(std::max(v.damping_ratio, 1e-5));
      }
      series.push_back(s);
    }
  }
  return series;
}

// damping-ratio.png by gnuplot: one colour per transfer, one dash pattern per a/t (the series come
// transfer by transfer, `per_transfer` of them each).
void draw_damping_chart(const std::filesystem::path& out, const std::vector<shellfrac::tools::charts::Series>& series,
                        size_t per_transfer) {
  using namespace shellfrac::tools;
  std::ostringstream gp;
  gp << "set title 'Simply supported plate, first mode: numerical damping ratio of the transfer (cfl 1)'\n"
     << "set logscale xy\nset grid\nset key outside right top\n"
     << "set xlabel 'cell size / thickness'\nset ylabel 'damping ratio zeta (1 = no oscillation; below 1e-5 drawn at 1e-5)'\n"
     << "set yrange [5e-6:2]\nplot ";
  static const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                         "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#000000"};
  for (size_t i = 0; i < series.size(); ++i)
    gp << (i ? ", " : "") << "'-' using 1:2 with linespoints lw 2 pt " << 5 + static_cast<int>(i % per_transfer) * 2
       << " dt " << 1 + static_cast<int>(i % per_transfer) << " lc rgb '" << kColours[(i / per_transfer) % 10]
       << "' title '" << series[i].title << "'";
  gp << "\n";
  for (const charts::Series& s : series) {
    for (size_t k = 0; k < s.x.size(); ++k) gp << s.x[k] << " " << s.y[k] << "\n";
    gp << "e\n";
  }
  charts::render_png(out / "damping-ratio.png", gp.str());
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shellfrac::tools;
  std::filesystem::path out = "docs/benchmarks";
  std::vector<std::string> cells = {"8", "16", "32"}, ratios = {"20", "100"}, transfers = {"pic", "apic", "aflip"};
  int degree = 2;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--free-sheet") {
      print_free_sheet(value);
      return 0;
    }
    if (key == "--tear") {
      print_tear(value);
      return 0;
    }
    if (key == "--out") out = value;
    else if (key == "--cells") cells = split(value);
    else if (key == "--ratios") ratios = split(value);
    else if (key == "--transfers") transfers = split(value);
    else if (key == "--degree") degree = std::stoi(value);
    else {
      std::cerr << "unknown option " << key << "\n";
      return 2;
    }
  }
  std::filesystem::create_directories(out);
  charts::CsvTable table{{"transfer", "flip_ratio", "a_over_t", "cells", "h_over_t", "damping_ratio", "period",
                          "reference_period", "period_error", "extrema", "steps"}, {}};
  const std::vector<charts::Series> series = damping_sweep(transfers, ratios, cells, degree, table);
  charts::write_csv(out / "damping.csv", table);
  try {
    draw_damping_chart(out, series, std::max<size_t>(ratios.size(), 1));
  } catch (const charts::ChartError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}
