// The pfx scene XML loader: the README's example scene loads into what it says and does what
// its comments promise (resting heights, a bounce, a hinge on its limit, a driven slider,
// geared hinges, filters, motion types); every kind of bad input is refused with its file,
// line, element and reason, and leaves the world as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_scene_loader.h"
#include "pfx_scene_test_util.h"

using namespace pfx;
using pfx_test::addMarker;
using pfx_test::body;
using pfx_test::joint;
using pfx_test::position;

namespace {

const std::string kData = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/";
const std::string kExample = kData + "scenes/example.xml";

// A scene around `inside`, with a ground box for joints and bodies to refer to.
std::string scene(const std::string& inside) {
  return "<?xml version=\"1.0\"?>\n<pfx_scene version=\"1\">\n"
         "<body name=\"ground\" motion=\"fixed\"><box size=\"10 10 1\"/></body>\n" +
         inside + "\n</pfx_scene>\n";
}

// Loads `xml` (see pfx_test::loadError); returns the message.
std::string loadError(const std::string& xml) {
  return pfx_test::loadError([&](PfxWorld& world, PfxSceneModel& model, std::string* message) {
    return pfxLoadSceneXmlString(world, xml, kData, PfxSceneLoadParam(), model, message);
  });
}

class ExampleScene : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
    std::string message;
    ASSERT_EQ(pfxLoadSceneXml(world, kExample, PfxSceneLoadParam(), model, &message), PFX_OK)
        << message;
  }
  void run(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / world.getParam().timeStep));
    for (int i = 0; i < steps; ++i) ASSERT_EQ(world.step(), PFX_OK);
  }
  PfxWorld world;
  PfxSceneModel model;
};

}  // namespace

