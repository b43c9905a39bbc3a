// Robot descriptions as people have them, written for other simulators: capsules and
// geometry urdfdom cannot read, massless helper links between joints whose axes do not
// meet, a root without mass, unexpanded xacro, targets beyond the joints' limits, robots
// whose URDF pose puts them inside the ground, and links that overlap in the zero pose.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_urdf_loader.h"

using namespace pfx;

namespace {

// A link of `mass` kg with the inertia of a 0.1 m cube of that mass, and `inside`.
std::string massiveLink(const std::string& name, const std::string& inside, double mass = 1) {
  const std::string m = std::to_string(mass);
  const std::string i = std::to_string(mass * 0.01 / 6);
  return "<link name=\"" + name + "\"><inertial><mass value=\"" + m + "\"/><inertia ixx=\"" + i +
         "\" ixy=\"0\" ixz=\"0\" iyy=\"" + i + "\" iyz=\"0\" izz=\"" + i + "\"/></inertial>" +
         inside + "</link>\n";
}

std::string collision(const std::string& geometry, const std::string& origin = "") {
  return "<collision>" + (origin.empty() ? "" : "<origin " + origin + "/>") + "<geometry>" +
         geometry + "</geometry></collision>";
}

void initZUpWorld(PfxWorld& world, PfxFloat timeStep = PfxFloat(1.0 / 240)) {
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.81));
  param.timeStep = timeStep;
  param.enableSleep = false;
  ASSERT_EQ(world.initialize(param), PFX_OK);
}

// A fixed box whose top face is the plane z = 0.
void addGround(PfxWorld& world) {
  PfxBodyInit init;
  init.mass = 0;
  init.position = PfxVector3(0, 0, -0.5f);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(20, 20, 0.5f)), init), PFX_OK);
}

void loadText(PfxWorld& world, const std::string& xml, const PfxUrdfLoadParam& param,
              PfxUrdfModel& model) {
  std::string message;
  ASSERT_EQ(pfxLoadUrdfString(world, xml, ".", param, model, &message), PFX_OK) << message;
}

// The load's error message, after checking that it failed and left the world empty.
std::string loadError(const std::string& xml, const PfxUrdfLoadParam& param = PfxUrdfLoadParam()) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  std::string message;
  EXPECT_NE(pfxLoadUrdfString(world, xml, ".", param, model, &message), PFX_OK);
  EXPECT_EQ(world.getNumRigidBodies(), 0u);
  EXPECT_TRUE(model.links.empty());
  return message;
}

// A warning that contains `text`; a final "\n" in `text` matches the warning's end.
bool hasWarningWith(const PfxUrdfModel& model, const std::string& text) {
  for (const std::string& warning : model.warnings) {
    if ((warning + "\n").find(text) != std::string::npos) return true;
  }
  return false;
}

std::string allWarnings(const PfxUrdfModel& model) {
  std::string all;
  for (const std::string& warning : model.warnings) all += warning + "\n";
  return all;
}

const PfxUrdfLink& linkNamed(const PfxUrdfModel& model, const std::string& name) {
  const PfxInt32 i = pfxFindUrdfLink(model, name);
  EXPECT_GE(i, 0) << name;
  return model.links[std::max(i, 0)];
}

PfxInt32 jointIndex(const PfxUrdfModel& model, const std::string& name) {
  const PfxInt32 i = pfxFindUrdfJoint(model, name);
  EXPECT_GE(i, 0) << name;
  return i;
}

void step(PfxWorld& world, double seconds) {
  const int steps = int(std::lround(seconds / double(world.getParam().timeStep)));
  for (int i = 0; i < steps; ++i) ASSERT_EQ(world.step(), PFX_OK);
}

