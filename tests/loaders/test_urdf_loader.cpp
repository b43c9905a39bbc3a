// The URDF loader: the robots in urdf/ load with the bodies, masses, joints and limits their
// files describe; massless chains collapse into universal and ball joints whose URDF angles
// read back exactly; a mimic pair keeps its ratio; every malformed file fails with a message
// naming the element and leaves the world and the model as they were; and the real robots
// hang, stand, rest and answer rays under gravity.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_ragdoll.h"
#include "pfx/loaders/pfx_urdf_loader.h"

using namespace pfx;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string robotPath(const std::string& name) {
  return std::string(PFX_SOURCE_DIR) + "/urdf/" + name;
}

// A 1 kg link with the inertia of a 0.24 m cube, and whatever else `inside` says.
std::string unitLink(const std::string& name, const std::string& inside = "") {
  return "<link name=\"" + name +
         "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" "
         "iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>" +
         inside + "</link>\n";
}

// A world for URDF robots: Z up.
void initZUpWorld(PfxWorld& world, PfxUInt32 subStep = 1) {
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.81));
  param.subStep = subStep;
  ASSERT_EQ(world.initialize(param), PFX_OK);
}

// A fixed box whose top face is the plane z = 0.
PfxUInt32 addGround(PfxWorld& world) {
  PfxBodyInit init;
  init.mass = 0;
  init.position = PfxVector3(0, 0, -0.5f);
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 20, 0.5f)), init, &id), PFX_OK);
  return id;
}

// Everything a failed load must leave as it was.
struct WorldSnapshot {
  PfxUInt32 numBodies, numJoints, numCouplings;
  std::vector<unsigned char> states;
  std::vector<unsigned char> joints;

  explicit WorldSnapshot(const PfxWorld& world)
      : numBodies(world.getNumRigidBodies()),
        numJoints(world.getNumJoints()),
        numCouplings(world.getNumJointCouplings()) {
    const auto* s = reinterpret_cast<const unsigned char*>(world.getRigidStates());
    states.assign(s, s + numBodies * sizeof(PfxRigidState));
    for (PfxUInt32 i = 0; i < numJoints; ++i) {
      const auto* j = reinterpret_cast<const unsigned char*>(&world.getJoint(i));
      joints.insert(joints.end(), j, j + sizeof(PfxJoint));
    }
  }
  bool operator==(const WorldSnapshot& o) const {
    return numBodies == o.numBodies && numJoints == o.numJoints && numCouplings == o.numCouplings &&
           states == o.states && joints == o.joints;
  }
};

const PfxUrdfJoint& jointNamed(const PfxUrdfModel& model, const std::string& name) {
  const PfxInt32 i = pfxFindUrdfJoint(model, name);
  EXPECT_GE(i, 0) << name;
  return model.joints[std::max(i, 0)];
}

const PfxUrdfLink& linkNamed(const PfxUrdfModel& model, const std::string& name) {
  const PfxInt32 i = pfxFindUrdfLink(model, name);
  EXPECT_GE(i, 0) << name;
  return model.links[std::max(i, 0)];
}

// How far the URDF angles lie outside their limits (0 inside), and which joint is worst.
double worstLimitViolation(const PfxWorld& world, const PfxUrdfModel& model,
                           std::string* worst = nullptr) {
  std::vector<double> q, v;
  pfxGetUrdfJointStates(world, model, q, v);
  double violation = 0;
  for (std::size_t i = 0; i < q.size(); ++i) {
    const PfxUrdfJoint& joint = model.joints[i];
    if (joint.type != kPfxUrdfRevolute && joint.type != kPfxUrdfPrismatic) continue;
    const double out = std::max(joint.lowerLimit - q[i], q[i] - joint.upperLimit);
    if (out > violation) {
      violation = out;
      if (worst) *worst = joint.name;
    }
  }
  return violation;
}

double maxSpeed(const PfxWorld& world, const PfxUrdfModel& model) {
  double speed = 0;
  for (PfxUInt32 b = model.firstBodyId; b < model.firstBodyId + model.numBodies; ++b) {
    speed = std::max<double>(speed, world.getRigidState(b).getLinearVelocity().norm());
  }
  return speed;
}

PfxFloat totalMass(const PfxWorld& world, const PfxUrdfModel& model) {
  PfxFloat mass = 0;
  for (PfxUInt32 b = model.firstBodyId; b < model.firstBodyId + model.numBodies; ++b) {
    if (world.getRigidState(b).getMotionType() == kPfxMotionTypeActive) {
      mass += world.getRigidBody(b).getMass();
    }
  }
  return mass;
}

// Loads robot `name` of urdf/, or URDF text, into `world`; the test stops with the
// loader's message when that fails.
void loadRobot(PfxWorld& world, const std::string& name, const PfxUrdfLoadParam& param,
               PfxUrdfModel& model) {
  std::string message;
  ASSERT_EQ(pfxLoadUrdfFile(world, robotPath(name), param, model, &message), PFX_OK) << message;
  EXPECT_TRUE(message.empty());
}

void loadText(PfxWorld& world, const std::string& xml, const PfxUrdfLoadParam& param,
              PfxUrdfModel& model) {
  std::string message;
  ASSERT_EQ(pfxLoadUrdfString(world, xml, ".", param, model, &message), PFX_OK) << message;
}

PfxUrdfLoadParam fixedBaseParam() {
  PfxUrdfLoadParam param;
  param.fixedBase = true;
  return param;
}

bool hasWarningWith(const PfxUrdfModel& model, const std::string& text) {
  for (const std::string& warning : model.warnings) {
    if (warning.find(text) != std::string::npos) return true;
  }
  return false;
}

Eigen::Matrix3d turn(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

}  // namespace

// ---------------------------------------------------------------------------------------
// urdf/ragdoll.urdf and urdf/arm.urdf as their files describe them.

