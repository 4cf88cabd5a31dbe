// The shatter loop: fracture events start only above the impulse threshold, with the impulse the rigid
// solver delivered; fragments keep the parent's mass, momentum and angular momentum and spawn without
// overlap; large fragments break again, tiny ones never.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <deque>
#include <vector>

#include "brittle/primitives.hpp"
#include "core/error.hpp"
#include "shatter/shatter_loop.hpp"

namespace shellfrac::shatter {
namespace {

using brittle::Vec3;

// A 10 cm ceramic-like cube (E 1 GPa, 1000 kg/m^3, sigma_f 0.3 MPa) of 1,000 particles on a 1 cm grid:
// an event's MPM run is about a thousand steps.
BreakableSpec cube(const Vec3& centre, double threshold) {
  BreakableSpec s;
  s.name = "cube";
  s.mesh = brittle::box_mesh(centre, Vec3::Constant(0.05), 1);
  brittle::BrittleMaterial m;
  m.youngs_modulus = 1e9;
  m.poisson_ratio = 0.25;
  m.density = 1000;
  m.failure_stress = 3e5;
  m.fracture_energy = 10;
  auto solid = std::make_shared<brittle::BrittleSolid>(
      brittle::make_solid(s.mesh, m, 0.01, brittle::Sampling::Regular, 1, "cube"));
  s.solver.dx = 0.01;
  solid->set_strength({}, {}, s.solver.dx);
  s.particles = solid;
  s.event.crack.grid.spacing = 0.01;
  s.impulse_threshold = threshold;
  return s;
}

ShatterOptions on_the_ground() {
  ShatterOptions o;
  o.dt = 1e-3;
  o.ground = GroundSpec{};
  o.ground->surface = rigid::Surface{0.5, 0.1};
  return o;
}

// Falls from 1.25 m (5 m/s at impact): Bullet resolves the collision over three steps (1.37, 4.21 and
// 0.09 N s), and the loop sums a body's impulses over its last three steps (ShatterOptions::impulse_window).
TEST(ShatterLoop, EventsStartOnlyAboveTheThresholdWithTheDeliveredImpulse) {
  for (const double threshold : {20.0, 5.0}) {
    ShatterLoop loop(on_the_ground());
    loop.add_breakable(cube(Vec3(0, 0, 1.3), threshold));
    std::deque<rigid::BodyState> before;  // the states before the last three steps
    bool hit = false;
    while (loop.time() < 0.6 && loop.events().empty()) {
      before.push_back(loop.world().state(loop.pieces()[0].body));
      if (before.size() > 3) before.pop_front();
      loop.step();
      hit = hit || !loop.world().contacts().empty();
    }
    ASSERT_TRUE(hit);
    if (threshold > 10) {
      EXPECT_TRUE(loop.events().empty()) << "20 N s is above the impact";
      continue;
    }
    ASSERT_EQ(loop.events().size(), 1u);
    const EventRecord& e = loop.events()[0];
    // The momentum the world gave the cube over the window, less gravity's, is the event's impulse (1e-9):
    // the whole collision (5.67 N s), judged once it passed its peak; more than any single step's
    // (4.21 N s), so the threshold of 5 N s is passed only by the sum.
    const double m = 1.0;
    const Vec3 change = m * (e.parent.velocity - before.front().velocity) - m * Vec3(0, 0, -9.81) * 3e-3;
    EXPECT_NEAR(change.z(), e.impulse, 1e-9 * e.impulse);
    EXPECT_GT(e.impulse, 5.0);
    EXPECT_LT(e.impulse, 20.0);
    EXPECT_GT(e.contact_time, 0);
    EXPECT_GT(e.mpm_steps, 0u);
  }
}

}  // namespace
}  // namespace shellfrac::shatter