// The height (world z) of the highest (up = 1) or lowest (up = -1) point of a shape of `body`.
PfxFloat extremeHeight(const PfxWorld& world, PfxUInt32 body, PfxUInt32 shape, PfxFloat up) {
  const PfxShape& s = world.getCollidable(body).getShape(shape);
  return pfxGetSupportPoint(s, world.getRigidState(body).getTransform() * s.getOffsetTransform(),
                            PfxVector3(0, 0, up))
      .z();
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Collision geometry: capsules, and nothing dropped without a word.

TEST(UrdfInputs, CapsulesLieAlongTheLinksZWithLengthTheirCylinderPart) {
  const std::string xml =
      "<robot name=\"capsules\">" +
      massiveLink("base",
                  collision("<capsule radius=\"0.05\" length=\"0.3\"/>", "xyz=\"0 0 0.5\"") +
                      collision("<box size=\"0.1 0.1 0.1\"/>", "xyz=\"0.4 0 0\"")) +
      "</robot>";
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, PfxUrdfLoadParam(), model));
  EXPECT_TRUE(model.warnings.empty()) << allWarnings(model);
  const PfxCollidable& collidable = world.getCollidable(model.firstBodyId);
  ASSERT_EQ(collidable.getNumShapes(), 2u);  // the box is not lost with the capsule
  const PfxShape& capsule = collidable.getShape(0);
  ASSERT_EQ(capsule.getType(), kPfxShapeCapsule);
  EXPECT_FLOAT_EQ(capsule.getCapsule().m_halfLen, 0.15f);
  EXPECT_FLOAT_EQ(capsule.getCapsule().m_radius, 0.05f);
  EXPECT_EQ(collidable.getShape(1).getType(), kPfxShapeBox);
  // Along Z: its top is 0.5 + 0.15 + 0.05 high, its bottom 0.3; the box reaches lower.
  EXPECT_NEAR(extremeHeight(world, model.firstBodyId, 0, 1), 0.7, 1e-5);
  EXPECT_NEAR(extremeHeight(world, model.firstBodyId, 0, -1), 0.3, 1e-5);
  EXPECT_NEAR(pfxGetUrdfLowestPoint(world, model), -0.05, 1e-5);
}

TEST(UrdfInputs, ACapsuleLinkDroppedOnItsSideComesToRestOnTheGround) {
  // A capsule turned onto its side (rpy about X) rests with its axis radius above the ground.
  const std::string xml = "<robot name=\"log\">" +
                          massiveLink("log", collision("<capsule radius=\"0.1\" length=\"0.6\"/>",
                                                       "rpy=\"1.5707963 0 0\"")) +
                          "</robot>";
  PfxWorld world;
  initZUpWorld(world);
  addGround(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.rootPosition = PfxVector3(0, 0, 0.5f);
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, param, model));
  ASSERT_NO_FATAL_FAILURE(step(world, 2));
  const PfxRigidState& state = world.getRigidState(model.firstBodyId);
  EXPECT_NEAR(state.getPosition().z(), 0.1, 0.01);
  EXPECT_LT(state.getLinearVelocity().norm(), 0.05f);
  EXPECT_NEAR(pfxGetUrdfLowestPoint(world, model), 0, 0.01);
}

TEST(UrdfInputs, GeometryThatCannotBeUsedIsNeverDroppedWithoutAWord) {
  // Unknown geometries and a collision without geometry are left out with a warning naming
  // the link and the line; the link's other shapes stay.
  const std::string xml = "<robot name=\"odd\">" +
                          massiveLink("base", collision("<plane normal=\"0 0 1\"/>") +
                                                  "\n<collision><geometry/></collision>\n" +
                                                  collision("<sphere radius=\"0.1\"/>")) +
                          "</robot>";
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, PfxUrdfLoadParam(), model));
  EXPECT_EQ(world.getCollidable(model.firstBodyId).getNumShapes(), 1u);
  EXPECT_TRUE(hasWarningWith(model,
                             "link 'base': <collision> on line 1 left out: unknown "
                             "geometry <plane>"))
      << allWarnings(model);
  EXPECT_TRUE(hasWarningWith(model,
                             "link 'base': <collision> on line 2 left out: it has no "
                             "geometry"))
      << allWarnings(model);

  // A mesh without a filename is a missing mesh: an error, or a warning when allowed.
  const std::string noFile = "<robot name=\"nofile\">" +
                             massiveLink("hand", collision("<mesh filename=\"\"/>")) + "</robot>";
  EXPECT_NE(loadError(noFile).find("link 'hand': <mesh> on line 1 has no filename"),
            std::string::npos);
  PfxUrdfLoadParam allowMissing;
  allowMissing.allowMissingMeshes = true;
  PfxWorld other;
  initZUpWorld(other);
  PfxUrdfModel loaded;
  ASSERT_NO_FATAL_FAILURE(loadText(other, noFile, allowMissing, loaded));
  EXPECT_TRUE(hasWarningWith(loaded, "link 'hand': <mesh> on line 1 has no filename; left out"))
      << allWarnings(loaded);
}