TEST(UrdfLoader, RagdollLoadsItsBodiesMassesJointsAndLimits) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.rootPosition = PfxVector3(0, 0, 1);
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "ragdoll.urdf", param, model));
  EXPECT_EQ(model.name, "ragdoll");
  EXPECT_EQ(model.links.size(), 30u);  // 16 segments and 14 helper links
  EXPECT_EQ(model.joints.size(), 29u);
  EXPECT_EQ(model.numBodies, 16u);  // no helper link becomes a body
  EXPECT_EQ(world.getNumRigidBodies(), 16u);
  EXPECT_NEAR(totalMass(world, model), 70, 1e-3);
  EXPECT_TRUE(model.warnings.empty()) << model.warnings.front();
  const std::pair<const char*, PfxFloat> masses[] = {
      {"pelvis", 11}, {"chest", 15}, {"head", 5}, {"thigh_l", 6.5f}, {"hand_r", 0.5f}};
  for (const auto& [name, mass] : masses) {
    EXPECT_FLOAT_EQ(world.getRigidBody(linkNamed(model, name).bodyId).getMass(), mass) << name;
  }
  // The centre of mass of the chest box is 0.15 m above its link frame, which sits at the
  // top of the upper spine, 0.3 m above the pelvis.
  EXPECT_NEAR(world.getRigidState(linkNamed(model, "chest").bodyId).getPosition().z(), 1.45, 1e-5);

  // Hips and shoulders: ball joints; wrists, ankles, neck and lower spine: universal;
  // knees, elbows and the upper spine: hinges.
  int balls = 0, universals = 0, hinges = 0;
  for (PfxUInt32 j = model.firstJointId; j < model.firstJointId + model.numJoints; ++j) {
    const PfxUInt8 type = world.getJoint(j).m_type;
    balls += type == kPfxJointBall;
    universals += type == kPfxJointUniversal;
    hinges += type == kPfxJointHinge;
  }
  EXPECT_EQ(model.numJoints, 15u);
  EXPECT_EQ(balls, 4);
  EXPECT_EQ(universals, 6);
  EXPECT_EQ(hinges, 5);
  printf("ragdoll: %u bodies, %.3f kg, %d ball, %d universal, %d hinge joints\n", model.numBodies,
         double(totalMass(world, model)), balls, universals, hinges);

  // URDF limits on the world axes: the knee on the hinge's twist, the hip's three joints on
  // swing1, swing2 (through its sign) and twist of one ball joint.
  const PfxUrdfJoint& knee = jointNamed(model, "knee_l");
  EXPECT_FALSE(knee.collapsed);
  EXPECT_EQ(knee.axis, kPfxJointAxisTwist);
  EXPECT_FLOAT_EQ(knee.lowerLimit, 0);
  EXPECT_FLOAT_EQ(knee.upperLimit, 2.4f);
  const PfxJointConstraint& kneeAxis = world.getJoint(knee.jointId).m_constraints[knee.axis];
  EXPECT_EQ(kneeAxis.m_lock, kPfxJointLockLimit);
  EXPECT_FLOAT_EQ(kneeAxis.m_movableLowerLimit, 0);
  EXPECT_FLOAT_EQ(kneeAxis.m_movableUpperLimit, 2.4f);
  const char* hip[3] = {"hip_r_flexion", "hip_r_abduction", "hip_r_twist"};
  const PfxUInt32 hipAxes[3] = {kPfxJointAxisSwing1, kPfxJointAxisSwing2, kPfxJointAxisTwist};
  for (int i = 0; i < 3; ++i) {
    const PfxUrdfJoint& joint = jointNamed(model, hip[i]);
    EXPECT_TRUE(joint.collapsed);
    EXPECT_EQ(joint.jointId, jointNamed(model, hip[0]).jointId);
    EXPECT_EQ(joint.axis, hipAxes[i]);
    const PfxJointConstraint& c = world.getJoint(joint.jointId).m_constraints[joint.axis];
    EXPECT_EQ(c.m_lock, kPfxJointLockLimit);
    EXPECT_FLOAT_EQ(joint.sign * (joint.sign > 0 ? c.m_movableLowerLimit : c.m_movableUpperLimit),
                    joint.lowerLimit);
    EXPECT_FLOAT_EQ(joint.sign * (joint.sign > 0 ? c.m_movableUpperLimit : c.m_movableLowerLimit),
                    joint.upperLimit);
  }
  EXPECT_FLOAT_EQ(jointNamed(model, "hip_r_abduction").lowerLimit, -0.8f);
  EXPECT_FLOAT_EQ(jointNamed(model, "hip_r_abduction").upperLimit, 0.3f);
  // A universal joint locks its twist.
  const PfxUrdfJoint& wrist = jointNamed(model, "wrist_l_flexion");
  EXPECT_EQ(world.getJoint(wrist.jointId).m_type, kPfxJointUniversal);
  EXPECT_EQ(world.getJoint(wrist.jointId).m_constraints[kPfxJointAxisTwist].m_lock,
            kPfxJointLockLocked);
  // Helper links ride on the parent body and turn with the chain's first joints.
  const PfxUrdfLink& helper = linkNamed(model, "hip_l_abduction_link");
  EXPECT_EQ(helper.bodyId, linkNamed(model, "pelvis").bodyId);
  EXPECT_EQ(helper.collapsedJointId, jointNamed(model, "hip_l_flexion").jointId);
  EXPECT_EQ(helper.collapsedAxes, 2u);
  EXPECT_EQ(linkNamed(model, "hip_l_flexion_link").collapsedAxes, 1u);
  // Every link where the file puts it: the left foot 0.1 + 0.42 + 0.41 m below the hip.
  const PfxTransform3 foot = pfxGetUrdfLinkPose(world, linkNamed(model, "foot_l"));
  EXPECT_NEAR((foot.translation() - PfxVector3(0, 0.1f, 1 - 0.1f - 0.42f - 0.41f)).norm(), 0, 1e-5);
  EXPECT_TRUE(foot.linear().isIdentity(1e-5f));
}

TEST(UrdfLoader, ArmLoadsItsMeshesMimicPairAndFrames) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "arm.urdf", fixedBaseParam(), model));
  // tool0 has no mass: it is a frame of the palm's body, and a warning says so.
  EXPECT_EQ(model.numBodies, 9u);
  EXPECT_EQ(model.numJoints, 8u);
  EXPECT_EQ(model.numCouplings, 1u);
  EXPECT_TRUE(hasWarningWith(model, "link 'tool0': no mass and no child joint"));
  EXPECT_EQ(linkNamed(model, "tool0").bodyId, linkNamed(model, "palm").bodyId);
  EXPECT_NEAR(totalMass(world, model), 2.5 + 2 + 1.5 + 0.6 + 0.5 + 0.5 + 0.1, 1e-4);
  const PfxUInt32 base = linkNamed(model, "base_link").bodyId;
  EXPECT_EQ(world.getRigidState(base).getMotionType(), kPfxMotionTypeFixed);
  // The fixed base's mesh is a large mesh; moving links' meshes are convex hulls.
  EXPECT_EQ(world.getCollidable(base).getShape(0).getType(), kPfxShapeLargeTriMesh);
  const PfxUInt32 palm = linkNamed(model, "palm").bodyId;
  const PfxShape& palmShape = world.getCollidable(palm).getShape(0);
  ASSERT_EQ(palmShape.getType(), kPfxShapeConvexMesh);
  // The Collada palm keeps its axes: 0.12 x 0.07 x 0.04 m.
  const PfxConvexMesh& hull = *palmShape.getConvexMesh();
  EXPECT_NEAR(hull.m_aabbHalf.x(), 0.06, 1e-5);
  EXPECT_NEAR(hull.m_aabbHalf.y(), 0.035, 1e-5);
  EXPECT_NEAR(hull.m_aabbHalf.z(), 0.02, 1e-5);
  EXPECT_EQ(model.convexMeshes.size(), 6u);  // the two wrists and two fingers share theirs
  EXPECT_EQ(model.largeMeshes.size(), 1u);

  const PfxUrdfJoint& left = jointNamed(model, "finger_left_joint");
  const PfxUrdfJoint& right = jointNamed(model, "finger_right_joint");
  EXPECT_EQ(left.type, kPfxUrdfPrismatic);
  EXPECT_EQ(world.getJoint(left.jointId).m_type, kPfxJointSlider);
  EXPECT_FLOAT_EQ(left.upperLimit, 0.02f);
  EXPECT_FLOAT_EQ(left.effortLimit, 20);
  EXPECT_FLOAT_EQ(left.velocityLimit, 0.1f);
  EXPECT_EQ(right.mimicLeader, pfxFindUrdfJoint(model, "finger_left_joint"));
  ASSERT_NE(right.couplingId, kPfxUrdfNoJoint);
  const PfxJointCoupling& coupling = world.getJointCoupling(right.couplingId);
  EXPECT_EQ(coupling.m_leaderJointId, left.jointId);
  EXPECT_EQ(coupling.m_followerJointId, right.jointId);
  EXPECT_FLOAT_EQ(coupling.m_multiplier, 1);
  const PfxUrdfJoint& joint2 = jointNamed(model, "joint_2");
  EXPECT_FLOAT_EQ(joint2.lowerLimit, -2);
  EXPECT_FLOAT_EQ(joint2.upperLimit, 2);
  EXPECT_FLOAT_EQ(joint2.effortLimit, 150);
  EXPECT_FLOAT_EQ(world.getJoint(joint2.jointId).m_constraints[kPfxJointAxisTwist].m_friction,
                  0.5f);
  // tool0 stands 1.15 m above the base, between the finger tips.
  const PfxTransform3 tool = pfxGetUrdfLinkPose(world, linkNamed(model, "tool0"));
  EXPECT_NEAR((tool.translation() - PfxVector3(0, 0, 1.15f)).norm(), 0, 1e-5);
}

