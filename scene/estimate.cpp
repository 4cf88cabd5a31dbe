// The resource estimate of a scene (scene/estimate.hpp). The bytes per element below are set from
// measurements of this build (peak resident memory of `run` over one step and the first frame, less the
// program's own 45 MB) and rounded up, so the estimate errs on the large side: a flat sheet of 200^2
// cells rendered at 400^2 peaked at 778 MiB (about 300 bytes per quadrature point); box solids of 1e6
// to 8e6 particles at 650 to 675 bytes per particle; level sets of 2e6 to 2.3e7 narrow-band voxels at
// 38 to 48 bytes per voxel (OpenVDB's distance and closest-triangle grids while the band is built);
// renders of the default sheet at 1024^2, 2048^2 and 4096^2 peaked at 319 MiB, 1.15 GiB and 4.59 GiB
// (270 to 291 bytes per render vertex) and wrote 164, 175 and 183 bytes of OBJ per vertex (2026-12-04;
// the bytes grow with the digits of the indices).
// The element counts follow the build: a flat or curved patch
// is quadratic with cells + 2 control points per direction (cells + pieces + 1 around a cylinder or
// cone, whose arc is made of rational pieces of at most 90 degrees), a control net gains (refine - 1)
// control points per non-empty knot span, each cell carries points^2 x layers quadrature points and one
// shear particle. The grid blocks of a shell are counted from its particles' positions (the patch's
// control net and cell centres, built as the build builds them) when there are at most a few million.
// A solid has volume / spacing^3 particles (the jittered and Poisson-disk samplers keep about one per
// spacing^3 cell inside the shape); a mesh level set has the voxels of a band of 2 x band_voxels voxels
// around the surface (meshToLevelSet fills band_voxels on each side, nothing deeper inside), at most
// the voxels of the mesh's bounding box grown by the band.
#include "scene/estimate.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <Eigen/Geometry>
#include <filesystem>
#include <unordered_set>

#include "core/constants.hpp"
#include "scene/build_context.hpp"
#include "scene/field_checks.hpp"
#include "scene/mesh_import.hpp"
#include "scene/quality.hpp"
#include "scene/range.hpp"
#include "scene/scene_error.hpp"
#include "scene/validate.hpp"