TEST(UrdfInputs, BadCapsulesFailNamingTheLink) {
  const auto robotWith = [](const std::string& geometry) {
    return "<robot name=\"bad\">" + massiveLink("arm", collision(geometry)) + "</robot>";
  };
  EXPECT_NE(loadError(robotWith("<capsule length=\"0.2\"/>"))
                .find("link 'arm': <capsule> on "
                      "line 1 has no radius"),
            std::string::npos);
  EXPECT_NE(loadError(robotWith("<capsule radius=\"0.1\"/>"))
                .find("link 'arm': <capsule> on "
                      "line 1 has no length"),
            std::string::npos);
  EXPECT_NE(loadError(robotWith("<capsule radius=\"0.1\" length=\"-1\"/>"))
                .find("link 'arm': capsule radius is not positive or its length is negative"),
            std::string::npos);
  EXPECT_NE(loadError(robotWith("<capsule radius=\"nan\" length=\"1\"/>"))
                .find("link 'arm': capsule radius 'nan' is not finite"),
            std::string::npos);
  EXPECT_NE(loadError(robotWith("<box size=\"1 1\"/>"))
                .find("link 'arm': box size '1 1' is not 3 "
                      "numbers"),
            std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Unexpanded xacro.

TEST(UrdfInputs, UnexpandedXacroIsRefusedWithAMessageToRunXacro) {
  const std::string link = massiveLink("base", "");
  const std::string cases[] = {
      "<robot name=\"x\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">"
      "<xacro:property name=\"pi\" value=\"3.14\"/>" +
          link + "</robot>",
      "<robot name=\"x\">" +
          massiveLink("base", collision("<mesh filename=\"$(find my_robot)/meshes/a.stl\"/>")) +
          "</robot>",
      "<robot name=\"x\">" + massiveLink("base", collision("<sphere radius=\"${r}\"/>")) +
          "</robot>",
      "<robot name=\"$(optenv ROBOT_NAME robot)\">" + link + "</robot>",
  };
  for (const std::string& xml : cases) {
    const std::string message = loadError(xml);
    EXPECT_NE(message.find("unexpanded xacro"), std::string::npos) << message;
    EXPECT_NE(message.find("expand it into a URDF first"), std::string::npos) << message;
  }
  // xmlns:xacro alone, as expanded files often keep it, is fine.
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(
      world, "<robot name=\"x\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">" + link + "</robot>",
      PfxUrdfLoadParam(), model));
}

// ---------------------------------------------------------------------------------------
// A root without mass.

TEST(UrdfInputs, ARootWithoutMassGetsAFixedBaseWithAWarning) {
  const std::string xml =
      R"(<robot name="arm">
  <link name="base_link"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
)" + massiveLink("upper", collision("<box size=\"0.05 0.05 0.4\"/>", "xyz=\"0 0 0.2\"")) +
      R"(<joint name="shoulder" type="revolute"><parent link="base_link"/><child link="upper"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>)";
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, xml, PfxUrdfLoadParam(), model));
  EXPECT_TRUE(model.fixedBase);
  EXPECT_TRUE(hasWarningWith(model,
                             "link 'base_link': the root link has no mass, so it cannot float; "
                             "the robot is loaded with a fixed base"))
      << allWarnings(model);
  const PfxUInt32 base = linkNamed(model, "base_link").bodyId;
  EXPECT_EQ(world.getRigidState(base).getMotionType(), kPfxMotionTypeFixed);
  ASSERT_NO_FATAL_FAILURE(step(world, 1));
  EXPECT_EQ(world.getRigidState(base).getPosition(), PfxVector3::Zero());

  // A root with mass still floats, and says nothing.
  PfxWorld free;
  initZUpWorld(free);
  PfxUrdfModel floating;
  ASSERT_NO_FATAL_FAILURE(loadText(free,
                                   "<robot name=\"ball\">" + massiveLink("ball", "") + "</robot>",
                                   PfxUrdfLoadParam(), floating));
  EXPECT_FALSE(floating.fixedBase);
  EXPECT_TRUE(floating.warnings.empty()) << allWarnings(floating);
  EXPECT_EQ(free.getRigidState(floating.firstBodyId).getMotionType(), kPfxMotionTypeActive);
}

// ---------------------------------------------------------------------------------------
// A massless helper between two joints whose axes do not meet: an ankle of two hinges
// 4 cm apart.

