#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

#include "brittle/fragments.hpp"
#include "brittle/triangle_index.hpp"
#include "core/union_find.hpp"

namespace shellfrac::brittle {

const char* to_string(Cutter c) { return c == Cutter::Exact ? "exact" : "level_set"; }

double FragmentSet::total_volume() const {
  double v = 0;
  for (const Fragment& f : fragments) v += f.properties.volume;
  return v;
}

double FragmentSet::volume_change() const { return input_volume > 0 ? (total_volume() - input_volume) / input_volume : 0.0; }

namespace {

// Generalised winding number of a closed mesh around x (1 inside, 0 outside).
double winding(const TriMesh& m, const Vec3& x) {
  double w = 0;
  for (const Tri& t : m.triangles) {
    const Vec3 a = m.positions[t[0]] - x, b = m.positions[t[1]] - x, c = m.positions[t[2]] - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    w += 2.0 * std::atan2(num, den);
  }
  return w / (4.0 * 3.14159265358979323846);
}

TriMesh submesh(const TriMesh& m, const std::vector<size_t>& tris) {
  TriMesh out;
  std::map<int, int> remap;
  for (size_t t : tris) {
    Tri nt;
    for (int k = 0; k < 3; ++k) {
      const int v = m.triangles[t][k];
      auto it = remap.find(v);
      if (it == remap.end()) {
        it = remap.emplace(v, static_cast<int>(out.positions.size())).first;
        out.positions.push_back(m.positions[static_cast<size_t>(v)]);
      }
      nt[k] = it->second;
    }
    out.triangles.push_back(nt);
  }
  return out;
}

}  // namespace

std::vector<TriMesh> split_solids(const TriMesh& mesh) {
  // Weld by position (cut meshes share exact coordinates along seams), then union triangles over vertices.
  std::map<std::tuple<double, double, double>, int> weld;
  std::vector<int> id(mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3& p = mesh.positions[v];
    id[v] = weld.emplace(std::make_tuple(p.x(), p.y(), p.z()), static_cast<int>(weld.size())).first->second;
  }
  core::UnionFind sets(weld.size());
  for (const Tri& t : mesh.triangles)
    for (int k = 1; k < 3; ++k) sets.unite(static_cast<size_t>(id[static_cast<size_t>(t[0])]), static_cast<size_t>(id[static_cast<size_t>(t[k])]));
  std::map<size_t, std::vector<size_t>> groups;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) groups[sets.find(static_cast<size_t>(id[static_cast<size_t>(mesh.triangles[t][0])]))].push_back(t);
  std::vector<TriMesh> solids, cavities;
  for (const auto& [root, tris] : groups) {
    TriMesh part = submesh(mesh, tris);
    const double v = mass_properties(part, 1.0).volume;
    if (v > 0) solids.push_back(std::move(part));
    else if (v < 0) cavities.push_back(std::move(part));
  }
  // Each cavity joins the smallest solid that encloses it.
  for (TriMesh& cav : cavities) {
    int best = -1;
    double best_v = std::numeric_limits<double>::infinity();
    for (size_t s = 0; s < solids.size(); ++s) {
      if (winding(solids[s], cav.positions.front()) < 0.5) continue;
      const double v = mass_properties(solids[s], 1.0).volume;
      if (v < best_v) {
        best_v = v;
        best = static_cast<int>(s);
      }
    }
    if (best >= 0) solids[static_cast<size_t>(best)].append(cav);
  }
  return solids;
}

size_t transfer_attributes(TriMesh& piece, const TriMesh& domain, double tol, double uv_scale, std::vector<char>* crack_faces) {
  Vec3 lo, hi;
  bounding_box(domain, lo, hi);
  const TriangleIndex index(domain.positions, domain.triangles, std::max((hi - lo).norm() / 64.0, 4.0 * tol), tol);
  TriMesh out;
  out.name = piece.name;
  std::map<std::tuple<int, double, double, double, double, double>, int> corners;
  size_t crack = 0;
  for (const Tri& t : piece.triangles) {
    const Vec3 &a = piece.positions[t[0]], &b = piece.positions[t[1]], &c = piece.positions[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const Vec3 nn = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
    const TriangleIndex::Hit hit = index.closest((a + b + c) / 3.0, tol);
    const bool on_input = hit.found && index.triangle_normal(hit.triangle).dot(nn) > 0.9;
    if (!on_input) ++crack;
    if (crack_faces) crack_faces->push_back(on_input ? 0 : 1);
    Tri nt;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = piece.positions[t[k]];
      Vec3 normal = nn;
      Vec2 uv;
      if (on_input) {
        const Tri& src = domain.triangles[static_cast<size_t>(hit.triangle)];
        Vec3 bc;
        closest_point_on_triangle(p, domain.positions[src[0]], domain.positions[src[1]], domain.positions[src[2]], &bc);
        if (domain.has_normals()) normal = (bc[0] * domain.normals[src[0]] + bc[1] * domain.normals[src[1]] + bc[2] * domain.normals[src[2]]).normalized();
        uv = domain.has_uvs() ? Vec2(bc[0] * domain.uvs[src[0]] + bc[1] * domain.uvs[src[1]] + bc[2] * domain.uvs[src[2]]) : Vec2(0, 0);
      } else {
        // Box projection along the dominant normal axis.
        int axis;
        nn.cwiseAbs().maxCoeff(&axis);
        uv = Vec2(p[(axis + 1) % 3], p[(axis + 2) % 3]) / uv_scale;
      }
      const auto key = std::make_tuple(t[k], normal.x(), normal.y(), normal.z(), uv.x(), uv.y());
      auto it = corners.find(key);
      if (it == corners.end()) {
        it = corners.emplace(key, static_cast<int>(out.positions.size())).first;
        out.positions.push_back(p);
        out.normals.push_back(normal);
        out.uvs.push_back(uv);
      }
      nt[k] = it->second;
    }
    out.triangles.push_back(nt);
  }
  piece = std::move(out);
  return crack;
}

void add_fragments(FragmentSet& set, const TriMesh& cut, int region, const TriMesh& domain, const FragmentOptions& o, double tol) {
  for (TriMesh& solid : split_solids(cut)) {
    Fragment f;
    f.region = region;
    f.properties = mass_properties(solid, o.density);
    f.crack_triangles = transfer_attributes(solid, domain, tol, o.uv_scale, &f.crack_faces);
    f.mesh = std::move(solid);
    set.fragments.push_back(std::move(f));
  }
}

void finish_fragments(FragmentSet& set, const std::string& base) {
  std::stable_sort(set.fragments.begin(), set.fragments.end(),
                   [](const Fragment& a, const Fragment& b) { return a.properties.volume > b.properties.volume; });
  for (size_t k = 0; k < set.fragments.size(); ++k) set.fragments[k].mesh.name = (base.empty() ? "object" : base) + "_fragment_" + std::to_string(k);
}

}  // namespace shellfrac::brittle
