// The SDFormat loader on real Gazebo worlds (tests/loaders/data/sdf, with their licences and
// origin in its README): each world does what its README says a physics engine should do
// with it (resting heights, a pendulum's period, joints that hold), not only loads. Then
// every joint type on small worlds written here, model:// resolution, and bad input, each
// refused with its line, element and reason and the world left as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_scene_loader.h"
#include "pfx_scene_test_util.h"

using namespace pfx;
using pfx_test::body;
using pfx_test::joint;
using pfx_test::position;

namespace {

const std::string kSdf = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/sdf/";

bool hasWarning(const PfxSceneModel& model, const std::string& text) {
  for (const std::string& warning : model.warnings) {
    if (warning.find(text) != std::string::npos) return true;
  }
  return false;
}

std::string allWarnings(const PfxSceneModel& model) {
  std::string all;
  for (const std::string& warning : model.warnings) all += warning + "\n";
  return all;
}

PfxSceneLoadParam withModels() {
  PfxSceneLoadParam param;
  param.modelPaths.push_back(kSdf + "models");
  return param;
}

class SdfWorld : public ::testing::Test {
 protected:
  void load(const std::string& file) {
    PfxWorldParam param;
    param.enableSleep = false;  // the tests measure motion over seconds
    ASSERT_EQ(world.initialize(param), PFX_OK);
    std::string message;
    ASSERT_EQ(pfxLoadSdfWorld(world, kSdf + "worlds/" + file, withModels(), model, &message),
              PFX_OK)
        << message;
    ASSERT_TRUE(model.physicsApplied);
  }
  void run(double seconds) {
    const int steps = static_cast<int>(std::lround(seconds / world.getParam().timeStep));
    for (int i = 0; i < steps; ++i) ASSERT_EQ(world.step(), PFX_OK);
  }
  PfxWorld world;
  PfxSceneModel model;
};

// The smallest SDF world around `models`.
std::string sdfWorld(const std::string& models) {
  return "<?xml version=\"1.0\"?>\n<sdf version=\"1.7\"><world name=\"w\">\n" + models +
         "\n</world></sdf>\n";
}

// A link of a 1 kg, 0.2 m cube at `pose` (model frame), with `inside` added.
std::string cubeLink(const std::string& name, const std::string& pose,
                     const std::string& inside = "") {
  return "<link name=\"" + name + "\"><pose>" + pose +
         "</pose><inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz>"
         "</inertia></inertial><collision name=\"c\"><geometry><box><size>0.2 0.2 0.2</size>"
         "</box></geometry></collision>" +
         inside + "</link>";
}

// Loads `sdf` (see pfx_test::loadError); returns the message.
std::string loadError(const std::string& sdf) {
  return pfx_test::loadError([&](PfxWorld& world, PfxSceneModel& model, std::string* message) {
    return pfxLoadSdfString(world, sdf, withModels(), model, message);
  });
}

}  // namespace

TEST_F(SdfWorld, ShapesRestOnTheGroundPlaneWithTheSdfDefaults) {
  load("shapes.world");
  EXPECT_EQ(world.getParam().gravity, PfxVector3(0, 0, PfxFloat(-9.8)));
  EXPECT_FLOAT_EQ(world.getParam().timeStep, 0.001f);
  // ground_plane's link, and the three shapes; the sun is only a light.
  EXPECT_EQ(model.bodies.size(), 4u);
  EXPECT_GE(pfxFindSceneBody(model, "ground_plane::link"), 0);
  const PfxRigidBody& box = world.getRigidBody(body(model, "box::link").bodyId);
  EXPECT_FLOAT_EQ(box.getMass(), 1);  // no <inertial>: 1 kg, I = identity
  EXPECT_TRUE(box.getInertia().isApprox(PfxMatrix3::Identity()));
  EXPECT_EQ(world.getCollidable(body(model, "cylinder::link").bodyId).getShape(0).getType(),
            kPfxShapeCylinder);
  // Every element the files set and pfx does not read is listed once.
  EXPECT_TRUE(hasWarning(model, "ignored <world/model/link/visual> (4 times)"))
      << allWarnings(model);
  EXPECT_TRUE(hasWarning(model, "ignored <world/light> (1 time)")) << allWarnings(model);
  EXPECT_TRUE(hasWarning(model, "mu 100 is used, mu2 50 is not")) << allWarnings(model);
  std::vector<std::string> sorted = model.warnings;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end());

  const PfxVector3 start[3] = {position(world, model, "box::link"),
                               position(world, model, "sphere::link"),
                               position(world, model, "cylinder::link")};
  run(3);
  const char* names[3] = {"box::link", "sphere::link", "cylinder::link"};
  for (int i = 0; i < 3; ++i) {
    const PfxVector3 p = position(world, model, names[i]);
    EXPECT_NEAR(p.z(), 0.5, 0.006) << names[i];
    EXPECT_LT((p - start[i]).head<2>().norm(), 0.005) << names[i];
    EXPECT_LT(world.getRigidState(body(model, names[i]).bodyId).getLinearVelocity().norm(), 0.01)
        << names[i];
  }
  // The cylinder still lies on its side, its axis along x.
  const PfxQuat q = world.getRigidState(body(model, "cylinder::link").bodyId).getOrientation();
  EXPECT_GT(std::abs((q * PfxVector3::UnitZ()).x()), 0.999);
}

