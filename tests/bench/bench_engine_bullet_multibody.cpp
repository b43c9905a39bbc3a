// Bullet 3's Featherstone articulations behind the benchmark's interface: every joint tree
// hanging from the world becomes one btMultiBody with a fixed base at the root joint's
// anchor, its bodies links with spherical or revolute joints, stepped in a
// btMultiBodyDynamicsWorld with the multibody constraint solver. Hinge limits are
// btMultiBodyJointLimitConstraints, motors btMultiBodyJointMotors (a velocity target held
// as a constraint row within the motor's impulse). Bodies outside the trees are plain
// btRigidBodies of the same world. Scenes without joints are left to the engine
// `bullet`; jointed groups floating free, and jointed bodies that start moving, are not
// built here (their root would need a floating base and its velocities mapped to joint
// rates).
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <string>

#include "bench_bullet_common.h"

namespace pfxbench {

namespace {

// Link parameters that keep the articulation undamped and unclamped like the other
// engines: Bullet caps joint rates at 100 rad/s and damps links by 0.04 by default.
constexpr btScalar kUnlimitedCoordinateVelocity = btScalar(1e6);
constexpr btScalar kUnlimitedImpulse = btScalar(1e10);

// Where a body of the scene lives: a plain rigid body, or link `link` of multibody `tree`.
struct BodySlot {
  int rigid = -1;
  int tree = -1;
  int link = -1;
};

// A joint's anchor as each of its two sides carries it: a point fixed in a link's frame,
// or in the base's (link -1), which sits still at the world anchor.
struct LinkPoint {
  int link = -1;
  btVector3 local{0, 0, 0};
};

struct TreeJoint {
  int tree = 0;
  LinkPoint onA;
  LinkPoint onB;
  // A revolute link's coordinate is the child's turn relative to its parent: the scene's
  // hinge angle times this (-1 where the scene names the child first).
  int link = -1;
  double angleSign = 1;
};

bool atRest(const BodyDesc& body) {
  return body.linearVelocity.isZero() && body.angularVelocity.isZero();
}

class BulletMultiBodyEngine final : public Engine {
 public:
  ~BulletMultiBodyEngine() override {
    if (!m_world) return;
    for (auto& constraint : m_constraints) m_world->removeMultiBodyConstraint(constraint.get());
    for (auto& collider : m_colliders) m_world->removeCollisionObject(collider.get());
    for (auto& tree : m_trees) m_world->removeMultiBody(tree.get());
    for (auto& body : m_bodies) m_world->removeRigidBody(body.get());
  }

  bool supports(const Scene& scene, const EngineSettings&, std::string& reason) const override {
    if (scene.joints.empty()) {
      reason = "bullet_multibody: no joints in this scene; the engine bullet runs it";
      return false;
    }
    JointForest forest;
    if (!buildJointForest(scene, forest, reason)) {
      reason = "bullet_multibody: " + reason;
      return false;
    }
    for (int body : forest.order) {
      const bool jointed = forest.parentJoint[body] >= 0 || hasChildren(forest, body);
      if (!jointed) continue;
      if (forest.parentJoint[body] < 0) {
        reason = "bullet_multibody: a jointed group not attached to the world (a floating base "
                 "is not built here)";
        return false;
      }
      if (!atRest(scene.bodies[body])) {
        reason = "bullet_multibody: a jointed body starts moving (joint rates are not derived "
                 "here)";
        return false;
      }
    }
    return true;
  }