namespace shellfrac::scene {

namespace {

constexpr double kBaseBytes = 64.0 * (1 << 20);   // the program, its libraries and thread stacks
constexpr double kControlPointBytes = 400;         // positions, velocities, masses, forces, pins, MLS data
constexpr double kQuadraturePointBase = 180;       // F, stress, damage, plastic state, positions
constexpr double kBasisFunctionBytes = 14;         // per support function and point (bases are shared per cell)
constexpr double kShearParticleBytes = 600;
constexpr double kSolidParticleBytes = 700;        // measured 650 to 675 over the first step (box of 8e6: 5.1 GiB)
constexpr double kGridBlockBytes = 64 * 160.0;     // a 4^3 block of nodes: mass, momentum, velocity, force, ...
constexpr double kRenderVertexBytes = 320;         // tessellation, shadow vertices, faces and the exporter's text
constexpr double kLevelSetVoxelBytes = 48;         // distance and closest-triangle grids with tree overhead
constexpr double kDiskBytesPerRenderVertex = 200;  // OBJ text: v, vt, vn lines and a share of the faces
// The sparse grid packs block coordinates in 21 bits (mpm/sparse_grid.cpp): |x| / (4 dx) < 2^20.
constexpr double kGridReachCells = 4.0 * (1 << 20);

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  void add(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool empty() const { return lo.x() > hi.x(); }
  double reach() const { return empty() ? 0.0 : std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()); }
};

Eigen::Vector3d vec(const Vec3& v) { return {v[0], v[1], v[2]}; }
double norm(const Opt<Vec3>& v) { return v ? vec(*v).norm() : 0.0; }

// Non-empty spans of a knot vector of the given degree, or 0 when it is too short.
int knot_spans(const std::vector<double>& k, int degree) {
  int spans = 0;
  const size_t d = static_cast<size_t>(degree);
  for (size_t i = d; i + d + 1 < k.size(); ++i)  // spans of the domain [k_p, k_{n}]
    if (k[i + 1] > k[i]) ++spans;
  return spans;
}

// What the estimate needs of one shell.
struct ShellSize {
  double control_points = 0, cells = 0, support = 9, area = 0, thickness = 0;
  int degree = 2;  // the larger of the two directions
  Box box;
  std::string count_path;  // cells or refine
};

ShellSize shell_size(const Shell& s, size_t i) {
  const std::string path = "/shells/" + std::to_string(i) + "/patch";
  const Patch& p = *s.patch;
  ShellSize out;
  out.thickness = *s.thickness;
  const Eigen::Vector3d origin = p.origin ? vec(*p.origin) : Eigen::Vector3d::Zero();
  if (p.type == "control_net") {
    const int du = (*p.degree)[0], dv = (*p.degree)[1];
    const Int2 refine = p.refine.value_or(Int2{1, 1}), elevate = p.elevate.value_or(Int2{0, 0});
    const double su = knot_spans(*p.knots_u, du), sv = knot_spans(*p.knots_v, dv);
    // Elevation by t adds t control points per span (each breakpoint's multiplicity and the ends grow by t).
    const double nu = std::max(0.0, static_cast<double>(p.knots_u->size()) - du - 1) + (refine[0] - 1) * su + elevate[0] * su;
    const double nv = std::max(0.0, static_cast<double>(p.knots_v->size()) - dv - 1) + (refine[1] - 1) * sv + elevate[1] * sv;
    out.control_points = nu * nv;
    out.cells = su * refine[0] * sv * refine[1];
    out.degree = std::max(du + elevate[0], dv + elevate[1]);
    out.support = (du + elevate[0] + 1.0) * (dv + elevate[1] + 1.0);
    const auto& pts = *p.control_points;
    for (const Vec3& c : pts) out.box.add(vec(c));
    // The control polygon's area bounds the surface's from above for the nets scenes use.
    const size_t cu = static_cast<size_t>(std::max(0.0, static_cast<double>(p.knots_u->size()) - du - 1));
    const size_t cv = cu ? pts.size() / cu : 0;
    for (size_t b = 0; b + 1 < cv; ++b)
      for (size_t a = 0; a + 1 < cu; ++a) {
        const Eigen::Vector3d p00 = vec(pts[a + cu * b]), p10 = vec(pts[a + 1 + cu * b]), p01 = vec(pts[a + cu * (b + 1)]);
        out.area += (p10 - p00).cross(p01 - p00).norm();
      }
    out.count_path = path + (p.refine ? "/refine" : "/knots_u");
    return out;
  }
  const double cu = (*p.cells)[0], cv = (*p.cells)[1];
  const Int2 degree = p.degree.value_or(Int2{2, 2});
  out.cells = cu * cv;
  out.count_path = path + "/cells";
  out.degree = std::max(degree[0], degree[1]);
  out.support = (degree[0] + 1.0) * (degree[1] + 1.0);
  if (p.type == "flat") {
    out.control_points = (cu + degree[0]) * (cv + degree[1]);
    out.area = (*p.size)[0] * (*p.size)[1];
    out.box.add(origin - Eigen::Vector3d::Constant((*p.size)[0] + (*p.size)[1]));
    out.box.add(origin + Eigen::Vector3d::Constant((*p.size)[0] + (*p.size)[1]));
    return out;
  }
  const double sweep = p.sweep_degrees.value_or(360.0) * core::kPi / 180.0;
  const double r0 = p.type == "cylinder" ? *p.radius : *p.radius_bottom;
  const double r1 = p.type == "cylinder" ? *p.radius : *p.radius_top;
  // The arc is rational quadratic in pieces of at most 90 degrees joined by double knots (2 pieces + 1
  // control points), each further cell adds one (nurbs::cone_segment); the axis is quadratic in cv cells.
  const double pieces = std::ceil(p.sweep_degrees.value_or(360.0) / 90.0 - 1e-10);
  // At degree p each piece carries p - 2 more points (the elevated arc), the axis cv + q.
  out.control_points = (cu + pieces * (degree[0] - 1) + 1) * (cv + degree[1]);
  out.area = 0.5 * (r0 + r1) * sweep * std::hypot(*p.height, r1 - r0);
  const double reach = std::max(r0, r1) + *p.height;
  out.box.add(origin - Eigen::Vector3d::Constant(reach));
  out.box.add(origin + Eigen::Vector3d::Constant(reach));
  return out;
}

// A mesh file's stats, or a SceneError at path/file as the build reports it.
MeshStats read_mesh(const Scene& scene, const MeshFile& m, const std::string& path) {
  std::filesystem::path file(*m.file);
  if (file.is_relative()) file = std::filesystem::path(scene.source).parent_path() / file;
  try {
    return mesh_stats(import_mesh(file.string(), m.scale.value_or(1.0), m.translate ? vec(*m.translate) : Eigen::Vector3d::Zero()));
  } catch (const std::exception& e) {
    throw SceneError(scene.source, path + "/file", file.string() + ": " + e.what());
  }
}

// The narrow-band voxels of a mesh level set: 2 x band voxels thick over the surface's area, but never
// more than the voxels of the bounding box grown by the band on every side (small or thin meshes).
double band_voxels(double area, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double voxel, double band) {
  const double sheet = area / (voxel * voxel) * 2.0 * band;
  const Eigen::Vector3d cells = ((hi - lo) / voxel).array() + 2.0 * band + 1.0;
  return std::min(sheet, cells.prod());
}

double wave_speed(double E, double nu, double density) { return std::sqrt(E / (density * (1 - nu * nu))); }

// The grid blocks that mpm::SparseGrid::rebuild activates for a set of particle positions: the block
// of each particle's stencil base node, floor(x / dx - 0.5), and its seven forward neighbours.
class GridBlocks {
 public:
  explicit GridBlocks(double dx) : inv_dx_(1.0 / dx) {}
  void add(const Eigen::Vector3d& x) {
    uint64_t key = 0;
    for (int d = 0; d < 3; ++d) {
      const long base = static_cast<long>(std::floor(x[d] * inv_dx_ - 0.5));
      const long block = base >= 0 ? base / 4 : -((-base + 3) / 4);
      key = (key << 21) | static_cast<uint64_t>(block + (1 << 20));
    }
    occupied_.insert(key);
  }
  size_t occupied() const { return occupied_.size(); }
  double active() const {
    std::vector<uint64_t> active;
    active.reserve(occupied_.size() * 8);
    constexpr uint64_t kMask = (1u << 21) - 1;
    for (const uint64_t k : occupied_)
      for (int d = 0; d < 8; ++d) {
        const uint64_t x = ((k >> 42) & kMask) + (d & 1), y = ((k >> 21) & kMask) + ((d >> 1) & 1), z = (k & kMask) + (d >> 2);
        active.push_back((x << 42) | (y << 21) | z);
      }
    std::sort(active.begin(), active.end());
    return static_cast<double>(std::unique(active.begin(), active.end()) - active.begin());
  }

