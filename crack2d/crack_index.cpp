#include "crack2d/crack_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::crack2d {

namespace {
constexpr int kMaxCellsPerSide = 512;
constexpr int kMinCellsPerSide = 4;
constexpr double kPadFraction = 1e-7;  // of a cell; covers round-off in the row/column arithmetic
}  // namespace

CrackIndex::CrackIndex(const Box& domain) : domain_(domain) {
  // Guard against an empty domain so cell sizes stay positive.
  for (int k = 0; k < 2; ++k)
    if (!(domain_.hi[k] > domain_.lo[k])) domain_.hi[k] = domain_.lo[k] + 1.0;
  resize_grid();
}

// By the reciprocal cell size (no division in the queries' inner loops). Insertion and queries use the
// same functions and the rasterisation is padded, so a cell boundary moved by round-off misses nothing.
int CrackIndex::column(double x) const {
  const double c = std::floor((x - domain_.lo.x()) * inv_cell_w_);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(nx_ - 1)));
}

int CrackIndex::row(double y) const {
  const double r = std::floor((y - domain_.lo.y()) * inv_cell_h_);
  return static_cast<int>(std::clamp(r, 0.0, static_cast<double>(ny_ - 1)));
}

void CrackIndex::resize_grid() {
  const Point extent = domain_.hi - domain_.lo;
  double mean_length = 0.0;
  for (const Segment& s : segments_) mean_length += (s.b - s.a).norm();
  int nx = kMinCellsPerSide, ny = kMinCellsPerSide;
  if (!segments_.empty() && mean_length > 0.0) {
    mean_length /= static_cast<double>(segments_.size());
    const double target = 2.0 * mean_length;
    nx = static_cast<int>(std::clamp(std::ceil(extent.x() / target), double(kMinCellsPerSide), double(kMaxCellsPerSide)));
    ny = static_cast<int>(std::clamp(std::ceil(extent.y() / target), double(kMinCellsPerSide), double(kMaxCellsPerSide)));
    // Empty buckets cost memory; keep the cell count within a small multiple of the segment count.
    const double budget = std::max(1024.0, 16.0 * static_cast<double>(segments_.size()));
    while (static_cast<double>(nx) * ny > budget && (nx > kMinCellsPerSide || ny > kMinCellsPerSide)) {
      nx = std::max(kMinCellsPerSide, nx / 2);
      ny = std::max(kMinCellsPerSide, ny / 2);
    }
  }
  nx_ = nx;
  ny_ = ny;
  cell_w_ = extent.x() / nx_;
  cell_h_ = extent.y() / ny_;
  inv_cell_w_ = 1.0 / cell_w_;
  inv_cell_h_ = 1.0 / cell_h_;
  cells_.assign(static_cast<size_t>(nx_) * ny_, {});
  for (size_t i = 0; i < segments_.size(); ++i) insert(static_cast<uint32_t>(i));
  grid_sized_for_ = segments_.size();
}

template <class Visit>
bool CrackIndex::for_each_cell_on_segment(const Point& a, const Point& b, Visit&& visit) const {
  const double pad_x = kPadFraction * cell_w_, pad_y = kPadFraction * cell_h_;
  const double y_min = std::min(a.y(), b.y()), y_max = std::max(a.y(), b.y());
  const double x_min = std::min(a.x(), b.x()), x_max = std::max(a.x(), b.x());
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  const int r0 = row(y_min - pad_y), r1 = row(y_max + pad_y);
  for (int r = r0; r <= r1; ++r) {
    // The part of the segment inside this row's (padded) band, as an x interval.
    const double band_lo = r == 0 ? y_min : std::max(y_min, domain_.lo.y() + r * cell_h_ - pad_y);
    const double band_hi = r == ny_ - 1 ? y_max : std::min(y_max, domain_.lo.y() + (r + 1) * cell_h_ + pad_y);
    double lo = x_min, hi = x_max;
    if (dy != 0.0 && r0 != r1) {
      const double xa = a.x() + (band_lo - a.y()) * (dx / dy);
      const double xb = a.x() + (band_hi - a.y()) * (dx / dy);
      lo = std::max(x_min, std::min(xa, xb));
      hi = std::min(x_max, std::max(xa, xb));
    }
    const int c0 = column(lo - pad_x), c1 = column(hi + pad_x);
    for (int c = c0; c <= c1; ++c)
      if (visit(static_cast<size_t>(r) * nx_ + c)) return true;
  }
  return false;
}