// The fingers' coupling holds while the leader is driven open and closed for 4 s.
TEST(UrdfLoader, MimicFingersKeepTheirRatioWhileTheLeaderIsDriven) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "arm.urdf", fixedBaseParam(), model));
  // Hold the arm up so that the gripper works at one place.
  for (const char* name : {"joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6"}) {
    ASSERT_EQ(pfxSetUrdfJointCommand(world, model, pfxFindUrdfJoint(model, name),
                                     kPfxJointDrivePosition, 0),
              PFX_OK);
  }
  const PfxUInt32 left = static_cast<PfxUInt32>(pfxFindUrdfJoint(model, "finger_left_joint"));
  const PfxUInt32 right = static_cast<PfxUInt32>(pfxFindUrdfJoint(model, "finger_right_joint"));
  double worstError = 0, lowest = 1, highest = -1;
  const int steps = 240;
  for (int i = 0; i < steps; ++i) {
    const double t = i / 60.0;
    const PfxFloat target = PfxFloat(0.01 - 0.01 * std::cos(2 * kPi * t / 2));  // 0 .. 0.02
    ASSERT_EQ(pfxSetUrdfJointCommand(world, model, left, kPfxJointDrivePosition, target), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
    std::vector<double> q, v;
    pfxGetUrdfJointStates(world, model, q, v);
    worstError = std::max(worstError, std::abs(q[right] - q[left]));
    lowest = std::min(lowest, q[left]);
    highest = std::max(highest, q[left]);
  }
  printf("mimic fingers over %d steps: leader %.4f .. %.4f m, |right - left| <= %.2e m\n", steps,
         lowest, highest, worstError);
  EXPECT_LT(worstError, 1e-3);
  EXPECT_GT(highest - lowest, 0.015);  // the leader really moved through its range
  // The follower is not commanded on its own.
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model, right, kPfxJointDrivePosition, 0.01f),
            PFX_ERR_INVALID_VALUE);
}

TEST(UrdfLoader, LumpedLinksAddMassesAndInertiasAboutTheirCommonCentre) {
  // Two 1 kg links 1 m apart on a fixed joint; the second's inertia (diagonal 0.1, 0.2, 0.3
  // in its inertial frame) turned by yaw pi/2, so it reads 0.2, 0.1, 0.3 in the link frame.
  const std::string xml = R"(<robot name="lumped">
  <link name="a"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial>
    <collision><geometry><sphere radius="0.1"/></geometry></collision></link>
  <link name="b"><inertial><origin rpy="0 0 1.5707963267948966"/><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial>
    <collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
  <joint name="weld" type="fixed"><parent link="a"/><child link="b"/><origin xyz="1 0 0"/></joint>
</robot>)";
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, PfxUrdfLoadParam(), model));
  ASSERT_EQ(model.numBodies, 1u);
  EXPECT_EQ(model.numJoints, 0u);
  const PfxRigidBody& body = world.getRigidBody(model.firstBodyId);
  EXPECT_FLOAT_EQ(body.getMass(), 2);
  // The body sits at the common centre, 0.5 m from each link; each adds m d^2 = 0.25 about
  // Y and Z.
  EXPECT_NEAR(
      (world.getRigidState(model.firstBodyId).getPosition() - PfxVector3(0.5f, 0, 0)).norm(), 0,
      1e-6);
  PfxMatrix3 expected = PfxMatrix3::Zero();
  expected.diagonal() << 0.1f + 0.2f, 0.2f + 0.1f + 0.5f, 0.3f + 0.3f + 0.5f;
  EXPECT_TRUE(body.getInertia().isApprox(expected, 1e-5f)) << body.getInertia();
  // Both links' shapes, each where its link is.
  const PfxCollidable& collidable = world.getCollidable(model.firstBodyId);
  ASSERT_EQ(collidable.getNumShapes(), 2u);
  EXPECT_NEAR((collidable.getShape(1).getOffsetPosition() - PfxVector3(0.5f, 0, 0)).norm(), 0,
              1e-6);
  EXPECT_NEAR(
      (pfxGetUrdfLinkPose(world, linkNamed(model, "b")).translation() - PfxVector3(1, 0, 0)).norm(),
      0, 1e-6);
}

TEST(UrdfLoader, PlanarFloatingAndPrismaticJointsMoveTheWayTheyShould) {
  // A planar joint with normal Z holds its child in a horizontal plane while a push moves it
  // along and turns it; a floating child falls freely; a prismatic child slides only along
  // its axis and stops at its limit.
  const std::string xml = "<robot name=\"mix\">" + unitLink("base") + unitLink("puck") +
                          unitLink("free") + unitLink("slider") + R"(
  <joint name="plane" type="planar"><parent link="base"/><child link="puck"/><origin xyz="0 0 1"/><axis xyz="0 0 1"/></joint>
  <joint name="loose" type="floating"><parent link="base"/><child link="free"/><origin xyz="3 0 1"/></joint>
  <joint name="rail" type="prismatic"><parent link="base"/><child link="slider"/><origin xyz="-3 0 1"/>
    <axis xyz="0 0 1"/><limit lower="-0.5" upper="0.5" effort="10" velocity="1"/></joint>
</robot>)";
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, fixedBaseParam(), model));
  EXPECT_EQ(model.numBodies, 4u);
  EXPECT_EQ(model.numJoints, 2u);  // no joint for the floating link
  EXPECT_EQ(jointNamed(model, "plane").jointId, kPfxUrdfNoJoint);
  EXPECT_EQ(jointNamed(model, "loose").jointId, kPfxUrdfNoJoint);
  const PfxUInt32 puck = linkNamed(model, "puck").bodyId;
  for (int i = 0; i < 60; ++i) {
    ASSERT_EQ(world.applyForce(puck, PfxVector3(3, 2, 0), PfxVector3(0, 0, 0.05f)), PFX_OK);
    ASSERT_EQ(world.step(), PFX_OK);
  }
  const PfxRigidState& p = world.getRigidState(puck);
  const PfxRigidState& f = world.getRigidState(linkNamed(model, "free").bodyId);
  const PfxRigidState& s = world.getRigidState(linkNamed(model, "slider").bodyId);
  printf(
      "after 1 s: puck at (%.3f, %.3f, %.4f) turned %.3f rad about Z; free link fell %.3f m; "
      "slider at z %.4f\n",
      p.getPosition().x(), p.getPosition().y(), p.getPosition().z(),
      2 * std::atan2(p.getOrientation().z(), p.getOrientation().w()), 1 - f.getPosition().z(),
      s.getPosition().z());
  EXPECT_GT(p.getPosition().x(), 1);
  EXPECT_GT(p.getPosition().y(), 0.7f);
  EXPECT_NEAR(p.getPosition().z(), 1, 1e-3);
  EXPECT_GT(std::abs(p.getOrientation().z()), 0.05f);  // turned about the normal
  EXPECT_NEAR(std::abs(p.getOrientation().x()) + std::abs(p.getOrientation().y()), 0, 1e-3);
  EXPECT_NEAR(1 - f.getPosition().z(), 0.5 * 9.81 * 1.0, 0.15);
  EXPECT_NEAR(s.getPosition().z(), 0.5, 0.01);  // fell onto its lower limit, 0.5 m down
  EXPECT_NEAR(s.getPosition().x(), -3, 1e-3);
  std::vector<double> q, v;
  pfxGetUrdfJointStates(world, model, q, v);
  EXPECT_NEAR(q[pfxFindUrdfJoint(model, "rail")], -0.5, 0.01);
}

