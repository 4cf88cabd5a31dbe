#pragma once
// CSV tables and gnuplot charts for the benchmark tooling (`shellfrac bench`): the numbers behind the
// charts (convergence-order fits, Pareto fronts) and the PNG files drawn by calling gnuplot.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace shellfrac::tools::charts {

// A table written as CSV: a header and rows of already formatted cells.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  void add(std::vector<std::string> row) { rows.push_back(std::move(row)); }
};

// "1.2345678e-05"-style number with 9 significant digits ("nan" for NaN), for CSV cells.
std::string number(double v);
// Quotes a CSV cell when it holds a comma, quote or newline.
std::string csv_cell(const std::string& s);
std::string to_csv(const CsvTable& table);
// Writes the table atomically (temporary file, then rename).
void write_csv(const std::filesystem::path& path, const CsvTable& table);

// Least-squares line log(error) = order * log(h) + log_constant through points with h > 0 and
// error > 0. `order` is NaN when fewer than two usable points with distinct h remain.
struct ConvergenceFit {
  double order = 0;
  double log_constant = 0;
  int points = 0;  // points used
};
ConvergenceFit fit_convergence_order(const std::vector<double>& h, const std::vector<double>& error);

// Pareto front of (cost, error) pairs, both to be minimised: result[i] is true when no other point is at
// least as cheap and at least as accurate and strictly better in one of the two. Points with a
// non-finite value are never on the front.
std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error);

// gnuplot is missing (the error names the Debian package to install).
class ChartError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

bool gnuplot_available();
// Runs a gnuplot script (without terminal/output lines) and renames its output into `png` only when
// gnuplot succeeded. Throws ChartError when gnuplot is missing or fails.
void render_png(const std::filesystem::path& png, const std::string& script, int width = 900, int height = 600);

// One series of points of a chart.
struct Series {
  std::string title;
  std::vector<double> x, y;
};

// Log-log scatter of error against cost, one colour per series, with the Pareto front of all points
// drawn as a step line through the front's points.
void error_vs_cost_chart(const std::filesystem::path& png, const std::string& title, const std::string& cost_label,
                         const std::vector<Series>& series);

// Log-log error against resolution (cells per side) per series, with each series's fitted line; the
// legend names the fitted order.
void error_vs_resolution_chart(const std::filesystem::path& png, const std::string& title,
                               const std::vector<Series>& series, const std::vector<ConvergenceFit>& fits);

// Horizontal bars of seconds per named stage with their share of the total (thesis Fig. 4.28).
void stage_breakdown_chart(const std::filesystem::path& png, const std::string& title,
                           const std::vector<std::pair<std::string, double>>& stage_seconds);

// A coloured table: rows x columns of cells, each with a short label and a colour (0xRRGGBB); an empty
// label leaves the cell grey ("not run").
struct ColouredCell {
  std::string label;
  unsigned colour = 0xdddddd;
};
void coloured_table_chart(const std::filesystem::path& png, const std::string& title,
                          const std::vector<std::string>& row_names, const std::vector<std::string>& column_names,
                          const std::vector<std::vector<ColouredCell>>& cells);

}  // namespace shellfrac::tools::charts