TEST_F(SdfWorld, TheFiveBoxStackStandsStill) {
  load("box_stack.world");
  EXPECT_NEAR(world.getRigidBody(body(model, "box_1::link").bodyId).getInertia()(0, 0), 0.1666666,
              1e-6);
  run(5);
  for (int k = 0; k < 5; ++k) {
    const std::string name = "box_" + std::to_string(k + 1) + "::link";
    const PfxVector3 p = position(world, model, name);
    EXPECT_NEAR(p.z(), 0.5 + k, 0.01) << name;
    EXPECT_LE(p.z(), 0.5 + k + 1e-3) << name;
    EXPECT_LT(std::hypot(p.x(), p.y() - 1.5), 0.005) << name;
    const PfxQuat q = world.getRigidState(body(model, name).bodyId).getOrientation();
    EXPECT_LT(q.angularDistance(PfxQuat::Identity()), 0.005) << name;
  }
}

// The angle of a pendulum's centre of mass from the downward vertical, positive on the side
// it was released from.
struct Pendulum {
  PfxUInt32 bodyId;
  PfxVector3 pivot;
  PfxVector3 side;  // unit, horizontal, towards the release point
  double angle(const PfxWorld& world) const {
    const PfxVector3 d = world.getRigidState(bodyId).getPosition() - pivot;
    return std::atan2(double(d.dot(side)), double(-d.z())) * 180 / PFX_PI;
  }
};

TEST_F(SdfWorld, SimplePendulumsSwingWithTheKnownPeriod) {
  load("simple_pendulums.world");
  EXPECT_EQ(world.getParam().gravity, PfxVector3(0, 0, PfxFloat(-9.81)));
  EXPECT_FLOAT_EQ(world.getParam().timeStep, 0.001f);  // SDF 1.3's <ode><solver><dt>
  EXPECT_EQ(world.getParam().iteration, 1000u);        // its <iters>
  std::vector<Pendulum> pendulums;
  for (const char* name : {"model_1", "model_2", "model_3"}) {
    const PfxSceneJoint& pivot = joint(model, std::string(name) + "::joint_0");
    EXPECT_EQ(pivot.parent, "world");
    EXPECT_EQ(pivot.type, "revolute");
    const PfxJoint& j = world.getJoint(pivot.jointId);
    Pendulum p;
    // model_1's two links weigh the same: their middle is the pendulum's centre of mass.
    p.bodyId = body(model, std::string(name) + "::link_1").bodyId;
    p.pivot = world.getRigidState(j.m_rigidBodyIdA).getTransform() * j.m_anchorA;
    EXPECT_NEAR(p.pivot.z(), 10.1, 1e-4) << name;
    const PfxVector3 d = world.getRigidState(p.bodyId).getPosition() - p.pivot;
    p.side = PfxVector3(d.x(), d.y(), 0).normalized();
    pendulums.push_back(p);
  }
  // model_1: a weld of its two links by a revolute joint with lower = upper = 0; link_2's
  // frame in link_1's must not change.
  const PfxSceneBody& rod = body(model, "model_1::link_1");
  const PfxSceneBody& ball = body(model, "model_1::link_2");
  const auto ballInRod = [&] {
    return PfxTransform3(pfxGetSceneBodyFrame(world, rod).inverse() *
                         pfxGetSceneBodyFrame(world, ball));
  };
  const PfxTransform3 weld = ballInRod();
  EXPECT_TRUE(weld.translation().isApprox(PfxVector3(0, 0, -10), 1e-5f))
      << weld.translation().transpose();
  EXPECT_NEAR(pendulums[1].angle(world), 90, 0.01);
  EXPECT_NEAR(pendulums[2].angle(world), 90, 0.01);

  const double expectedAt[3] = {62.12, -10.24, -88.16};  // at 1, 2 and 4 s (README)
  const double dt = world.getParam().timeStep;
  double previous[3] = {90, 90, 90}, returnTime[3] = {0, 0, 0}, peak[3] = {0, 0, 0};
  const int steps = static_cast<int>(std::lround(8.0 / dt));
  for (int s = 1; s <= steps; ++s) {
    ASSERT_EQ(world.step(), PFX_OK);
    const double t = s * dt;
    for (int i = 0; i < 3; ++i) {
      const double a = pendulums[i].angle(world);
      if (s == 1000 || s == 2000 || s == 4000) {
        EXPECT_NEAR(a, expectedAt[s == 1000 ? 0 : (s == 2000 ? 1 : 2)], 1.0)
            << "model_" << i + 1 << " at " << t << " s";
      }
      // Back at the release side: the angle stops rising after 6 s.
      if (t > 6 && a < previous[i] && returnTime[i] == 0) {
        returnTime[i] = t - dt;
        peak[i] = previous[i];
      }
      previous[i] = a;
    }
    if (s % 500 == 0) {
      const PfxTransform3 now = ballInRod();
      EXPECT_LT((now.translation() - weld.translation()).norm(), 2e-3) << t << " s";
      EXPECT_LT(PfxQuat(now.linear()).angularDistance(PfxQuat(weld.linear())), 1e-3) << t << " s";
    }
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(returnTime[i], 7.488, 0.03) << "model_" << i + 1;
    EXPECT_NEAR(peak[i], 90.0, 1.0) << "model_" << i + 1;  // energy kept
  }
}

