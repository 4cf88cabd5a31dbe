#include "brittle/particles_vdb.hpp"

#include <openvdb/openvdb.h>
#include <openvdb/points/PointAttribute.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointCount.h>

#include <mutex>
#include <sstream>
#include <stdexcept>

namespace shellfrac::brittle {

namespace {

void init_vdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

template <class T, class Tree, class Index>
void add_attribute(Tree& tree, const Index& index, const char* name, const std::vector<T>& values) {
  openvdb::points::appendAttribute<T>(tree, name);
  openvdb::points::populateAttribute<Tree, Index, openvdb::points::PointAttributeVector<T>>(
      tree, index, name, openvdb::points::PointAttributeVector<T>(values));
}

// The archive io::File writes, but into memory: io::File::write does not check its stream after writing,
// so a full disk would leave a truncated file. The caller writes these bytes with checked I/O.
class MemoryArchive : public openvdb::io::Archive {
 public:
  std::string bytes(const openvdb::GridCPtrVec& grids) const {
    std::ostringstream os(std::ios_base::out | std::ios_base::binary);
    Archive::write(os, grids, /*seekable=*/true);  // a string stream seeks, as a file does
    if (!os) throw std::runtime_error("cannot serialise the particle grid");
    return os.str();
  }
};

}  // namespace

std::string particles_vdb_bytes(const BrittleSolid& solid, bool use_rest) {
  init_vdb();
  const size_t n = solid.size();
  std::vector<openvdb::Vec3R> positions(n);
  std::vector<openvdb::Vec3f> velocity(n);
  std::vector<float> damage(n), c_his(n), tau(n);
  std::vector<int32_t> id(n);
  for (size_t p = 0; p < n; ++p) {
    const Vec3& x = use_rest ? solid.rest[p] : solid.particles.x[p];
    positions[p] = openvdb::Vec3R(x.x(), x.y(), x.z());
    const Vec3& v = solid.particles.v[p];
    velocity[p] = openvdb::Vec3f(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
    damage[p] = static_cast<float>(solid.damage[p].c);
    c_his[p] = static_cast<float>(solid.damage[p].c_his);
    tau[p] = static_cast<float>(solid.damage[p].tau);
    id[p] = static_cast<int32_t>(p);
  }
  const openvdb::points::PointAttributeVector<openvdb::Vec3R> wrapper(positions);
  // About eight points per voxel; a single point or none still gets a valid transform.
  const float voxel = n > 1 ? openvdb::points::computeVoxelSize(wrapper, 8) : 1.0f;
  const auto transform = openvdb::math::Transform::createLinearTransform(voxel);
  const auto index = openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(wrapper, *transform);
  auto grid = openvdb::points::createPointDataGrid<openvdb::points::NullCodec, openvdb::points::PointDataGrid>(*index, wrapper, *transform);
  grid->setName("particles");
  auto& tree = grid->tree();
  add_attribute(tree, index->tree(), "v", velocity);
  add_attribute(tree, index->tree(), "damage", damage);
  add_attribute(tree, index->tree(), "c_his", c_his);
  add_attribute(tree, index->tree(), "tau", tau);
  add_attribute(tree, index->tree(), "id", id);

  return MemoryArchive().bytes({grid});
}

ParticlePoints read_particles_vdb(const std::filesystem::path& file) {
  init_vdb();
  openvdb::io::File in(file.string());
  in.open();
  const auto grid = openvdb::gridPtrCast<openvdb::points::PointDataGrid>(in.readGrid("particles"));
  in.close();
  if (!grid) throw std::runtime_error(file.string() + ": no points grid named 'particles'");
  const size_t n = static_cast<size_t>(openvdb::points::pointCount(grid->tree()));
  ParticlePoints out;
  out.position.resize(n);
  out.velocity.resize(n);
  out.damage.resize(n);
  out.c_his.resize(n);
  out.tau.resize(n);
  for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::points::AttributeHandle<openvdb::Vec3f> P(leaf->constAttributeArray("P"));
    const openvdb::points::AttributeHandle<openvdb::Vec3f> v(leaf->constAttributeArray("v"));
    const openvdb::points::AttributeHandle<float> c(leaf->constAttributeArray("damage")), h(leaf->constAttributeArray("c_his")),
        t(leaf->constAttributeArray("tau"));
    const openvdb::points::AttributeHandle<int32_t> id(leaf->constAttributeArray("id"));
    for (auto it = leaf->beginIndexOn(); it; ++it) {
      const size_t p = static_cast<size_t>(id.get(*it));
      if (p >= n) throw std::runtime_error(file.string() + ": particle id out of range");
      const openvdb::Vec3d world = grid->transform().indexToWorld(P.get(*it) + it.getCoord().asVec3d());
      out.position[p] = Vec3(world.x(), world.y(), world.z());
      const openvdb::Vec3f vv = v.get(*it);
      out.velocity[p] = Vec3(vv.x(), vv.y(), vv.z());
      out.damage[p] = c.get(*it);
      out.c_his[p] = h.get(*it);
      out.tau[p] = t.get(*it);
    }
  }
  return out;
}

}  // namespace shellfrac::brittle