TEST_F(ExampleScene, LoadsEveryPartWithItsNameAndPhysics) {
  EXPECT_EQ(model.name, "example");
  EXPECT_TRUE(model.physicsApplied);
  const PfxWorldParam& p = world.getParam();
  EXPECT_EQ(p.gravity, PfxVector3(0, 0, PfxFloat(-9.81)));
  EXPECT_NEAR(p.timeStep, 1.0 / 120, 1e-6);
  EXPECT_EQ(p.subStep, 2u);
  EXPECT_EQ(p.iteration, 10u);
  EXPECT_EQ(p.worldExtent, PfxVector3(50, 50, 50));
  EXPECT_EQ(model.numBodies, 23u);
  EXPECT_EQ(model.bodies.size(), 23u);
  EXPECT_EQ(model.numJoints, 8u);
  EXPECT_EQ(model.numCouplings, 1u);
  EXPECT_EQ(world.getNumRigidBodies(), 23u);
  EXPECT_TRUE(model.warnings.empty());
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    EXPECT_EQ(model.bodies[i].bodyId, model.firstBodyId + i);
  }

  const auto motion = [&](const std::string& name) {
    return world.getRigidState(body(model, name).bodyId).getMotionType();
  };
  EXPECT_EQ(motion("ground"), kPfxMotionTypeFixed);
  EXPECT_EQ(motion("box"), kPfxMotionTypeActive);
  EXPECT_EQ(motion("platform"), kPfxMotionTypeKeyframe);
  EXPECT_EQ(motion("rider"), kPfxMotionTypeOneWay);
  EXPECT_EQ(motion("sensor"), kPfxMotionTypeTrigger);

  const auto shape = [&](const std::string& name, PfxUInt32 i = 0) {
    return world.getCollidable(body(model, name).bodyId).getShape(i);
  };
  EXPECT_EQ(shape("box").getType(), kPfxShapeBox);
  EXPECT_EQ(shape("box").getBox().m_half, PfxVector3::Constant(0.25f));
  EXPECT_EQ(shape("sphere").getType(), kPfxShapeSphere);
  EXPECT_EQ(shape("capsule").getType(), kPfxShapeCapsule);
  EXPECT_FLOAT_EQ(shape("capsule").getCapsule().m_halfLen, 0.3f);
  EXPECT_EQ(shape("cylinder").getType(), kPfxShapeCylinder);
  EXPECT_EQ(shape("hull").getType(), kPfxShapeConvexMesh);
  EXPECT_EQ(shape("platform").getType(), kPfxShapeLargeTriMesh);
  EXPECT_EQ(model.convexMeshes.size(), 1u);
  EXPECT_EQ(model.largeMeshes.size(), 1u);
  const PfxCollidable& dumbbell = world.getCollidable(body(model, "dumbbell").bodyId);
  ASSERT_EQ(dumbbell.getNumShapes(), 3u);
  EXPECT_EQ(dumbbell.getShape(2).getOffsetPosition(), PfxVector3(0.5f, 0, 0));

  const PfxRigidBody& bar = world.getRigidBody(body(model, "dumbbell").bodyId);
  EXPECT_FLOAT_EQ(bar.getMass(), 2);
  EXPECT_FLOAT_EQ(bar.getInertia()(1, 1), 0.2f);
  const PfxRigidBody& ball = world.getRigidBody(body(model, "ball").bodyId);
  EXPECT_FLOAT_EQ(ball.getFriction(), 0.9f);
  EXPECT_FLOAT_EQ(ball.getRestitution(), 0.6f);
  // Inertia from the shape when the file gives none: a 1 kg, 0.5 m cube has m a^2 / 6.
  EXPECT_NEAR(world.getRigidBody(body(model, "box").bodyId).getInertia()(0, 0), 0.25 / 6, 1e-6);
  const PfxRigidState& ghost = world.getRigidState(body(model, "ghost_a").bodyId);
  EXPECT_EQ(ghost.getContactFilterSelf(), 2u);
  EXPECT_EQ(ghost.getContactFilterTarget(), 1u);

  const PfxJoint& hinge = world.getJoint(joint(model, "hinge").jointId);
  EXPECT_EQ(hinge.m_type, kPfxJointHinge);
  EXPECT_FLOAT_EQ(hinge.m_constraints[kPfxJointAxisTwist].m_movableUpperLimit, 1);
  const PfxJoint& rail = world.getJoint(joint(model, "rail").jointId);
  EXPECT_EQ(rail.m_constraints[kPfxJointAxisX].m_drive, kPfxJointDriveVelocity);
  EXPECT_FLOAT_EQ(rail.m_constraints[kPfxJointAxisX].m_driveMaxForce, 100);
  EXPECT_EQ(world.getJoint(joint(model, "socket").jointId).m_type, kPfxJointBall);
  EXPECT_EQ(world.getJoint(joint(model, "shoulder").jointId).m_type, kPfxJointSwingTwist);
  EXPECT_EQ(world.getJoint(joint(model, "weld_joint").jointId).m_type, kPfxJointFixed);
  EXPECT_EQ(world.getJoint(joint(model, "cardan").jointId).m_type, kPfxJointUniversal);
  EXPECT_EQ(joint(model, "cardan").axes[1], PfxUInt32(kPfxJointAxisSwing2));
  const PfxJointCoupling& gearing = world.getJointCoupling(model.couplings[0].couplingId);
  EXPECT_FLOAT_EQ(gearing.m_multiplier, -2);
  EXPECT_EQ(gearing.m_followerJointId, joint(model, "gear_b_axle").jointId);
}

