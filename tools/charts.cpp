#include "tools/charts.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "output/interrupt.hpp"
#include "render_mesh/atomic_write.hpp"

namespace shellfrac::tools::charts {

namespace fs = std::filesystem;

std::string number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string to_csv(const CsvTable& table) {
  std::ostringstream os;
  auto line = [&](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size(); ++i) os << (i ? "," : "") << csv_cell(cells[i]);
    os << "\n";
  };
  line(table.header);
  for (const auto& r : table.rows) line(r);
  return os.str();
}

void write_csv(const fs::path& path, const CsvTable& table) { render_mesh::write_file_atomically(path, to_csv(table)); }

ConvergenceFit fit_convergence_order(const std::vector<double>& h, const std::vector<double>& error) {
  // Ordinary least squares in log-log coordinates.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  double h_min = std::numeric_limits<double>::infinity(), h_max = 0;
  for (size_t i = 0; i < h.size() && i < error.size(); ++i) {
    if (!(h[i] > 0) || !(error[i] > 0) || !std::isfinite(h[i]) || !std::isfinite(error[i])) continue;
    const double x = std::log(h[i]), y = std::log(error[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++n;
    h_min = std::min(h_min, h[i]);
    h_max = std::max(h_max, h[i]);
  }
  ConvergenceFit fit;
  fit.points = n;
  const double det = n * sxx - sx * sx;
  if (n < 2 || !(h_max > h_min) || !(std::abs(det) > 0)) {
    fit.order = fit.log_constant = std::numeric_limits<double>::quiet_NaN();
    return fit;
  }
  fit.order = (n * sxy - sx * sy) / det;
  fit.log_constant = (sy - fit.order * sx) / n;
  return fit;
}

std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error) {
  const size_t n = std::min(cost.size(), error.size());
  std::vector<bool> front(n, false);
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(cost[i]) || !std::isfinite(error[i])) continue;
    bool dominated = false;
    for (size_t j = 0; j < n && !dominated; ++j) {
      if (j == i || !std::isfinite(cost[j]) || !std::isfinite(error[j])) continue;
      dominated = cost[j] <= cost[i] && error[j] <= error[i] && (cost[j] < cost[i] || error[j] < error[i]);
    }
    front[i] = !dominated;
  }
  return front;
}

namespace {

// A gnuplot single-quoted string (a quote is written twice).
std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

// A tic label: gnuplot reads it as a format, so a literal % is written twice.
std::string tic_label(const std::string& s) {
  std::string t;
  for (char c : s) t += c == '%' ? std::string("%%") : std::string(1, c);
  return (quoted)(t);  // parenthesised: no argument-dependent lookup of std::quoted
}

// A string column inside a gnuplot data block.
std::string data_string(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? '\'' : c;
  return q + "\"";
}

std::string shell_quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Nine distinguishable colours for series.
const char* kSeriesColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e",
                                "#8c564b", "#e377c2", "#17becf", "#7f7f7f"};
const char* series_colour(size_t i) { return kSeriesColours[i % (sizeof kSeriesColours / sizeof *kSeriesColours)]; }

bool positive_point(double x, double y) { return x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y); }

}  // namespace

bool gnuplot_available() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