void CrackIndex::insert(uint32_t id) {
  const Segment& s = segments_[id];
  for_each_cell_on_segment(s.a, s.b, [&](size_t cell) {
    cells_[cell].push_back(id);
    return false;
  });
}

void CrackIndex::rebuild(const CrackGraph& g) {
  segments_.clear();
  segments_.reserve(g.num_edges());
  for (size_t e = 0; e < g.num_edges(); ++e) segments_.push_back(g.segment(e));
  resize_grid();
}

void CrackIndex::add_edges(const CrackGraph& g, size_t first_edge) {
  // Edges below num_segments() are indexed already; starting there (not at first_edge) never leaves a gap.
  (void)first_edge;
  const size_t begin = segments_.size();
  for (size_t e = begin; e < g.num_edges(); ++e) segments_.push_back(g.segment(e));
  if (segments_.size() > 2 * grid_sized_for_ + 64) {
    resize_grid();
    return;
  }
  for (size_t e = begin; e < segments_.size(); ++e) insert(static_cast<uint32_t>(e));
}

bool CrackIndex::crosses(const Point& a, const Point& b) const {
  if (segments_.empty()) return false;
  return for_each_cell_on_segment(a, b, [&](size_t cell) {
    for (uint32_t id : cells_[cell])
      if (segments_intersect(a, b, segments_[id].a, segments_[id].b)) return true;
    return false;
  });
}

bool CrackIndex::touches(const Box& box, size_t first_edge) const {
  if (first_edge >= segments_.size()) return false;
  const double pad_x = kPadFraction * cell_w_, pad_y = kPadFraction * cell_h_;
  const int c0 = column(box.lo.x() - pad_x), c1 = column(box.hi.x() + pad_x);
  const int r0 = row(box.lo.y() - pad_y), r1 = row(box.hi.y() + pad_y);
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      for (uint32_t id : cells_[static_cast<size_t>(r) * nx_ + c])
        if (id >= first_edge && segment_intersects_box(segments_[id], box)) return true;
  return false;
}

std::vector<uint32_t> CrackIndex::segments_near(const Box& box) const {
  std::vector<uint32_t> ids;
  if (segments_.empty()) return ids;
  const double pad_x = kPadFraction * cell_w_, pad_y = kPadFraction * cell_h_;
  const int c0 = column(box.lo.x() - pad_x), c1 = column(box.hi.x() + pad_x);
  const int r0 = row(box.lo.y() - pad_y), r1 = row(box.hi.y() + pad_y);
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      for (uint32_t id : cells_[static_cast<size_t>(r) * nx_ + c]) ids.push_back(id);
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

double CrackIndex::distance(const Point& p, double max_distance) const { return nearest(p, max_distance).distance; }

CrackIndex::Nearest CrackIndex::nearest(const Point& p, double max_distance) const {
  Nearest best{max_distance, -1, p};
  if (segments_.empty()) return best;
  const int pc = column(p.x()), pr = row(p.y());
  const double ring_step = std::min(cell_w_, cell_h_);
  const int max_ring = std::max(nx_, ny_);
  auto scan = [&](int r, int c) {
    for (uint32_t id : cells_[static_cast<size_t>(r) * nx_ + c]) {
      const Segment& s = segments_[id];
      const Point d = s.b - s.a;
      const double len2 = d.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((p - s.a).dot(d) / len2, 0.0, 1.0) : 0.0;
      const Point q = s.a + t * d;
      const double dist = (q - p).norm();
      if (dist < best.distance || (dist == best.distance && best.segment >= 0 && static_cast<int>(id) < best.segment))
        best = {dist, static_cast<int>(id), q};
    }
  };
  for (int ring = 0; ring <= max_ring; ++ring) {
    // Clamping is 1-Lipschitz in the index, so any segment first seen in ring k is at least (k-1) cells away.
    if (ring >= 1 && (ring - 1) * ring_step > best.distance) break;
    const int r_lo = pr - ring, r_hi = pr + ring, c_lo = pc - ring, c_hi = pc + ring;
    for (int r = std::max(r_lo, 0); r <= std::min(r_hi, ny_ - 1); ++r) {
      const bool edge_row = (r == r_lo || r == r_hi);
      if (edge_row) {
        for (int c = std::max(c_lo, 0); c <= std::min(c_hi, nx_ - 1); ++c) scan(r, c);
      } else {
        if (c_lo >= 0) scan(r, c_lo);
        if (c_hi < nx_ && c_hi != c_lo) scan(r, c_hi);
      }
    }
  }
  return best;
}

}  // namespace shellfrac::crack2d