TEST_F(ExampleScene, DoesWhatItsCommentsSay) {
  double ballTop = 0;
  bool ballLanded = false;
  const PfxFloat dt = world.getParam().timeStep;
  for (int i = 0; i < static_cast<int>(3 / dt); ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    const double z = position(world, model, "ball").z();
    ballLanded = ballLanded || z < 0.12;
    if (ballLanded) ballTop = std::max(ballTop, z);
  }
  // Resting heights (contact slop 5 mm).
  EXPECT_NEAR(position(world, model, "box").z(), 0.25, 0.01);
  EXPECT_NEAR(position(world, model, "sphere").z(), 0.2, 0.01);
  EXPECT_NEAR(position(world, model, "capsule").z(), 0.15, 0.01);
  EXPECT_NEAR(position(world, model, "cylinder").z(), 0.2, 0.01);
  EXPECT_NEAR(position(world, model, "hull").z(), 0.2, 0.01);
  EXPECT_NEAR(position(world, model, "dumbbell").z(), 0.25, 0.01);
  EXPECT_NEAR(position(world, model, "rider").z(), 0.75, 0.01);
  // The ball came back up: restitution 0.6 from 2 m gives about 0.36^... well above 0.3 m.
  EXPECT_GT(ballTop, 0.3);
  // The ghosts overlap and stay so, each on the ground.
  EXPECT_NEAR(position(world, model, "ghost_a").z(), 0.25, 0.01);
  EXPECT_NEAR(position(world, model, "ghost_b").z(), 0.25, 0.01);
  EXPECT_LT((position(world, model, "ghost_a") - position(world, model, "ghost_b")).norm(), 0.45);
  // The trigger and the keyframe platform stay where they were put.
  EXPECT_EQ(position(world, model, "sensor"), PfxVector3(0, 0, 1));
  EXPECT_EQ(position(world, model, "platform"), PfxVector3(6, 0, -0.5f));
  // The pendulum fell 1 rad to its limit and rests there.
  EXPECT_NEAR(std::abs(pfxGetSceneJointPosition(world, joint(model, "hinge"))), 1.0, 0.02);
  // The cart rides at the drive's 0.5 m/s: 1.5 m in 3 s.
  EXPECT_NEAR(pfxGetSceneJointPosition(world, joint(model, "rail")), 1.5, 0.05);
  // The weld holds its box above the post; the ball and cone bobs hang below theirs.
  EXPECT_NEAR(position(world, model, "weld").z(), 2.3, 0.005);
  EXPECT_NEAR(position(world, model, "bob").z(), 1.0, 0.005);
  EXPECT_NEAR(position(world, model, "cone_bob").z(), 1.0, 0.005);
  EXPECT_NEAR(position(world, model, "cross").z(), 1.0, 0.005);
  // Gear a turns at its drive's 1 rad/s (3 rad, wrapped to (-pi, pi]), gear b at -2 times.
  const PfxFloat a = pfxGetSceneJointPosition(world, joint(model, "gear_a_axle"));
  const PfxFloat b = pfxGetSceneJointPosition(world, joint(model, "gear_b_axle"));
  EXPECT_NEAR(a, 3.0, 0.05);
  EXPECT_NEAR(std::remainder(b + 2 * a, 2 * PFX_PI), 0.0, 0.02);
}

TEST(SceneXml, TheFileEntryPointPicksTheReaderFromTheRootElement) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  ASSERT_EQ(pfxLoadSceneFile(world, kExample, PfxSceneLoadParam(), model, &message), PFX_OK)
      << message;
  EXPECT_EQ(model.name, "example");
  PfxWorld other;
  ASSERT_EQ(other.initialize(PfxWorldParam()), PFX_OK);
  EXPECT_NE(
      pfxLoadSceneFile(other, kData + "pfx_sim_arm.urdf", PfxSceneLoadParam(), model, &message),
      PFX_OK);
  EXPECT_NE(message.find("root element <robot> is neither <pfx_scene> nor <sdf>"),
            std::string::npos)
      << message;
  EXPECT_EQ(other.getNumRigidBodies(), 0u);
}

TEST(SceneXml, PhysicsAreReportedButNotAppliedToAWorldThatHoldsBodies) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  addMarker(world);
  PfxSceneModel model;
  std::string message;
  ASSERT_EQ(pfxLoadSceneXml(world, kExample, PfxSceneLoadParam(), model, &message), PFX_OK)
      << message;
  EXPECT_FALSE(model.physicsApplied);
  EXPECT_EQ(model.worldParam.gravity, PfxVector3(0, 0, PfxFloat(-9.81)));
  EXPECT_EQ(world.getParam().gravity, PfxWorldParam().gravity);
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_NE(model.warnings[0].find("physics: not applied"), std::string::npos);
  EXPECT_EQ(model.firstBodyId, 1u);
  EXPECT_EQ(body(model, "ground").bodyId, 1u);
  // And with applyPhysics off an empty world keeps its parameters.
  PfxWorld empty;
  ASSERT_EQ(empty.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneLoadParam keep;
  keep.applyPhysics = false;
  ASSERT_EQ(pfxLoadSceneXml(empty, kExample, keep, model, &message), PFX_OK) << message;
  EXPECT_EQ(empty.getParam().gravity, PfxWorldParam().gravity);
  EXPECT_FALSE(model.physicsApplied);
}