  bool build(const Scene& scene, const EngineSettings& settings, std::string& error) override {
    JointForest forest;
    if (!buildJointForest(scene, forest, error)) {
      error = "bullet_multibody: " + error;
      return false;
    }
    useMatchedMaterialCombination();
    m_dispatcher = std::make_unique<btCollisionDispatcher>(&m_configuration);
    m_world = std::make_unique<btMultiBodyDynamicsWorld>(m_dispatcher.get(), &m_broadphase,
                                                         &m_solver, &m_configuration);
    m_world->setGravity(toBt(scene.gravity));
    matchSolverSettings(m_world->getSolverInfo(), settings);
    m_subTimeStep = btScalar(settings.dt / settings.substeps);
    m_substeps = settings.substeps;

    m_slots.assign(scene.bodies.size(), BodySlot());
    m_treeJoints.assign(scene.joints.size(), TreeJoint());
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      const BodyDesc& desc = scene.bodies[i];
      if (!desc.fixed && (forest.parentJoint[i] >= 0 || hasChildren(forest, static_cast<int>(i)))) {
        continue;
      }
      m_shapes.push_back(makeBtShape(desc.shape));
      m_bodies.push_back(makeBtRigidBody(desc, m_shapes.back().get()));
      m_world->addRigidBody(m_bodies.back().get());
      m_slots[i].rigid = static_cast<int>(m_bodies.size()) - 1;
    }
    for (int root : forest.order) {
      if (forest.parentJoint[root] >= 0 && forest.parentBody[root] == kWorld) {
        buildTree(scene, forest, root);
      }
    }
    for (std::size_t j = 0; j < scene.joints.size(); ++j) {
      const JointDesc& desc = scene.joints[j];
      if (desc.type != JointType::Hinge || !desc.limited()) continue;
      const TreeJoint& joint = m_treeJoints[j];
      const double a = joint.angleSign * desc.lowerLimit, b = joint.angleSign * desc.upperLimit;
      addConstraint(std::make_unique<btMultiBodyJointLimitConstraint>(
          m_trees[joint.tree].get(), joint.link, btScalar(std::min(a, b)),
          btScalar(std::max(a, b))));
    }
    // A motor's impulse is bounded per solver step, which is one sub-step here.
    for (const JointMotorDesc& desc : scene.motors) {
      const TreeJoint& joint = m_treeJoints[desc.joint];
      auto motor = std::make_unique<btMultiBodyJointMotor>(
          m_trees[joint.tree].get(), joint.link, btScalar(0),
          btScalar(desc.maxTorque) * m_subTimeStep);
      m_motors.push_back({motor.get(), joint.angleSign});
      addConstraint(std::move(motor));
    }
    return true;
  }

  void setMotorRates(const std::vector<double>& rates) override {
    for (std::size_t i = 0; i < rates.size(); ++i) {
      m_motors[i].constraint->setVelocityTarget(btScalar(m_motors[i].angleSign * rates[i]));
    }
  }

  bool step(std::string&) override {
    for (int i = 0; i < m_substeps; ++i) m_world->stepSimulation(m_subTimeStep, 0);
    return true;
  }

  void readBodies(std::vector<BodyState>& states) const override {
    updateLinkPoses();
    states.resize(m_slots.size());
    for (std::size_t i = 0; i < m_slots.size(); ++i) {
      const BodySlot& slot = m_slots[i];
      BodyState& s = states[i];
      if (slot.rigid >= 0) {
        const btRigidBody& body = *m_bodies[slot.rigid];
        const btTransform& t = body.getWorldTransform();
        s.position = fromBt(t.getOrigin());
        s.orientation = fromBt(t.getRotation());
        s.linearVelocity = fromBt(body.getLinearVelocity());
        s.angularVelocity = fromBt(body.getAngularVelocity());
        continue;
      }
      const btMultiBody& tree = *m_trees[slot.tree];
      const btTransform& t = tree.getLink(slot.link).m_cachedWorldTransform;
      s.position = fromBt(t.getOrigin());
      s.orientation = fromBt(t.getRotation());
      // Link velocities come in the link's own frame; entry 0 is the base.
      const std::vector<btVector3>& omega = m_linkOmega[slot.tree];
      const std::vector<btVector3>& velocity = m_linkVelocity[slot.tree];
      s.linearVelocity = fromBt(t.getBasis() * velocity[slot.link + 1]);
      s.angularVelocity = fromBt(t.getBasis() * omega[slot.link + 1]);
    }
  }