TEST_F(SdfWorld, AFixedJointToTheWorldHoldsItsLink) {
  load("fixed_joint.world");
  EXPECT_EQ(world.getParam().gravity, PfxVector3::Zero());  // <gravity> under <world>
  const PfxSceneJoint& weld = joint(model, "fixed_joint_test::world_to_base_joint");
  EXPECT_EQ(weld.parent, "world");
  EXPECT_EQ(weld.child, "fixed_joint_test::base_link");
  EXPECT_FLOAT_EQ(
      world.getRigidBody(body(model, "fixed_joint_test::base_link").bodyId).getInertia()(0, 1),
      0.01f);
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxRigidState& s = world.getRigidState(body(model, "fixed_joint_test::base_link").bodyId);
    ASSERT_EQ(s.getPosition(), PfxVector3(0, 0, 0.5f)) << "step " << i;
    ASSERT_EQ(s.getLinearVelocity(), PfxVector3::Zero()) << "step " << i;
  }
}

TEST_F(SdfWorld, ARevoluteJointWhoseParentIsTheUpperBodyHolds) {
  load("joints.world");
  const PfxSceneJoint& hinge = joint(model, "revolute_model::revolute_joint");
  EXPECT_EQ(hinge.parent, "revolute_model::body2");
  EXPECT_EQ(hinge.child, "revolute_model::body1");
  const PfxJoint& j = world.getJoint(hinge.jointId);
  const PfxVector3 anchor = world.getRigidState(j.m_rigidBodyIdA).getTransform() * j.m_anchorA;
  EXPECT_TRUE(anchor.isApprox(PfxVector3(0, 0, 1.5f), 1e-5f)) << anchor.transpose();
  // The hinge turns about the vertical.
  const PfxMatrix3 frame =
      world.getRigidState(j.m_rigidBodyIdA).getOrientation().toRotationMatrix() * j.m_frameA;
  EXPECT_NEAR(std::abs(frame.col(0).z()), 1, 1e-5);
  run(3);
  EXPECT_NEAR(position(world, model, "revolute_model::body1").z(), 0.5, 0.006);
  EXPECT_TRUE(
      position(world, model, "revolute_model::body2").isApprox(PfxVector3(0, 0.5f, 2.5f), 0.005f))
      << position(world, model, "revolute_model::body2").transpose();
  EXPECT_NEAR(pfxGetSceneJointPosition(world, hinge), 0, 0.01);
}