// ---------------------------------------------------------------------------------------
// Massless chains.

namespace {

// A 1 kg box and, below it through `helpers` massless links and revolute joints meeting at
// one point, another box. Axes are given in the links' frames.
std::string chainUrdf(const std::vector<std::string>& axes,
                      const std::string& secondOrigin = "0 0 0") {
  std::string xml =
      "<robot name=\"chain\">" +
      unitLink("top", "<collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>") +
      R"(
  <link name="bottom">
    <inertial><origin xyz="0 0 -0.2"/><mass value="2"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.01"/></inertial>
    <collision><origin xyz="0 0 -0.2"/><geometry><box size="0.1 0.1 0.2"/></geometry></collision>
  </link>
)";
  for (std::size_t i = 0; i + 1 < axes.size(); ++i) {
    xml += "  <link name=\"helper" + std::to_string(i) + "\"/>\n";
  }
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const std::string parent = i == 0 ? "top" : "helper" + std::to_string(i - 1);
    const std::string child = i + 1 == axes.size() ? "bottom" : "helper" + std::to_string(i);
    const std::string origin = i == 0 ? "0 0 -0.1" : i == 1 ? secondOrigin : "0 0 0";
    xml += "  <joint name=\"j" + std::to_string(i) + "\" type=\"revolute\"><parent link=\"" +
           parent + "\"/><child link=\"" + child + "\"/><origin xyz=\"" + origin +
           "\"/><axis xyz=\"" + axes[i] +
           "\"/><limit lower=\"-1.5\" upper=\"1.5\" effort=\"10\" velocity=\"1\"/></joint>\n";
  }
  return xml + "</robot>\n";
}

// Puts the bottom body where the URDF angles q put it (top fixed at the origin frame,
// joints at (0, 0, -0.1)) and reads the angles and the helper poses back.
void checkChainAngles(const std::vector<Eigen::Vector3d>& axes, const std::vector<double>& q) {
  std::vector<std::string> axisText;
  for (const Eigen::Vector3d& a : axes) {
    char text[128];
    std::snprintf(text, sizeof(text), "%.17g %.17g %.17g", a.x(), a.y(), a.z());
    axisText.push_back(text);
  }
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, chainUrdf(axisText), fixedBaseParam(), model));
  ASSERT_EQ(model.numBodies, 2u);
  ASSERT_EQ(model.numJoints, 1u);
  EXPECT_EQ(world.getJoint(model.firstJointId).m_type,
            axes.size() == 2 ? kPfxJointUniversal : kPfxJointBall);

  // Rotation of the bottom link: the product of the turns about the axes (the helpers'
  // frames coincide with the top's here, so the axes are the same in every frame).
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  std::vector<Eigen::Matrix3d> partial;
  for (std::size_t i = 0; i < axes.size(); ++i) {
    rotation = rotation * turn(q[i], axes[i]);
    partial.push_back(rotation);
  }
  const Eigen::Vector3d pivot(0, 0, -0.1);
  const PfxUrdfLink& bottom = linkNamed(model, "bottom");
  const Eigen::Isometry3d linkPose = Eigen::Translation3d(pivot) * Eigen::Isometry3d(rotation);
  const Eigen::Isometry3d bodyPose = linkPose * bottom.linkInBody.inverse().cast<double>();
  PfxRigidState state = world.getRigidState(bottom.bodyId);
  state.setPosition(bodyPose.translation().cast<PfxFloat>());
  state.setOrientation(PfxQuat(Eigen::Quaterniond(bodyPose.linear()).cast<PfxFloat>()));
  ASSERT_EQ(world.setRigidState(bottom.bodyId, state), PFX_OK);

  std::vector<double> positions, velocities;
  pfxGetUrdfJointStates(world, model, positions, velocities);
  for (std::size_t i = 0; i < axes.size(); ++i) {
    EXPECT_NEAR(positions[i], q[i], 2e-6) << "joint j" << i;
  }
  for (std::size_t i = 0; i + 1 < axes.size(); ++i) {
    const PfxTransform3 helper =
        pfxGetUrdfLinkPose(world, linkNamed(model, "helper" + std::to_string(i)));
    EXPECT_TRUE(helper.linear().cast<double>().isApprox(partial[i], 1e-5)) << "helper" << i;
    EXPECT_NEAR((helper.translation().cast<double>() - pivot).norm(), 0, 1e-6);
  }
  const PfxTransform3 read = pfxGetUrdfLinkPose(world, bottom);
  EXPECT_TRUE(read.linear().cast<double>().isApprox(rotation, 1e-5));
}

}  // namespace

TEST(UrdfLoader, MasslessChainsCollapseAndReadBackTheirUrdfAnglesExactly) {
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  checkChainAngles({x, z}, {0.7, -0.4});
  checkChainAngles({y, x}, {-1.1, 0.9});
  checkChainAngles({x, z, y}, {0.6, -0.8, 1.2});    // a shoulder
  checkChainAngles({y, x, z}, {-1.4, 0.5, -0.3});   // a hip
  checkChainAngles({z, -y, x}, {1.3, 0.2, -1.0});   // the second axis reversed
  const Eigen::Vector3d tilted = turn(0.3, z) * x;  // axes off the link frame's
  checkChainAngles({tilted, z, z.cross(tilted)}, {0.4, 0.5, 0.6});
}

TEST(UrdfLoader, CollapsedJointStatesReportRatesOfTheUrdfAngles) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.fixedBase = true;
  std::string message;
  ASSERT_EQ(
      pfxLoadUrdfString(world, chainUrdf({"1 0 0", "0 0 1", "0 1 0"}), ".", param, model, &message),
      PFX_OK)
      << message;
  // Turning the bottom about the first axis alone moves only the first angle.
  const PfxUInt32 bottom = linkNamed(model, "bottom").bodyId;
  PfxRigidState state = world.getRigidState(bottom);
  state.setAngularVelocity(PfxVector3(0.5f, 0, 0));
  ASSERT_EQ(world.setRigidState(bottom, state), PFX_OK);
  std::vector<double> q, v;
  pfxGetUrdfJointStates(world, model, q, v);
  EXPECT_NEAR(v[0], 0.5, 1e-6);
  EXPECT_NEAR(v[1], 0, 1e-6);
  EXPECT_NEAR(v[2], 0, 1e-6);
}

