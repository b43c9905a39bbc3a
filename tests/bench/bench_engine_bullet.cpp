// Bullet 3 behind the benchmark's interface: btDiscreteDynamicsWorld with the sequential
// impulse solver. Sub-steps are taken as separate variable-length steps of exactly
// dt / substeps: Bullet's fixed-step accumulator (stepSimulation(dt, N, dt / N)) divides
// single-precision time by the rounded sub-step, and when N is not a power of two it now
// and then defers a sub-step to the next call.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "bench_engine.h"

namespace pfxbench {

namespace {

btVector3 toBt(const Vec3& v) { return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z())); }
btQuaternion toBt(const Quat& q) {
  return btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w()));
}
Vec3 fromBt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// Bullet multiplies the two bodies' coefficients by default; pfx takes the geometric mean
// of friction and the larger restitution.
btScalar combinedFriction(const btCollisionObject* a, const btCollisionObject* b) {
  return std::sqrt(a->getFriction() * b->getFriction());
}
btScalar combinedRestitution(const btCollisionObject* a, const btCollisionObject* b) {
  return std::max(a->getRestitution(), b->getRestitution());
}

std::unique_ptr<btCollisionShape> makeBtShape(const ShapeDesc& shape) {
  const auto radius = btScalar(shape.radius);
  const auto half = btScalar(shape.halfLength);
  std::unique_ptr<btCollisionShape> made;
  switch (shape.type) {
    case ShapeType::Sphere: made = std::make_unique<btSphereShape>(radius); break;
    case ShapeType::Box: made = std::make_unique<btBoxShape>(toBt(shape.halfExtents)); break;
    case ShapeType::Capsule: made = std::make_unique<btCapsuleShapeX>(radius, 2 * half); break;
    case ShapeType::Cylinder:
      made = std::make_unique<btCylinderShapeX>(btVector3(half, radius, radius));
      break;
  }
  // A sphere's margin is its radius; for the others the default 4 cm margin is carved out
  // of the shape, which a thin box cannot hold.
  if (shape.type != ShapeType::Sphere) {
    made->setMargin(std::min(made->getMargin(), btScalar(0.1 * shape.innerRadius())));
  }
  return made;
}

class BulletEngine final : public Engine {
 public:
  ~BulletEngine() override {
    if (!m_world) return;
    for (auto& body : m_bodies) m_world->removeRigidBody(body.get());
  }

  bool build(const Scene& scene, const EngineSettings& settings, std::string&) override {
    gCalculateCombinedFrictionCallback = combinedFriction;
    gCalculateCombinedRestitutionCallback = combinedRestitution;
    m_dispatcher = std::make_unique<btCollisionDispatcher>(&m_configuration);
    m_world = std::make_unique<btDiscreteDynamicsWorld>(m_dispatcher.get(), &m_broadphase,
                                                        &m_solver, &m_configuration);
    m_world->setGravity(toBt(scene.gravity));
    btContactSolverInfo& info = m_world->getSolverInfo();
    info.m_numIterations = settings.iterations;
    // As pfx: every overlap beyond a 5 mm slop is pushed out by split impulses, a fifth per
    // step (Bullet's default erp2), rotation included; warm starting in full.
    info.m_linearSlop = btScalar(0.005);
    info.m_splitImpulse = 1;
    info.m_splitImpulsePenetrationThreshold = 0;
    info.m_splitImpulseTurnErp = 1;
    info.m_erp2 = btScalar(0.2);
    info.m_warmstartingFactor = 1;
    m_subTimeStep = btScalar(settings.dt / settings.substeps);
    m_substeps = settings.substeps;

    for (const BodyDesc& desc : scene.bodies) {
      m_shapes.push_back(makeBtShape(desc.shape));
      btCollisionShape* shape = m_shapes.back().get();
      const btScalar mass = desc.fixed ? 0 : btScalar(desc.mass);
      btRigidBody::btRigidBodyConstructionInfo ci(
          mass, nullptr, shape, desc.fixed ? btVector3(0, 0, 0) : toBt(desc.inertia));
      ci.m_startWorldTransform = btTransform(toBt(desc.orientation), toBt(desc.position));
      ci.m_friction = btScalar(desc.friction);
      ci.m_restitution = btScalar(desc.restitution);
      m_bodies.push_back(std::make_unique<btRigidBody>(ci));
      btRigidBody* body = m_bodies.back().get();
      if (!desc.fixed) {
        body->setLinearVelocity(toBt(desc.linearVelocity));
        body->setAngularVelocity(toBt(desc.angularVelocity));
        body->setActivationState(DISABLE_DEACTIVATION);
        body->setCcdMotionThreshold(btScalar(desc.shape.innerRadius()));
        body->setCcdSweptSphereRadius(btScalar(desc.shape.innerRadius()));
      }
      m_world->addRigidBody(body);
    }
    return true;
  }

  bool step(std::string&) override {
    for (int i = 0; i < m_substeps; ++i) m_world->stepSimulation(m_subTimeStep, 0);
    return true;
  }

  void readBodies(std::vector<BodyState>& states) const override {
    states.resize(m_bodies.size());
    for (std::size_t i = 0; i < m_bodies.size(); ++i) {
      const btRigidBody& body = *m_bodies[i];
      const btTransform& t = body.getWorldTransform();
      const btQuaternion q = t.getRotation();
      states[i].position = fromBt(t.getOrigin());
      states[i].orientation = Quat(q.w(), q.x(), q.y(), q.z());
      states[i].linearVelocity = fromBt(body.getLinearVelocity());
      states[i].angularVelocity = fromBt(body.getAngularVelocity());
    }
  }

 private:
  // Declared in the order of construction; the world goes first on destruction.
  btDefaultCollisionConfiguration m_configuration;
  btDbvtBroadphase m_broadphase;
  btSequentialImpulseConstraintSolver m_solver;
  std::unique_ptr<btCollisionDispatcher> m_dispatcher;
  std::vector<std::unique_ptr<btCollisionShape>> m_shapes;
  std::vector<std::unique_ptr<btRigidBody>> m_bodies;
  std::unique_ptr<btDiscreteDynamicsWorld> m_world;
  btScalar m_subTimeStep = btScalar(1) / 60;
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createBulletEngine() { return std::make_unique<BulletEngine>(); }

}  // namespace pfxbench
