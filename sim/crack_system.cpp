// Set-up of prescribed cuts, consistent crack extraction (thesis sec. 4.4.2) with MLS basis
// updates (sec. 4.6), and the phantom-node partition (sec. 4.7.1).
#include "sim/crack_system.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <vector>

#include "scene/scene_error.hpp"
#include "sim/seam_system.hpp"

namespace shellfrac::sim {

namespace {

// Visibility of particle pairs, memoised: an open-addressing table (linear probing, power-of-two size,
// at most half full) keyed by the packed pair. Cheaper than a node-based map: one multiply to hash and
// usually one probe, no allocation per entry.
class PairVisibilityMap {
 public:
  // The stored answer for `key`, or -1 when absent.
  int find(uint64_t key) const {
    if (keys_.empty()) return -1;
    for (size_t i = slot(key);; i = (i + 1) & (keys_.size() - 1)) {
      if (keys_[i] == key) return values_[i];
      if (keys_[i] == kEmpty) return -1;
    }
  }
  void insert(uint64_t key, bool value) {
    if (2 * (used_ + 1) > keys_.size()) grow();
    size_t i = slot(key);
    while (keys_[i] != kEmpty && keys_[i] != key) i = (i + 1) & (keys_.size() - 1);
    if (keys_[i] == kEmpty) ++used_;
    keys_[i] = key;
    values_[i] = value;
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t{0};  // not a valid pair key (particle numbers < 2^24)
  size_t slot(uint64_t key) const {
    return static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);  // Fibonacci hashing
  }
  void grow() {
    std::vector<uint64_t> keys = std::move(keys_);
    std::vector<unsigned char> values = std::move(values_);
    const size_t size = keys.empty() ? 1024 : 2 * keys.size();
    keys_.assign(size, kEmpty);
    values_.assign(size, 0);
    shift_ = 64 - static_cast<int>(std::log2(static_cast<double>(size)));
    used_ = 0;
    for (size_t i = 0; i < keys.size(); ++i)
      if (keys[i] != kEmpty) insert(keys[i], values[i] != 0);
  }
  std::vector<uint64_t> keys_;
  std::vector<unsigned char> values_;
  size_t used_ = 0;
  int shift_ = 64;
};

// The partition's view of each particle set: shell sets with their near-crack flags, or a solid.
std::vector<mpm::PartitionRole> partition_roles(const World& world) {
  std::vector<mpm::PartitionRole> roles(world.particle_sets().size());
  for (size_t s = 0; s < roles.size(); ++s) {
    const SetRef& r = world.set(s);
    if (r.kind == SetKind::ControlPoints)
      roles[s] = {mpm::FieldKind::Shell, world.shell(r.body).control_near_crack().data()};
    else if (r.kind == SetKind::ShearParticles)
      roles[s] = {mpm::FieldKind::Shell, world.shell(r.body).shear_near_crack().data()};
    else
      roles[s] = {mpm::FieldKind::Solid, nullptr};
  }
  return roles;
}

// Whether the visibility cache's keys can pack (set, particle) of every shell particle into 32 bits:
// shell sets < 2^8, particles < 2^24.
bool cache_keys_fit(const World& world) {
  const std::vector<mpm::ParticleSet>& sets = world.particle_sets();
  size_t shell_sets = 0;
  for (size_t s = 0; s < sets.size(); ++s)
    if (world.set(s).kind != SetKind::SolidParticles) {
      shell_sets = s + 1;
      if (sets[s].count >= (size_t{1} << 24)) return false;
    }
  return shell_sets < (size_t{1} << 8);
}

// Per set, looked up once per partition rather than per query: shell or not, its body, and (for shells)
// whether that shell has a crack and is on a coupled seam.
struct SetInfo {
  bool shell;
  bool cracked;
  bool coupled;
  size_t body;
};

std::vector<SetInfo> set_infos(const World& world, const std::vector<unsigned char>& coupled_patch) {
  std::vector<SetInfo> info(world.particle_sets().size());
  for (size_t s = 0; s < info.size(); ++s) {
    const SetRef& r = world.set(s);
    const bool shell = r.kind != SetKind::SolidParticles;
    info[s] = {shell, shell && world.shell(r.body).crack() != nullptr, shell && coupled_patch[r.body] != 0, r.body};
  }
  return info;
}

}  // namespace

struct CrackSystem::VisibilityCache {
  tbb::enumerable_thread_specific<PairVisibilityMap> per_thread;
  size_t segments = 0;  // crack segments when the cache was filled
  // Unique per cache ever made, so a thread can remember its table without looking it up per query.
  const uint64_t generation = next_generation();
  static uint64_t next_generation() {
    static std::atomic<uint64_t> counter{0};
    return ++counter;
  }
  // This thread's table. The thread_local pair is only trusted for the generation it was taken from,
  // which no later cache reuses.
  PairVisibilityMap& local() {
    thread_local uint64_t seen = 0;
    thread_local PairVisibilityMap* table = nullptr;
    if (seen != generation) {
      table = &per_thread.local();
      seen = generation;
    }
    return *table;
  }
};

CrackSystem::CrackSystem(const scene::Model& model, World& world) {
  mls_settings_.max_factor = model.cracks.max_support;
  if (model.cracks.tip_diffraction) mls_settings_.tip.mode = shell::TipWeights::Mode::diffraction;
  mls_settings_.rule = model.cracks.continuous_support ? shell::SupportRule::continuous : shell::SupportRule::stepped;
  mls_settings_.support_margin = model.cracks.support_margin;
  phantom_nodes_ = model.cracks.phantom_nodes;
  cracks_.resize(world.num_shells());
  damaged_count_.assign(world.num_shells(), 0);
  coupled_patch_.assign(world.num_shells(), 0);
  for (const scene::model::InterfaceSpec& spec : model.interfaces)  // every one coupled ("none" seams are apart)
    coupled_patch_[static_cast<size_t>(spec.coupling.leader_patch)] =
        coupled_patch_[static_cast<size_t>(spec.coupling.follower_patch)] = 1;
  for (size_t i = 0; i < world.num_shells(); ++i) {
    const scene::model::Shell& s = model.shells[i];
    shell::ShellPatch& patch = world.shell(i);
    const std::string path = "/shells/" + std::to_string(i);
    if (!s.can_crack()) continue;
    patch.set_mass_scaling_budget(model.cracks.mass_scaling);
    const auto& ku = s.surface.knots_u();
    const auto& kv = s.surface.knots_v();
    const crack2d::Box domain{{ku.domain_begin(), kv.domain_begin()}, {ku.domain_end(), kv.domain_end()}};
    cracks_[i] = std::make_unique<crack2d::ConsistentCrackExtractor>(domain, patch.parameter_spacing());
    for (size_t c = 0; c < s.cuts.size(); ++c) {
      try {
        cracks_[i]->add_prescribed_cut(s.cuts[c].points, s.cuts[c].closed);
      } catch (const crack2d::CutError& e) {
        throw scene::SceneError(model.source, path + "/cuts/" + std::to_string(c) + "/points", e.what());
      }
    }
    if (cracks_[i]->graph().num_edges() > 0) {
      const shell::CrackUpdate u = patch.update_crack(cracks_[i]->index(), 0, mls_settings_);
      record_update(world, i, u);
    }
  }
  count_state(world);
}

CrackSystem::~CrackSystem() = default;

bool CrackSystem::any() const {
  for (const auto& c : cracks_)
    if (c) return true;
  return false;
}

void CrackSystem::record_update(World& world, size_t shell, const shell::CrackUpdate& u) {
  world.refresh_control_mass(shell);
  if (stats_.first_mls_failure.empty() && !u.first_failure.empty())
    stats_.first_mls_failure = "shell \"" + world.shell_name(shell) + "\" " + u.first_failure;
  if (stats_.first_sliver.empty() && !u.first_sliver.empty())
    stats_.first_sliver = "shell \"" + world.shell_name(shell) + "\" " + u.first_sliver;
}

bool CrackSystem::extract(World& world) {
  const size_t edges_before = stats_.crack_segments;
  stats_.crack_segments = stats_.mls_points = stats_.mls_failures = 0;
  for (size_t i = 0; i < world.num_shells(); ++i) {
    if (!cracks_[i]) continue;
    shell::ShellPatch& patch = world.shell(i);
    // The fully damaged set only grows (c_his is a running maximum): an unchanged count means an
    // unchanged set, and the extraction would add nothing (so the set itself is listed only then).
    const size_t count = patch.fractures() ? patch.num_fully_damaged_points() : 0;
    if (patch.fractures() && count != damaged_count_[i]) {
      damaged_count_[i] = count;
      const std::vector<unsigned char> damaged = patch.fully_damaged_points();
      const size_t first = cracks_[i]->graph().num_edges();
      const crack2d::ExtractionStats st = cracks_[i]->extract(patch.inplane_parameters(), damaged);
      ++stats_.extractions;
      stats_.subset_violations += st.subset_violations;
      // Only points whose support the new segments touch are rebuilt (thesis sec. 4.6).
      if (cracks_[i]->graph().num_edges() > first) {
        const shell::CrackUpdate u = patch.update_crack(cracks_[i]->index(), first, mls_settings_);
        record_update(world, i, u);
      }
    }
    stats_.crack_segments += cracks_[i]->graph().num_edges();
    stats_.mls_points += patch.num_mls_points();
    stats_.mls_failures += patch.num_mls_failures();
  }
  return stats_.crack_segments != edges_before;
}

bool CrackSystem::add_cut(World& world, size_t shell, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  crack2d::ConsistentCrackExtractor& cracks = *cracks_[shell];
  const size_t first = cracks.graph().num_edges();
  try {
    cracks.add_prescribed_cut({from, to}, false);
  } catch (const crack2d::CutError&) {
    return false;
  }
  const shell::CrackUpdate u = world.shell(shell).update_crack(cracks.index(), first, mls_settings_);
  record_update(world, shell, u);
  return true;
}

void CrackSystem::count_state(const World& world) {
  stats_.crack_segments = stats_.mls_points = stats_.mls_failures = 0;
  for (size_t i = 0; i < world.num_shells(); ++i)
    if (cracks_[i]) {
      stats_.crack_segments += cracks_[i]->graph().num_edges();
      stats_.mls_points += world.shell(i).num_mls_points();
      stats_.mls_failures += world.shell(i).num_mls_failures();
    }
}

void CrackSystem::partition(const World& world, mpm::SparseGrid& grid, const SeamSystem& seams) {
  bool any_mls = false;
  for (size_t i = 0; i < world.num_shells(); ++i) any_mls = any_mls || world.shell(i).num_mls_points() > 0;
  if (!phantom_nodes_ || !any_mls) {
    phantoms_ = mpm::PhantomLayout{};
    partition_memo_.clear();  // the memo describes phantoms_, which is now empty
    return;
  }
  const std::vector<mpm::ParticleSet>& sets = world.particle_sets();
  auto parameter = [&](uint32_t set, uint32_t particle) {
    const SetRef& r = world.set(set);
    const shell::ShellPatch& p = world.shell(r.body);
    return r.kind == SetKind::ControlPoints ? p.control_parameter(particle) : p.shear_parameter(particle);
  };
  size_t segments = 0;
  for (const auto& c : cracks_) segments += c ? c->graph().num_edges() : 0;
  const bool cacheable = cache_keys_fit(world);
  if (!visibility_ || segments != visibility_->segments) {
    visibility_ = std::make_unique<VisibilityCache>();
    visibility_->segments = segments;
    partition_memo_.clear();
  }
  // Same cracks, same grid numbering, same particles near the split nodes on the same base nodes: the
  // layout is the one phantoms_ holds (the last partition's).
  if (partition_memo_.unchanged(grid)) {
    grid.set_phantom_copies(phantoms_);
    return;
  }
  // Two particles are on the same fragment side locally when they belong to the same body and, on a
  // shell, the parameter-space segment between them crosses no crack. Coupled patches are one body:
  // there the path runs through the seam (SeamSystem::connected).
  auto visible = [&](uint32_t sa, uint32_t a, uint32_t sb, uint32_t b) {
    const size_t pa = world.set(sa).body, pb = world.set(sb).body;
    if (pa != pb) return seams.connected(world, pa, parameter(sa, a), pb, parameter(sb, b));
    const crack2d::CrackIndex* index = world.shell(pa).crack();
    return !index || !index->crosses(parameter(sa, a), parameter(sb, b));
  };
  const std::vector<SetInfo> info = set_infos(world, coupled_patch_);
  VisibilityCache& cache_owner = *visibility_;
  const mpm::Connectivity connected = [&](uint32_t sa, uint32_t a, uint32_t sb, uint32_t b) {
    const SetInfo &ia = info[sa], &ib = info[sb];
    if (!ia.shell || !ib.shell) return sa == sb;
    if (ia.body != ib.body && !(ia.coupled && ib.coupled)) return false;
    if (ia.body == ib.body && !ia.cracked) return true;
    if (!cacheable) return visible(sa, a, sb, b);
    uint64_t ka = (uint64_t{sa} << 24) | a, kb = (uint64_t{sb} << 24) | b;
    if (ka > kb) std::swap(ka, kb);
    PairVisibilityMap& cache = cache_owner.local();
    const uint64_t key = (ka << 32) | kb;
    const int known = cache.find(key);
    if (known >= 0) return known != 0;
    const bool result = visible(sa, a, sb, b);
    cache.insert(key, result);
    return result;
  };
  // A node whose particles all lie on one shell, with no crack segment meeting the parameter box around
  // them, is one component: every segment between two of them stays inside the box (most flagged nodes are
  // beside the crack, not on it). Exact, as crosses() and touches() use the same exact predicates.
  const mpm::GroupConnectivity one_component = [&](const uint32_t* set, const uint32_t* particle, int n) {
    const SetInfo& first = info[set[0]];
    if (!first.shell) return false;
    for (int i = 1; i < n; ++i)
      if (!info[set[i]].shell || info[set[i]].body != first.body) return false;
    if (!first.cracked) return true;
    crack2d::Box box{parameter(set[0], particle[0]), parameter(set[0], particle[0])};
    for (int i = 1; i < n; ++i) {
      const Eigen::Vector2d u = parameter(set[i], particle[i]);
      box.lo = box.lo.cwiseMin(u);
      box.hi = box.hi.cwiseMax(u);
    }
    return !world.shell(first.body).crack()->touches(box);
  };
  phantoms_ = mpm::partition_nodes(grid, sets, partition_roles(world), connected, one_component, &partition_memo_);
  grid.set_phantom_copies(phantoms_);
  stats_.max_split_nodes = std::max(stats_.max_split_nodes, phantoms_.split_nodes);
}

}  // namespace shellfrac::sim