TEST_F(SdfWorld, FallingBoxesLandWhenTheyShouldAndComeToRestOnTheSlab) {
  load("falling_boxes.world");
  EXPECT_EQ(world.getParam().gravity, PfxVector3(0, 0, -10));
  EXPECT_FLOAT_EQ(world.getParam().timeStep, 0.001f);
  EXPECT_EQ(world.getRigidState(body(model, "model_ground::ground").bodyId).getMotionType(),
            kPfxMotionTypeFixed);
  EXPECT_FLOAT_EQ(world.getRigidBody(body(model, "model_ground::ground").bodyId).getFriction(),
                  0.5f);
  EXPECT_TRUE(hasWarning(model, "mu 0.5 is used, mu2 0.2 is not")) << allWarnings(model);
  const char* names[2] = {"model_box1::link_box1", "model_cylinder1::link_cylinder1"};
  const double contactTime[2] = {0.86693, 0.88322};  // README: first touch of z = 0.5
  double landed[2] = {0, 0};
  const double dt = world.getParam().timeStep;
  // The cylinder tumbles longest: it lies still on its side from about 6 s.
  for (int s = 1; s <= 7000; ++s) {
    ASSERT_EQ(world.step(), PFX_OK);
    for (int i = 0; i < 2; ++i) {
      const PfxRigidState& state = world.getRigidState(body(model, names[i]).bodyId);
      // Free fall gives -g t exactly; the first contact slows the body.
      if (landed[i] == 0 && state.getLinearVelocity().z() > -10 * s * dt + 0.05) {
        landed[i] = s * dt;
      }
    }
  }
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(landed[i], contactTime[i], 0.02) << names[i];
    const PfxRigidState& state = world.getRigidState(body(model, names[i]).bodyId);
    EXPECT_NEAR(state.getPosition().z(), 1.0, 0.01) << names[i];
    EXPECT_LT(state.getPosition().head<2>().cwiseAbs().maxCoeff(), 4.5) << names[i];
    EXPECT_LT(state.getLinearVelocity().norm(), 0.01) << names[i];
  }
}

TEST(SdfLoader, TheFileEntryPointReadsSdf) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  ASSERT_EQ(pfxLoadSceneFile(world, kSdf + "worlds/box_stack.world", withModels(), model, &message),
            PFX_OK)
      << message;
  EXPECT_EQ(model.bodies.size(), 6u);
  EXPECT_EQ(world.getParam().gravity, PfxVector3(0, 0, PfxFloat(-9.8)));
}

TEST(SdfLoader, AModelFileLoadsIntoTheWorldAsItIs) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  ASSERT_EQ(pfxLoadSdfWorld(world, kSdf + "models/ground_plane/model.sdf", PfxSceneLoadParam(),
                            model, &message),
            PFX_OK)
      << message;
  EXPECT_EQ(model.name, "ground_plane");
  ASSERT_EQ(model.bodies.size(), 1u);
  EXPECT_EQ(world.getRigidState(model.bodies[0].bodyId).getMotionType(), kPfxMotionTypeFixed);
  // A model has no physics: the world keeps its own.
  EXPECT_FALSE(model.physicsApplied);
  EXPECT_EQ(world.getParam().gravity, PfxWorldParam().gravity);
}

TEST(SdfLoader, ModelUrisResolveThroughGazeboModelPathAndSdfPath) {
  const std::string sdf = sdfWorld("<include><uri>model://ground_plane</uri></include>");
  for (const char* variable : {"GAZEBO_MODEL_PATH", "SDF_PATH"}) {
    PfxWorld world;
    ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
    PfxSceneModel model;
    std::string message;
    ASSERT_EQ(setenv(variable, (kSdf + "models").c_str(), 1), 0);
    EXPECT_EQ(pfxLoadSdfString(world, sdf, PfxSceneLoadParam(), model, &message), PFX_OK)
        << variable << ": " << message;
    unsetenv(variable);
    EXPECT_GE(pfxFindSceneBody(model, "ground_plane::link"), 0) << variable;
  }
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  EXPECT_NE(pfxLoadSdfString(world, sdf, PfxSceneLoadParam(), model, &message), PFX_OK);
  EXPECT_NE(message.find("model://ground_plane"), std::string::npos) << message;
  EXPECT_EQ(world.getNumRigidBodies(), 0u);
}

