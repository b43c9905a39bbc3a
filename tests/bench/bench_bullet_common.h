// What the two Bullet adapters (rigid bodies, and Featherstone multibodies) share: unit
// conversions, shapes with the margin they can hold, the solver settings matched to pfx,
// and plain rigid bodies.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <memory>

#include "bench_engine.h"

namespace pfxbench {

inline btVector3 toBt(const Vec3& v) {
  return btVector3(btScalar(v.x()), btScalar(v.y()), btScalar(v.z()));
}
inline btQuaternion toBt(const Quat& q) {
  return btQuaternion(btScalar(q.x()), btScalar(q.y()), btScalar(q.z()), btScalar(q.w()));
}
inline Vec3 fromBt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
inline Quat fromBt(const btQuaternion& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }

// Friction and restitution combined as pfx combines them (Bullet multiplies by default).
void useMatchedMaterialCombination();

std::unique_ptr<btCollisionShape> makeBtShape(const ShapeDesc& shape);

// Iterations, slop, split impulses and warm starting as pfx does them.
void matchSolverSettings(btContactSolverInfo& info, const EngineSettings& settings);

// A body of the scene as a btRigidBody (static when fixed) on the given shape, awake for
// good and with continuous collision for fast motion.
std::unique_ptr<btRigidBody> makeBtRigidBody(const BodyDesc& desc, btCollisionShape* shape);

}  // namespace pfxbench