namespace {

// A fixed shank; 0.3 m below its frame the ankle's pitch (Y), through a massless helper the
// roll (X) 0.04 m lower, then the foot.
const std::string kOffsetAnkle =
    "<robot name=\"ankle\">" +
    massiveLink("shank", collision("<box size=\"0.06 0.06 0.26\"/>", "xyz=\"0 0 -0.13\""), 3) +
    "<link name=\"ankle_helper\"/>" +
    massiveLink("foot", collision("<box size=\"0.2 0.08 0.03\"/>", "xyz=\"0.05 0 -0.04\"")) +
    R"(<joint name="ankle_pitch" type="revolute"><parent link="shank"/><child link="ankle_helper"/>
    <origin xyz="0 0 -0.3"/><axis xyz="0 1 0"/><limit lower="-0.8" upper="0.5" effort="60" velocity="5"/></joint>
  <joint name="ankle_roll" type="revolute"><parent link="ankle_helper"/><child link="foot"/>
    <origin xyz="0 0 -0.04"/><axis xyz="1 0 0"/><limit lower="-0.3" upper="0.4" effort="60" velocity="5"/></joint>
</robot>)";

Eigen::Isometry3d footPoseOfUrdf(double pitch, double roll) {
  return Eigen::Translation3d(0, 0, -0.3) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::Translation3d(0, 0, -0.04) * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

void expectPose(const PfxTransform3& actual, const Eigen::Isometry3d& expected, double metres,
                double radians, const std::string& what) {
  EXPECT_LT((actual.translation().cast<double>() - expected.translation()).norm(), metres) << what;
  const Eigen::AngleAxisd turn(actual.linear().cast<double>().transpose() * expected.linear());
  EXPECT_LT(std::abs(turn.angle()), radians) << what;
}

}  // namespace

TEST(UrdfInputs, AMasslessLinkBetweenOffsetJointsBecomesALightBodyWithTheUrdfsKinematics) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.fixedBase = true;
  ASSERT_NO_FATAL_FAILURE(loadText(world, kOffsetAnkle, param, model));
  EXPECT_TRUE(hasWarningWith(model,
                             "link 'ankle_helper': no mass, and joints 'ankle_pitch' and "
                             "'ankle_roll' do not meet at one point (0.04 m apart)"))
      << allWarnings(model);
  EXPECT_TRUE(hasWarningWith(
      model, "loaded as a light body of 0.1 kg (a tenth of the mass of link 'foot')"))
      << allWarnings(model);
  ASSERT_EQ(model.numBodies, 3u);
  ASSERT_EQ(model.numJoints, 2u);
  const PfxUInt32 helper = linkNamed(model, "ankle_helper").bodyId;
  EXPECT_NEAR(world.getRigidBody(helper).getMass(), 0.1, 1e-6);

  // Each URDF joint is one hinge with the URDF's limits.
  for (const char* name : {"ankle_pitch", "ankle_roll"}) {
    const PfxUrdfJoint& joint = model.joints[pfxFindUrdfJoint(model, name)];
    ASSERT_NE(joint.jointId, kPfxUrdfNoJoint) << name;
    EXPECT_FALSE(joint.collapsed);
    const PfxJointConstraint& axis = world.getJoint(joint.jointId).m_constraints[joint.axis];
    EXPECT_EQ(axis.m_lock, kPfxJointLockLimit) << name;
    EXPECT_FLOAT_EQ(axis.m_movableLowerLimit, joint.lowerLimit) << name;
    EXPECT_FLOAT_EQ(axis.m_movableUpperLimit, joint.upperLimit) << name;
  }

  // Placed where the URDF's chain puts them, the bodies read back the URDF angles and no
  // joint is pulled apart: the reach is the URDF's.
  const PfxUrdfLink& helperLink = linkNamed(model, "ankle_helper");
  const PfxUrdfLink& foot = linkNamed(model, "foot");
  const double angles[][2] = {{0, 0}, {0.4, -0.2}, {-0.7, 0.35}, {0.2, 0.3}};
  for (const auto& q : angles) {
    const Eigen::Isometry3d helperPose =
        Eigen::Translation3d(0, 0, -0.3) * Eigen::AngleAxisd(q[0], Eigen::Vector3d::UnitY());
    const Eigen::Isometry3d footPose = footPoseOfUrdf(q[0], q[1]);
    for (const auto& [link, pose] :
         {std::make_pair(&helperLink, helperPose), std::make_pair(&foot, footPose)}) {
      const Eigen::Isometry3d body = pose * link->linkInBody.inverse().cast<double>();
      PfxRigidState state = world.getRigidState(link->bodyId);
      state.setPosition(body.translation().cast<PfxFloat>());
      state.setOrientation(PfxQuat(Eigen::Quaterniond(body.linear()).cast<PfxFloat>()));
      ASSERT_EQ(world.setRigidState(link->bodyId, state), PFX_OK);
    }
    std::vector<double> positions, velocities;
    pfxGetUrdfJointStates(world, model, positions, velocities);
    EXPECT_NEAR(positions[jointIndex(model, "ankle_pitch")], q[0], 1e-5);
    EXPECT_NEAR(positions[jointIndex(model, "ankle_roll")], q[1], 1e-5);
    for (PfxUInt32 j = model.firstJointId; j < model.firstJointId + model.numJoints; ++j) {
      const PfxJoint& joint = world.getJoint(j);
      PfxFloat c[6];
      pfxCalcJointCoordinates(joint, world.getRigidState(joint.m_rigidBodyIdA),
                              world.getRigidState(joint.m_rigidBodyIdB), c);
      EXPECT_LT(PfxVector3(c[0], c[1], c[2]).norm(), 1e-5f) << "joint " << j;
      EXPECT_LT(std::abs(c[kPfxJointAxisSwing1]) + std::abs(c[kPfxJointAxisSwing2]), 1e-5f);
    }
    expectPose(pfxGetUrdfLinkPose(world, foot), footPose, 1e-5, 1e-5, "placed foot");
  }
}