TEST(UrdfLoader, MasslessLinksThatCannotCollapseBecomeLightBodiesWithAWarning) {
  struct Case {
    const char* what;
    std::string xml;
    PfxUInt32 joints;  // world joints
    const char* expected;
  };
  const Case cases[] = {
      {"offset joints", chainUrdf({"1 0 0", "0 0 1"}, "0 0 -0.05"), 2,
       "link 'helper0': no mass, and joints 'j0' and 'j1' do not meet at one point (0.05 m "
       "apart), so its joints cannot become one; loaded as a light body of 0.1 kg (a tenth of "
       "the mass of link 'top')"},
      {"parallel axes", chainUrdf({"1 0 0", "1 0 0"}), 2,
       "link 'helper0': no mass, and the axes of joints 'j0' and 'j1' are not perpendicular"},
      // The first helper becomes a body; the three joints below it meet and make a ball.
      {"four joints", chainUrdf({"1 0 0", "0 0 1", "0 1 0", "1 0 0"}), 2,
       "link 'helper0': no mass, and it is not a helper between two or three revolute joints "
       "meeting at one point"},
  };
  for (const Case& c : cases) {
    PfxWorld world;
    initZUpWorld(world);
    PfxUrdfModel model;
    ASSERT_NO_FATAL_FAILURE(loadText(world, c.xml, fixedBaseParam(), model));
    EXPECT_TRUE(hasWarningWith(model, c.expected)) << c.what << ": " << model.warnings[0];
    EXPECT_EQ(model.numBodies, 3u) << c.what;
    EXPECT_EQ(model.numJoints, c.joints) << c.what;
    const PfxUInt32 helper = linkNamed(model, "helper0").bodyId;
    EXPECT_NE(helper, linkNamed(model, "top").bodyId);
    EXPECT_NEAR(world.getRigidBody(helper).getMass(), 0.1, 1e-6) << c.what;
  }
}

TEST(UrdfLoader, MasslessChainsAreErrorsWhenCollapsingIsOff) {
  PfxUrdfLoadParam noCollapse = fixedBaseParam();
  noCollapse.collapseMasslessChains = false;
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  std::string message;
  EXPECT_EQ(pfxLoadUrdfString(world, chainUrdf({"1 0 0", "0 0 1"}), ".", noCollapse, model,
                              &message),
            PFX_ERR_INVALID_VALUE);
  EXPECT_NE(message.find("link 'helper0': no mass (no <inertial>, or mass 0) and joints below "
                         "it, and collapseMasslessChains is off"),
            std::string::npos)
      << message;
  EXPECT_EQ(world.getNumRigidBodies(), 0u);
}

TEST(UrdfLoader, MasslessLeafOnAMovingJointIsAFrameWithAWarning) {
  const std::string xml =
      "<robot name=\"leaf\">" +
      unitLink("base", "<collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>") +
      R"(
  <link name="sensor"><collision><origin xyz="0.2 0 0"/><geometry><sphere radius="0.02"/></geometry></collision></link>
  <joint name="pan" type="revolute"><parent link="base"/><child link="sensor"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>)";
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, PfxUrdfLoadParam(), model));
  EXPECT_EQ(model.numBodies, 1u);
  EXPECT_EQ(model.numJoints, 0u);
  EXPECT_TRUE(hasWarningWith(model,
                             "link 'sensor': no mass and no child joint; carried as a "
                             "frame by the body of link 'base', with joint 'pan' held at zero"));
  EXPECT_EQ(jointNamed(model, "pan").jointId, kPfxUrdfNoJoint);
  // Its geometry rides on the base: two shapes.
  EXPECT_EQ(world.getCollidable(model.firstBodyId).getNumShapes(), 2u);
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model, 0, kPfxJointDriveVelocity, 1),
            PFX_ERR_INVALID_VALUE);
}

// ---------------------------------------------------------------------------------------
// Malformed files: each fails with a message naming the element and the reason, and the
// world and the model stay as they were.

namespace {

const char* kLinkWithInertial =
    R"(<link name="%s"><inertial><mass value="%s"/><inertia ixx="%s" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>)";

std::string linkXml(const std::string& name, const std::string& mass = "1",
                    const std::string& ixx = "0.01") {
  char text[1024];
  std::snprintf(text, sizeof(text), kLinkWithInertial, name.c_str(), mass.c_str(), ixx.c_str());
  return text;
}

std::string jointXml(const std::string& name, const std::string& type, const std::string& parent,
                     const std::string& child, const std::string& extra = "") {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
         "\"/><child link=\"" + child + "\"/>" + extra + "</joint>";
}

// The <axis> and <limit> of a revolute joint.
std::string hingeAxis(const std::string& axis, const std::string& lower, const std::string& upper) {
  return "<axis xyz=\"" + axis + "\"/><limit lower=\"" + lower + "\" upper=\"" + upper +
         "\" effort=\"5\" velocity=\"1\"/>";
}

const std::string kHingeLimits = hingeAxis("0 1 0", "-1", "1");

std::string robot(const std::string& body) { return "<robot name=\"bad\">" + body + "</robot>"; }

}  // namespace

TEST(UrdfLoader, MalformedFilesFailNamingTheElementAndChangeNothing) {
  struct Case {
    const char* what;
    std::string xml;
    PfxInt32 code;
    const char* expected;
  };
  const Case cases[] = {
      {"malformed XML", "<robot name=\"bad\"><link name=\"a\"></robot>", PFX_ERR_INVALID_VALUE,
       "malformed XML"},
      {"no robot", "<model name=\"m\"/>", PFX_ERR_INVALID_VALUE,
       "robot: the top element is not <robot>"},
      {"missing mesh",
       robot("<link name=\"a\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" "
             "iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial><collision><geometry><mesh "
             "filename=\"package://pfx/urdf/meshes/no_such_mesh.stl\"/></geometry></collision></"
             "link>"),
       PFX_ERR_INVALID_VALUE,
       "link 'a': mesh 'package://pfx/urdf/meshes/no_such_mesh.stl' not found"},
      {"negative mass",
       robot(linkXml("a") + linkXml("forearm", "-2") + jointXml("j", "fixed", "a", "forearm")),
       PFX_ERR_INVALID_VALUE, "link 'forearm': mass -2 is negative"},
      {"NaN mass", robot(linkXml("forearm", "nan")), PFX_ERR_INVALID_VALUE,
       "link 'forearm': mass 'nan' is not finite"},
      {"mass not a number", robot(linkXml("forearm", "heavy")), PFX_ERR_INVALID_VALUE,
       "link 'forearm': mass 'heavy' is not a number"},
      {"inertia not positive definite", robot(linkXml("forearm", "1", "-0.01")),
       PFX_ERR_INVALID_VALUE, "link 'forearm': inertia is not positive definite"},
      // 0.05 kg m^2 about x beside 0.01 about y and z: no mass distribution has them.
      {"inertia of no rigid body", robot(linkXml("forearm", "1", "0.05")), PFX_ERR_INVALID_VALUE,
       "link 'forearm': principal moments of inertia of no rigid body"},
      {"unknown joint type", robot(linkXml("a") + linkXml("b") + jointXml("j", "ball", "a", "b")),
       PFX_ERR_INVALID_FLAG, "joint 'j': unknown type 'ball'"},
      {"cycle",
       robot(linkXml("root") + linkXml("a") + linkXml("b") +
             jointXml("to_a", "fixed", "root", "a") + jointXml("a_b", "fixed", "a", "b") +
             jointXml("b_a", "fixed", "b", "a")),
       PFX_ERR_INVALID_VALUE, "link 'a': child of two joints, 'to_a' and 'b_a'"},
      {"cycle beside the tree",
       robot(linkXml("root") + linkXml("a") + linkXml("b") + jointXml("a_b", "fixed", "a", "b") +
             jointXml("b_a", "fixed", "b", "a")),
       PFX_ERR_INVALID_VALUE, "closes a cycle through links"},
      {"dangling parent", robot(linkXml("a") + jointXml("j", "fixed", "nowhere", "a")),
       PFX_ERR_INVALID_VALUE, "joint 'j': parent link 'nowhere' is not defined"},
      {"dangling child", robot(linkXml("a") + jointXml("j", "fixed", "a", "nowhere")),
       PFX_ERR_INVALID_VALUE, "joint 'j': child link 'nowhere' is not defined"},
      {"two roots", robot(linkXml("a") + linkXml("b")), PFX_ERR_INVALID_VALUE,
       "links 'a' and 'b' are both roots"},
      {"duplicate link", robot(linkXml("a") + linkXml("a")), PFX_ERR_INVALID_VALUE,
       "link 'a': defined twice"},
      {"duplicate joint",
       robot(linkXml("a") + linkXml("b") + linkXml("c") + jointXml("j", "fixed", "a", "b") +
             jointXml("j", "fixed", "a", "c")),
       PFX_ERR_INVALID_VALUE, "joint 'j': defined twice"},
      {"limits the wrong way round",
       robot(linkXml("a") + linkXml("b") +
             jointXml("j", "revolute", "a", "b", hingeAxis("0 0 1", "1", "-1"))),
       PFX_ERR_INVALID_VALUE, "joint 'j': lower limit 1 is above upper limit -1"},
      {"zero axis",
       robot(linkXml("a") + linkXml("b") +
             jointXml("j", "revolute", "a", "b", hingeAxis("0 0 0", "-1", "1"))),
       PFX_ERR_DEGENERATE, "joint 'j': axis is zero"},
      {"unknown mimic leader",
       robot(linkXml("a") + linkXml("b") +
             jointXml("j", "revolute", "a", "b", kHingeLimits + "<mimic joint=\"k\"/>")),
       PFX_ERR_INVALID_VALUE, "joint 'j': mimics joint 'k', which is not defined"},
      {"zero-size box",
       robot("<link name=\"a\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" "
             "iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial><collision><geometry><box size=\"0 1 1\"/>"
             "</geometry></collision></link>"),
       PFX_ERR_DEGENERATE, "link 'a': box size is not positive"},
  };

  // A world with a robot and a few steps behind it, and a model of that robot.
  PfxWorld world;
  initZUpWorld(world);
  addGround(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.rootPosition = PfxVector3(0, 0, 1.2f);
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "ragdoll.urdf", param, model));
  for (int i = 0; i < 10; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const WorldSnapshot before(world);
  const std::size_t links = model.links.size();

  for (const Case& c : cases) {
    std::string message;
    EXPECT_EQ(pfxLoadUrdfString(world, c.xml, PFX_SOURCE_DIR "/urdf", PfxUrdfLoadParam(), model,
                                &message),
              c.code)
        << c.what;
    EXPECT_EQ(message.rfind("<urdf string>: ", 0), 0u) << c.what << ": " << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
    EXPECT_TRUE(WorldSnapshot(world) == before) << c.what;
    EXPECT_EQ(model.name, "ragdoll") << c.what;
    EXPECT_EQ(model.links.size(), links) << c.what;
    printf("%-30s %s\n", c.what, message.c_str());
  }
  // The world still steps the ragdoll it holds.
  ASSERT_EQ(world.step(), PFX_OK);
}

