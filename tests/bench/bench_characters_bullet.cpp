// The characters scene on Bullet: the course in a btDiscreteDynamicsWorld, one
// btKinematicCharacterController on a btPairCachingGhostObject per walker, the way Bullet's
// own character demo sets them up (a btGhostPairCallback on the broad phase so that each
// ghost keeps its overlapping pairs), except that the characters' ghosts also see each
// other, as pfx's characters block each other. Bodies never sleep, as in every engine of
// pfx_bench.
#include "bench_characters.h"

#ifdef PFX_BENCH_HAVE_BULLET

#include <BulletCollision/CollisionDispatch/btGhostObject.h>
#include <BulletDynamics/Character/btKinematicCharacterController.h>
#include <btBulletDynamicsCommon.h>

#include "bench_bullet_common.h"

namespace pfxbench {

namespace {

class BulletCharacterEngine : public CharacterEngine {
 public:
  ~BulletCharacterEngine() override {
    for (auto& controller : m_controllers) m_world.removeAction(controller.get());
    for (auto& ghost : m_ghosts) m_world.removeCollisionObject(ghost.get());
    for (auto& body : m_bodies) m_world.removeRigidBody(body.get());
  }

  bool build(const CharacterCourse& course, double dt, std::string& error) override {
    m_dt = btScalar(dt);
    m_world.setGravity(btVector3(0, btScalar(-kCharacterGravity), 0));
    m_broadphase.getOverlappingPairCache()->setInternalGhostPairCallback(&m_ghostPairCallback);
    for (const CourseBox& box : course.fixedBoxes) add(box, 0, false);
    for (const CourseBox& box : course.platforms) m_platforms.push_back(add(box, 0, true));
    for (const CourseBox& box : course.looseBoxes) add(box, btScalar(kLooseBoxMass), false);

    // btCapsuleShape's height is that of its cylinder, between the two half spheres.
    m_capsule = std::make_unique<btCapsuleShape>(btScalar(kCharacterRadius),
                                                 btScalar(kCharacterHeight - 2 * kCharacterRadius));
    const btVector3 up(0, 1, 0);
    for (const Vec3& start : course.starts) {
      auto ghost = std::make_unique<btPairCachingGhostObject>();
      ghost->setCollisionShape(m_capsule.get());
      ghost->setCollisionFlags(btCollisionObject::CF_CHARACTER_OBJECT);
      auto controller = std::make_unique<btKinematicCharacterController>(
          ghost.get(), m_capsule.get(), btScalar(kCharacterStepHeight), up);
      // Placed after the controller is made: its constructor turns the ghost from its own
      // default up axis (Z) to the one given, which would lay a Y capsule on its side.
      ghost->setWorldTransform(btTransform(btQuaternion::getIdentity(),
                                           toBt(start) + up * btScalar(kCharacterHeight / 2)));
      controller->setGravity(btVector3(0, btScalar(-kCharacterGravity), 0));
      controller->setMaxSlope(btScalar(kCharacterMaxSlopeDegrees * SIMD_PI / 180));
      controller->setJumpSpeed(btScalar(kCharacterJumpSpeed));
      controller->setFallSpeed(btScalar(kCharacterMaxFallSpeed));
      m_world.addCollisionObject(ghost.get(), btBroadphaseProxy::CharacterFilter,
                                 btBroadphaseProxy::StaticFilter |
                                     btBroadphaseProxy::DefaultFilter |
                                     btBroadphaseProxy::CharacterFilter);
      m_world.addAction(controller.get());
      m_ghosts.push_back(std::move(ghost));
      m_controllers.push_back(std::move(controller));
    }
    (void)error;
    return true;
  }

  void movePlatform(int index, const Vec3& position, const Quat& orientation) override {
    // A kinematic body's motion state is read at the start of the step, and Bullet derives
    // its velocity from the change.
    m_platforms[index]->getMotionState()->setWorldTransform(
        btTransform(toBt(orientation), toBt(position)));
  }

  void setDesiredVelocity(int character, const Vec3& velocity) override {
    // The walk direction is this step's displacement.
    m_controllers[character]->setWalkDirection(toBt(velocity) * m_dt);
  }

  void jump(int character) override {
    // Bullet's jump() starts a jump in the air too; pfx's requestJump only on the ground.
    if (m_controllers[character]->canJump()) m_controllers[character]->jump();
  }

  bool step(std::string& error) override {
    // No sub-steps: exactly one step of dt, as pfx takes.
    m_world.stepSimulation(m_dt, 0);
    (void)error;
    return true;
  }

  Vec3 foot(int character) const override {
    return fromBt(m_ghosts[character]->getWorldTransform().getOrigin()) -
           Vec3(0, kCharacterHeight / 2, 0);
  }

 private:
  btRigidBody* add(const CourseBox& box, btScalar mass, bool kinematic) {
    m_shapes.push_back(std::make_unique<btBoxShape>(toBt(box.half)));
    btCollisionShape* shape = m_shapes.back().get();
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    m_motionStates.push_back(std::make_unique<btDefaultMotionState>(
        btTransform(toBt(box.orientation), toBt(box.center))));
    btRigidBody::btRigidBodyConstructionInfo info(mass, m_motionStates.back().get(), shape,
                                                  inertia);
    m_bodies.push_back(std::make_unique<btRigidBody>(info));
    btRigidBody* body = m_bodies.back().get();
    if (kinematic) {
      body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    }
    body->setActivationState(DISABLE_DEACTIVATION);
    m_world.addRigidBody(body);
    return body;
  }

  btDefaultCollisionConfiguration m_configuration;
  btCollisionDispatcher m_dispatcher{&m_configuration};
  // Before the broad phase, which refers to it until its end.
  btGhostPairCallback m_ghostPairCallback;
  btDbvtBroadphase m_broadphase;
  btSequentialImpulseConstraintSolver m_solver;
  btDiscreteDynamicsWorld m_world{&m_dispatcher, &m_broadphase, &m_solver, &m_configuration};
  std::vector<std::unique_ptr<btCollisionShape>> m_shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> m_motionStates;
  std::vector<std::unique_ptr<btRigidBody>> m_bodies;
  std::vector<btRigidBody*> m_platforms;
  std::unique_ptr<btCapsuleShape> m_capsule;
  std::vector<std::unique_ptr<btPairCachingGhostObject>> m_ghosts;
  std::vector<std::unique_ptr<btKinematicCharacterController>> m_controllers;
  btScalar m_dt = btScalar(1.0 / 60);
};

}  // namespace

std::unique_ptr<CharacterEngine> makeBulletCharacterEngine() {
  return std::make_unique<BulletCharacterEngine>();
}

}  // namespace pfxbench

#else

namespace pfxbench {
std::unique_ptr<CharacterEngine> makeBulletCharacterEngine() { return nullptr; }
}  // namespace pfxbench

#endif
