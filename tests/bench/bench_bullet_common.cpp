#include "bench_bullet_common.h"

#include <algorithm>
#include <cmath>

namespace pfxbench {

namespace {

btScalar combinedFriction(const btCollisionObject* a, const btCollisionObject* b) {
  return std::sqrt(a->getFriction() * b->getFriction());
}
btScalar combinedRestitution(const btCollisionObject* a, const btCollisionObject* b) {
  return std::max(a->getRestitution(), b->getRestitution());
}

}  // namespace

void useMatchedMaterialCombination() {
  gCalculateCombinedFrictionCallback = combinedFriction;
  gCalculateCombinedRestitutionCallback = combinedRestitution;
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

void matchSolverSettings(btContactSolverInfo& info, const EngineSettings& settings) {
  info.m_numIterations = settings.iterations;
  // As pfx: every overlap beyond a 5 mm slop is pushed out by split impulses, a fifth per
  // step (Bullet's default erp2), rotation included; warm starting in full.
  info.m_linearSlop = btScalar(0.005);
  info.m_splitImpulse = 1;
  info.m_splitImpulsePenetrationThreshold = 0;
  info.m_splitImpulseTurnErp = 1;
  info.m_erp2 = btScalar(0.2);
  info.m_warmstartingFactor = 1;
}

std::unique_ptr<btRigidBody> makeBtRigidBody(const BodyDesc& desc, btCollisionShape* shape) {
  const btScalar mass = desc.fixed ? 0 : btScalar(desc.mass);
  btRigidBody::btRigidBodyConstructionInfo ci(
      mass, nullptr, shape, desc.fixed ? btVector3(0, 0, 0) : toBt(desc.inertia));
  ci.m_startWorldTransform = btTransform(toBt(desc.orientation), toBt(desc.position));
  ci.m_friction = btScalar(desc.friction);
  ci.m_restitution = btScalar(desc.restitution);
  auto body = std::make_unique<btRigidBody>(ci);
  if (!desc.fixed) {
    body->setLinearVelocity(toBt(desc.linearVelocity));
    body->setAngularVelocity(toBt(desc.angularVelocity));
    body->setActivationState(DISABLE_DEACTIVATION);
    body->setCcdMotionThreshold(btScalar(desc.shape.innerRadius()));
    body->setCcdSweptSphereRadius(btScalar(desc.shape.innerRadius()));
  }
  return body;
}

}  // namespace pfxbench