TEST(UrdfLoader, FileErrorsNameTheFile) {
  const std::string path = testing::TempDir() + "ragdoll_bad.urdf";
  {
    std::ofstream out(path);
    out << robot(linkXml("forearm", "1", "-1"));
  }
  PfxWorld world;
  PfxUrdfModel model;
  std::string message;
  EXPECT_EQ(pfxLoadUrdfFile(world, path, PfxUrdfLoadParam(), model, &message),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(message.rfind(path + ": link 'forearm': inertia is not positive definite", 0), 0u)
      << message;
  std::remove(path.c_str());
  EXPECT_EQ(pfxLoadUrdfFile(world, path, PfxUrdfLoadParam(), model, &message),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(message, path + ": cannot be read (no such file)");
  // Bad parameters are refused the same way.
  PfxUrdfLoadParam param;
  param.rootPosition.x() = std::numeric_limits<PfxFloat>::quiet_NaN();
  EXPECT_EQ(pfxLoadUrdfFile(world, robotPath("arm.urdf"), param, model, &message),
            PFX_ERR_INVALID_VALUE);
  EXPECT_NE(message.find("load parameters"), std::string::npos);
  EXPECT_EQ(world.getNumRigidBodies(), 0u);
}

TEST(UrdfLoader, JointCommandsRejectBadInputAndChangeNothing) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "arm.urdf", fixedBaseParam(), model));
  const WorldSnapshot before(world);
  const PfxUInt32 joint2 = static_cast<PfxUInt32>(pfxFindUrdfJoint(model, "joint_2"));
  const PfxFloat nan = std::numeric_limits<PfxFloat>::quiet_NaN();
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model, 99, kPfxJointDrivePosition, 0),
            PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model, joint2, kPfxJointDrivePosition, nan),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model, joint2, kPfxJointDrivePosition, 0, -1),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model, joint2, static_cast<PfxJointDrive>(7), 0),
            PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model,
                                   static_cast<PfxUInt32>(pfxFindUrdfJoint(model, "tool0_joint")),
                                   kPfxJointDriveVelocity, 1),
            PFX_ERR_INVALID_VALUE);
  EXPECT_TRUE(WorldSnapshot(world) == before);
  // A velocity beyond the joint's limit is cut to it; the effort limit bounds the force.
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, joint2, kPfxJointDriveVelocity, 50), PFX_OK);
  const PfxJointConstraint& axis =
      world.getJoint(model.joints[joint2].jointId).m_constraints[kPfxJointAxisTwist];
  EXPECT_EQ(axis.m_drive, kPfxJointDriveVelocity);
  EXPECT_FLOAT_EQ(axis.m_driveTarget, 2);
  EXPECT_FLOAT_EQ(axis.m_driveMaxForce, 150);
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, joint2, kPfxJointDriveNone, 0), PFX_OK);
  EXPECT_EQ(world.getJoint(model.joints[joint2].jointId).m_constraints[kPfxJointAxisTwist].m_drive,
            kPfxJointDriveNone);
}

// ---------------------------------------------------------------------------------------
// Meshes and their URIs.

namespace {

// One link with urdf/meshes/finger.stl (0.015 x 0.01 x 0.05 m) scaled by `scale`.
std::string scaledFinger(const std::string& uri, const std::string& scale) {
  return robot(
      "<link name=\"finger\"><inertial><mass value=\"0.1\"/><inertia ixx=\"1e-4\" "
      "ixy=\"0\" ixz=\"0\" iyy=\"1e-4\" iyz=\"0\" izz=\"1e-4\"/></inertial><collision>"
      "<geometry><mesh filename=\"" +
      uri + "\" scale=\"" + scale + "\"/></geometry></collision></link>");
}

PfxVector3 meshHalfExtent(const PfxShape& shape) {
  if (shape.getType() == kPfxShapeConvexMesh) return shape.getConvexMesh()->m_aabbHalf;
  const PfxLargeTriMesh& mesh = *shape.getLargeTriMesh();
  return (mesh.m_aabbMax - mesh.m_aabbMin) / 2;
}

}  // namespace