  void readJointAnchors(std::vector<JointAnchors>& anchors) const override {
    updateLinkPoses();
    anchors.resize(m_treeJoints.size());
    for (std::size_t i = 0; i < m_treeJoints.size(); ++i) {
      const TreeJoint& joint = m_treeJoints[i];
      anchors[i].onA = worldPoint(joint.tree, joint.onA);
      anchors[i].onB = worldPoint(joint.tree, joint.onB);
    }
  }

 private:
  static bool hasChildren(const JointForest& forest, int body) {
    for (int other : forest.order) {
      if (forest.parentBody[other] == body) return true;
    }
    return false;
  }

  // The tree below `root` (which hangs from the world): its links in the forest's order,
  // so that every link comes after its parent as btMultiBody requires.
  void buildTree(const Scene& scene, const JointForest& forest, int root) {
    std::vector<int> links;
    std::vector<int> linkOfBody(scene.bodies.size(), -1);
    for (int body : forest.order) {
      int top = body;
      while (forest.parentBody[top] != kWorld) top = forest.parentBody[top];
      if (top != root) continue;
      linkOfBody[body] = static_cast<int>(links.size());
      links.push_back(body);
    }
    const int treeIndex = static_cast<int>(m_trees.size());
    const Vec3 basePosition = scene.joints[forest.parentJoint[root]].anchor;
    // The base is fixed, so its mass and inertia take no part; Bullet only wants them set.
    auto tree = std::make_unique<btMultiBody>(static_cast<int>(links.size()), btScalar(1),
                                              btVector3(1, 1, 1), true, false);
    tree->setBasePos(toBt(basePosition));
    tree->setWorldToBaseRot(btQuaternion::getIdentity());

    for (std::size_t k = 0; k < links.size(); ++k) {
      const int body = links[k];
      const BodyDesc& desc = scene.bodies[body];
      const int jointIndex = forest.parentJoint[body];
      const JointDesc& joint = scene.joints[jointIndex];
      const int parentBody = forest.parentBody[body];
      const int parentLink = parentBody == kWorld ? -1 : linkOfBody[parentBody];
      const Vec3 parentPosition =
          parentBody == kWorld ? basePosition : scene.bodies[parentBody].position;
      const Quat parentOrientation =
          parentBody == kWorld ? Quat::Identity() : scene.bodies[parentBody].orientation;
      const Quat parentToThis = desc.orientation.conjugate() * parentOrientation;
      const Vec3 pivotInParent = parentOrientation.conjugate() * (joint.anchor - parentPosition);
      const Vec3 pivotInThis = desc.orientation.conjugate() * (joint.anchor - desc.position);
      const int link = static_cast<int>(k);
      if (joint.type == JointType::Ball) {
        tree->setupSpherical(link, btScalar(desc.mass), toBt(desc.inertia), parentLink,
                             toBt(parentToThis), toBt(pivotInParent), toBt(-pivotInThis), true);
      } else {
        const Vec3 axis = desc.orientation.conjugate() * joint.axis.normalized();
        tree->setupRevolute(link, btScalar(desc.mass), toBt(desc.inertia), parentLink,
                            toBt(parentToThis), toBt(axis), toBt(pivotInParent),
                            toBt(-pivotInThis), true);
      }
      m_slots[body] = {-1, treeIndex, link};
      // Report the anchors in the scene's order: the parent side is A unless the joint
      // names the child first.
      const LinkPoint onParent{parentLink, toBt(pivotInParent)};
      const LinkPoint onThis{link, toBt(pivotInThis)};
      const bool childIsB = joint.bodyB == body;
      m_treeJoints[jointIndex] = {treeIndex, childIsB ? onParent : onThis,
                                  childIsB ? onThis : onParent, link, childIsB ? 1.0 : -1.0};
    }
    tree->finalizeMultiDof();
    tree->setLinearDamping(0);
    tree->setAngularDamping(0);
    tree->setMaxCoordinateVelocity(kUnlimitedCoordinateVelocity);
    tree->setMaxAppliedImpulse(kUnlimitedImpulse);
    tree->setHasSelfCollision(true);
    tree->setCanSleep(false);
    m_world->addMultiBody(tree.get());

    for (std::size_t k = 0; k < links.size(); ++k) {
      const BodyDesc& desc = scene.bodies[links[k]];
      m_shapes.push_back(makeBtShape(desc.shape));
      auto collider = std::make_unique<btMultiBodyLinkCollider>(tree.get(), static_cast<int>(k));
      collider->setCollisionShape(m_shapes.back().get());
      collider->setWorldTransform(btTransform(toBt(desc.orientation), toBt(desc.position)));
      collider->setFriction(btScalar(desc.friction));
      collider->setRestitution(btScalar(desc.restitution));
      m_world->addCollisionObject(collider.get(), btBroadphaseProxy::DefaultFilter,
                                  btBroadphaseProxy::AllFilter);
      tree->getLink(static_cast<int>(k)).m_collider = collider.get();
      m_colliders.push_back(std::move(collider));
    }
    m_trees.push_back(std::move(tree));
    m_linkOmega.emplace_back(links.size() + 1);
    m_linkVelocity.emplace_back(links.size() + 1);
  }

