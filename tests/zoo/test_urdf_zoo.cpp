// urdf_zoo: every robot description the package ships (urdf/ and its folders) and every
// public one kept beside the checkout (../shared/realworld), loaded as a user loads it and
// dropped onto the ground for a few seconds at a large and a small time step. Each run must
// stay finite and bounded, keep its joints closed and within their URDF limits, not sink
// into the ground or itself, and come to rest. The figures of every run are printed as a
// table (bodies, joints, wall seconds per simulated second, largest joint gap, deepest
// penetration, largest limit excursion, final speed).
//
//   test_urdf_zoo [--dt 1/60,1/240] [--seconds 3] [--robot NAME] [gtest options]
//
// Files written for other simulators break assumptions that our own never test: what each
// robot needs (a fixed base for an arm with a massless root, say) is decided by the loader,
// as for any user, never by a list here.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_urdf_loader.h"

using namespace pfx;
namespace fs = std::filesystem;

namespace {

struct ZooOptions {
  std::vector<double> timeSteps = {1.0 / 60.0, 1.0 / 240.0};
  double seconds = 3;
  std::string robot;  // run only files whose name contains this
};
ZooOptions gOptions;

// Bounds every robot must keep. Joints and contacts are position-corrected, so the bounds
// are those a user sees in rviz as "closed", "on the floor" and "within limits".
constexpr double kMaxJointGap = 0.005;        // m
// Deepest overlap at any step, and while at rest. A jointed robot landing on light feet at
// dt 1/60 sinks 4 to 5 cm for a few steps (the feet's contacts are iterated, not solved with
// the joint tree) before the overlap is pushed out.
constexpr double kMaxPenetration = 0.06;      // m
constexpr double kMaxRestingPenetration = 0.01;  // m
constexpr double kMaxLimitExcursion = 0.05;   // rad or m past a URDF limit
constexpr double kMaxSpeed = 30;              // m/s at any step
constexpr double kMaxTravel = 20;             // m from where the robot was dropped
constexpr double kRestSpeed = 0.01;           // m/s: still when no point moves faster
constexpr double kStillSeconds = 0.5;         // at rest: still for this long
constexpr double kExtraSettleSeconds = 3;     // beyond --seconds, for a robot still moving
constexpr double kDropClearance = 0.05;       // m between the lowest shape and the ground

struct ZooRobot {
  std::string name;  // the path below urdf/, or realworld/ and the path below it
  std::string path;
};

void PrintTo(const ZooRobot& robot, std::ostream* out) { *out << robot.name; }

std::vector<ZooRobot> zooRobots() {
  std::vector<ZooRobot> robots;
  const std::pair<fs::path, std::string> roots[] = {
      {fs::path(PFX_SOURCE_DIR) / "urdf", ""},
      {fs::path(PFX_SOURCE_DIR) / ".." / "shared" / "realworld", "realworld/"}};
  for (const auto& [root, prefix] : roots) {
    std::error_code error;
    if (!fs::is_directory(root, error)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(root, error)) {
      if (entry.is_regular_file() && entry.path().extension() == ".urdf") {
        robots.push_back({prefix + fs::relative(entry.path(), root).string(),
                          fs::weakly_canonical(entry.path()).string()});
      }
    }
  }
  std::sort(robots.begin(), robots.end(),
            [](const ZooRobot& a, const ZooRobot& b) { return a.name < b.name; });
  return robots;
}

struct ZooResult {
  std::string robot;
  double dt = 0;
  bool fixedBase = false;
  PfxUInt32 bodies = 0, joints = 0;
  double wallPerSimulated = 0;
  double maxJointGap = 0, maxPenetration = 0, restingPenetration = 0, maxLimitExcursion = 0;
  double maxSpeed = 0, maxTravel = 0;
  double restSpeed = 0;  // fastest point at the end
  double restTime = 0;   // since when it has been still
  bool atRest = false;
  std::string worstJoint;
  bool finite = true;
};
std::vector<ZooResult> gResults;

// The fastest point of the robot's bodies: linear speed plus angular speed times the body's
// half-diagonal, so a spinning wheel counts as moving.
double fastestPoint(const PfxWorld& world, const PfxUrdfModel& model) {
  double fastest = 0;
  for (PfxUInt32 id = model.firstBodyId; id < model.firstBodyId + model.numBodies; ++id) {
    const PfxRigidState& state = world.getRigidState(id);
    PfxVector3 center, half;
    world.getCollidable(id).getWorldAabb(state.getTransform(), center, half);
    const double reach = double(half.norm()) + double((center - state.getPosition()).norm());
    fastest = std::max(fastest, double(state.getLinearVelocity().norm()) +
                                    double(state.getAngularVelocity().norm()) * reach);
  }
  return fastest;
}

double lowestPoint(const PfxWorld& world, const PfxUrdfModel& model) {
  double lowest = 1e30;
  for (PfxUInt32 id = model.firstBodyId; id < model.firstBodyId + model.numBodies; ++id) {
    PfxVector3 center, half;
    world.getCollidable(id).getWorldAabb(world.getRigidState(id).getTransform(), center, half);
    lowest = std::min(lowest, double(center.z() - half.z()));
  }
  return lowest;
}

void runRobot(const ZooRobot& robot, double dt, ZooResult& result) {
  result.robot = robot.name;
  result.dt = dt;
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.81));
  param.timeStep = PfxFloat(dt);
  param.enableSleep = false;  // the figures measure the solver on every step
  PfxWorld world;
  ASSERT_EQ(world.initialize(param), PFX_OK);

  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, 0, PfxFloat(-0.5));
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(50, 50, PfxFloat(0.5))), ground), PFX_OK);

  PfxUrdfLoadParam load;
  load.rootPosition = PfxVector3(0, 0, 2);  // well above the ground; placed below
  // Descriptions copied without all of their meshes (r2d2's gripper) load without them,
  // each named in a warning.
  load.allowMissingMeshes = true;
  PfxUrdfModel model;
  std::string message;
  const PfxInt32 loaded = pfxLoadUrdfFile(world, robot.path, load, model, &message);
  ASSERT_EQ(loaded, PFX_OK) << result.robot << ": " << message;
  if (dt == gOptions.timeSteps.front()) {
    for (const std::string& warning : model.warnings) {
      std::printf("  %s: warning: %s\n", result.robot.c_str(), warning.c_str());
    }
  }
  result.fixedBase = model.fixedBase;
  result.bodies = model.numBodies;
  result.joints = model.numJoints;

  // The robot's lowest collision shape starts kDropClearance above the ground.
  const PfxFloat lift = PfxFloat(kDropClearance - lowestPoint(world, model));
  for (PfxUInt32 id = model.firstBodyId; id < model.firstBodyId + model.numBodies; ++id) {
    PfxRigidState state = world.getRigidState(id);
    state.setPosition(state.getPosition() + PfxVector3(0, 0, lift));
    ASSERT_EQ(world.setRigidState(id, state), PFX_OK);
  }
  std::vector<PfxVector3> start;
  for (PfxUInt32 id = model.firstBodyId; id < model.firstBodyId + model.numBodies; ++id) {
    start.push_back(world.getRigidState(id).getPosition());
  }

  // The run lasts the given seconds and then, for a robot still moving, up to
  // kExtraSettleSeconds more until it has been still for kStillSeconds: a ragdoll dropped
  // upright may balance for seconds before it falls.
  const long steps = std::lround(gOptions.seconds / dt);
  const long maxSteps = std::lround((gOptions.seconds + kExtraSettleSeconds) / dt);
  std::vector<double> positions, velocities;
  double wall = 0, stillSince = 0;
  std::vector<double> penetrations;  // of every step, for the overlap while still
  long step = 1;
  for (; step <= maxSteps; ++step) {
    const auto before = std::chrono::steady_clock::now();
    ASSERT_EQ(world.step(), PFX_OK) << result.robot << " step " << step;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();

    const PfxWorldStats& stats = world.getStats();
    result.maxJointGap = std::max(result.maxJointGap, double(stats.maxJointGap));
    result.maxPenetration = std::max(result.maxPenetration, double(stats.maxPenetration));
    penetrations.push_back(double(stats.maxPenetration));
    for (PfxUInt32 i = 0; i < model.numBodies; ++i) {
      const PfxRigidState& state = world.getRigidState(model.firstBodyId + i);
      if (!state.getPosition().allFinite() || !state.getLinearVelocity().allFinite() ||
          !state.getAngularVelocity().allFinite() || !state.getOrientation().coeffs().allFinite()) {
        result.finite = false;
      }
      result.maxSpeed = std::max(result.maxSpeed, double(state.getLinearVelocity().norm()));
      result.maxTravel =
          std::max(result.maxTravel, double((state.getPosition() - start[i]).norm()));
    }
    if (!result.finite) break;
    pfxGetUrdfJointStates(world, model, positions, velocities);
    for (size_t j = 0; j < model.joints.size(); ++j) {
      const PfxUrdfJoint& joint = model.joints[j];
      if (joint.type != kPfxUrdfRevolute && joint.type != kPfxUrdfPrismatic) continue;
      if (joint.jointId == kPfxUrdfNoJoint) continue;
      const double past = std::max({0.0, positions[j] - double(joint.upperLimit),
                                    double(joint.lowerLimit) - positions[j]});
      if (past > result.maxLimitExcursion) {
        result.maxLimitExcursion = past;
        result.worstJoint = joint.name;
      }
    }
    const double time = double(step) * dt;
    result.restSpeed = fastestPoint(world, model);
    if (result.restSpeed >= kRestSpeed) stillSince = time;
    if (step >= steps && time - stillSince >= kStillSeconds) break;
  }
  const long stepsRun = std::min(step, maxSteps);
  result.atRest = double(stepsRun) * dt - stillSince >= kStillSeconds;
  result.restTime = stillSince;
  const size_t stillSteps = size_t(std::lround(kStillSeconds / dt));
  for (size_t i = penetrations.size() - std::min(stillSteps, penetrations.size());
       i < penetrations.size(); ++i) {
    result.restingPenetration = std::max(result.restingPenetration, penetrations[i]);
  }
  result.wallPerSimulated = wall / (double(stepsRun) * dt);
}