TEST(UrdfInputs, TheOffsetAnkleReachesDrivenPosesAndStopsAtItsLimits) {
  PfxUrdfLoadParam param;
  param.fixedBase = true;
  const PfxInt32 pitchIndex = 0, rollIndex = 1;  // file order
  // Driven under gravity, the foot goes where the URDF's chain puts it.
  const double targets[][2] = {{0.3, -0.2}, {-0.6, 0.3}};
  for (const auto& q : targets) {
    PfxWorld world;
    initZUpWorld(world);
    PfxUrdfModel model;
    ASSERT_NO_FATAL_FAILURE(loadText(world, kOffsetAnkle, param, model));
    ASSERT_EQ(
        pfxSetUrdfJointCommand(world, model, pitchIndex, kPfxJointDrivePosition, PfxFloat(q[0])),
        PFX_OK);
    ASSERT_EQ(
        pfxSetUrdfJointCommand(world, model, rollIndex, kPfxJointDrivePosition, PfxFloat(q[1])),
        PFX_OK);
    ASSERT_NO_FATAL_FAILURE(step(world, 2));
    expectPose(pfxGetUrdfLinkPose(world, linkNamed(model, "foot")), footPoseOfUrdf(q[0], q[1]),
               0.005, 0.02, "driven foot");
    EXPECT_LT(world.getStats().maxJointGap, 1e-3f);
  }
  // Pushed beyond its limits by velocity drives, each joint stops at its limit.
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  ASSERT_NO_FATAL_FAILURE(loadText(world, kOffsetAnkle, param, model));
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, pitchIndex, kPfxJointDriveVelocity, 2), PFX_OK);
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, rollIndex, kPfxJointDriveVelocity, -2), PFX_OK);
  ASSERT_NO_FATAL_FAILURE(step(world, 2));
  std::vector<double> q, v;
  pfxGetUrdfJointStates(world, model, q, v);
  EXPECT_NEAR(q[pitchIndex], 0.5, 0.02);
  EXPECT_NEAR(q[rollIndex], -0.3, 0.02);
}

// ---------------------------------------------------------------------------------------
// Targets beyond the limits, and the URDF's effort as the default force limit.

namespace {

// A fixed palm and two prismatic fingers, the right one mimicking the left.
const std::string kGripper =
    "<robot name=\"gripper\">" + massiveLink("palm", collision("<box size=\"0.1 0.2 0.04\"/>")) +
    massiveLink("left", collision("<box size=\"0.02 0.02 0.08\"/>", "xyz=\"0 0 0.04\""), 0.1) +
    massiveLink("right", collision("<box size=\"0.02 0.02 0.08\"/>", "xyz=\"0 0 0.04\""), 0.1) +
    R"(<joint name="left_finger" type="prismatic"><parent link="palm"/><child link="left"/>
    <origin xyz="0 0.02 0.02"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="20" velocity="0.5"/></joint>
  <joint name="right_finger" type="prismatic"><parent link="palm"/><child link="right"/>
    <origin xyz="0 -0.02 0.02"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="20" velocity="0.5"/>
    <mimic joint="left_finger"/></joint>
</robot>)";

}  // namespace