TEST(SdfLoader, EveryJointTypeBecomesItsPfxJoint) {
  const std::string models =
      "<model name=\"m\"><pose>0 0 5 0 0 0</pose>" + cubeLink("base", "0 0 0 0 0 0") +
      cubeLink("a", "1 0 0 0 0 0") + cubeLink("b", "2 0 0 0 0 0") + cubeLink("c", "3 0 0 0 0 0") +
      cubeLink("d", "4 0 0 0 0 0") + cubeLink("e", "5 0 0 0 0 0") + cubeLink("f", "6 0 0 0 0 0") +
      cubeLink("g", "7 0 0 0 0 0") +
      "<joint name=\"pin\" type=\"fixed\"><parent>world</parent><child>base</child></joint>"
      "<joint name=\"hinge\" type=\"revolute\"><parent>base</parent><child>a</child>"
      "<axis><xyz>0 1 0</xyz><limit><lower>-0.5</lower><upper>0.5</upper></limit>"
      "<dynamics><damping>2</damping><friction>0.1</friction></dynamics></axis></joint>"
      "<joint name=\"slide\" type=\"prismatic\"><parent>a</parent><child>b</child>"
      "<axis><xyz>1 0 0</xyz><limit><lower>-0.1</lower><upper>0.2</upper></limit></axis></joint>"
      "<joint name=\"spin\" type=\"continuous\"><parent>b</parent><child>c</child>"
      "<axis><xyz>1 0 0</xyz></axis></joint>"
      "<joint name=\"socket\" type=\"ball\"><parent>c</parent><child>d</child></joint>"
      "<joint name=\"cross\" type=\"universal\"><parent>d</parent><child>e</child>"
      "<axis><xyz>0 1 0</xyz></axis><axis2><xyz>0 0 1</xyz></axis2></joint>"
      "<joint name=\"wrist\" type=\"revolute2\"><parent>e</parent><child>f</child>"
      "<axis><xyz>0 1 0</xyz><limit><lower>-0.3</lower><upper>0.3</upper></limit></axis>"
      "<axis2><xyz>0 0 1</xyz></axis2></joint>"
      "<joint name=\"screw\" type=\"screw\"><parent>f</parent><child>g</child>"
      "<thread_pitch>-6.283185307</thread_pitch><axis><xyz>1 0 0</xyz></axis></joint>"
      "</model>";
  PfxWorld world;
  PfxWorldParam param;
  param.enableSleep = false;
  ASSERT_EQ(world.initialize(param), PFX_OK);
  PfxSceneModel model;
  std::string message;
  ASSERT_EQ(pfxLoadSdfString(world, sdfWorld(models), PfxSceneLoadParam(), model, &message), PFX_OK)
      << message;
  const auto type = [&](const char* name) {
    return world.getJoint(joint(model, std::string("m::") + name).jointId).m_type;
  };
  EXPECT_EQ(type("pin"), kPfxJointFixed);
  EXPECT_EQ(type("hinge"), kPfxJointHinge);
  EXPECT_EQ(type("slide"), kPfxJointSlider);
  EXPECT_EQ(type("spin"), kPfxJointHinge);
  EXPECT_EQ(type("socket"), kPfxJointBall);
  EXPECT_EQ(type("cross"), kPfxJointUniversal);
  EXPECT_EQ(type("wrist"), kPfxJointUniversal);
  EXPECT_EQ(type("screw"), kPfxJointCustom);
  const PfxJoint& hinge = world.getJoint(joint(model, "m::hinge").jointId);
  const PfxJointConstraint& twist = hinge.m_constraints[kPfxJointAxisTwist];
  EXPECT_EQ(twist.m_lock, kPfxJointLockLimit);
  EXPECT_FLOAT_EQ(twist.m_movableLowerLimit, -0.5f);
  EXPECT_FLOAT_EQ(twist.m_friction, 0.1f);
  EXPECT_GT(twist.m_damping, 0);
  EXPECT_LT(twist.m_damping, 1);
  const PfxJoint& slide = world.getJoint(joint(model, "m::slide").jointId);
  EXPECT_FLOAT_EQ(slide.m_constraints[kPfxJointAxisX].m_movableUpperLimit, 0.2f);
  EXPECT_EQ(
      world.getJoint(joint(model, "m::spin").jointId).m_constraints[kPfxJointAxisTwist].m_lock,
      kPfxJointLockFree);
  const PfxJoint& wrist = world.getJoint(joint(model, "m::wrist").jointId);
  EXPECT_EQ(wrist.m_rotation, kPfxJointRotationEulerYZX);
  EXPECT_FLOAT_EQ(wrist.m_constraints[kPfxJointAxisSwing1].m_movableUpperLimit, 0.3f);
  EXPECT_EQ(wrist.m_constraints[kPfxJointAxisSwing2].m_lock, kPfxJointLockFree);
  EXPECT_EQ(wrist.m_constraints[kPfxJointAxisTwist].m_lock, kPfxJointLockLocked);
  // The screw: one turn (thread_pitch -2 pi rad/m) advances 1 m along the axis. Spin link g
  // and let the coupling carry the slide.
  ASSERT_EQ(model.couplings.size(), 1u);
  const PfxSceneJoint& screw = joint(model, "m::screw");
  PfxRigidState g = world.getRigidState(body(model, "m::g").bodyId);
  g.setAngularVelocity(PfxVector3(2, 0, 0));
  ASSERT_EQ(world.setRigidState(body(model, "m::g").bodyId, g), PFX_OK);
  for (int i = 0; i < 200; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxFloat angle = pfxGetSceneJointPosition(world, screw, 0);
  const PfxFloat slideOut = pfxGetSceneJointPosition(world, screw, 1);
  EXPECT_GT(std::abs(angle), 0.05);
  EXPECT_NEAR(slideOut, angle / (2 * PFX_PI), 1e-3);
}

TEST(SdfLoader, AMissingFileIsRefused) {
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  EXPECT_EQ(
      pfxLoadSdfWorld(world, kSdf + "worlds/none.world", PfxSceneLoadParam(), model, &message),
      PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(message, kSdf + "worlds/none.world: cannot be read (no such file)");
  EXPECT_EQ(world.getNumRigidBodies(), 0u);
}

struct BadSdf {
  const char* what;
  std::string sdf;
  const char* message;  // how the message goes on after "<sdf string>:"
};

class SdfBadInput : public ::testing::TestWithParam<BadSdf> {};

TEST_P(SdfBadInput, IsRefusedWithItsLineElementAndReasonAndChangesNothing) {
  const std::string message = loadError(GetParam().sdf);
  const std::string expected = std::string("<sdf string>:") + GetParam().message;
  EXPECT_EQ(message.rfind(expected, 0), 0u) << GetParam().what << ": " << message;
}

INSTANTIATE_TEST_SUITE_P(
    All, SdfBadInput,
    ::testing::Values(
        BadSdf{"malformed", "<sdf version=\"1.7\"><world name=\"w\"></sdf>", " sdformat: "},
        BadSdf{"NaN mass",
               sdfWorld("<model name=\"m\"><link name=\"l\"><inertial><mass>nan</mass>"
                        "</inertial></link></model>"),
               " sdformat: A link named l has invalid inertia."},
        BadSdf{"negative mass",
               sdfWorld("<model name=\"m\"><link name=\"l\"><inertial><mass>-1</mass>"
                        "</inertial></link></model>"),
               " sdformat: A link named l has invalid inertia."},
        BadSdf{"inertia not positive definite",
               sdfWorld("<model name=\"m\"><link name=\"l\"><inertial><mass>1</mass><inertia>"
                        "<ixx>1</ixx><iyy>1</iyy><izz>-1</izz></inertia></inertial></link>"
                        "</model>"),
               " sdformat: A link named l has invalid inertia."},
        BadSdf{"infinite pose",
               sdfWorld("<model name=\"m\"><pose>0 0 inf 0 0 0</pose>" +
                        cubeLink("l", "0 0 0 0 0 0") + "</model>"),
               "3: sdformat: Error reading element <pose>"},
        BadSdf{"restitution above 1",
               sdfWorld("<model name=\"m\">" +
                        cubeLink("l", "0 0 0 0 0 0")
                            .replace(cubeLink("l", "0 0 0 0 0 0").find("</collision>"), 0,
                                     "<surface><bounce><restitution_coefficient>2"
                                     "</restitution_coefficient></bounce></surface>") +
                        "</model>"),
               "3: sdformat: Error reading element <restitution_coefficient>"},
        BadSdf{"negative friction",
               sdfWorld(
                   "<model name=\"m\">" +
                   cubeLink("l", "0 0 0 0 0 0")
                       .replace(cubeLink("l", "0 0 0 0 0 0").find("</collision>"), 0,
                                "<surface><friction><ode><mu>-1</mu></ode></friction></surface>") +
                   "</model>"),
               "3: sdformat: Error reading element <mu>"},
        BadSdf{"zero box",
               sdfWorld("<model name=\"m\"><link name=\"l\"><collision name=\"c\"><geometry>"
                        "<box><size>0 1 1</size></box></geometry></collision></link></model>"),
               "3: collision 'm::l::c': box size must be positive and finite"},
        BadSdf{"a plane that moves",
               sdfWorld("<model name=\"m\"><link name=\"l\"><collision name=\"c\"><geometry>"
                        "<plane><normal>0 0 1</normal></plane></geometry></collision></link>"
                        "</model>"),
               "3: collision 'm::l::c': a plane can only belong to a static model"},
        BadSdf{"a geometry pfx has not",
               sdfWorld("<model name=\"m\"><link name=\"l\"><collision name=\"c\"><geometry>"
                        "<ellipsoid><radii>1 2 3</radii></ellipsoid></geometry></collision>"
                        "</link></model>"),
               "3: collision 'm::l::c': pfx has no shape for this geometry"},
        BadSdf{"a missing mesh",
               sdfWorld("<model name=\"m\"><static>true</static><link name=\"l\">"
                        "<collision name=\"c\"><geometry><mesh><uri>model://nothing/x.stl</uri>"
                        "</mesh></geometry></collision></link></model>"),
               "3: collision 'm::l::c': mesh 'model://nothing/x.stl' not found"},
        BadSdf{"an include that is not there",
               sdfWorld("<include><uri>model://no_such_model</uri></include>"),
               "3: sdformat: Unable to find uri[model://no_such_model]"},
        BadSdf{"a gearbox",
               sdfWorld("<model name=\"m\">" + cubeLink("a", "0 0 0 0 0 0") +
                        cubeLink("b", "1 0 0 0 0 0") +
                        "<joint name=\"g\" type=\"gearbox\"><parent>a</parent><child>b</child>"
                        "<gearbox_reference_body>a</gearbox_reference_body>"
                        "<axis><xyz>1 0 0</xyz></axis><axis2><xyz>1 0 0</xyz></axis2></joint>"
                        "</model>"),
               "3: joint 'm::g': pfx cannot honour this joint type"},
        BadSdf{"universal axes not perpendicular",
               sdfWorld("<model name=\"m\">" + cubeLink("a", "0 0 0 0 0 0") +
                        cubeLink("b", "1 0 0 0 0 0") +
                        "<joint name=\"u\" type=\"universal\"><parent>a</parent><child>b</child>"
                        "<axis><xyz>1 0 0</xyz></axis><axis2><xyz>1 1 0</xyz></axis2></joint>"
                        "</model>"),
               "3: joint 'm::u': pfx holds the two axes of a universal or revolute2 joint only "
               "when they are perpendicular"},
        BadSdf{"a screw without pitch",
               sdfWorld("<model name=\"m\">" + cubeLink("a", "0 0 0 0 0 0") +
                        cubeLink("b", "1 0 0 0 0 0") +
                        "<joint name=\"s\" type=\"screw\"><parent>a</parent><child>b</child>"
                        "<thread_pitch>0</thread_pitch><axis><xyz>1 0 0</xyz></axis></joint>"
                        "</model>"),
               "3: joint 'm::s': a screw needs a finite, non-zero thread_pitch"},
        BadSdf{"limits crossed",
               sdfWorld("<model name=\"m\">" + cubeLink("a", "0 0 0 0 0 0") +
                        cubeLink("b", "1 0 0 0 0 0") +
                        "<joint name=\"h\" type=\"revolute\"><parent>a</parent><child>b</child>"
                        "<axis><xyz>1 0 0</xyz><limit><lower>1</lower><upper>-1</upper></limit>"
                        "</axis></joint></model>"),
               "3: joint 'm::h': limits must be numbers with lower <= upper (got [1, -1])"},
        BadSdf{"negative damping",
               sdfWorld("<model name=\"m\">" + cubeLink("a", "0 0 0 0 0 0") +
                        cubeLink("b", "1 0 0 0 0 0") +
                        "<joint name=\"h\" type=\"revolute\"><parent>a</parent><child>b</child>"
                        "<axis><xyz>1 0 0</xyz><dynamics><damping>-1</damping></dynamics>"
                        "</axis></joint></model>"),
               "3: joint 'm::h': dynamics damping and friction must be finite and >= 0"},
        BadSdf{"non-positive step",
               sdfWorld("<physics name=\"p\" type=\"ode\"><max_step_size>0</max_step_size>"
                        "</physics>"),
               "3: physics 'p': max_step_size must be positive and finite (got 0)"},
        BadSdf{"NaN gravity", sdfWorld("<gravity>0 0 nan</gravity>"),
               "3: sdformat: Error reading element <gravity>"}));

TEST(SdfLoader, NestedModelsShapesSurfacesAndMotionTypes) {
  const std::string cube = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/cube.stl";
  const std::string models =
      "<model name=\"floor\"><static>true</static><link name=\"l\">"
      "<collision name=\"plane\"><geometry><plane><normal>0 0 1</normal><size>20 20</size>"
      "</plane></geometry></collision>"
      "<collision name=\"step\"><pose>3 0 0 0 0 0</pose><geometry><mesh><uri>" +
      cube +
      "</uri><scale>1 1 0.4</scale></mesh></geometry></collision></link></model>\n"
      "<model name=\"outer\"><pose>1 2 0 0 0 1.5707963</pose>"
      "<link name=\"base\"><pose>0 0 0.5 0 0 0</pose><kinematic>true</kinematic>"
      "<collision name=\"c\"><geometry><capsule><radius>0.1</radius><length>0.4</length>"
      "</capsule></geometry><surface><bounce><restitution_coefficient>0.5"
      "</restitution_coefficient></bounce><contact><collide_bitmask>0x3</collide_bitmask>"
      "</contact></surface></collision></link>"
      "<model name=\"inner\"><pose>1 0 0 0 0 0</pose>" +
      cubeLink("l", "0 0 1 0 0 0",
               "<collision name=\"hull\"><pose>0 0 -0.5 0 0 0</pose><geometry><mesh><uri>" + cube +
                   "</uri><scale>0.2 0.2 0.2</scale></mesh></geometry></collision>") +
      "</model>"
      "<joint name=\"j\" type=\"revolute\"><parent>base</parent><child>inner::l</child>"
      "<axis><xyz>0 0 1</xyz></axis></joint></model>";
  PfxWorld world;
  ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
  PfxSceneModel model;
  std::string message;
  ASSERT_EQ(pfxLoadSdfString(world, sdfWorld(models), PfxSceneLoadParam(), model, &message), PFX_OK)
      << message;
  // The floor: a fixed body, the plane as a box whose top face is z = 0, the step a large
  // mesh.
  const PfxSceneBody& floor = body(model, "floor::l");
  EXPECT_EQ(world.getRigidState(floor.bodyId).getMotionType(), kPfxMotionTypeFixed);
  const PfxCollidable& floorShapes = world.getCollidable(floor.bodyId);
  ASSERT_EQ(floorShapes.getNumShapes(), 2u);
  EXPECT_EQ(floorShapes.getShape(0).getType(), kPfxShapeBox);
  EXPECT_TRUE(floorShapes.getShape(0).getBox().m_half.isApprox(PfxVector3(10, 10, 0.5f)));
  EXPECT_TRUE(floorShapes.getShape(0).getOffsetPosition().isApprox(PfxVector3(0, 0, -0.5f)));
  EXPECT_EQ(floorShapes.getShape(1).getType(), kPfxShapeLargeTriMesh);
  // A kinematic link is a keyframe body; its surface gives restitution and filters.
  const PfxUInt32 base = body(model, "outer::base").bodyId;
  EXPECT_EQ(world.getRigidState(base).getMotionType(), kPfxMotionTypeKeyframe);
  EXPECT_TRUE(world.getRigidState(base).getPosition().isApprox(PfxVector3(1, 2, 0.5f), 1e-5f));
  EXPECT_EQ(world.getRigidState(base).getContactFilterSelf(), 3u);
  EXPECT_EQ(world.getRigidState(base).getContactFilterTarget(), 3u);
  EXPECT_FLOAT_EQ(world.getRigidBody(base).getRestitution(), 0.5f);
  const PfxShape& capsule = world.getCollidable(base).getShape(0);
  EXPECT_EQ(capsule.getType(), kPfxShapeCapsule);
  // pfx's capsule lies along X: turned onto the link's Z.
  EXPECT_NEAR(std::abs((capsule.getOffsetOrientation() * PfxVector3::UnitX()).z()), 1, 1e-5);
  // The nested model's link: its pose composed through both models (the outer one turned a
  // quarter about Z), a box and a convex hull.
  const PfxSceneBody& inner = body(model, "outer::inner::l");
  EXPECT_TRUE(pfxGetSceneBodyFrame(world, inner).translation().isApprox(PfxVector3(1, 3, 1), 1e-5f))
      << pfxGetSceneBodyFrame(world, inner).translation().transpose();
  EXPECT_EQ(world.getCollidable(inner.bodyId).getShape(1).getType(), kPfxShapeConvexMesh);
  const PfxSceneJoint& j = joint(model, "outer::j");
  EXPECT_EQ(j.parent, "outer::base");
  EXPECT_EQ(j.child, "outer::inner::l");
}

// Gazebo collides the links of one model only with self_collide: two overlapping links stay
// where they are without it, and are pushed apart with it.
TEST(SdfLoader, LinksOfOneModelCollideOnlyWithSelfCollide) {
  for (const bool selfCollide : {false, true}) {
    const std::string models = "<gravity>0 0 0</gravity><model name=\"m\"><self_collide>" +
                               std::string(selfCollide ? "true" : "false") + "</self_collide>" +
                               cubeLink("a", "0 0 1 0 0 0") + cubeLink("b", "0.1 0 1 0 0 0") +
                               "</model>";
    PfxWorld world;
    ASSERT_EQ(world.initialize(PfxWorldParam()), PFX_OK);
    PfxSceneModel model;
    std::string message;
    ASSERT_EQ(pfxLoadSdfString(world, sdfWorld(models), PfxSceneLoadParam(), model, &message),
              PFX_OK)
        << message;
    for (int i = 0; i < 500; ++i) ASSERT_EQ(world.step(), PFX_OK);
    const PfxFloat apart = (position(world, model, "m::a") - position(world, model, "m::b")).norm();
    if (selfCollide) {
      EXPECT_GT(apart, 0.19f);
    } else {
      EXPECT_FLOAT_EQ(apart, 0.1f);
    }
  }
}
