// pfx behind the benchmark's interface: the stable pipeline (cached pairs and contacts,
// warm-started solver), sub-steps by stepping the world several times at dt / substeps,
// on as many threads as the settings say.
// Joints are PfxJoints made by pfxInitializeBallJoint / pfxInitializeHingeJoint; joints to
// the world hang from one extra fixed body that collides with nothing. A motor is the
// velocity drive of its hinge's twist axis, its force limit the motor's torque.
#include <cmath>
#include <string>
#include <vector>

#include "bench_engine.h"
#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"

namespace pfxbench {

namespace {

using namespace pfx;

PfxVector3 toPfx(const Vec3& v) { return v.cast<PfxFloat>(); }
PfxQuat toPfx(const Quat& q) { return q.cast<PfxFloat>().normalized(); }

PfxShape makePfxShape(const ShapeDesc& shape) {
  const auto half = static_cast<PfxFloat>(shape.halfLength);
  const auto radius = static_cast<PfxFloat>(shape.radius);
  switch (shape.type) {
    case ShapeType::Sphere: return pfxMakeShape(PfxSphere(radius));
    case ShapeType::Box: return pfxMakeShape(PfxBox(toPfx(shape.halfExtents)));
    case ShapeType::Capsule: return pfxMakeShape(PfxCapsule(half, radius));
    case ShapeType::Cylinder: return pfxMakeShape(PfxCylinder(half, radius));
  }
  return pfxMakeShape(PfxSphere(radius));
}

class PfxEngine final : public Engine {
 public:
  bool build(const Scene& scene, const EngineSettings& settings, std::string& error) override {
    PfxWorldParam param;
    param.pipeline = kPfxPipelineStable;
    param.gravity = toPfx(scene.gravity);
    param.timeStep = static_cast<PfxFloat>(settings.dt / settings.substeps);
    param.iteration = static_cast<PfxUInt32>(settings.iterations);
    param.enableSleep = false;  // no engine sleeps (bench_engine.h)
    param.numThreads = static_cast<PfxUInt32>(settings.threads);
    if (const PfxInt32 err = m_world.initialize(param); err != PFX_OK) {
      error = std::string("pfx: world parameters rejected: ") + pfxErrorString(err);
      return false;
    }
    m_substeps = settings.substeps;
    // The scene's count is known: the world's arrays are sized to it, not doubled as bodies
    // come (the ODE engine reserves its arrays the same way).
    m_world.reserveRigidBodies(static_cast<PfxUInt32>(scene.bodies.size()));
    for (const BodyDesc& desc : scene.bodies) {
      PfxRigidState state;
      state.reset();
      state.setPosition(toPfx(desc.position));
      state.setOrientation(toPfx(desc.orientation));
      state.setLinearVelocity(toPfx(desc.linearVelocity));
      state.setAngularVelocity(toPfx(desc.angularVelocity));
      state.setMotionType(desc.fixed ? kPfxMotionTypeFixed : kPfxMotionTypeActive);
      PfxRigidBody body;
      body.reset();
      body.setFriction(static_cast<PfxFloat>(desc.friction));
      body.setRestitution(static_cast<PfxFloat>(desc.restitution));
      if (!desc.fixed) {
        body.setMass(static_cast<PfxFloat>(desc.mass));
        body.setInertia(toPfx(desc.inertia).asDiagonal());
      }
      const PfxShape shape = makePfxShape(desc.shape);
      if (const PfxInt32 err = m_world.addRigidBody(state, body, &shape, 1); err != PFX_OK) {
        error = std::string("pfx: body rejected: ") + pfxErrorString(err);
        return false;
      }
    }
    m_numSceneBodies = m_world.getNumRigidBodies();
    return addJoints(scene, error) && addMotors(scene, error);
  }

  // The hinge's twist axis (its angle, B's turn relative to A about the axis) is driven at
  // the target rate; a hinge's joint has the scene joint's index.
  void setMotorRates(const std::vector<double>& rates) override {
    for (std::size_t i = 0; i < rates.size(); ++i) {
      PfxJoint joint = m_world.getJoint(m_motorJoints[i]);
      joint.m_constraints[kPfxJointAxisTwist].m_driveTarget = static_cast<PfxFloat>(rates[i]);
      m_world.setJoint(m_motorJoints[i], joint);
    }
  }

  bool step(std::string& error) override {
    for (int i = 0; i < m_substeps; ++i) {
      if (const PfxInt32 err = m_world.step(); err != PFX_OK) {
        error = std::string("pfx: step failed: ") + pfxErrorString(err);
        return false;
      }
    }
    return true;
  }