 private:
  double inv_dx_;
  std::unordered_set<uint64_t> occupied_;
};

// Shells with at most this many grid particles and blocks (by the area formula) have their blocks
// counted from the particle positions (control points and the shear particles at the cell centres, as
// sim::World puts them on the grid; a few tens of MB at most); bigger ones (and memory bombs) use the
// area formula, which allocates nothing.
constexpr double kCountedParticles = 2e6, kCountedBlocks = 2e5;

// Adds a shell's grid particles to `blocks`: its control points, and its cell centres on the surface.
void add_shell_particles(const Scene& scene, const Shell& s, const std::string& path, GridBlocks& blocks) {
  const nurbs::NurbsSurface surface = detail::patch_surface(detail::Builder{scene}, *s.patch, path + "/patch");
  for (const auto& c : surface.control_points()) blocks.add(c);
  auto spans = [](const nurbs::KnotVector& k) {
    std::vector<double> mid;
    for (int i = k.degree(); i < k.num_basis(); ++i)
      if (k[i + 1] > k[i]) mid.push_back(0.5 * (k[i] + k[i + 1]));
    return mid;
  };
  for (const double v : spans(surface.knots_v()))
    for (const double u : spans(surface.knots_u())) blocks.add(surface.point(u, v));
}

// A solid's volume, surface area and bounds, and the level-set voxels of a mesh solid.
struct SolidSize {
  double volume = 0, area = 0, voxel = 0, band = 3;
  Box box;
};

SolidSize solid_size(const Scene& scene, size_t i) {
  const Solid& s = scene.solids[i];
  SolidSize out;
  if (s.shape == "mesh") {
    const MeshStats m = read_mesh(scene, s.mesh, "/solids/" + std::to_string(i));
    out.volume = std::abs(m.volume);
    out.area = m.area;
    out.voxel = s.mesh.voxel_size.value_or(0.5 * *s.spacing);
    out.band = s.mesh.band_voxels.value_or(3.0);
    out.box.add(m.lo);
    out.box.add(m.hi);
  } else if (s.shape == "sphere") {
    out.volume = 4.0 / 3.0 * core::kPi * std::pow(*s.radius, 3);
    out.box.add(vec(*s.center) - Eigen::Vector3d::Constant(*s.radius));
    out.box.add(vec(*s.center) + Eigen::Vector3d::Constant(*s.radius));
  } else {
    const Eigen::Vector3d h = vec(*s.half_extents);
    out.volume = 8.0 * h.prod();
    out.box.add(vec(*s.center) - h);
    out.box.add(vec(*s.center) + h);
  }
  return out;
}

// The step: the stability bound of sim/simulation.cpp (elastic waves, cfl, particle speed) and time.dt, with
// the scene path that sets it.
double stable_step(const Scene& scene, const std::vector<ShellSize>& shells, double grid_dx, std::string& dt_path) {
  const double cfl = scene.time.cfl.value_or(0.5);
  double bound = 1e300;
  std::string bound_path = "/time/dt";
  for (size_t i = 0; i < shells.size(); ++i) {
    const Material& m = *scene.shells[i].material;
    const double c = wave_speed(*m.youngs_modulus, *m.poisson_ratio, *m.density);
    const double h = std::min(grid_dx, shells[i].cells > 0 ? std::sqrt(shells[i].area / shells[i].cells) : grid_dx);
    const double b = std::min(h / c, std::sqrt(3.0) * h * h / (c * shells[i].thickness));
    if (b < bound) {
      bound = b;
      // The more extreme of stiffness and density names the problem.
      const std::string mat = "/shells/" + std::to_string(i) + "/material/";
      bound_path = mat + (std::abs(std::log10(*m.youngs_modulus / 1e6)) >= std::abs(std::log10(*m.density / 1e3)) ? "E" : "density");
    }
  }
  for (size_t i = 0; i < scene.solids.size(); ++i) {
    if (scene.solids[i].rigid_body) continue;  // the shatter loop's bodies: MPM runs only inside events
    const SolidMaterial& m = *scene.solids[i].material;
    const double E = *m.youngs_modulus, nu = *m.poisson_ratio;
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    const double b = grid_dx / std::sqrt((lambda + 2 * mu) / *m.density);
    if (b < bound) {
      bound = b;
      const std::string mat = "/solids/" + std::to_string(i) + "/material/";
      bound_path = mat + (std::abs(std::log10(E / 1e6)) >= std::abs(std::log10(*m.density / 1e3)) ? "E" : "density");
    }
  }
  double dt = cfl * bound;
  dt_path = scene.time.cfl && cfl < 1e-3 ? "/time/cfl" : bound_path;
  if (scene.time.enforce_stability_bound == false) {
    dt = *scene.time.dt;
    dt_path = "/time/dt";
  } else if (scene.time.dt && *scene.time.dt < dt) {
    dt = *scene.time.dt;
    dt_path = "/time/dt";
  }
  double vmax = 0;
  std::string v_path;
  for (size_t i = 0; i < scene.shells.size(); ++i)
    if (norm(scene.shells[i].initial_velocity) > vmax) {
      vmax = norm(scene.shells[i].initial_velocity);
      v_path = "/shells/" + std::to_string(i) + "/initial_velocity";
    }
  for (size_t i = 0; i < scene.solids.size(); ++i)
    if (!scene.solids[i].rigid_body && norm(scene.solids[i].initial_velocity) > vmax) {
      vmax = norm(scene.solids[i].initial_velocity);
      v_path = "/solids/" + std::to_string(i) + "/initial_velocity";
    }
  if (vmax > 0 && cfl * grid_dx / vmax < dt && scene.time.enforce_stability_bound != false) {
    dt = cfl * grid_dx / vmax;
    dt_path = v_path;
  }
  return dt;
}

// The scene's parts as the estimate sees them, and the box they span.
struct SceneExtent {
  std::vector<ShellSize> shells;
  std::vector<SolidSize> solids;
  Box box;
  double smallest_cell = 1e300;  // the default grid spacing (as sim/simulation.cpp chooses it)
};

SceneExtent measure_extent(const Scene& scene) {
  SceneExtent x;
  for (size_t i = 0; i < scene.shells.size(); ++i) {
    x.shells.push_back(shell_size(scene.shells[i], i));
    const ShellSize& s = x.shells.back();
    if (!s.box.empty()) {
      x.box.add(s.box.lo);
      x.box.add(s.box.hi);
    }
    if (s.cells > 0) x.smallest_cell = std::min(x.smallest_cell, std::sqrt(s.area / s.cells));
  }
  // Mesh solids read their file here (bounds, area, volume; no level set).
  for (size_t i = 0; i < scene.solids.size(); ++i) {
    x.solids.push_back(solid_size(scene, i));
    x.box.add(x.solids.back().box.lo);
    x.box.add(x.solids.back().box.hi);
    x.smallest_cell = std::min(x.smallest_cell, 2.0 * *scene.solids[i].spacing);
  }
  return x;
}

// Sets e.grid_dx and refuses a spacing whose block coordinates would overflow; returns the JSON path
// that sets the spacing.
std::string choose_grid_spacing(const Scene& scene, const SceneExtent& x, ResourceEstimate& e) {
  e.grid_dx = scene.grid.dx.value_or(x.smallest_cell);
  const std::string dx_path =
      scene.grid.dx ? "/grid/dx" : x.shells.empty() ? "/solids/0/spacing" : x.shells[0].count_path;
  if (x.box.reach() / e.grid_dx > kGridReachCells)
    FieldChecks(scene.source, "")
        .fail(dx_path.substr(1), "grid spacing " + format_value(e.grid_dx) + " m cannot hold the scene: it reaches " +
                                     format_value(x.box.reach()) + " m from the origin, more than the grid's " +
                                     format_value(kGridReachCells) + " cells (" +
                                     format_value(kGridReachCells * e.grid_dx) + " m at this spacing); use a larger \"dx\"");
  return dx_path;
}

// What the particles ask of the sparse grid: their count and the 4^3 node blocks they touch.
struct GridDemand {
  double particles = 0;
  double blocks = 0;  // estimated from areas and volumes
  GridBlocks counted;  // blocks of the shells small enough to count exactly
  explicit GridDemand(double dx) : counted(dx) {}
};

void add_shell_items(const Scene& scene, const SceneExtent& x, ResourceEstimate& e, GridDemand& grid) {
  const double block = 4.0 * e.grid_dx;
  for (size_t i = 0; i < x.shells.size(); ++i) {
    const ShellSize& s = x.shells[i];
    const Shell& in = scene.shells[i];
    const double points = in.quadrature.points.value_or(std::max(4, s.degree + 1)), layers = in.quadrature.layers.value_or(3);
    const double qp = s.cells * points * points * layers;
    const std::string name = "shell \"" + in.name.value_or("shell" + std::to_string(i)) + "\" ";
    e.memory.push_back({name + "control points", s.control_points, s.control_points * kControlPointBytes, s.count_path});
    e.memory.push_back({name + "quadrature points", qp, qp * (kQuadraturePointBase + kBasisFunctionBytes * s.support),
                        s.count_path});
    e.memory.push_back({name + "shear particles", s.cells, s.cells * kShearParticleBytes, s.count_path});
    grid.particles += s.control_points + qp + s.cells;
    // A sheet touches about two layers of blocks (thicker sheets more), never more than 8 per particle.
    const double area_blocks =
        std::min(8.0 * (s.control_points + s.cells), s.area / (block * block) * (2.0 + s.thickness / block));
    if (s.control_points + s.cells <= kCountedParticles && area_blocks <= kCountedBlocks)
      add_shell_particles(scene, in, "/shells/" + std::to_string(i), grid.counted);
    else
      grid.blocks += area_blocks;
  }
}

void add_solid_items(const Scene& scene, const SceneExtent& x, ResourceEstimate& e, GridDemand& grid) {
  const double block = 4.0 * e.grid_dx;
  for (size_t i = 0; i < x.solids.size(); ++i) {
    const SolidSize& s = x.solids[i];
    const Solid& in = scene.solids[i];
    const std::string path = "/solids/" + std::to_string(i);
    const std::string name = "solid \"" + in.name.value_or("solid" + std::to_string(i)) + "\" ";
    const double n = s.volume / std::pow(*in.spacing, 3);
    e.memory.push_back({name + "particles", n, n * kSolidParticleBytes, path + "/spacing"});
    grid.particles += n;
    grid.blocks += std::min(8.0 * n, s.volume / std::pow(block, 3) + s.area / (block * block));
    if (s.voxel > 0) {
      const double voxels = band_voxels(s.area, s.box.lo, s.box.hi, s.voxel, s.band);
      e.memory.push_back({name + "level-set voxels", voxels, voxels * kLevelSetVoxelBytes,
                          path + (in.mesh.voxel_size ? "/voxel_size" : "/spacing")});
    }
  }
}

void add_collider_items(const Scene& scene, ResourceEstimate& e) {
  for (size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& c = scene.colliders[i];
    if (c.shape != "mesh") continue;
    const std::string path = "/colliders/" + std::to_string(i);
    const MeshStats m = read_mesh(scene, c.mesh, path);
    const double voxel = *c.mesh.voxel_size;
    const double voxels = band_voxels(m.area, m.lo, m.hi, voxel, c.mesh.band_voxels.value_or(3.0));
    e.memory.push_back({"collider \"" + c.name.value_or("collider" + std::to_string(i)) + "\" level-set voxels", voxels,
                        voxels * kLevelSetVoxelBytes, path + "/voxel_size"});
  }
}

// The step, the number of steps and frames, and the frames' size on disk.
void add_time_estimate(const Scene& scene, const SceneExtent& x, double render_vertices, ResourceEstimate& e) {
  std::string dt_path;
  e.dt = stable_step(scene, x.shells, e.grid_dx, dt_path);
  const double end = scene.time.end.value_or(1.0), rate = scene.time.frame_rate.value_or(24.0);
  e.frames = model::frames_after_start(end, rate) + 1;
  e.frames_path = rate > 1000 ? "/time/frame_rate" : "/time/end";
  // At least one step per frame (sim::Simulation::advance_to); the shatter loop's rigid steps run inside.
  e.steps = std::max(end / e.dt, e.frames - 1);
  bool rigid_bodies = false;
  for (const Solid& s : scene.solids) rigid_bodies = rigid_bodies || s.rigid_body.has_value();
  if (rigid_bodies) {
    const double rigid_dt = scene.rigid && scene.rigid->dt ? *scene.rigid->dt : 1e-3;
    if (end / rigid_dt > e.steps) {
      e.steps = end / rigid_dt;
      e.dt = rigid_dt;
      dt_path = scene.rigid && scene.rigid->dt ? "/rigid/dt" : "/time/end";
    }
  }
  e.steps_path = e.frames - 1 >= e.steps ? e.frames_path : end > 1e4 ? "/time/end" : dt_path;
  e.frame_bytes = render_vertices * kDiskBytesPerRenderVertex + 256.0 * static_cast<double>(x.shells.size());
  e.disk_bytes = e.frames * e.frame_bytes;
}

}  // namespace