std::string formatStep(double dt) {
  char text[32];
  std::snprintf(text, sizeof text, "1/%.0f", 1.0 / dt);
  return text;
}

class UrdfZoo : public ::testing::TestWithParam<ZooRobot> {};

TEST_P(UrdfZoo, DropsFiniteBoundedWithinLimitsAndRests) {
  const ZooRobot& robot = GetParam();
  if (!gOptions.robot.empty() && robot.name.find(gOptions.robot) == std::string::npos) {
    GTEST_SKIP() << "not selected by --robot";
  }
  for (const double dt : gOptions.timeSteps) {
    ZooResult result;
    runRobot(robot, dt, result);
    if (HasFatalFailure()) return;
    gResults.push_back(result);
    const std::string what = result.robot + " at dt " + formatStep(dt);
    EXPECT_TRUE(result.finite) << what << ": a body state became NaN or infinite";
    EXPECT_LT(result.maxSpeed, kMaxSpeed) << what;
    EXPECT_LT(result.maxTravel, kMaxTravel) << what;
    EXPECT_LT(result.maxJointGap, kMaxJointGap) << what << ": a joint came apart";
    EXPECT_LT(result.maxPenetration, kMaxPenetration) << what << ": bodies sank into each other";
    EXPECT_LT(result.restingPenetration, kMaxRestingPenetration)
        << what << ": bodies rest inside each other";
    EXPECT_LT(result.maxLimitExcursion, kMaxLimitExcursion)
        << what << ": joint '" << result.worstJoint << "' passed its URDF limit";
    EXPECT_TRUE(result.atRest) << what << ": still moving after "
                               << gOptions.seconds + kExtraSettleSeconds << " s ("
                               << result.restSpeed << " m/s)";
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, UrdfZoo, ::testing::ValuesIn(zooRobots()),
                         // Not `info`: the macro's own function has a parameter of that name.
                         [](const ::testing::TestParamInfo<ZooRobot>& robot) {
                           std::string name = robot.param.name;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

TEST(UrdfZooFiles, FindsTheRobotsOfThePackage) {
  const std::vector<ZooRobot> robots = zooRobots();
  for (const char* name : {"arm.urdf", "ragdoll.urdf", "r2d2.urdf", "kuka_iiwa/model.urdf"}) {
    EXPECT_TRUE(std::any_of(robots.begin(), robots.end(),
                            [&](const ZooRobot& robot) { return robot.name == name; }))
        << name;
  }
}

bool parseTimeStep(const std::string& text, double& dt) {
  const size_t slash = text.find('/');
  char* end = nullptr;
  if (slash == std::string::npos) {
    dt = std::strtod(text.c_str(), &end);
    return *end == '\0' && dt > 0 && dt <= 1;
  }
  const double num = std::strtod(text.substr(0, slash).c_str(), &end);
  if (*end != '\0') return false;
  const double den = std::strtod(text.substr(slash + 1).c_str(), &end);
  if (*end != '\0' || !(den > 0)) return false;
  dt = num / den;
  return dt > 0 && dt <= 1;
}

void printTable() {
  if (gResults.empty()) return;
  std::printf("\n%-30s %-6s %-5s %6s %6s %9s %9s %9s %9s %10s %8s %9s\n", "robot", "dt",
              "base", "bodies", "joints", "wall/sim", "joint gap", "penetr.", "at rest",
              "past limit", "still at", "end m/s");
  for (const ZooResult& r : gResults) {
    std::printf("%-30s %-6s %-5s %6u %6u %9.4f %9.2e %9.2e %9.2e %10.2e %7.2fs %9.2e\n",
                r.robot.c_str(), formatStep(r.dt).c_str(), r.fixedBase ? "fixed" : "free",
                r.bodies, r.joints, r.wallPerSimulated, r.maxJointGap, r.maxPenetration,
                r.restingPenetration, r.maxLimitExcursion, r.restTime, r.restSpeed);
  }
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool hasValue = i + 1 < argc;
    if (arg == "--dt" && hasValue) {
      gOptions.timeSteps.clear();
      std::string list = argv[++i];
      for (size_t start = 0; start <= list.size();) {
        const size_t comma = std::min(list.find(',', start), list.size());
        double dt = 0;
        if (!parseTimeStep(list.substr(start, comma - start), dt)) {
          std::fprintf(stderr, "test_urdf_zoo: --dt takes steps such as 1/60,1/240\n");
          return 2;
        }
        gOptions.timeSteps.push_back(dt);
        start = comma + 1;
      }
    } else if (arg == "--seconds" && hasValue) {
      char* end = nullptr;
      gOptions.seconds = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(gOptions.seconds > 0.5) || gOptions.seconds > 600) {
        std::fprintf(stderr, "test_urdf_zoo: --seconds takes a number from 0.5 to 600\n");
        return 2;
      }
    } else if (arg == "--robot" && hasValue) {
      gOptions.robot = argv[++i];
    } else {
      std::fprintf(stderr, "test_urdf_zoo: unknown argument %s\n", arg.c_str());
      return 2;
    }
  }
  const int status = RUN_ALL_TESTS();
  printTable();
  return status;
}