TEST(UrdfLoader, MeshScaleGivesTheRightSizeOnMovingAndFixedLinks) {
  for (const bool fixedBase : {false, true}) {
    PfxWorld world;
    initZUpWorld(world);
    PfxUrdfModel model;
    PfxUrdfLoadParam param;
    param.fixedBase = fixedBase;
    std::string message;
    ASSERT_EQ(
        pfxLoadUrdfString(world, scaledFinger("package://pfx/urdf/meshes/finger.stl", "2 3 4"),
                          PFX_SOURCE_DIR "/urdf", param, model, &message),
        PFX_OK)
        << message;
    const PfxShape& shape = world.getCollidable(model.firstBodyId).getShape(0);
    EXPECT_EQ(shape.getType(), fixedBase ? kPfxShapeLargeTriMesh : kPfxShapeConvexMesh);
    const PfxVector3 half = meshHalfExtent(shape);
    printf("finger.stl scaled 2 3 4 (%s): %.4f x %.4f x %.4f m\n",
           fixedBase ? "large mesh" : "hull", 2 * half.x(), 2 * half.y(), 2 * half.z());
    EXPECT_NEAR(2 * half.x(), 0.015 * 2, 1e-5);
    EXPECT_NEAR(2 * half.y(), 0.01 * 3, 1e-5);
    EXPECT_NEAR(2 * half.z(), 0.05 * 4, 1e-5);
  }
  PfxWorld world;
  PfxUrdfModel model;
  std::string message;
  EXPECT_EQ(pfxLoadUrdfString(world, scaledFinger("package://pfx/urdf/meshes/finger.stl", "1 0 1"),
                              PFX_SOURCE_DIR "/urdf", PfxUrdfLoadParam(), model, &message),
            PFX_ERR_INVALID_VALUE);
  EXPECT_NE(message.find("link 'finger': mesh 'package://pfx/urdf/meshes/finger.stl': scale must "
                         "be positive and finite"),
            std::string::npos)
      << message;
}

TEST(UrdfLoader, MeshUrisResolveThroughRosPackagePathThenTheUrdfsFolders) {
  const char* saved = std::getenv("ROS_PACKAGE_PATH");
  const std::string savedValue = saved ? saved : "";
  const std::string empty = testing::TempDir();
  struct Case {
    const char* rosPackagePath;  // null: unset
    std::string uri;
    std::string basePath;
    std::string packageRoot;
    bool found;
  };
  const std::string source = PFX_SOURCE_DIR;
  const Case cases[] = {
      {source.c_str(), "package://pfx/urdf/meshes/finger.stl", "/", "", true},
      {empty.c_str(), "package://pfx/urdf/meshes/finger.stl", source + "/urdf", "", true},
      {nullptr, "package://pfx/urdf/meshes/finger.stl", source + "/urdf/meshes", "", true},
      {nullptr, "package://pfx/urdf/meshes/finger.stl", "/", source, true},
      {nullptr, "package://pfx/urdf/meshes/finger.stl", "/", "", false},
      {nullptr, "file://" + source + "/urdf/meshes/finger.stl", "/", "", true},
      {nullptr, "meshes/finger.stl", source + "/urdf", "", true},
      {nullptr, "http://example.com/finger.stl", source + "/urdf", "", false},
  };
  for (const Case& c : cases) {
    if (c.rosPackagePath) {
      setenv("ROS_PACKAGE_PATH", c.rosPackagePath, 1);
    } else {
      unsetenv("ROS_PACKAGE_PATH");
    }
    PfxWorld world;
    PfxUrdfModel model;
    PfxUrdfLoadParam param;
    param.packageRoot = c.packageRoot;
    std::string message;
    const PfxInt32 err =
        pfxLoadUrdfString(world, scaledFinger(c.uri, "1 1 1"), c.basePath, param, model, &message);
    EXPECT_EQ(err == PFX_OK, c.found) << c.uri << " from " << c.basePath << ": " << message;
    if (!c.found) {
      EXPECT_NE(message.find("link 'finger': mesh"), std::string::npos) << message;
    }
  }
  if (saved) {
    setenv("ROS_PACKAGE_PATH", savedValue.c_str(), 1);
  } else {
    unsetenv("ROS_PACKAGE_PATH");
  }
}

// ---------------------------------------------------------------------------------------
// Options.

TEST(UrdfLoader, FixedJointsCanBeKeptAndSelfCollisionSwitchedOff) {
  PfxWorld lumped, kept;
  initZUpWorld(lumped);
  initZUpWorld(kept);
  PfxUrdfModel lumpedModel, keptModel;
  PfxUrdfLoadParam param;
  param.allowMissingMeshes = true;
  param.disableSelfCollision = true;
  ASSERT_NO_FATAL_FAILURE(loadRobot(lumped, "r2d2.urdf", param, lumpedModel));
  param.lumpFixedJoints = false;
  ASSERT_NO_FATAL_FAILURE(loadRobot(kept, "r2d2.urdf", param, keptModel));
  // r2d2 has 16 links, 7 of them joined to their parent by fixed joints.
  EXPECT_EQ(lumpedModel.numBodies, 9u);
  EXPECT_EQ(keptModel.numBodies, 16u);
  int fixedJoints = 0;
  for (PfxUInt32 j = 0; j < kept.getNumJoints(); ++j)
    fixedJoints += kept.getJoint(j).m_type == kPfxJointFixed;
  EXPECT_EQ(fixedJoints, 7);
  EXPECT_EQ(keptModel.numJoints, lumpedModel.numJoints + 7);
  EXPECT_NEAR(totalMass(kept, keptModel), totalMass(lumped, lumpedModel), 1e-4);
  // The robot's bodies with shapes do not meet each other, but do meet the rest.
  const PfxRigidState& base = lumped.getRigidState(linkNamed(lumpedModel, "base_link").bodyId);
  const PfxRigidState& head = lumped.getRigidState(linkNamed(lumpedModel, "head").bodyId);
  EXPECT_FALSE(pfxContactFiltersMatch(base.getContactFilterSelf(), base.getContactFilterTarget(),
                                      head.getContactFilterSelf(), head.getContactFilterTarget()));
  EXPECT_TRUE(pfxContactFiltersMatch(base.getContactFilterSelf(), base.getContactFilterTarget(),
                                     0xffffffffu, 0xffffffffu));
  // The gripper links lost their meshes: their bodies carry a shape that meets nothing.
  const PfxRigidState& gripper =
      lumped.getRigidState(linkNamed(lumpedModel, "left_gripper").bodyId);
  EXPECT_EQ(gripper.getContactFilterSelf(), 0u);
  EXPECT_EQ(gripper.getContactFilterTarget(), 0u);
  EXPECT_TRUE(hasWarningWith(lumpedModel, "mesh 'l_finger.stl' not found"));
}

TEST(UrdfLoader, JointDampingIsTheFractionOfAPendulumsViscousDecay) {
  // A 2 kg point-like bob 0.5 m below a fixed pivot: I = 0.001 + 2 * 0.25 kg m^2.
  const std::string xml = R"(<robot name="pendulum">
  <link name="pivot"/>
  <link name="bob"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
    <collision><origin xyz="0 0 -0.5"/><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="swing" type="continuous"><parent link="pivot"/><child link="bob"/><axis xyz="0 1 0"/>
    <dynamics damping="3" friction="0.25"/></joint>
</robot>)";
  PfxWorld world;
  initZUpWorld(world, 2);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, fixedBaseParam(), model));
  const PfxUrdfJoint& swing = jointNamed(model, "swing");
  const PfxJointConstraint& axis = world.getJoint(swing.jointId).m_constraints[swing.axis];
  const double h = 1.0 / 120;
  EXPECT_NEAR(axis.m_damping, 1 - std::exp(-3 * h / (0.001 + 2 * 0.25)), 1e-6);
  EXPECT_FLOAT_EQ(axis.m_friction, 0.25f);
  EXPECT_EQ(axis.m_lock, kPfxJointLockFree);
  EXPECT_TRUE(std::isinf(swing.upperLimit));
}

// ---------------------------------------------------------------------------------------
// Real robots under gravity.