TEST(UrdfInputs, TargetsBeyondTheLimitsAreCutSayingWhichJointAndLimit) {
  PfxWorld world;
  initZUpWorld(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.fixedBase = true;
  ASSERT_NO_FATAL_FAILURE(loadText(world, kGripper, param, model));
  const PfxInt32 left = jointIndex(model, "left_finger");
  const PfxInt32 right = jointIndex(model, "right_finger");
  const PfxUrdfJoint& leader = model.joints[left];

  std::string note = "stale";
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, left, kPfxJointDrivePosition, 0.1f, 0, &note),
            PFX_OK);
  EXPECT_EQ(note, "joint 'left_finger': position target 0.1 cut to its upper limit 0.04");
  const PfxJointConstraint& axis = world.getJoint(leader.jointId).m_constraints[leader.axis];
  EXPECT_FLOAT_EQ(axis.m_driveTarget, 0.04f);
  EXPECT_FLOAT_EQ(axis.m_driveMaxForce, 20);  // the URDF's effort, none being asked for

  // Driven into the limit, both fingers stay within it.
  ASSERT_NO_FATAL_FAILURE(step(world, 2));
  std::vector<double> q, v;
  pfxGetUrdfJointStates(world, model, q, v);
  EXPECT_NEAR(q[left], 0.04, 1e-3);
  EXPECT_NEAR(q[right], 0.04, 1e-3);
  EXPECT_LE(q[left], 0.04 + 1e-3);
  EXPECT_LE(q[right], 0.04 + 1e-3);

  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, left, kPfxJointDrivePosition, -0.5f, 5, &note),
            PFX_OK);
  EXPECT_EQ(note, "joint 'left_finger': position target -0.5 cut to its lower limit 0");
  EXPECT_FLOAT_EQ(world.getJoint(leader.jointId).m_constraints[leader.axis].m_driveMaxForce, 5);
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, left, kPfxJointDriveVelocity, 3, 0, &note),
            PFX_OK);
  EXPECT_EQ(note, "joint 'left_finger': velocity target 3 cut to its upper velocity limit 0.5");
  // An effort beyond the URDF's effort limit is cut to it, and a larger force limit asked
  // for does not lift the URDF's.
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, left, kPfxJointDriveEffort, -50, 100, &note),
            PFX_OK);
  EXPECT_EQ(note, "joint 'left_finger': effort target -50 cut to its lower effort limit -20");
  const PfxJointConstraint& pushed = world.getJoint(leader.jointId).m_constraints[leader.axis];
  EXPECT_EQ(pushed.m_drive, kPfxJointDriveEffort);
  EXPECT_FLOAT_EQ(std::abs(pushed.m_driveTarget), 20);
  EXPECT_FLOAT_EQ(pushed.m_driveMaxForce, 20);
  ASSERT_EQ(pfxSetUrdfJointCommand(world, model, left, kPfxJointDrivePosition, 0.02f, 0, &note),
            PFX_OK);
  EXPECT_EQ(note, "");
  PfxFloat target = 0.01f;
  EXPECT_EQ(pfxClampUrdfJointTarget(leader, kPfxJointDrivePosition, target), target);

  // A refused command leaves the note empty.
  note = "stale";
  EXPECT_EQ(pfxSetUrdfJointCommand(world, model, right, kPfxJointDrivePosition, 0.1f, 0, &note),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(note, "");
}

// ---------------------------------------------------------------------------------------
// Placing a robot above the ground.

namespace {

// A free torso whose legs reach 1.0 m below its frame (feet spheres of radius 0.05).
const std::string kStander =
    "<robot name=\"stander\">" +
    massiveLink("torso", collision("<box size=\"0.3 0.2 0.4\"/>"), 10) +
    massiveLink("leg",
                collision("<cylinder radius=\"0.04\" length=\"0.9\"/>", "xyz=\"0 0 -0.45\"") +
                    collision("<sphere radius=\"0.05\"/>", "xyz=\"0 0 -0.95\""),
                3) +
    R"(<joint name="hip" type="revolute"><parent link="torso"/><child link="leg"/>
    <origin xyz="0 0 -0.2"/><axis xyz="0 1 0"/><limit lower="-0.5" upper="0.5" effort="100" velocity="2"/></joint>
</robot>)";

}  // namespace