  void readBodies(std::vector<BodyState>& states) const override {
    states.resize(m_numSceneBodies);
    for (PfxUInt32 i = 0; i < m_numSceneBodies; ++i) {
      const PfxRigidState& s = m_world.getRigidState(i);
      states[i].position = s.getPosition().cast<double>();
      states[i].orientation = s.getOrientation().cast<double>();
      states[i].linearVelocity = s.getLinearVelocity().cast<double>();
      states[i].angularVelocity = s.getAngularVelocity().cast<double>();
    }
  }

  void readJointAnchors(std::vector<JointAnchors>& anchors) const override {
    anchors.resize(m_world.getNumJoints());
    for (PfxUInt32 i = 0; i < m_world.getNumJoints(); ++i) {
      const PfxJoint& joint = m_world.getJoint(i);
      const PfxRigidState& a = m_world.getRigidState(joint.m_rigidBodyIdA);
      const PfxRigidState& b = m_world.getRigidState(joint.m_rigidBodyIdB);
      anchors[i].onA = (a.getPosition() + a.getOrientation() * joint.m_anchorA).cast<double>();
      anchors[i].onB = (b.getPosition() + b.getOrientation() * joint.m_anchorB).cast<double>();
    }
  }

 private:
  // The fixed body that joints to the world hang from, added after the scene's bodies.
  PfxInt32 addWorldAnchor(PfxUInt32& id) {
    PfxRigidState state;
    state.reset();
    state.setMotionType(kPfxMotionTypeFixed);
    state.setContactFilterSelf(0);
    state.setContactFilterTarget(0);
    PfxRigidBody body;
    body.reset();
    const PfxShape shape = pfxMakeShape(PfxSphere(PfxFloat(0.01)));
    return m_world.addRigidBody(state, body, &shape, 1, &id);
  }

  bool addJoints(const Scene& scene, std::string& error) {
    PfxUInt32 worldAnchor = 0;
    bool haveWorldAnchor = false;
    for (const JointDesc& desc : scene.joints) {
      if (desc.bodyA == kWorld && !haveWorldAnchor) {
        if (const PfxInt32 err = addWorldAnchor(worldAnchor); err != PFX_OK) {
          error = std::string("pfx: world anchor rejected: ") + pfxErrorString(err);
          return false;
        }
        haveWorldAnchor = true;
      }
      const PfxUInt32 idA = desc.bodyA == kWorld ? worldAnchor : static_cast<PfxUInt32>(desc.bodyA);
      const PfxRigidState& stateA = m_world.getRigidState(idA);
      const PfxRigidState& stateB = m_world.getRigidState(static_cast<PfxUInt32>(desc.bodyB));
      PfxJoint joint;
      PfxInt32 err = PFX_OK;
      if (desc.type == JointType::Ball) {
        PfxBallJointInitParam param;
        param.anchorPoint = toPfx(desc.anchor);
        err = pfxInitializeBallJoint(joint, stateA, stateB, param);
      } else {
        PfxHingeJointInitParam param;
        param.anchorPoint = toPfx(desc.anchor);
        param.axis = toPfx(desc.axis).normalized();
        if (desc.limited()) {
          param.lowerAngle = static_cast<PfxFloat>(desc.lowerLimit);
          param.upperAngle = static_cast<PfxFloat>(desc.upperLimit);
        }
        err = pfxInitializeHingeJoint(joint, stateA, stateB, param);
        // Without a limit the hinge turns freely; the init function would limit it to a turn.
        if (err == PFX_OK && !desc.limited()) {
          joint.m_constraints[kPfxJointAxisTwist].m_lock = kPfxJointLockFree;
        }
      }
      if (err == PFX_OK) err = m_world.addJoint(joint);
      if (err != PFX_OK) {
        error = std::string("pfx: joint rejected: ") + pfxErrorString(err);
        return false;
      }
    }
    return true;
  }

  bool addMotors(const Scene& scene, std::string& error) {
    for (const JointMotorDesc& motor : scene.motors) {
      const auto id = static_cast<PfxUInt32>(motor.joint);
      PfxJoint joint = m_world.getJoint(id);
      PfxJointConstraint& twist = joint.m_constraints[kPfxJointAxisTwist];
      twist.m_drive = kPfxJointDriveVelocity;
      twist.m_driveTarget = 0;
      twist.m_driveMaxForce = static_cast<PfxFloat>(motor.maxTorque);
      if (const PfxInt32 err = m_world.setJoint(id, joint); err != PFX_OK) {
        error = std::string("pfx: motor rejected: ") + pfxErrorString(err);
        return false;
      }
      m_motorJoints.push_back(id);
    }
    return true;
  }

  PfxWorld m_world;
  std::vector<PfxUInt32> m_motorJoints;  // per motor of the scene
  PfxUInt32 m_numSceneBodies = 0;
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createPfxEngine() { return std::make_unique<PfxEngine>(); }

}  // namespace pfxbench
