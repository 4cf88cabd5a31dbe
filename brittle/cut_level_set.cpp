// OpenVDB level-set cutting (thesis sec. 3.5.2, Fig. 3.9e and f) and the dispatch between the cutters.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/GridTransformer.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <cmath>
#include <mutex>
#include <sstream>

#include "brittle/errors.hpp"
#include "brittle/fragments.hpp"

namespace shellfrac::brittle {

FragmentSet cut_fragments_exact(const TriMesh& domain, const VoronoiDiagram& diagram, const Regions& regions,
                                const FragmentOptions& o, const std::string& source);

namespace {

constexpr float kHalfWidth = 3.0f;  // narrow band, voxels each side

void init_vdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

void to_vdb(const TriMesh& m, std::vector<openvdb::Vec3s>& p, std::vector<openvdb::Vec3I>& t) {
  p.clear();
  t.clear();
  for (const Vec3& v : m.positions) p.emplace_back(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
  for (const Tri& tri : m.triangles) t.emplace_back(static_cast<unsigned>(tri[0]), static_cast<unsigned>(tri[1]), static_cast<unsigned>(tri[2]));
}

openvdb::FloatGrid::Ptr level_set(const TriMesh& m, const openvdb::math::Transform& xform, float half_width = kHalfWidth) {
  std::vector<openvdb::Vec3s> p;
  std::vector<openvdb::Vec3I> t;
  to_vdb(m, p, t);
  return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(xform, p, t, half_width);
}

// Surface of the zero level set, outward, as triangles (quads split).
TriMesh mesh_of(const openvdb::FloatGrid& grid) {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(grid, points, tris, quads, 0.0, 0.0);
  TriMesh m;
  for (const auto& p : points) m.positions.emplace_back(p.x(), p.y(), p.z());
  for (const auto& t : tris) m.triangles.emplace_back(static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2]));
  for (const auto& q : quads) {
    m.triangles.emplace_back(static_cast<int>(q[0]), static_cast<int>(q[1]), static_cast<int>(q[2]));
    m.triangles.emplace_back(static_cast<int>(q[0]), static_cast<int>(q[2]), static_cast<int>(q[3]));
  }
  // volumeToMesh winds faces the other way round from our outward convention: flip if inside out.
  if (mass_properties(m, 1.0).volume < 0)
    for (Tri& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

}  // namespace

double level_set_cut_bytes(double voxel, double area) {
  const double voxels = area / (voxel * voxel) * 2.0 * kHalfWidth;
  return voxels * 12.0;  // float value + topology overhead of the sparse tree
}

namespace {

// Refuses a voxel that would need more than the limit for a narrow band around `area` of surface.
void check_voxel(double voxel, double area, size_t limit, const std::string& what) {
  if (!(voxel > 0) || !std::isfinite(voxel)) throw InputError(what + ": voxel size must be > 0");
  const double bytes = level_set_cut_bytes(voxel, area);
  if (bytes > static_cast<double>(limit)) {
    std::ostringstream m;
    m << what << ": voxel size " << voxel << " m is too small: its level sets would need about " << bytes / 1e9
      << " GB (limit " << limit / 1e9 << " GB); use a voxel of at least " << voxel * std::sqrt(bytes / static_cast<double>(limit))
      << " m";
    throw InputError(m.str());
  }
}

double default_voxel(const TriMesh& domain) {
  Vec3 lo, hi;
  bounding_box(domain, lo, hi);
  return (hi - lo).norm() / 200.0;
}

}  // namespace

FragmentSet cut_fragments(const TriMesh& domain, const VoronoiDiagram& diagram, const Regions& regions,
                          const FragmentOptions& o, const std::string& source) {
  require_closed_solid(domain, source);
  FragmentSet set;
  if (regions.count == 0 || diagram.num_cells() == 0) {  // nothing extracted: the object is one fragment
    set.cutter = o.cutter;
    set.input_volume = mass_properties(domain, 1.0).volume;
    TriMesh whole = domain;
    whole.normals.clear();
    whole.uvs.clear();
    add_fragments(set, whole, -1, domain, o, 1e-9);
    finish_fragments(set, domain.name);
    return set;
  }
  {  // The regions partition the Voronoi container: material outside it would be lost without a word.
    Vec3 lo, hi;
    bounding_box(domain, lo, hi);
    if ((lo.array() < diagram.box_lo.array()).any() || (hi.array() > diagram.box_hi.array()).any()) {
      std::ostringstream m;
      m << source << ": mesh '" << domain.name << "' (box " << lo.transpose() << " .. " << hi.transpose()
        << ") reaches outside the Voronoi container (" << diagram.box_lo.transpose() << " .. " << diagram.box_hi.transpose()
        << "); extract the crack with CrackExtractionOptions::cover_lo/hi set to the mesh's box";
      throw NumericalError(m.str());
    }
  }
  if (o.cutter == Cutter::Exact) {
    set = cut_fragments_exact(domain, diagram, regions, o, source);
    finish_fragments(set, domain.name);
    return set;
  }
  init_vdb();
  const double voxel = o.voxel > 0 ? o.voxel : default_voxel(domain);
  check_voxel(voxel, 3.0 * surface_area(domain), o.memory_limit, source + ": level-set cutter");
  set.cutter = Cutter::LevelSet;
  set.voxel = voxel;
  set.input_volume = mass_properties(domain, 1.0).volume;
  const auto xform = openvdb::math::Transform::createLinearTransform(voxel);
  const openvdb::FloatGrid::Ptr domain_ls = level_set(domain, *xform);
  for (int r = 0; r < regions.count; ++r) {
    const openvdb::FloatGrid::Ptr region_ls = level_set(region_boundary(diagram, regions, r), *xform);
    const openvdb::FloatGrid::Ptr piece = openvdb::tools::csgIntersectionCopy(*domain_ls, *region_ls);
    if (piece->activeVoxelCount() == 0) continue;
    TriMesh cut = mesh_of(*piece);
    if (cut.triangles.empty()) continue;
    // Vertices on the input surface are within about a voxel of it.
    add_fragments(set, cut, r, domain, o, 0.75 * voxel);
  }
  finish_fragments(set, domain.name);
  return set;
}

FragmentSet cut_thickened_crack(const TriMesh& domain, const TriMesh& crack, double width, const FragmentOptions& o,
                                const std::string& source) {
  require_closed_solid(domain, source);
  if (!(width > 0)) throw InputError(source + ": thickened crack width must be > 0");
  init_vdb();
  const double voxel = o.voxel > 0 ? o.voxel : 0.5 * width;
  check_voxel(voxel, 3.0 * (surface_area(domain) + 2.0 * surface_area(crack)), o.memory_limit, source + ": thickened-crack cutter");
  FragmentSet set;
  set.cutter = Cutter::LevelSet;
  set.voxel = voxel;
  set.input_volume = mass_properties(domain, 1.0).volume;
  const auto xform = openvdb::math::Transform::createLinearTransform(voxel);
  const float half = static_cast<float>(0.5 * width / voxel);  // half width in voxels
  openvdb::FloatGrid::Ptr solid = level_set(domain, *xform, kHalfWidth + half);
  if (!crack.triangles.empty()) {
    std::vector<openvdb::Vec3s> p;
    std::vector<openvdb::Vec3I> t;
    std::vector<openvdb::Vec4I> q;
    to_vdb(crack, p, t);
    // Unsigned distance d to the (open, possibly non-manifold) crack surface; d - w/2 is the signed
    // distance of the thickened sheet.
    openvdb::FloatGrid::Ptr sheet = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*xform, p, t, q, kHalfWidth + half);
    const float shift = static_cast<float>(0.5 * width);
    for (auto it = sheet->beginValueOn(); it; ++it) it.setValue(it.getValue() - shift);
    sheet->tree().root().setBackground(sheet->background() - shift, true);
    sheet->setGridClass(openvdb::GRID_LEVEL_SET);
    solid = openvdb::tools::csgDifferenceCopy(*solid, *sheet);
  }
  // One surface for everything; split_solids (in add_fragments) separates the pieces and keeps a gap
  // that does not reach the surface as a cavity of its piece (segmenting the level set instead would
  // make the cavity's surface a piece of its own).
  const TriMesh cut = mesh_of(*solid);
  if (!cut.triangles.empty()) add_fragments(set, cut, -1, domain, o, 0.75 * voxel);
  finish_fragments(set, domain.name);
  return set;
}

TriMesh clip_to_domain(const TriMesh& crack, const TriMesh& domain, double voxel) {
  init_vdb();
  TriMesh out;
  out.name = crack.name;
  if (crack.triangles.empty()) return out;
  const auto xform = openvdb::math::Transform::createLinearTransform(voxel);
  const openvdb::FloatGrid::Ptr ls = level_set(domain, *xform);
  // Inside the band the value is the distance; beyond it the background, whose sign openvdb keeps by
  // marking interior tiles (negative background inside after meshToLevelSet's sign flood fill).
  const auto acc = ls->getConstAccessor();
  auto phi = [&](const Vec3& x) {
    const openvdb::Vec3d ijk = xform->worldToIndex(openvdb::Vec3d(x.x(), x.y(), x.z()));
    // Trilinear interpolation of the eight voxel values around x.
    const openvdb::Coord c(static_cast<int>(std::floor(ijk.x())), static_cast<int>(std::floor(ijk.y())), static_cast<int>(std::floor(ijk.z())));
    const double fx = ijk.x() - c.x(), fy = ijk.y() - c.y(), fz = ijk.z() - c.z();
    double v = 0;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx)
          v += (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz) * acc.getValue(c.offsetBy(dx, dy, dz));
    return v;
  };
  std::vector<double> value(crack.positions.size());
  for (size_t v = 0; v < crack.positions.size(); ++v) value[v] = phi(crack.positions[v]);
  // Split each triangle at the zero crossings along its edges (linear interpolation) and keep the
  // inside part (phi < 0).
  for (const Tri& t : crack.triangles) {
    std::vector<Vec3> poly;
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const double pa = value[static_cast<size_t>(a)], pb = value[static_cast<size_t>(b)];
      if (pa < 0) poly.push_back(crack.positions[static_cast<size_t>(a)]);
      if ((pa < 0) != (pb < 0)) {
        // Bisection: beyond the narrow band the field is clamped, so a linear guess along a long edge
        // would miss the surface; the sign is right everywhere.
        Vec3 in = crack.positions[static_cast<size_t>(pa < 0 ? a : b)], outside = crack.positions[static_cast<size_t>(pa < 0 ? b : a)];
        while ((outside - in).norm() > 0.01 * voxel) {
          const Vec3 mid = 0.5 * (in + outside);
          (phi(mid) < 0 ? in : outside) = mid;
        }
        poly.push_back(0.5 * (in + outside));
      }
    }
    if (poly.size() < 3) continue;
    const int first = static_cast<int>(out.positions.size());
    out.positions.insert(out.positions.end(), poly.begin(), poly.end());
    for (size_t i = 1; i + 1 < poly.size(); ++i) out.triangles.emplace_back(first, first + static_cast<int>(i), first + static_cast<int>(i) + 1);
  }
  return out;
}

}  // namespace shellfrac::brittle