TEST(UrdfInputs, PlacedAboveTheGroundTheLowestShapeStartsAtTheClearance) {
  for (const bool fixedBase : {false, true}) {
    SCOPED_TRACE(fixedBase ? "fixed base" : "free");
    // As the URDF places it, the legs are in the ground.
    PfxWorld asGiven;
    initZUpWorld(asGiven);
    PfxUrdfModel model;
    PfxUrdfLoadParam param;
    param.fixedBase = fixedBase;
    param.rootPosition = PfxVector3(1, 2, 0);
    ASSERT_NO_FATAL_FAILURE(loadText(asGiven, kStander, param, model));
    EXPECT_NEAR(pfxGetUrdfLowestPoint(asGiven, model), -1.2, 1e-5);

    param.placeAboveGround = true;
    param.groundHeight = 0.25f;
    param.groundClearance = 0.05f;
    param.rootOrientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f, PfxVector3(1, 0, 0)));
    PfxWorld world;
    initZUpWorld(world);
    addGround(world);
    PfxUrdfModel placed;
    ASSERT_NO_FATAL_FAILURE(loadText(world, kStander, param, placed));
    EXPECT_NEAR(pfxGetUrdfLowestPoint(world, placed), 0.3, 1e-5);
    const PfxTransform3 torso = pfxGetUrdfLinkPose(world, linkNamed(placed, "torso"));
    EXPECT_NEAR(torso.translation().x(), 1, 1e-5);  // x and y as asked
    EXPECT_NEAR(torso.translation().y(), 2, 1e-5);
    EXPECT_TRUE(torso.linear().isApprox(param.rootOrientation.toRotationMatrix(), 1e-5f));
    EXPECT_EQ(placed.fixedBase, fixedBase);
  }
  // Dropped 5 cm onto the ground at z = 0, a free robot lands on it, not in it.
  PfxWorld world;
  initZUpWorld(world);
  addGround(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.placeAboveGround = true;
  ASSERT_NO_FATAL_FAILURE(loadText(world, kStander, param, model));
  EXPECT_NEAR(pfxGetUrdfLowestPoint(world, model), 0.05, 1e-5);
  ASSERT_NO_FATAL_FAILURE(step(world, 1));
  EXPECT_GT(pfxGetUrdfLowestPoint(world, model), -0.01f);
  EXPECT_LT(world.getStats().maxPenetration, 0.01f);

  // Non-finite heights are refused and nothing is added.
  param.groundClearance = std::numeric_limits<PfxFloat>::quiet_NaN();
  PfxWorld empty;
  initZUpWorld(empty);
  PfxUrdfModel none;
  std::string message;
  EXPECT_EQ(pfxLoadUrdfString(empty, kStander, ".", param, none, &message), PFX_ERR_INVALID_VALUE);
  EXPECT_NE(message.find("groundHeight and groundClearance must be finite"), std::string::npos)
      << message;
  EXPECT_EQ(empty.getNumRigidBodies(), 0u);
}

// ---------------------------------------------------------------------------------------
// Links that overlap where the robot starts.

namespace {

// A fixed palm; two fingers on sliders whose boxes cross each other's at zero (a closed
// gripper drawn with its fingertips overlapping); a wrist chain whose hand, two hinges
// below the forearm, reaches back into it; and a massless ankle helper between a shank and
// a foot that overlap.
const std::string kOverlapping =
    "<robot name=\"overlapping\">" +
    massiveLink("palm", collision("<box size=\"0.1 0.1 0.04\"/>")) +
    massiveLink("left", collision("<box size=\"0.02 0.03 0.08\"/>", "xyz=\"0 -0.005 0.06\""), 0.1) +
    massiveLink("right", collision("<box size=\"0.02 0.03 0.08\"/>", "xyz=\"0 0.005 0.06\""), 0.1) +
    massiveLink("wrist", collision("<sphere radius=\"0.01\"/>"), 0.2) +
    massiveLink("hand", collision("<box size=\"0.06 0.06 0.1\"/>", "xyz=\"0 0 0.02\""), 0.5) +
    "<link name=\"ankle_helper\"/>" +
    massiveLink("foot", collision("<box size=\"0.1 0.1 0.1\"/>"), 0.5) +
    R"(<joint name="left_finger" type="prismatic"><parent link="palm"/><child link="left"/>
    <origin xyz="0 0.01 0"/><axis xyz="0 1 0"/><limit lower="-0.01" upper="0.04" effort="5" velocity="1"/></joint>
  <joint name="right_finger" type="prismatic"><parent link="palm"/><child link="right"/>
    <origin xyz="0 -0.01 0"/><axis xyz="0 -1 0"/><limit lower="-0.01" upper="0.04" effort="5" velocity="1"/></joint>
  <joint name="wrist_pitch" type="revolute"><parent link="palm"/><child link="wrist"/>
    <origin xyz="0.06 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="1"/></joint>
  <joint name="wrist_roll" type="revolute"><parent link="wrist"/><child link="hand"/>
    <origin xyz="0 0 0.03"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="5" velocity="1"/></joint>
  <joint name="ankle_pitch" type="revolute"><parent link="palm"/><child link="ankle_helper"/>
    <origin xyz="-0.07 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="5" velocity="1"/></joint>
  <joint name="ankle_roll" type="revolute"><parent link="ankle_helper"/><child link="foot"/>
    <origin xyz="0 0 0.04"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="5" velocity="1"/></joint>
</robot>)";

}  // namespace

