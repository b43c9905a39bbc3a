// Bullet 3 behind the benchmark's interface: btDiscreteDynamicsWorld with the sequential
// impulse solver; ball joints are btPoint2PointConstraints, hinges btHingeConstraints,
// motors their angular motors.
// Sub-steps are taken as separate variable-length steps of exactly dt / substeps:
// Bullet's fixed-step accumulator (stepSimulation(dt, N, dt / N)) divides
// single-precision time by the rounded sub-step, and when N is not a power of two it now
// and then defers a sub-step to the next call.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "bench_bullet_common.h"

namespace pfxbench {

namespace {

// A joint as Bullet holds it. A joint to the world is made on body B alone, which Bullet
// then calls its body A; `swapped` says so, to report the anchors in the scene's order.
struct BtJoint {
  std::unique_ptr<btTypedConstraint> constraint;
  bool swapped = false;
  // Bullet's hinge angle is its body A's turn relative to its body B (btHingeConstraint's
  // default reference frame B): the scene's angle times this.
  double angleSign() const { return swapped ? 1 : -1; }
};

class BulletEngine final : public Engine {
 public:
  ~BulletEngine() override {
    if (!m_world) return;
    for (auto& joint : m_joints) m_world->removeConstraint(joint.constraint.get());
    for (auto& body : m_bodies) m_world->removeRigidBody(body.get());
  }

  bool build(const Scene& scene, const EngineSettings& settings, std::string&) override {
    useMatchedMaterialCombination();
    m_dispatcher = std::make_unique<btCollisionDispatcher>(&m_configuration);
    m_world = std::make_unique<btDiscreteDynamicsWorld>(m_dispatcher.get(), &m_broadphase,
                                                        &m_solver, &m_configuration);
    m_world->setGravity(toBt(scene.gravity));
    matchSolverSettings(m_world->getSolverInfo(), settings);
    m_subTimeStep = btScalar(settings.dt / settings.substeps);
    m_substeps = settings.substeps;

    for (const BodyDesc& desc : scene.bodies) {
      m_shapes.push_back(makeBtShape(desc.shape));
      m_bodies.push_back(makeBtRigidBody(desc, m_shapes.back().get()));
      m_world->addRigidBody(m_bodies.back().get());
    }
    for (const JointDesc& desc : scene.joints) {
      m_joints.push_back(makeJoint(desc));
      // Bodies held together by a joint do not collide, as in pfx.
      m_world->addConstraint(m_joints.back().constraint.get(), true);
    }
    // A motor's impulse is bounded per solver step, which is one sub-step here.
    for (const JointMotorDesc& motor : scene.motors) {
      m_motors.push_back({motor.joint, btScalar(motor.maxTorque) * m_subTimeStep});
    }
    return true;
  }

  void setMotorRates(const std::vector<double>& rates) override {
    for (std::size_t i = 0; i < rates.size(); ++i) {
      const BtJoint& joint = m_joints[m_motors[i].joint];
      auto& hinge = static_cast<btHingeConstraint&>(*joint.constraint);
      hinge.enableAngularMotor(true, btScalar(joint.angleSign() * rates[i]),
                               m_motors[i].maxImpulse);
    }
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
      states[i].position = fromBt(t.getOrigin());
      states[i].orientation = fromBt(t.getRotation());
      states[i].linearVelocity = fromBt(body.getLinearVelocity());
      states[i].angularVelocity = fromBt(body.getAngularVelocity());
    }
  }

  void readJointAnchors(std::vector<JointAnchors>& anchors) const override {
    anchors.resize(m_joints.size());
    for (std::size_t i = 0; i < m_joints.size(); ++i) {
      const btTypedConstraint& c = *m_joints[i].constraint;
      btVector3 onFirst, onSecond;
      if (c.getConstraintType() == POINT2POINT_CONSTRAINT_TYPE) {
        const auto& p2p = static_cast<const btPoint2PointConstraint&>(c);
        onFirst = p2p.getRigidBodyA().getCenterOfMassTransform() * p2p.getPivotInA();
        onSecond = p2p.getRigidBodyB().getCenterOfMassTransform() * p2p.getPivotInB();
      } else {
        const auto& hinge = static_cast<const btHingeConstraint&>(c);
        onFirst = hinge.getRigidBodyA().getCenterOfMassTransform() * hinge.getAFrame().getOrigin();
        onSecond = hinge.getRigidBodyB().getCenterOfMassTransform() * hinge.getBFrame().getOrigin();
      }
      if (m_joints[i].swapped) std::swap(onFirst, onSecond);
      anchors[i].onA = fromBt(onFirst);
      anchors[i].onB = fromBt(onSecond);
    }
  }