// Mounted on a slope (its base tilted 0.6 rad, the arm leaning over), the arm swings down
// until joint 2 meets its limit (2.09 rad; hanging straight down would take 2.54) and
// hangs there.
TEST(UrdfLoader, KukaIiwaHangsAgainstItsJointLimitsAndAnswersRays) {
  PfxWorld world;
  initZUpWorld(world, 2);
  PfxUrdfModel model;
  PfxUrdfLoadParam param = fixedBaseParam();
  param.rootOrientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.6f, PfxVector3::UnitY()));
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "kuka_iiwa/model.urdf", param, model));
  EXPECT_EQ(model.numBodies, 8u);
  EXPECT_EQ(model.numJoints, 7u);
  EXPECT_NEAR(totalMass(world, model), 4 + 4 + 3 + 2.7 + 1.7 + 1.8 + 0.3, 1e-4);
  const PfxUInt32 base = linkNamed(model, "lbr_iiwa_link_0").bodyId;
  EXPECT_EQ(world.getRigidState(base).getMotionType(), kPfxMotionTypeFixed);
  EXPECT_EQ(world.getCollidable(base).getShape(0).getType(), kPfxShapeLargeTriMesh);
  EXPECT_EQ(world.getCollidable(linkNamed(model, "lbr_iiwa_link_4").bodyId).getShape(0).getType(),
            kPfxShapeConvexMesh);
  double worst = 0, largestGap = 0;
  std::string worstJoint;
  for (int i = 0; i < 300; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    std::string name;
    const double violation = worstLimitViolation(world, model, &name);
    if (violation > worst) {
      worst = violation;
      worstJoint = name;
    }
    largestGap = std::max<double>(largestGap, world.getStats().maxJointGap);
  }
  std::vector<double> q, v;
  pfxGetUrdfJointStates(world, model, q, v);
  const PfxTransform3 flange = pfxGetUrdfLinkPose(world, linkNamed(model, "lbr_iiwa_link_7"));
  const double joint2 = q[pfxFindUrdfJoint(model, "lbr_iiwa_joint_2")];
  printf(
      "kuka iiwa after 5 s: joint 2 at %.3f rad (limit 2.094), link 7 at (%.3f, %.3f, %.3f), worst "
      "limit violation %.2e rad (%s), largest joint gap %.2e m\n",
      joint2, flange.translation().x(), flange.translation().y(), flange.translation().z(), worst,
      worstJoint.c_str(), largestGap);
  EXPECT_NEAR(joint2, 2.0944, 0.03);       // resting on its limit
  EXPECT_LT(flange.translation().z(), 0);  // it swung down
  EXPECT_LT(worst, 0.02);
  EXPECT_LT(largestGap, 1e-3);
  // Every link stays within the arm's reach (1.3 m) of the base.
  for (PfxUInt32 b = model.firstBodyId; b < model.firstBodyId + model.numBodies; ++b) {
    EXPECT_LT(world.getRigidState(b).getPosition().norm(), 1.3f) << "body " << b;
  }

  // A horizontal ray through the base hits the base's large mesh; a ray across the last
  // link hits it.
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = PfxVector3(0, 1, 0.05f);
  ray.m_direction = PfxVector3(0, -2, 0);
  PfxRayOutput out;
  ASSERT_EQ(world.castRay(ray, out), PFX_OK);
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_EQ(out.m_objectId, base);
  const double baseDistance = out.m_variable * 2;
  const PfxUInt32 last = linkNamed(model, "lbr_iiwa_link_7").bodyId;
  const PfxVector3 target = world.getRigidState(last).getPosition();
  ray.m_startPosition = target + PfxVector3(0, 2, 0);
  ray.m_direction = PfxVector3(0, -4, 0);
  ASSERT_EQ(world.castRay(ray, out), PFX_OK);
  ASSERT_TRUE(out.m_contactFlag);
  EXPECT_EQ(out.m_objectId, last);
  printf(
      "kuka iiwa: ray through the base hits it %.3f m from y = 1; ray across link 7 hits it "
      "%.3f m before its centre\n",
      baseDistance, double(2 - out.m_variable * 4));
}

TEST(UrdfLoader, R2d2StandsOnTheGround) {
  PfxWorld world;
  initZUpWorld(world, 2);
  addGround(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.allowMissingMeshes = true;
  // The wheels' lowest point is 0.47 m below the base link.
  param.rootPosition = PfxVector3(0, 0, 0.48f);
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "r2d2.urdf", param, model));
  const PfxUInt32 base = linkNamed(model, "base_link").bodyId;
  double lowest = 1e9, fastest = 0;
  for (int i = 0; i < 180; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    for (PfxUInt32 b = model.firstBodyId; b < model.firstBodyId + model.numBodies; ++b) {
      const PfxRigidState& s = world.getRigidState(b);
      ASSERT_TRUE(s.isValid());
      lowest = std::min<double>(lowest, s.getPosition().z());
    }
    if (i >= 60) fastest = std::max(fastest, maxSpeed(world, model));
  }
  const PfxTransform3 pose = pfxGetUrdfLinkPose(world, linkNamed(model, "base_link"));
  const double upright = pose.linear().col(2).z();
  printf(
      "r2d2 after 3 s: base link at z %.3f m (loaded at 0.48), upright %.4f, lowest body "
      "centre z %.3f m, fastest body after 1 s %.3f m/s, deepest contact %.4f m\n",
      pose.translation().z(), upright, lowest, fastest, world.getStats().maxPenetration);
  EXPECT_NEAR(pose.translation().z(), 0.47, 0.02);
  EXPECT_GT(upright, 0.99);
  EXPECT_GT(lowest, 0);
  EXPECT_LT(fastest, 0.1);
  EXPECT_LT(world.getRigidState(base).getLinearVelocity().norm(), 0.05);
}

TEST(UrdfLoader, RagdollDroppedOnTheGroundComesToRestWithinItsLimits) {
  PfxWorld world;
  initZUpWorld(world, 2);
  addGround(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  // Tipped forward and turned, 0.3 m above standing, so that it falls over.
  param.rootPosition = PfxVector3(0, 0, 1.3f);
  param.rootOrientation =
      PfxQuat(Eigen::AngleAxis<PfxFloat>(0.5f, PfxVector3(1, 1, 0).normalized()));
  ASSERT_NO_FATAL_FAILURE(loadRobot(world, "ragdoll.urdf", param, model));
  double worst = 0, highestSpeed = 0;
  std::string worstJoint;
  const int steps = 360;
  for (int i = 0; i < steps; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    std::string name;
    const double violation = worstLimitViolation(world, model, &name);
    if (violation > worst) {
      worst = violation;
      worstJoint = name;
    }
    highestSpeed = std::max(highestSpeed, maxSpeed(world, model));
  }
  double lowest = 1e9;
  for (PfxUInt32 b = model.firstBodyId; b < model.firstBodyId + model.numBodies; ++b) {
    lowest = std::min<double>(lowest, world.getRigidState(b).getPosition().z());
  }
  const double restSpeed = maxSpeed(world, model);
  const double pelvis = pfxGetUrdfLinkPose(world, linkNamed(model, "pelvis")).translation().z();
  printf(
      "ragdoll after %d steps: pelvis at z %.3f m, lowest body centre %.3f m, speed %.4f m/s "
      "(at most %.2f while falling), worst URDF limit violation %.4f rad (%s), deepest "
      "contact %.4f m\n",
      steps, pelvis, lowest, restSpeed, highestSpeed, worst, worstJoint.c_str(),
      world.getStats().maxPenetration);
  EXPECT_LT(pelvis, 0.3);  // lying on the ground
  EXPECT_GT(lowest, 0);
  EXPECT_LT(restSpeed, 0.05);
  EXPECT_LT(worst, 0.05);
}