TEST(UrdfInputs, LinksThatOverlapWhereTheRobotStartsAreNotPushedApart) {
  PfxWorld world;
  PfxWorldParam worldParam;
  worldParam.gravity = PfxVector3::Zero();  // only contacts could move anything
  worldParam.enableSleep = false;
  ASSERT_EQ(world.initialize(worldParam), PFX_OK);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.fixedBase = true;
  ASSERT_NO_FATAL_FAILURE(loadText(world, kOverlapping, param, model));
  ASSERT_NO_FATAL_FAILURE(step(world, 1));
  std::vector<double> q, v;
  pfxGetUrdfJointStates(world, model, q, v);
  for (std::size_t j = 0; j < q.size(); ++j) {
    EXPECT_NEAR(q[j], 0, 1e-4) << model.joints[j].name;
    EXPECT_NEAR(v[j], 0, 1e-4) << model.joints[j].name;
  }
  EXPECT_LT(world.getStats().maxPenetration, 1e-4f);  // no overlapping pair is in contact
  // Pairs joined through a joint or a light helper body are not listed: they never collide.
  EXPECT_TRUE(hasWarningWith(model,
                             "links that overlap where the robot starts never collide with each "
                             "other: 'palm' and 'hand' (0.02 m), 'left' and 'right' (0.02 m)\n"))
      << allWarnings(model);

  // Links that do not overlap at the start still collide: the hand put onto the foot meets it.
  const PfxUInt32 hand = linkNamed(model, "hand").bodyId;
  PfxRigidState state = world.getRigidState(hand);
  state.setPosition(world.getRigidState(linkNamed(model, "foot").bodyId).getPosition() +
                    PfxVector3(0, 0, 0.05f));
  ASSERT_EQ(world.setRigidState(hand, state), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_GT(world.getStats().maxPenetration, 0.01f);
}

// ---------------------------------------------------------------------------------------
// bullet3's humanoid (urdf/zoo), written for Bullet: capsule limbs and ankles of two hinges
// 4 cm apart through massless links. It loads whole, and stands dropped onto the ground.

TEST(UrdfInputs, BulletsHumanoidKeepsItsCapsulesAndItsOffsetAnkles) {
  PfxWorld world;
  initZUpWorld(world);
  addGround(world);
  PfxUrdfModel model;
  PfxUrdfLoadParam param;
  param.placeAboveGround = true;
  std::string message;
  ASSERT_EQ(pfxLoadUrdfFile(world, std::string(PFX_SOURCE_DIR) + "/urdf/zoo/humanoid.urdf", param,
                            model, &message),
            PFX_OK)
      << message;
  PfxUInt32 capsules = 0;
  for (PfxUInt32 b = model.firstBodyId; b < model.firstBodyId + model.numBodies; ++b) {
    const PfxCollidable& collidable = world.getCollidable(b);
    for (PfxUInt32 s = 0; s < collidable.getNumShapes(); ++s) {
      capsules += collidable.getShape(s).getType() == kPfxShapeCapsule;
    }
  }
  EXPECT_EQ(capsules, 16u);  // every <capsule> of the file
  EXPECT_FALSE(hasWarningWith(model, "left out")) << allWarnings(model);
  for (const char* helper : {"link1_13", "link1_22"}) {
    EXPECT_TRUE(hasWarningWith(model, std::string("link '") + helper + "': no mass, and joints"))
        << allWarnings(model);
  }
  ASSERT_NO_FATAL_FAILURE(step(world, 1));
  EXPECT_GT(pfxGetUrdfLowestPoint(world, model), -0.02f);
  EXPECT_LT(world.getStats().maxJointGap, 0.01f);
}