const ResourceItem& ResourceEstimate::largest() const {
  return *std::max_element(memory.begin(), memory.end(),
                           [](const ResourceItem& a, const ResourceItem& b) { return a.bytes < b.bytes; });
}

ResourceEstimate estimate_resources(const Scene& input) {
  validate(input);
  Scene scene = input;
  apply_quality(scene);
  ResourceEstimate e;
  const SceneExtent extent = measure_extent(scene);
  const std::string dx_path = choose_grid_spacing(scene, extent, e);

  // Memory, item by item.
  GridDemand grid(e.grid_dx);
  add_shell_items(scene, extent, e, grid);
  add_solid_items(scene, extent, e, grid);
  add_collider_items(scene, e);
  const double blocks = grid.blocks + grid.counted.active();
  e.memory.push_back({"grid nodes", 64 * blocks, blocks * kGridBlockBytes, scene.grid.dx ? "/grid/dx" : dx_path});
  const double ru = scene.output.resolution ? (*scene.output.resolution)[0] : 32;
  const double rv = scene.output.resolution ? (*scene.output.resolution)[1] : 32;
  const double render_vertices = static_cast<double>(extent.shells.size()) * (ru + 1) * (rv + 1);
  e.memory.push_back({"render vertices", render_vertices, render_vertices * kRenderVertexBytes, "/output/resolution"});
  e.memory_bytes = kBaseBytes;
  for (const ResourceItem& item : e.memory) e.memory_bytes += item.bytes;

  add_time_estimate(scene, extent, render_vertices, e);
  e.work = e.steps * std::max(grid.particles, 1.0);
  return e;
}