void render_png(const fs::path& png, const std::string& script, int width, int height) {
  if (!gnuplot_available())
    throw ChartError("cannot draw " + png.string() +
                     ": gnuplot was not found; install the Debian package gnuplot-nox (scripts/setup.sh does). "
                     "The CSV files were written.");
  const fs::path dir = png.has_parent_path() ? png.parent_path() : fs::path(".");
  const fs::path tmp_png = dir / ("." + png.filename().string() + ".tmp");
  const fs::path script_path = dir / ("." + png.stem().string() + ".gp.tmp");
  const fs::path log_path = dir / ("." + png.stem().string() + ".gnuplot.log");
  std::ostringstream text;
  text << "set terminal pngcairo noenhanced size " << width << "," << height << " font 'Sans,10'\n"
       << "set output " << quoted(tmp_png.string()) << "\n"
       << script << "\nunset output\n";
  render_mesh::write_file_durably(script_path, text.str());
  const std::string cmd =
      "gnuplot " + shell_quoted(script_path.string()) + " >" + shell_quoted(log_path.string()) + " 2>&1";
  const int rc = std::system(cmd.c_str());  // SIGINT is ignored here while gnuplot runs, see below
  std::string log;
  {
    std::ifstream in(log_path);
    std::ostringstream ss;
    ss << in.rdbuf();
    log = ss.str();
  }
  std::string image;
  {
    std::ifstream in(tmp_png, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    image = ss.str();
  }
  std::error_code ec;
  fs::remove(script_path, ec);
  fs::remove(log_path, ec);
  fs::remove(tmp_png, ec);
  // Ctrl-C reaches gnuplot (same process group) and ends it with SIGINT, which std::system reports as a
  // wait status or as the shell's exit code 130; SIGTERM and SIGHUP reach the handler.
  const bool sigint = (WIFSIGNALED(rc) && WTERMSIG(rc) == SIGINT) || (WIFEXITED(rc) && WEXITSTATUS(rc) == 128 + SIGINT);
  if (output::interrupt_signal() != 0 || sigint) {
    const int signal = output::interrupt_signal() ? output::interrupt_signal() : SIGINT;
    throw output::Interrupted("drawing " + png.string() + " stopped by " + output::signal_name(signal), signal);
  }
  if (rc != 0 || image.empty()) throw ChartError("gnuplot failed to draw " + png.string() + ": " + log);
  // gnuplot does not report a full disk: a PNG must end with its IEND chunk, or it is truncated.
  static const std::string kPngEnd("IEND\xae\x42\x60\x82", 8);
  if (image.size() < 8 + kPngEnd.size() || image.compare(image.size() - kPngEnd.size(), kPngEnd.size(), kPngEnd) != 0)
    throw ChartError("cannot write " + png.string() + ": gnuplot wrote an incomplete PNG (" + std::to_string(image.size()) +
                     " bytes; is the disk full?)");
  render_mesh::write_file_atomically(png, image);
}

void error_vs_cost_chart(const fs::path& png, const std::string& title, const std::string& cost_label,
                         const std::vector<Series>& series) {
  std::ostringstream gp;
  std::vector<double> all_cost, all_error;
  for (size_t s = 0; s < series.size(); ++s) {
    gp << "$s" << s << " << EOD\n";
    for (size_t i = 0; i < series[s].x.size(); ++i) {
      if (!positive_point(series[s].x[i], series[s].y[i])) continue;
      gp << number(series[s].x[i]) << " " << number(series[s].y[i]) << "\n";
      all_cost.push_back(series[s].x[i]);
      all_error.push_back(series[s].y[i]);
    }
    gp << "EOD\n";
  }
  const std::vector<bool> front = pareto_front(all_cost, all_error);
  std::vector<std::pair<double, double>> front_points;
  for (size_t i = 0; i < front.size(); ++i)
    if (front[i]) front_points.emplace_back(all_cost[i], all_error[i]);
  std::sort(front_points.begin(), front_points.end());
  gp << "$front << EOD\n";
  for (const auto& [c, e] : front_points) gp << number(c) << " " << number(e) << "\n";
  gp << "EOD\n";
  gp << "set title " << quoted(title) << "\nset logscale xy\nset grid\nset key outside right top\n"
     << "set xlabel " << quoted(cost_label) << "\nset ylabel 'relative error'\n"
     << "set format y '%.0e'\n";
  gp << "plot ";
  for (size_t s = 0; s < series.size(); ++s)
    gp << "$s" << s << " using 1:2 with points pt 7 ps 1.2 lc rgb '" << series_colour(s) << "' title "
       << quoted(series[s].title) << ", ";
  gp << "$front using 1:2 with steps lw 2 lc rgb 'black' title 'Pareto front', "
     << "$front using 1:2 with points pt 6 ps 2.2 lw 2 lc rgb 'black' notitle\n";
  render_png(png, gp.str(), 1000, 600);
}

void error_vs_resolution_chart(const fs::path& png, const std::string& title, const std::vector<Series>& series,
                               const std::vector<ConvergenceFit>& fits) {
  std::ostringstream gp;
  for (size_t s = 0; s < series.size(); ++s) {
    gp << "$s" << s << " << EOD\n";
    for (size_t i = 0; i < series[s].x.size(); ++i)
      if (positive_point(series[s].x[i], series[s].y[i]))
        gp << number(series[s].x[i]) << " " << number(series[s].y[i]) << "\n";
    gp << "EOD\n";
  }
  gp << "set title " << quoted(title) << "\nset logscale xy\nset grid\nset key outside right top\n"
     << "set xlabel 'cell size h [m] (or [parameter units] for MLS)'\nset ylabel 'relative error'\n"
     << "set format y '%.0e'\n";
  gp << "plot ";
  for (size_t s = 0; s < series.size(); ++s) {
    const ConvergenceFit fit = s < fits.size() ? fits[s] : ConvergenceFit{std::nan(""), 0, 0};
    char order[64];
    std::snprintf(order, sizeof order, " (order %.2f)", fit.order);
    gp << (s ? ", " : "") << "$s" << s << " using 1:2 with points pt 7 ps 1.3 lc rgb '" << series_colour(s)
       << "' title " << quoted(series[s].title + (std::isfinite(fit.order) ? order : " (no fit)"));
    if (std::isfinite(fit.order))
      gp << ", exp(" << number(fit.log_constant) << ") * x**(" << number(fit.order) << ") with lines lw 1.5 dt 2 lc rgb '"
         << series_colour(s) << "' notitle";
  }
  gp << "\n";
  render_png(png, gp.str(), 1000, 600);
}

void stage_breakdown_chart(const fs::path& png, const std::string& title,
                           const std::vector<std::pair<std::string, double>>& stage_seconds) {
  double total = 0;
  for (const auto& s : stage_seconds) total += s.second;
  std::ostringstream gp;
  gp << "$d << EOD\n";
  for (size_t i = 0; i < stage_seconds.size(); ++i) {
    char label[96];
    std::snprintf(label, sizeof label, "%.3g s (%.1f%%)", stage_seconds[i].second,
                  total > 0 ? 100.0 * stage_seconds[i].second / total : 0.0);
    gp << i << " " << number(stage_seconds[i].second) << " " << data_string(stage_seconds[i].first) << " "
       << data_string(label) << "\n";
  }
  gp << "EOD\n";
  gp << "set title " << quoted(title) << "\nset grid x\nset xlabel 'wall seconds'\nset yrange [-0.6:"
     << static_cast<double>(stage_seconds.size()) - 0.4 << "]\nset xrange [0:" << number(std::max(total, 1e-9) * 1.0)
     << "]\nset offsets 0, 0, 0, 0\nset style fill solid 0.8\n";
  gp << "plot $d using (0.5*$2):1:(0.5*$2):(0.38):ytic(3) with boxxyerror lc rgb '#1f77b4' notitle, "
     << "$d using 2:1:4 with labels left offset 0.5,0 notitle\n";
  render_png(png, gp.str(), 900, 80 + 45 * static_cast<int>(stage_seconds.size()) + 120);
}

void coloured_table_chart(const fs::path& png, const std::string& title, const std::vector<std::string>& row_names,
                          const std::vector<std::string>& column_names,
                          const std::vector<std::vector<ColouredCell>>& cells) {
  std::ostringstream gp;
  gp << "$d << EOD\n";
  for (size_t r = 0; r < row_names.size(); ++r)
    for (size_t c = 0; c < column_names.size(); ++c) {
      const ColouredCell cell = r < cells.size() && c < cells[r].size() ? cells[r][c] : ColouredCell{};
      gp << c << " " << r << " " << cell.colour << " " << data_string(cell.label.empty() ? "not run" : cell.label)
         << "\n";
    }
  gp << "EOD\n";
  const double rows = static_cast<double>(row_names.size()), cols = static_cast<double>(column_names.size());
  gp << "set title " << quoted(title) << "\nunset key\nset border 0\nset xrange [-0.5:" << cols - 0.5
     << "]\nset yrange [" << rows - 0.5 << ":-0.5]\nset x2tics nomirror scale 0 (";
  for (size_t c = 0; c < column_names.size(); ++c) gp << (c ? ", " : "") << tic_label(column_names[c]) << " " << c;
  gp << ")\nunset xtics\nset ytics nomirror scale 0 (";
  for (size_t r = 0; r < row_names.size(); ++r) gp << (r ? ", " : "") << tic_label(row_names[r]) << " " << r;
  gp << ")\nset style fill solid 1.0 border lc rgb 'white'\n";
  gp << "plot $d using 1:2:(0.5):(0.5):3 with boxxyerror lc rgb variable, "
     << "$d using 1:2:4 with labels font 'Sans,9'\n";
  render_png(png, gp.str(), 320 + 330 * static_cast<int>(column_names.size()),
             120 + 34 * static_cast<int>(row_names.size()));
}

}  // namespace shellfrac::tools::charts