TEST(SceneXml, AMissingFileIsRefused) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  EXPECT_EQ(pfxLoadSceneXml(world, kData + "scenes/none.xml", PfxSceneLoadParam(), model, &message),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(message, kData + "scenes/none.xml: cannot be read (no such file)");
  EXPECT_EQ(world.getNumRigidBodies(), 0u);
}

struct BadInput {
  const char* what;
  std::string xml;
  const char* message;  // how the message goes on after "<scene string>:"
};

class SceneXmlBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(SceneXmlBadInput, IsRefusedWithItsLineElementAndReasonAndChangesNothing) {
  const std::string message = loadError(GetParam().xml);
  const std::string expected = std::string("<scene string>:") + GetParam().message;
  // The whole message, but for XML syntax errors, whose wording after the line is tinyxml2's.
  if (expected.back() == '(') {
    EXPECT_EQ(message.rfind(expected, 0), 0u) << GetParam().what << ": " << message;
  } else {
    EXPECT_EQ(message, expected) << GetParam().what;
  }
}

INSTANTIATE_TEST_SUITE_P(
    All, SceneXmlBadInput,
    ::testing::Values(
        BadInput{"malformed", "<pfx_scene version=\"1\"><body name=\"a\"></pfx_scene>",
                 "1: not well-formed XML ("},
        // Found by fuzz_scene: a declaration alone parses and has no root element.
        BadInput{"no element", "<?xml version=\"1.0\"?>", "1: no element (a <pfx_scene> root)"},
        BadInput{"wrong root", "<robot name=\"r\"/>",
                 "1: robot 'r': the root element must be <pfx_scene>"},
        BadInput{"no version", "<pfx_scene/>",
                 "1: pfx_scene: version must be \"1\" (the only version of the format)"},
        BadInput{"unknown element", scene("<bdy name=\"x\"/>"),
                 "4: bdy 'x': unknown element (a scene holds world, material, body, joint, "
                 "coupling)"},
        BadInput{"unknown attribute", scene("<body name=\"b\" mass=\"1\" fricton=\"1\"/>"),
                 "4: body 'b': unknown attribute 'fricton'"},
        BadInput{"NaN mass", scene("<body name=\"b\" mass=\"nan\"><sphere radius=\"1\"/></body>"),
                 "4: body 'b': mass=\"nan\": expected 1 finite number"},
        BadInput{"beyond double's range",
                 scene("<body name=\"b\" mass=\"1e400\"><sphere radius=\"1\"/></body>"),
                 "4: body 'b': mass=\"1e400\": expected 1 finite number"},
        BadInput{"infinite position",
                 scene("<body name=\"b\" mass=\"1\" position=\"0 inf 0\"><sphere "
                       "radius=\"1\"/></body>"),
                 "4: body 'b': position=\"0 inf 0\": expected 3 finite numbers"},
        BadInput{"short vector", scene("<world gravity=\"0 -9.8\"/>"),
                 "4: world: gravity=\"0 -9.8\": expected 3 finite numbers"},
        BadInput{"trailing text", scene("<world gravity=\"0 0 -9.8 1\"/>"),
                 "4: world: gravity=\"0 0 -9.8 1\": expected 3 numbers, found more text"},
        BadInput{"negative mass",
                 scene("<body name=\"b\" mass=\"-1\"><sphere radius=\"1\"/></body>"),
                 "4: body 'b': mass must be positive"},
        BadInput{"missing mass", scene("<body name=\"b\"><sphere radius=\"1\"/></body>"),
                 "4: body 'b': an active or one_way body needs a mass"},
        BadInput{
            "mass on a fixed body",
            scene("<body name=\"b\" motion=\"fixed\" mass=\"1\"><sphere radius=\"1\"/></body>"),
            "4: body 'b': mass and inertia apply only to active and one_way bodies"},
        BadInput{"restitution above 1",
                 scene("<body name=\"b\" mass=\"1\" restitution=\"1.5\"><sphere "
                       "radius=\"1\"/></body>"),
                 "4: body 'b': restitution must lie in [0, 1]"},
        BadInput{"negative friction", scene("<material name=\"m\" friction=\"-0.1\"/>"),
                 "4: material 'm': friction must be >= 0"},
        BadInput{"unknown material",
                 scene("<body name=\"b\" mass=\"1\" material=\"steel\"><sphere "
                       "radius=\"1\"/></body>"),
                 "4: body 'b': material 'steel' is not defined above the body"},
        BadInput{"unknown motion",
                 scene("<body name=\"b\" motion=\"static\"><sphere radius=\"1\"/></body>"),
                 "4: body 'b': motion=\"static\": expected active, fixed, keyframe, one_way or "
                 "trigger"},
        BadInput{"duplicate body", scene("<body name=\"ground\" motion=\"fixed\"/>"),
                 "4: body 'ground': a body of that name already exists"},
        BadInput{"no shape", scene("<body name=\"b\" mass=\"1\"/>"),
                 "4: body 'b': a body needs at least one shape"},
        BadInput{"zero radius", scene("<body name=\"b\" mass=\"1\"><sphere radius=\"0\"/></body>"),
                 "4: sphere: radius must be positive"},
        BadInput{"unknown shape", scene("<body name=\"b\" mass=\"1\"><cone/></body>"),
                 "4: cone: unknown shape (sphere, box, capsule, cylinder, convex_mesh, "
                 "large_mesh)"},
        BadInput{"not a unit quaternion",
                 scene("<body name=\"b\" mass=\"1\" quat=\"2 0 0 0\"><sphere "
                       "radius=\"1\"/></body>"),
                 "4: body 'b': quat is not a unit quaternion (length 2.000000)"},
        BadInput{"rpy and quat",
                 scene("<body name=\"b\" mass=\"1\" rpy=\"0 0 0\" quat=\"1 0 0 0\"><sphere "
                       "radius=\"1\"/></body>"),
                 "4: body 'b': give rpy or quat, not both"},
        BadInput{"inertia not positive definite",
                 scene("<body name=\"b\" mass=\"1\" inertia=\"1 1 -1 0 0 0\"><sphere "
                       "radius=\"1\"/></body>"),
                 "4: body 'b': inertia (ixx iyy izz ixy ixz iyz) or mass: inertia not positive "
                 "definite"},
        BadInput{"large mesh on an active body",
                 scene("<body name=\"b\" mass=\"1\"><large_mesh file=\"cube.stl\"/></body>"),
                 "4: large_mesh: a large mesh has no volume, so only a body that forces do not "
                 "move (fixed, keyframe, trigger) may hold one; use convex_mesh"},
        BadInput{"filter out of range",
                 scene("<body name=\"b\" mass=\"1\" filter_self=\"0x100000000\"><sphere "
                       "radius=\"1\"/></body>"),
                 "4: body 'b': filter_self=\"0x100000000\": expected a whole number in [0, "
                 "4294967295]"},
        BadInput{"zero sub-steps", scene("<world sub_steps=\"0\"/>"),
                 "4: world: sub_steps=\"0\": expected a whole number in [1, 100]"},
        BadInput{"too many iterations", scene("<world iterations=\"1001\"/>"),
                 "4: world: iterations=\"1001\": expected a whole number in [1, 1000]"},
        BadInput{"NaN time step", scene("<world time_step=\"nan\"/>"),
                 "4: world: time_step=\"nan\": expected 1 finite number"},
        BadInput{"negative time step", scene("<world time_step=\"-0.01\"/>"),
                 "4: world: time_step must be positive"},
        BadInput{"two worlds", scene("<world/><world/>"), "4: world: a scene has one <world>"},
        BadInput{"unknown pipeline", scene("<world pipeline=\"fast\"/>"),
                 "4: world: pipeline=\"fast\": expected stable or simple"},
        BadInput{"unknown joint body",
                 scene("<joint name=\"j\" type=\"hinge\" body_a=\"ground\" body_b=\"arm\"/>"),
                 "4: joint 'j': body_b 'arm' is not a body defined above"},
        BadInput{"unknown joint type",
                 scene("<joint name=\"j\" type=\"screw\" body_a=\"ground\" body_b=\"ground\"/>"),
                 "4: joint 'j': type must be ball, swing_twist, hinge, slider, fixed or "
                 "universal"},
        BadInput{"joint to itself",
                 scene("<joint name=\"j\" type=\"hinge\" body_a=\"ground\" body_b=\"ground\"/>"),
                 "4: joint 'j': body_a and body_b are the same body"},
        BadInput{"zero axis",
                 scene("<body name=\"b\" mass=\"1\"><sphere radius=\"1\"/></body>"
                       "<joint name=\"j\" type=\"hinge\" body_a=\"ground\" body_b=\"b\" "
                       "axis=\"0 0 0\"/>"),
                 "4: joint 'j': axis has no direction"},
        BadInput{"limits crossed",
                 scene("<body name=\"b\" mass=\"1\"><sphere radius=\"1\"/></body>\n"
                       "<joint name=\"j\" type=\"hinge\" body_a=\"ground\" body_b=\"b\">"
                       "<axis index=\"twist\" lower=\"1\" upper=\"-1\"/></joint>"),
                 "5: axis: lower is above upper"},
        BadInput{"damping above 1",
                 scene("<body name=\"b\" mass=\"1\"><sphere radius=\"1\"/></body>\n"
                       "<joint name=\"j\" type=\"hinge\" body_a=\"ground\" body_b=\"b\">"
                       "<axis index=\"twist\" damping=\"2\"/></joint>"),
                 "5: axis: damping must lie in [0, 1]"},
        BadInput{"unknown axis",
                 scene("<body name=\"b\" mass=\"1\"><sphere radius=\"1\"/></body>\n"
                       "<joint name=\"j\" type=\"hinge\" body_a=\"ground\" body_b=\"b\">"
                       "<axis index=\"w\"/></joint>"),
                 "5: axis: index must be x, y, z, twist, swing1 or swing2"},
        BadInput{"coupling on a locked axis",
                 scene("<body name=\"b\" mass=\"1\"><sphere radius=\"1\"/></body>\n"
                       "<joint name=\"j\" type=\"hinge\" body_a=\"ground\" body_b=\"b\"/>\n"
                       "<coupling name=\"c\" leader=\"j\" leader_axis=\"twist\" "
                       "follower=\"j\" follower_axis=\"x\"/>"),
                 "6: coupling 'c': an axis is locked, or leader and follower are the same axis"},
        BadInput{"coupling to an unknown joint",
                 scene("<coupling name=\"c\" leader=\"j\" leader_axis=\"twist\" follower=\"j\" "
                       "follower_axis=\"twist\"/>"),
                 "4: coupling 'c': leader must name a joint defined above"}));