  void addConstraint(std::unique_ptr<btMultiBodyConstraint> constraint) {
    m_world->addMultiBodyConstraint(constraint.get());
    constraint->finalizeMultiDof();
    m_constraints.push_back(std::move(constraint));
  }

  // Link poses and velocities from the joint coordinates as they are now. Only reads
  // derived from the state are refreshed; the next step recomputes them anyway.
  void updateLinkPoses() const {
    for (std::size_t t = 0; t < m_trees.size(); ++t) {
      m_trees[t]->forwardKinematics(m_scratchRotations, m_scratchOrigins);
      m_trees[t]->compTreeLinkVelocities(m_linkOmega[t].data(), m_linkVelocity[t].data());
    }
  }

  Vec3 worldPoint(int tree, const LinkPoint& point) const {
    const btMultiBody& body = *m_trees[tree];
    if (point.link < 0) return fromBt(body.getBasePos() + point.local);
    return fromBt(body.getLink(point.link).m_cachedWorldTransform * point.local);
  }

  // Declared in the order of construction; the world goes first on destruction.
  btDefaultCollisionConfiguration m_configuration;
  btDbvtBroadphase m_broadphase;
  btMultiBodyConstraintSolver m_solver;
  std::unique_ptr<btCollisionDispatcher> m_dispatcher;
  std::vector<std::unique_ptr<btCollisionShape>> m_shapes;
  std::vector<std::unique_ptr<btRigidBody>> m_bodies;
  std::vector<std::unique_ptr<btMultiBody>> m_trees;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> m_colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> m_constraints;  // limits and motors
  struct Motor {
    btMultiBodyJointMotor* constraint;
    double angleSign;
  };
  std::vector<Motor> m_motors;  // per motor of the scene
  std::unique_ptr<btMultiBodyDynamicsWorld> m_world;
  std::vector<BodySlot> m_slots;        // indexed like the scene's bodies
  std::vector<TreeJoint> m_treeJoints;  // indexed like the scene's joints
  mutable std::vector<std::vector<btVector3>> m_linkOmega;     // per tree, base first
  mutable std::vector<std::vector<btVector3>> m_linkVelocity;  // per tree, base first
  mutable btAlignedObjectArray<btQuaternion> m_scratchRotations;
  mutable btAlignedObjectArray<btVector3> m_scratchOrigins;
  btScalar m_subTimeStep = btScalar(1) / 60;
  int m_substeps = 1;
};

}  // namespace

std::unique_ptr<Engine> createBulletMultiBodyEngine() {
  return std::make_unique<BulletMultiBodyEngine>();
}

}  // namespace pfxbench