namespace {

// Counts and steps as whole numbers while they are readable, else in exponent form.
std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, std::abs(v) < 1e15 && v == std::floor(v) ? "%.0f" : "%.4g", v);
  return buf;
}

}  // namespace

std::vector<std::string> budget_warnings(const ResourceEstimate& e, const ResourceBudget& b) {
  std::vector<std::string> out;
  if (e.frames > b.max_frames)
    out.push_back(e.frames_path + ": the run would write " + number(e.frames) + " frames, more than the budget of " +
                  number(b.max_frames));
  if (e.steps > b.max_steps)
    out.push_back(e.steps_path + ": the run would take about " + number(std::ceil(e.steps)) + " steps (dt " + number(e.dt) +
                  " s), more than the budget of " + number(b.max_steps));
  if (b.free_disk_bytes && e.disk_bytes > *b.free_disk_bytes)
    out.push_back(e.frames_path + ": the frames would take about " + format_bytes(e.disk_bytes) + " on disk, more than the " +
                  format_bytes(*b.free_disk_bytes) + " free");
  return out;
}

void check_budget(const ResourceEstimate& e, const ResourceBudget& b, const std::string& source) {
  if (b.memory_bytes > 0 && e.memory_bytes > b.memory_bytes) {
    const ResourceItem& big = e.largest();
    throw SceneError(source, big.json_path,
                     "the scene needs about " + format_bytes(e.memory_bytes) + " of memory, more than the budget of " +
                         format_bytes(b.memory_bytes) + " (" +
                         (b.memory_source.empty() ? std::string("--max-memory; default: the available memory") : b.memory_source) +
                         "); the largest part is " +
                         number(std::ceil(big.count)) + " " + big.what + " (" + format_bytes(big.bytes) + ")");
  }
  if (e.frames > INT_MAX)
    throw SceneError(source, e.frames_path, "the run would write " + number(e.frames) + " frames, more than any run can (" +
                                                std::to_string(INT_MAX) + ")");
  if (b.force) return;
  const std::vector<std::string> problems = budget_warnings(e, b);
  if (problems.empty()) return;
  const std::string& first = problems.front();
  const size_t colon = first.find(": ");
  throw SceneError(source, first.substr(0, colon), first.substr(colon + 2) + "; --force runs it anyway");
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) {
    bytes /= 1024;
    ++u;
  }
  char buf[64];
  if (u == 6 && bytes >= 1024)
    std::snprintf(buf, sizeof buf, "%.3g %s", bytes, units[u]);
  else
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
  return buf;
}

std::string describe_estimate(const ResourceEstimate& e) {
  std::string s = "  estimate: memory " + format_bytes(e.memory_bytes) + ", " + number(std::ceil(e.steps)) + " steps of " +
                  number(e.dt) + " s, " + number(e.frames) + " frames (" + format_bytes(e.disk_bytes) + " on disk), work " +
                  number(std::ceil(e.work)) + " particle-steps\n";
  for (const ResourceItem& item : e.memory)
    if (item.count > 0)
      s += "    " + item.what + ": " + number(std::ceil(item.count)) + " (" + format_bytes(item.bytes) + ")\n";
  return s;
}

}  // namespace shellfrac::scene