// The missing mesh's message names the file the loader looked for; checked apart since it
// holds the data folder's absolute path.
TEST(SceneXml, AMissingMeshNamesTheFile) {
  const std::string message =
      loadError(scene("<body name=\"b\" mass=\"1\"><convex_mesh file=\"none.stl\"/></body>"));
  EXPECT_EQ(message.rfind("<scene string>:4: convex_mesh: " + kData + "none.stl: ", 0), 0u)
      << message;
}

// The README's small example scene, read from the README itself so that the two never part:
// the crate lands and rests, the motor opens the door at 0.5 rad/s up to its 1.6 rad limit.
TEST(SceneXml, TheReadmeExampleDoesWhatTheReadmeSays) {
  std::ifstream in(std::string(PFX_SOURCE_DIR) + "/README.md");
  std::stringstream readme;
  readme << in.rdbuf();
  const std::string text = readme.str();
  const std::size_t begin =
      text.find("<?xml version=\"1.0\"?>\n<pfx_scene version=\"1\" name=\"door\">");
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = text.find("```", begin);
  ASSERT_NE(end, std::string::npos);
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  ASSERT_EQ(pfxLoadSceneXmlString(world, text.substr(begin, end - begin), kData,
                                  PfxSceneLoadParam(), model, &message),
            PFX_OK)
      << message;
  const PfxFloat dt = world.getParam().timeStep;
  for (int i = 0; i < static_cast<int>(std::lround(2 / dt)); ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(pfxGetSceneJointPosition(world, joint(model, "hinge")), 1.0, 0.05);
  EXPECT_NEAR(position(world, model, "crate").z(), 0.2, 0.01);
  for (int i = 0; i < static_cast<int>(std::lround(3 / dt)); ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(pfxGetSceneJointPosition(world, joint(model, "hinge")), 1.6, 0.02);
}