namespace shellfrac::shatter {
namespace {

// Drops a spinning, sliding cube until its first fracture event; returns the loop.
std::unique_ptr<ShatterLoop> broken_cube(const VolumeRatios& ratios) {
  auto loop = std::make_unique<ShatterLoop>(on_the_ground());
  BreakableSpec s = cube(Vec3(0, 0, 1.3), 1.0);
  s.velocity = Vec3(0.7, -0.4, 0);  // 5 m/s at the ground
  s.angular_velocity = Vec3(3, -5, 7);
  s.spawn.ratios = ratios;
  loop->add_breakable(s);
  while (loop->time() < 0.6 && loop->events().empty()) loop->step();
  return loop;
}

std::vector<size_t> alive(const ShatterLoop& loop) {
  std::vector<size_t> out;
  for (size_t i = 0; i < loop.pieces().size(); ++i)
    if (loop.alive(i)) out.push_back(i);
  return out;
}

// thesis sec. 3.6.1: fragments start with the parent's rigid velocity field. Checked independently of the
// loop's own bookkeeping: masses and inertia from the meshes, velocities from the world.
TEST(ShatterLoop, FragmentsKeepMassMomentumAndAngularMomentum) {
  const auto loop = broken_cube(VolumeRatios{});
  ASSERT_EQ(loop->events().size(), 1u);
  const EventRecord& e = loop->events()[0];
  ASSERT_EQ(e.outcome, "broken") << e.message << " damaged " << e.damaged_particles << " of " << e.particles
                                 << " fragments " << e.fragments << " t_c " << e.contact_time << " steps " << e.mpm_steps;
  ASSERT_GE(e.fragments, 2u);
  const Piece& parent = loop->pieces()[0];
  const rigid::Pose w = e.parent.pose * parent.material_to_body;
  const brittle::MassProperties pm = brittle::mass_properties(parent.mesh, 1000);
  const Vec3 centre = w.apply(pm.centroid);
  const rigid::Mat3 R = w.rotation.toRotationMatrix();
  const Vec3 P = pm.mass * e.parent.velocity;
  const Vec3 L = R * pm.inertia * R.transpose() * e.parent.angular_velocity;
  const double E = 0.5 * pm.mass * e.parent.velocity.squaredNorm() + 0.5 * e.parent.angular_velocity.dot(L);
  double mass = 0, energy = 0;
  Vec3 p = Vec3::Zero(), l = Vec3::Zero();
  const std::vector<size_t> pieces = alive(*loop);
  ASSERT_EQ(pieces.size(), e.fragments);
  for (size_t i : pieces) {
    const Piece& f = loop->pieces()[i];
    const brittle::MassProperties fm = brittle::mass_properties(f.mesh, 1000);
    const rigid::BodyState s = loop->world().state(f.body);
    const rigid::Pose fw = s.pose * f.material_to_body;
    const rigid::Mat3 Rf = fw.rotation.toRotationMatrix();
    const Vec3 spin = Rf * fm.inertia * Rf.transpose() * s.angular_velocity;
    mass += fm.mass;
    p += fm.mass * s.velocity;
    l += spin + fm.mass * (fw.apply(fm.centroid) - centre).cross(s.velocity);
    energy += 0.5 * fm.mass * s.velocity.squaredNorm() + 0.5 * s.angular_velocity.dot(spin);
    EXPECT_LE((fw.apply(fm.centroid) - s.pose.translation).norm(), 1e-12);  // body origin at its centre
  }
  EXPECT_NEAR(mass, pm.mass, 1e-10 * pm.mass);
  EXPECT_LE((p - P).norm(), 1e-10 * P.norm());
  EXPECT_LE((l - L).norm(), 1e-10 * L.norm());
  EXPECT_LE(energy, E * (1 + 1e-12));
  // the loop's own record says the same
  EXPECT_LE(e.mass_error, 1e-10);
  EXPECT_LE(e.momentum_error, 1e-10);
  EXPECT_LE(e.angular_momentum_error, 1e-10);
  EXPECT_LE(e.energy_ratio, 1 + 1e-12);
  EXPECT_LE(std::abs(e.volume_change), 1e-9);  // the exact cutter's fragments sum to the cube
}

// Siblings are cut from one solid and touch along the crack. The target is that their
// collision shapes overlap by no more than their margins at birth: NOT MET. Hulls and meshes only
// approximate curved crack faces (measured on this cube: hulls overlap by up to 20.6 mm, a tetrahedron
// decomposition of the surface by 3.1 mm at 34K contacts per step, GImpact meshes report 32 mm for two
// boxes touching face to face). What the loop guarantees instead, asserted here: siblings ignore each
// other until their bounds part, so the first free step (gravity off) adds no energy between them, and
// once apart they collide again.
TEST(ShatterLoop, SiblingsDoNotPushEachOtherApartAtBirth) {
  auto loop = broken_cube(VolumeRatios{});
  ASSERT_EQ(loop->events().size(), 1u);
  ASSERT_EQ(loop->events()[0].outcome, "broken");
  const std::vector<size_t> pieces = alive(*loop);
  // the fragments' kinetic energy just after the event, then one step of free flight
  const double before = loop->moments(pieces).kinetic_energy;
  loop->world().set_gravity(Vec3::Zero());
  size_t sibling_contacts = 0;
  loop->step();
  for (const rigid::ContactPoint& c : loop->world().contacts())
    if (c.a != 0 && c.b != 0 && c.impulse > 0) ++sibling_contacts;
  EXPECT_EQ(sibling_contacts, 0u);
  // Ground contacts may take energy out, never put it in (restitution <= 1): 1e-9 relative.
  EXPECT_LE(loop->moments(pieces).kinetic_energy, before * (1 + 1e-9));
}

// A large fragment is breakable again: thrown at the ground it has its own fracture event.
TEST(ShatterLoop, LargeFragmentBreaksAgain) {
  const auto loop = broken_cube(VolumeRatios{});
  ASSERT_EQ(loop->events().size(), 1u);
  size_t large = loop->pieces().size();
  for (size_t i : alive(*loop))
    if (loop->pieces()[i].fragment_class == FragmentClass::Large) large = i;
  ASSERT_LT(large, loop->pieces().size()) << "the first event made no large fragment";
  const std::string name = loop->pieces()[large].name;
  // 6 m/s (8 and 10 break it too; 3 and 4 damage 14-27 % of its 1,075 particles without a crack that
  // separates it: outcome "intact")
  loop->world().set_velocity(loop->pieces()[large].body, Vec3(0, 0, -6), Vec3::Zero());
  const double until = loop->time() + 0.3;
  while (loop->time() < until && loop->alive(large)) loop->step();
  bool found = false;
  for (const EventRecord& e : loop->events())
    if (e.body == name) {
      found = true;
      EXPECT_EQ(e.generation, 1);
      EXPECT_EQ(e.outcome, "broken") << e.message << " damaged " << e.damaged_particles << " of " << e.particles
                                     << " fragments " << e.fragments << " impulse " << e.impulse;
    }
  EXPECT_TRUE(found);
}

// With VR_t above every fragment's share, all fragments are tiny: slammed into the ground at 12 m/s, none
// breaks.
TEST(ShatterLoop, TinyFragmentsNeverBreak) {
  const auto loop = broken_cube(VolumeRatios{0.97, 0.98, 0.99});
  ASSERT_EQ(loop->events().size(), 1u);
  ASSERT_EQ(loop->events()[0].outcome, "broken");
  for (size_t i : alive(*loop)) {
    ASSERT_EQ(loop->pieces()[i].fragment_class, FragmentClass::Tiny);
    EXPECT_FALSE(loop->pieces()[i].breakable);
    loop->world().set_velocity(loop->pieces()[i].body, Vec3(0, 0, -12), Vec3::Zero());
  }
  const double until = loop->time() + 0.3;
  while (loop->time() < until) loop->step();
  EXPECT_EQ(loop->events().size(), 1u);
}

// The observer sees every MPM step of an event in order, and abandoning the event (Ctrl-C in the run
// driver) leaves the body whole and flying, with the event recorded as interrupted after those steps.
TEST(ShatterLoop, ObserverSeesEveryEventStepAndCanAbandonTheEvent) {
  ShatterLoop loop(on_the_ground());
  loop.add_breakable(cube(Vec3(0, 0, 1.3), 5.0));
  std::vector<size_t> steps;
  double end_time = 0, last_time = 0;
  size_t particles = 0;
  loop.set_event_observer([&](const EventProgress& e) {
    EXPECT_EQ(e.body, "cube");
    particles = e.particles;
    steps.push_back(e.steps);
    end_time = e.end_time;
    last_time = e.time;
    return e.steps < 7;
  });
  while (loop.time() < 0.6 && loop.events().empty()) loop.step();
  ASSERT_EQ(loop.events().size(), 1u);
  const EventRecord& r = loop.events()[0];
  EXPECT_EQ(r.outcome, "interrupted");
  EXPECT_EQ(r.mpm_steps, 7u);
  EXPECT_EQ(particles, r.particles);
  EXPECT_GT(particles, 0u);
  EXPECT_EQ(steps, (std::vector<size_t>{1, 2, 3, 4, 5, 6, 7}));
  EXPECT_NEAR(end_time, 3 * r.contact_time, 1e-12 * end_time);  // contact_times' default
  EXPECT_GT(last_time, 0.0);
  EXPECT_LT(last_time, end_time);
  EXPECT_TRUE(loop.alive(0));
  EXPECT_EQ(loop.totals().broken, 0u);
  EXPECT_EQ(loop.totals().failed, 0u);
}

TEST(ShatterLoop, BadSpecsAreRefused) {
  ShatterLoop loop(on_the_ground());
  EXPECT_THROW(loop.add_breakable(cube(Vec3(0, 0, 1), 0.0)), core::InputError);
  BreakableSpec s = cube(Vec3(0, 0, 1), 1.0);
  s.spawn.ratios = VolumeRatios{0.3, 0.2, 0.98};
  EXPECT_THROW(loop.add_breakable(s), core::InputError);
  EXPECT_EQ(classify(0.04, VolumeRatios{}), FragmentClass::Tiny);
  EXPECT_EQ(classify(0.05, VolumeRatios{}), FragmentClass::Small);
  EXPECT_EQ(classify(0.2, VolumeRatios{}), FragmentClass::Large);
  EXPECT_EQ(classify(0.98, VolumeRatios{}), FragmentClass::NearlyWhole);
}

}  // namespace
}  // namespace shellfrac::shatter
