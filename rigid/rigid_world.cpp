#include "rigid/rigid_world.hpp"

#include <BulletCollision/Gimpact/btGImpactCollisionAlgorithm.h>
#include <LinearMath/btConvexHullComputer.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace shellfrac::rigid {

namespace {

btVector3 bt(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 eig(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
btTransform bt(const Pose& p) {
  return btTransform(btQuaternion(p.rotation.x(), p.rotation.y(), p.rotation.z(), p.rotation.w()), bt(p.translation));
}
Pose eig(const btTransform& t) {
  const btQuaternion q = t.getRotation();
  Pose p;
  p.rotation = Quat(q.w(), q.x(), q.y(), q.z()).normalized();
  p.translation = eig(t.getOrigin());
  return p;
}

// Pose after moving rigidly with (v, w) for dt: translation by v dt, rotation by the angle |w| dt about w.
Pose advance(const Pose& p, const Vec3& v, const Vec3& w, double dt) {
  Pose out = p;
  out.translation += v * dt;
  const double angle = w.norm() * dt;
  if (angle > 0) out.rotation = (Quat(Eigen::AngleAxisd(angle, w.normalized())) * p.rotation).normalized();
  return out;
}

// Bullet pads every convex shape by its margin. Shapes built from the margin-offset surface collide as the
// surface itself, so sibling fragments that share a crack face start touching, not overlapping by two
// margins. Hull: the hull's planes moved inward by the margin (btConvexHullComputer's shrink).
std::vector<btScalar> shrunk_hull(const brittle::TriMesh& mesh, double margin) {
  btConvexHullComputer hull;
  const double moved = hull.compute(mesh.positions.data()->data(), static_cast<int>(sizeof(brittle::Vec3)),
                                    static_cast<int>(mesh.positions.size()), margin, 0.25);
  if (moved < 0 || hull.vertices.size() < 4)  // degenerate: keep the plain vertices
    hull.compute(mesh.positions.data()->data(), static_cast<int>(sizeof(brittle::Vec3)),
                 static_cast<int>(mesh.positions.size()), 0, 0);
  std::vector<btScalar> out;
  for (int i = 0; i < hull.vertices.size(); ++i)
    out.insert(out.end(), {hull.vertices[i].x(), hull.vertices[i].y(), hull.vertices[i].z()});
  return out;
}

// Mesh: every vertex moved inward by the margin along its area-weighted normal.
brittle::TriMesh inset(const brittle::TriMesh& mesh, double margin) {
  brittle::TriMesh out = mesh;
  brittle::compute_vertex_normals(out);
  for (size_t i = 0; i < out.positions.size(); ++i) out.positions[i] -= margin * out.normals[i];
  return out;
}

}  // namespace

// One object of the world. Triangle data live here because Bullet's mesh shapes only point at them.
struct Entry {
  std::string name;
  std::vector<btScalar> vertices;
  std::vector<int> indices;
  std::unique_ptr<btTriangleIndexVertexArray> arrays;
  std::unique_ptr<btCollisionShape> shape;
  std::unique_ptr<btDefaultMotionState> motion;
  std::unique_ptr<btCollisionObject> object;  // a btRigidBody
  bool dynamic = false, kinematic = false;
  Vec3 kinematic_velocity = Vec3::Zero(), kinematic_angular_velocity = Vec3::Zero();
  Pose kinematic_pose;
  double margin = 0;
  std::vector<int> ignored;  // ids of the bodies ignore_pair pairs it with
  BodyState before;  // at the start of the last step (for approach speeds)
};

struct RigidWorld::Impl {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
  std::vector<std::unique_ptr<Entry>> entries;

  Entry& at(int id) {
    if (id < 0 || static_cast<size_t>(id) >= entries.size() || !entries[static_cast<size_t>(id)])
      throw core::InputError("rigid world: no body with id " + std::to_string(id));
    return *entries[static_cast<size_t>(id)];
  }
  void set_ignored(int a, int b, bool ignore) {
    Entry& ea = at(a);
    Entry& eb = at(b);
    ea.object->setIgnoreCollisionCheck(eb.object.get(), ignore);
    eb.object->setIgnoreCollisionCheck(ea.object.get(), ignore);
    const auto note = [ignore](std::vector<int>& list, int other) {
      list.erase(std::remove(list.begin(), list.end(), other), list.end());
      if (ignore) list.push_back(other);
    };
    note(ea.ignored, b);
    note(eb.ignored, a);
  }
  int add(std::unique_ptr<Entry> e, double mass, const Vec3& inertia, const Pose& pose, const Surface& surface) {
    e->motion = std::make_unique<btDefaultMotionState>(bt(pose));
    btRigidBody::btRigidBodyConstructionInfo info(mass, e->motion.get(), e->shape.get(), bt(inertia));
    info.m_friction = surface.friction;
    info.m_restitution = surface.restitution;
    auto body = std::make_unique<btRigidBody>(info);
    const int id = static_cast<int>(entries.size());
    body->setUserIndex(id);
    world.addRigidBody(body.get());
    e->object = std::move(body);
    entries.push_back(std::move(e));
    return id;
  }
};

RigidWorld::RigidWorld(const Options& options) : impl_(std::make_unique<Impl>()) {
  btGImpactCollisionAlgorithm::registerAlgorithm(&impl_->dispatcher);
  impl_->world.setGravity(bt(options.gravity));
  btContactSolverInfo& info = impl_->world.getSolverInfo();
  info.m_numIterations = options.solver_iterations;
  // Two friction directions, so that the friction impulse is reported in full for every point.
  info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
  // Every penetration is pushed out by split impulses (position only), never by adding to the contact's
  // velocity impulse: the applied impulse read for fracture (thesis sec. 3.6.2) is then the collision's.
  // Bullet's default splits only beyond 4 cm, so a 1 mm overlap of a resting or new-born fragment was
  // resolved with impulses of several N s at closing speeds of 2 cm/s.
  info.m_splitImpulse = true;
  info.m_splitImpulsePenetrationThreshold = 0;
}

RigidWorld::~RigidWorld() {
  for (auto& e : impl_->entries)
    if (e) impl_->world.removeRigidBody(static_cast<btRigidBody*>(e->object.get()));
}

int RigidWorld::add_ground(const Vec3& point, const Vec3& normal, const Surface& surface) {
  if (!(normal.norm() > 0)) throw core::InputError("rigid world: the ground normal must not be zero");
  auto e = std::make_unique<Entry>();
  e->name = "ground";
  const Vec3 n = normal.normalized();
  e->shape = std::make_unique<btStaticPlaneShape>(bt(n), n.dot(point));
  return impl_->add(std::move(e), 0, Vec3::Zero(), Pose{}, surface);
}

int RigidWorld::add_static_mesh(const std::string& name, const brittle::TriMesh& mesh, const Surface& surface) {
  if (mesh.triangles.empty()) throw core::InputError("rigid world: static mesh \"" + name + "\" has no triangles");
  auto e = std::make_unique<Entry>();
  e->name = name;
  for (const brittle::Vec3& p : mesh.positions) e->vertices.insert(e->vertices.end(), {p.x(), p.y(), p.z()});
  for (const brittle::Tri& t : mesh.triangles) e->indices.insert(e->indices.end(), {t[0], t[1], t[2]});
  e->arrays = std::make_unique<btTriangleIndexVertexArray>(
      static_cast<int>(mesh.triangles.size()), e->indices.data(), static_cast<int>(3 * sizeof(int)),
      static_cast<int>(mesh.positions.size()), e->vertices.data(), static_cast<int>(3 * sizeof(btScalar)));
  e->shape = std::make_unique<btBvhTriangleMeshShape>(e->arrays.get(), true);
  return impl_->add(std::move(e), 0, Vec3::Zero(), Pose{}, surface);
}

int RigidWorld::add_static_box(const std::string& name, const Pose& pose, const Vec3& half_extents,
                               const Surface& surface) {
  auto e = std::make_unique<Entry>();
  e->name = name;
  e->shape = std::make_unique<btBoxShape>(bt(half_extents));
  return impl_->add(std::move(e), 0, Vec3::Zero(), pose, surface);
}

int RigidWorld::add_body(const BodyDesc& d) {
  const std::string who = "rigid body \"" + d.name + "\"";
  if (!d.kinematic && !(d.mass > 0 && std::isfinite(d.mass)))
    throw core::InputError(who + ": a dynamic body needs a positive, finite mass");
  if (!d.kinematic && !(d.inertia.minCoeff() > 0 && d.inertia.allFinite()))
    throw core::InputError(who + ": a dynamic body needs positive principal moments of inertia");
  auto e = std::make_unique<Entry>();
  e->name = d.name;
  if (d.shape == Shape::Sphere) {
    if (!(d.radius > 0)) throw core::InputError(who + ": a sphere needs a positive radius");
    e->shape = std::make_unique<btSphereShape>(d.radius);
  } else {
    if (d.mesh.positions.size() < 4 || d.mesh.triangles.empty())
      throw core::InputError(who + ": the collision mesh has fewer than 4 vertices");
    if (d.shape == Shape::ConvexHull) {
      e->vertices = shrunk_hull(d.mesh, d.margin);
      e->shape = std::make_unique<btConvexHullShape>(e->vertices.data(), static_cast<int>(e->vertices.size() / 3),
                                                     static_cast<int>(3 * sizeof(btScalar)));
    } else {
      // Bullet's GImpact mesh of the triangles, inset by the margin.
      const brittle::TriMesh in = inset(d.mesh, d.margin);
      for (const brittle::Vec3& p : in.positions) e->vertices.insert(e->vertices.end(), {p.x(), p.y(), p.z()});
      for (const brittle::Tri& t : in.triangles) e->indices.insert(e->indices.end(), {t[0], t[1], t[2]});
      e->arrays = std::make_unique<btTriangleIndexVertexArray>(
          static_cast<int>(in.triangles.size()), e->indices.data(), static_cast<int>(3 * sizeof(int)),
          static_cast<int>(in.positions.size()), e->vertices.data(), static_cast<int>(3 * sizeof(btScalar)));
      auto gimpact = std::make_unique<btGImpactMeshShape>(e->arrays.get());
      gimpact->setMargin(d.margin);
      gimpact->updateBound();
      e->shape = std::move(gimpact);
    }
  }
  e->shape->setMargin(d.margin);
  e->margin = d.shape == Shape::Sphere ? e->shape->getMargin() : d.margin;
  e->dynamic = !d.kinematic;
  e->kinematic = d.kinematic;
  e->kinematic_velocity = d.velocity;
  e->kinematic_angular_velocity = d.angular_velocity;
  e->kinematic_pose = d.pose;
  const int id = impl_->add(std::move(e), d.kinematic ? 0.0 : d.mass, d.kinematic ? Vec3::Zero() : d.inertia,
                            d.pose, d.surface);
  auto* body = static_cast<btRigidBody*>(impl_->entries.back()->object.get());
  if (d.kinematic) {
    body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    body->setActivationState(DISABLE_DEACTIVATION);
  } else {
    // Continuous collision detection for bodies that move more than a fraction of their size in a step
    // (a 13 mm ball at 80 m/s moves 40 mm per 0.5 ms step and passed through a statue without it).
    double size = 2 * d.radius;
    if (d.shape != Shape::Sphere) {
      brittle::Vec3 lo, hi;
      brittle::bounding_box(d.mesh, lo, hi);
      size = (hi - lo).minCoeff();
    }
    body->setCcdMotionThreshold(0.25 * size);
    body->setCcdSweptSphereRadius(0.4 * size);
    body->setLinearVelocity(bt(d.velocity));
    body->setAngularVelocity(bt(d.angular_velocity));
    body->activate(true);
  }
  return id;
}

void RigidWorld::remove_body(int id) {
  Entry& e = impl_->at(id);
  // Bullet keeps ignored partners as raw pointers. A pointer left behind would make the survivor ignore
  // whatever body is allocated next at the freed address (a fragment spawned later, depending on the heap).
  for (const int other : e.ignored) {
    Entry& o = impl_->at(other);  // ignored partners are removed before they leave (below)
    o.object->setIgnoreCollisionCheck(e.object.get(), false);
    o.ignored.erase(std::remove(o.ignored.begin(), o.ignored.end(), id), o.ignored.end());
  }
  impl_->world.removeRigidBody(static_cast<btRigidBody*>(e.object.get()));
  impl_->entries[static_cast<size_t>(id)].reset();
}

bool RigidWorld::has_body(int id) const {
  return id >= 0 && static_cast<size_t>(id) < impl_->entries.size() && impl_->entries[static_cast<size_t>(id)];
}

size_t RigidWorld::num_bodies() const {
  size_t n = 0;
  for (const auto& e : impl_->entries) n += e && (e->dynamic || e->kinematic);
  return n;
}

const std::string& RigidWorld::name(int id) const { return impl_->at(id).name; }

BodyState RigidWorld::state(int id) const {
  const Entry& e = impl_->at(id);
  const auto* body = static_cast<const btRigidBody*>(e.object.get());
  BodyState s;
  s.pose = eig(body->getWorldTransform());
  if (e.kinematic) {
    s.velocity = e.kinematic_velocity;
    s.angular_velocity = e.kinematic_angular_velocity;
  } else if (e.dynamic) {
    s.velocity = eig(body->getLinearVelocity());
    s.angular_velocity = eig(body->getAngularVelocity());
  }
  return s;
}

void RigidWorld::set_gravity(const Vec3& gravity) {
  impl_->world.setGravity(bt(gravity));
  for (auto& e : impl_->entries)
    if (e && e->dynamic) static_cast<btRigidBody*>(e->object.get())->setGravity(bt(gravity));
}

void RigidWorld::set_velocity(int id, const Vec3& velocity, const Vec3& angular_velocity) {
  Entry& e = impl_->at(id);
  if (!e.dynamic) throw core::InputError("rigid world: \"" + e.name + "\" is not a dynamic body");
  auto* body = static_cast<btRigidBody*>(e.object.get());
  body->setLinearVelocity(bt(velocity));
  body->setAngularVelocity(bt(angular_velocity));
  body->activate(true);
}

double RigidWorld::mass(int id) const {
  const Entry& e = impl_->at(id);
  return e.dynamic ? 1.0 / static_cast<const btRigidBody*>(e.object.get())->getInvMass() : 0.0;
}

double RigidWorld::margin(int id) const { return impl_->at(id).margin; }

Vec3 RigidWorld::principal_inertia(int id) const {
  const Entry& e = impl_->at(id);
  if (!e.dynamic) return Vec3::Zero();
  return eig(static_cast<const btRigidBody*>(e.object.get())->getLocalInertia());
}

void RigidWorld::step(double dt) {
  for (auto& e : impl_->entries) {
    if (!e) continue;
    e->before = state(static_cast<const btRigidBody*>(e->object.get())->getUserIndex());
    if (e->kinematic) {  // Bullet takes a kinematic body's velocity from its motion state's change
      e->kinematic_pose = advance(e->kinematic_pose, e->kinematic_velocity, e->kinematic_angular_velocity, dt);
      e->motion->setWorldTransform(bt(e->kinematic_pose));
    }
  }
  impl_->world.stepSimulation(dt, 0);  // maxSubSteps 0: exactly one step of dt
  ++steps_;
  contacts_.clear();
  const bool two_directions = impl_->world.getSolverInfo().m_solverMode & SOLVER_USE_2_FRICTION_DIRECTIONS;
  for (int i = 0; i < impl_->dispatcher.getNumManifolds(); ++i) {
    const btPersistentManifold* m = impl_->dispatcher.getManifoldByIndexInternal(i);
    const int a = m->getBody0()->getUserIndex(), b = m->getBody1()->getUserIndex();
    const Entry& ea = impl_->at(a);
    const Entry& eb = impl_->at(b);
    for (int j = 0; j < m->getNumContacts(); ++j) {
      const btManifoldPoint& p = m->getContactPoint(j);
      ContactPoint c;
      c.a = a;
      c.b = b;
      c.point = 0.5 * (eig(p.getPositionWorldOnA()) + eig(p.getPositionWorldOnB()));
      c.normal = eig(p.m_normalWorldOnB);
      c.impulse = p.getAppliedImpulse();
      c.friction_impulse = eig(p.m_lateralFrictionDir1) * p.m_appliedImpulseLateral1;
      if (two_directions) c.friction_impulse += eig(p.m_lateralFrictionDir2) * p.m_appliedImpulseLateral2;
      c.distance = p.getDistance();
      const auto speed_at = [&](const Entry& e) {
        return Vec3(e.before.velocity + e.before.angular_velocity.cross(c.point - e.before.pose.translation));
      };
      c.approach_speed = -(speed_at(ea) - speed_at(eb)).dot(c.normal);
      contacts_.push_back(c);
    }
  }
}

void RigidWorld::ignore_pair(int a, int b, bool ignore) {
  impl_->set_ignored(a, b, ignore);
  if (!ignore) {
    impl_->at(a).object->activate(true);
    impl_->at(b).object->activate(true);
  }
}

size_t RigidWorld::ignored_count(int id) const {
  return static_cast<size_t>(impl_->at(id).object->getNumObjectsWithoutCollision());
}

bool RigidWorld::bounds_overlap(int a, int b) const {
  btVector3 lo_a, hi_a, lo_b, hi_b;
  impl_->at(a).object->getCollisionShape()->getAabb(impl_->at(a).object->getWorldTransform(), lo_a, hi_a);
  impl_->at(b).object->getCollisionShape()->getAabb(impl_->at(b).object->getWorldTransform(), lo_b, hi_b);
  for (int k = 0; k < 3; ++k)
    if (hi_a[k] < lo_b[k] || hi_b[k] < lo_a[k]) return false;
  return true;
}

double RigidWorld::pair_distance(int a, int b) const {
  struct Closest : btCollisionWorld::ContactResultCallback {
    double distance = std::numeric_limits<double>::infinity();
    btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                             const btCollisionObjectWrapper*, int, int) override {
      distance = std::min(distance, static_cast<double>(cp.getDistance()));
      return 0;
    }
  } closest;
  impl_->world.contactPairTest(impl_->at(a).object.get(), impl_->at(b).object.get(), closest);
  return closest.distance;
}

}  // namespace shellfrac::rigid