 private:
  BtJoint makeJoint(const JointDesc& desc) {
    btRigidBody& b = *m_bodies[desc.bodyB];
    const btTransform toB = b.getCenterOfMassTransform().inverse();
    const btVector3 pivotInB = toB * toBt(desc.anchor);
    BtJoint joint;
    if (desc.bodyA == kWorld) {
      joint.swapped = true;
      if (desc.type == JointType::Ball) {
        joint.constraint = std::make_unique<btPoint2PointConstraint>(b, pivotInB);
      } else {
        // Against Bullet's fixed body, whose frame is the world's: the one-body constructor
        // would place the frame's origin in the world but keep its axes in body B's frame,
        // twisting any body that does not start unrotated.
        const btTransform frame = hingeFrame(desc);
        auto hinge = std::make_unique<btHingeConstraint>(b, btTypedConstraint::getFixedBody(),
                                                         toB * frame, frame);
        limitHinge(*hinge, desc, joint.angleSign());
        joint.constraint = std::move(hinge);
      }
      return joint;
    }
    btRigidBody& a = *m_bodies[desc.bodyA];
    const btTransform toA = a.getCenterOfMassTransform().inverse();
    const btVector3 pivotInA = toA * toBt(desc.anchor);
    if (desc.type == JointType::Ball) {
      joint.constraint = std::make_unique<btPoint2PointConstraint>(a, b, pivotInA, pivotInB);
    } else {
      const btTransform frame = hingeFrame(desc);
      auto hinge = std::make_unique<btHingeConstraint>(a, b, toA * frame, toB * frame);
      limitHinge(*hinge, desc, joint.angleSign());
      joint.constraint = std::move(hinge);
    }
    return joint;
  }

  // The hinge's frame in the world (its Z axis is the hinge axis), given to both bodies as
  // they are now, so that Bullet's angle is zero at the initial pose as in the other engines.
  static btTransform hingeFrame(const JointDesc& desc) {
    btVector3 axis = toBt(desc.axis.normalized()), u, v;
    btPlaneSpace1(axis, u, v);
    return btTransform(btMatrix3x3(u.x(), v.x(), axis.x(), u.y(), v.y(), axis.y(), u.z(), v.z(),
                                   axis.z()),
                       toBt(desc.anchor));
  }

  static void limitHinge(btHingeConstraint& hinge, const JointDesc& desc, double sign) {
    if (!desc.limited()) return;
    const double a = sign * desc.lowerLimit, b = sign * desc.upperLimit;
    hinge.setLimit(btScalar(std::min(a, b)), btScalar(std::max(a, b)));
  }

  // Declared in the order of construction; the world goes first on destruction.
  btDefaultCollisionConfiguration m_configuration;
  btDbvtBroadphase m_broadphase;
  btSequentialImpulseConstraintSolver m_solver;
  std::unique_ptr<btCollisionDispatcher> m_dispatcher;
  std::vector<std::unique_ptr<btCollisionShape>> m_shapes;
  std::vector<std::unique_ptr<btRigidBody>> m_bodies;
  std::vector<BtJoint> m_joints;
  struct Motor {
    int joint;
    btScalar maxImpulse;
  };
  std::vector<Motor> m_motors;  // per motor of the scene
  std::unique_ptr<btDiscreteDynamicsWorld> m_world;
  btScalar m_subTimeStep = btScalar(1) / 60;
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createBulletEngine() { return std::make_unique<BulletEngine>(); }

}  // namespace pfxbench
