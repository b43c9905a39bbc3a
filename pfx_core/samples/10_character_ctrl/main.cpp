// Sample 10_character_ctrl: characters (pfx_character_controller.h) walk from the west side
// of a course to targets on the east side, through pillars, a staircase up and down, a ramp
// too steep to climb in front of a plateau, a turning and sliding keyframe platform, loose
// boxes that they push aside and a ragdoll lying in the way. Each follows a naive walker:
// straight at its target, and when that makes no progress for a second, a hop and a detour
// to one side for a while. One character is sent onto the plateau, which only the steep
// ramp leads to: it must not get there, and says so.
//
// Prints every state machine transition counted over all characters, then each character
// that did not reach its target and why, and the processor time the controller and the
// world took per step. Exits with 1 when a character other than the plateau one never
// reaches its target, when one falls through the floor, is flung or climbs the steep ramp,
// and when the plateau one reaches the plateau. The first argument sets the number of
// characters (120 by default), the second the seconds simulated (30).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_character_controller.h"
#include "pfx/high_level/pfx_ragdoll.h"

using namespace pfx;

namespace {

constexpr PfxFloat kDegree = PFX_PI / 180;
constexpr PfxFloat kTimeStep = PfxFloat(1) / 60;
constexpr PfxFloat kWalkSpeed = 3;
constexpr PfxFloat kArrived = 0.5f;  // m from the target, horizontally

// The steep ramp: 50 degrees from x = kRampStart up to the plateau's edge, 2.5 m high.
constexpr PfxFloat kRampAngle = 50 * kDegree;
constexpr PfxFloat kRampStart = -1;
constexpr PfxFloat kPlateauHeight = 2.5f;
constexpr PfxFloat kRampZ = -2, kRampHalfWidth = 1.5f;

PfxUInt32 addBox(PfxWorld& world, const PfxVector3& center, const PfxVector3& half,
                 PfxFloat mass = 0, const PfxQuat& orientation = PfxQuat::Identity(),
                 PfxMotionType type = kPfxMotionTypeActive) {
  PfxBodyInit init;
  init.position = center;
  init.orientation = orientation;
  init.mass = mass;
  init.motionType = type;
  PfxUInt32 id = 0;
  if (pfxAddBody(world, pfxMakeShape(PfxBox(half.x(), half.y(), half.z())), init, &id) != PFX_OK) {
    std::printf("could not add a box\n");
    std::exit(1);
  }
  return id;
}

PfxFloat rampRun() { return kPlateauHeight / std::tan(kRampAngle); }

// A foot over the ramp this high has got up it: a running jump into the ramp, which deflects
// it upward, got a foot to 2.15 m among 200 characters before the character slid back.
constexpr PfxFloat kUpTheRamp = kPlateauHeight - 0.1f;
// Faster than any push of the course can make a character walk: it was flung.
constexpr PfxFloat kFlung = 8;

bool overRamp(const PfxVector3& foot) {
  return foot.x() > kRampStart && foot.x() < kRampStart + rampRun() &&
         std::abs(foot.z() - kRampZ) < kRampHalfWidth;
}

bool onPlateau(const PfxVector3& foot) {
  return foot.x() > kRampStart + rampRun() && foot.x() < kRampStart + rampRun() + 2 &&
         std::abs(foot.z() - kRampZ) < kRampHalfWidth && foot.y() > kPlateauHeight - 0.1f;
}

struct Course {
  PfxUInt32 ramp = 0;
  PfxUInt32 platform = 0;
  PfxVector3 plateauTarget;
  std::vector<PfxUInt32> looseBoxes;
  PfxUInt32 ragdollPelvis = 0;
};

// The course between x = -8 and x = 12; characters start west of it and walk east.
Course buildCourse(PfxWorld& world, PfxFloat halfLength, PfxFloat halfWidth) {
  Course course;
  addBox(world, PfxVector3(0, -0.5f, 0), PfxVector3(halfLength, 0.5f, halfWidth + 10));
  // Staircase for z in [-12, -6]: four 0.25 m steps up to a 1 m landing, four down.
  for (int i = 0; i < 4; ++i) {
    const PfxFloat top = 0.25f * PfxFloat(i + 1);
    const PfxFloat depth = 0.4f;
    addBox(world, PfxVector3(-8 + depth * (PfxFloat(i) + 0.5f), top / 2, -9),
           PfxVector3(depth / 2, top / 2, 3));
    addBox(world, PfxVector3(-3.2f - depth * (PfxFloat(i) + 0.5f), top / 2, -9),
           PfxVector3(depth / 2, top / 2, 3));
  }
  addBox(world, PfxVector3(-5.6f, 0.5f, -9), PfxVector3(0.8f, 0.5f, 3));  // landing
  // The steep ramp, leaning on the plateau's west face.
  const PfxVector3 along(std::cos(kRampAngle), std::sin(kRampAngle), 0);
  const PfxVector3 normal(-std::sin(kRampAngle), std::cos(kRampAngle), 0);
  const PfxFloat length = kPlateauHeight / std::sin(kRampAngle);
  course.ramp = addBox(
      world, PfxVector3(kRampStart, 0, kRampZ) + along * (length / 2) - normal * PfxFloat(0.1),
      PfxVector3(length / 2, 0.1f, kRampHalfWidth), 0,
      PfxQuat(Eigen::AngleAxis<PfxFloat>(kRampAngle, PfxVector3::UnitZ())));
  const PfxFloat plateauX = kRampStart + rampRun() + 1;
  addBox(world, PfxVector3(plateauX, kPlateauHeight / 2, kRampZ),
         PfxVector3(1, kPlateauHeight / 2, kRampHalfWidth));
  course.plateauTarget = PfxVector3(plateauX, kPlateauHeight, kRampZ);
  // Pillars.
  for (const PfxFloat z : {-4.5f, 1.5f, 4.5f, 10.5f}) {
    addBox(world, PfxVector3(-6 + std::abs(z) * 0.3f, 1, z), PfxVector3(0.5f, 1, 0.5f));
  }
  // A keyframe platform 0.2 m high (a step up) for z in [3, 9], driven in main().
  course.platform = addBox(world, PfxVector3(6, 0.1f, 6), PfxVector3(2, 0.1f, 2), 500,
                           PfxQuat::Identity(), kPfxMotionTypeKeyframe);
  // Loose boxes.
  std::mt19937 rng(7);
  std::uniform_real_distribution<PfxFloat> unit(0, 1);
  for (int i = 0; i < 20; ++i) {
    const PfxFloat half = 0.2f + 0.1f * unit(rng);
    course.looseBoxes.push_back(
        addBox(world, PfxVector3(2 + 8 * unit(rng), half, -halfWidth + 2 * halfWidth * unit(rng)),
               PfxVector3(half, half, half), 10));
  }
  // A ragdoll dropped across the path, to lie there.
  PfxRagdoll doll;
  const PfxQuat lying(Eigen::AngleAxis<PfxFloat>(PFX_PI / 2, PfxVector3::UnitX()));
  if (pfxAddRagdoll(world, PfxVector3(3, 0.5f, 1), lying, &doll) != PFX_OK) {
    std::printf("could not add the ragdoll\n");
    std::exit(1);
  }
  course.ragdollPelvis = doll.bodies[0];
  return course;
}

// The naive walker of one character.
struct Walker {
  PfxUInt32 id = 0;
  PfxVector3 target;
  bool toPlateau = false;
  bool arrived = false;
  PfxFloat arrivalTime = 0;
  // Progress check: the distance a second ago, and a detour in force until detourEnd.
  PfxFloat lastDistance = 1e9f;
  PfxFloat nextCheck = 1;
  PfxFloat detourEnd = 0;
  PfxFloat detourSide = 1;
  int detours = 0;
  bool rodePlatform = false;
  PfxFloat fastest = 0;  // horizontal speed, m/s
  PfxFloat lowestFoot = 1e9f;
  bool climbedRamp = false;
  bool reachedPlateau = false;
  PfxCharacterState state = kPfxCharacterStanding;
};

PfxVector3 horizontal(const PfxVector3& v) { return PfxVector3(v.x(), 0, v.z()); }

// Straight at the target; after a second without half a metre of progress, a hop (over a
// box or a limb, perhaps) and 1.5 s at 75 degrees to one side, the side alternating from
// detour to detour.
PfxVector3 steer(PfxCharacterController& controller, Walker& walker, const PfxVector3& foot,
                 PfxFloat time) {
  const PfxVector3 toTarget = horizontal(walker.target - foot);
  const PfxFloat distance = toTarget.norm();
  if (distance < kArrived) return PfxVector3::Zero();
  if (time >= walker.nextCheck) {
    if (walker.lastDistance - distance < 0.5f && time >= walker.detourEnd) {
      walker.detourEnd = time + 1.5f;
      walker.detourSide = (walker.id + walker.detours) % 2 == 0 ? 1.0f : -1.0f;
      ++walker.detours;
      controller.requestJump(walker.id);
    }
    walker.lastDistance = distance;
    walker.nextCheck = time + 1;
  }
  PfxVector3 direction = toTarget / distance;
  if (time < walker.detourEnd) {
    direction = Eigen::AngleAxis<PfxFloat>(walker.detourSide * 75 * kDegree, PfxVector3::UnitY()) *
                direction;
  }
  return direction * std::min(kWalkSpeed, 2 * distance);
}

}  // namespace

int main(int argc, char** argv) {
  const int numCharacters = argc > 1 ? std::max(1, std::atoi(argv[1])) : 120;
  const PfxFloat seconds = argc > 2 ? PfxFloat(std::atof(argv[2])) : 30;
  const int lanes = 24;
  const int rows = (numCharacters + lanes - 1) / lanes;
  const PfxFloat laneWidth = 1.2f;
  const PfxFloat halfWidth = lanes * laneWidth / 2;

  PfxWorldParam param;
  param.timeStep = kTimeStep;
  param.worldExtent = PfxVector3(100 + rows * 2, 50, 100);
  PfxWorld world;
  if (world.initialize(param) != PFX_OK) return 1;
  const Course course = buildCourse(world, 25 + 2 * PfxFloat(rows), halfWidth);
  PfxCharacterController controller(world);

  std::vector<PfxVector3> boxesAtStart;
  for (const PfxUInt32 box : course.looseBoxes) {
    boxesAtStart.push_back(world.getRigidState(box).getPosition());
  }
  const PfxVector3 ragdollAtStart = world.getRigidState(course.ragdollPelvis).getPosition();

  std::vector<Walker> walkers(numCharacters);
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> laneShift(-3, 3);
  for (int i = 0; i < numCharacters; ++i) {
    const int row = i / lanes, lane = i % lanes;
    const PfxFloat z = -halfWidth + laneWidth * (PfxFloat(lane) + 0.5f);
    const PfxVector3 start(-14 - 1.2f * PfxFloat(row), 0, z);
    Walker& walker = walkers[i];
    // Targets on a grid 2 m by one lane, the lanes turned by a few places; the first row
    // to arrive takes the furthest, so that none has to pass through those who arrived.
    const int targetLane = (lane + lanes + laneShift(rng)) % lanes;
    walker.target = PfxVector3(18 + 2 * PfxFloat(rows - 1 - row), 0,
                               -halfWidth + laneWidth * (PfxFloat(targetLane) + 0.5f));
    if (controller.addCharacter(PfxCharacterParam(), start, &walker.id) != PFX_OK) {
      std::printf("could not add character %d\n", i);
      return 1;
    }
  }
  walkers[lanes / 2].toPlateau = true;
  walkers[lanes / 2].target = course.plateauTarget;

  int transitions[kPfxCharacterStateCount][kPfxCharacterStateCount] = {};
  PfxFloat highestOverRamp = 0;
  double controllerSeconds = 0, worldSeconds = 0;
  const int steps = static_cast<int>(seconds / kTimeStep);
  PfxFloat time = 0;
  for (int step = 0; step < steps; ++step) {
    time += kTimeStep;
    // The platform slides 2 m to and fro along x every 8 s and turns a quarter turn and back.
    const PfxVector3 platformAt(6 + 2 * std::sin(2 * PFX_PI * time / 8), 0.1f, 6);
    const PfxQuat platformTurn(
        Eigen::AngleAxis<PfxFloat>(0.5f * std::sin(2 * PFX_PI * time / 10), PfxVector3::UnitY()));
    world.setKeyframeTarget(course.platform, platformAt, platformTurn);
    for (Walker& walker : walkers) {
      PfxCharacterStatus status;
      controller.getStatus(walker.id, status);
      const PfxVector3 desired = steer(controller, walker, status.footPosition, time);
      if (!walker.arrived && desired.isZero()) {
        walker.arrived = true;
        walker.arrivalTime = time;
      }
      controller.setDesiredVelocity(walker.id, desired);
    }
    // Processor time, not wall time: the figures should not depend on what else the machine
    // runs. The world runs on this one thread (PfxWorldParam::numThreads is 1).
    const std::clock_t t0 = std::clock();
    if (controller.update() != PFX_OK) return 1;
    const std::clock_t t1 = std::clock();
    if (world.step() != PFX_OK) return 1;
    const std::clock_t t2 = std::clock();
    controllerSeconds += double(t1 - t0) / CLOCKS_PER_SEC;
    worldSeconds += double(t2 - t1) / CLOCKS_PER_SEC;
    for (Walker& walker : walkers) {
      PfxCharacterStatus status;
      controller.getStatus(walker.id, status);
      if (status.state != walker.state) ++transitions[walker.state][status.state];
      walker.state = status.state;
      walker.lowestFoot = std::min(walker.lowestFoot, status.footPosition.y());
      if (overRamp(status.footPosition)) {
        highestOverRamp = std::max(highestOverRamp, status.footPosition.y());
      }
      // Up the ramp, or standing on it, which a slope too steep to stand on must not allow.
      walker.climbedRamp =
          walker.climbedRamp ||
          (overRamp(status.footPosition) && status.footPosition.y() > kUpTheRamp) ||
          status.groundBodyId == course.ramp;
      walker.fastest = std::max(walker.fastest, horizontal(status.velocity).norm());
      walker.reachedPlateau = walker.reachedPlateau || onPlateau(status.footPosition);
      walker.rodePlatform = walker.rodePlatform || status.groundBodyId == course.platform;
    }
  }

  std::printf("%d characters, %.0f s simulated; state machine transitions, all characters:\n",
              numCharacters, double(seconds));
  for (int from = 0; from < kPfxCharacterStateCount; ++from) {
    for (int to = 0; to < kPfxCharacterStateCount; ++to) {
      if (transitions[from][to] == 0) continue;
      std::printf(
          "  %-8s -> %-8s %6d\n", pfxGetCharacterStateName(static_cast<PfxCharacterState>(from)),
          pfxGetCharacterStateName(static_cast<PfxCharacterState>(to)), transitions[from][to]);
    }
  }

  int reached = 0, failures = 0, riders = 0, boxesPushed = 0;
  for (std::size_t i = 0; i < course.looseBoxes.size(); ++i) {
    const PfxVector3 moved =
        world.getRigidState(course.looseBoxes[i]).getPosition() - boxesAtStart[i];
    if (horizontal(moved).norm() > 0.1f) ++boxesPushed;
  }
  const PfxFloat ragdollMoved =
      horizontal(world.getRigidState(course.ragdollPelvis).getPosition() - ragdollAtStart).norm();
  PfxUInt32 stepsClimbed = 0;
  PfxFloat latest = 0;
  for (const Walker& walker : walkers) {
    PfxCharacterStatus status;
    controller.getStatus(walker.id, status);
    const PfxFloat left = horizontal(walker.target - status.footPosition).norm();
    stepsClimbed += status.numSteps;
    if (walker.rodePlatform) ++riders;
    if (walker.lowestFoot < -0.05f) {
      std::printf("character %u FELL THROUGH the floor (foot at %.2f m)\n", walker.id,
                  double(walker.lowestFoot));
      ++failures;
    }
    if (walker.fastest > kFlung) {
      std::printf("character %u was FLUNG at %.1f m/s\n", walker.id, double(walker.fastest));
      ++failures;
    }
    if (walker.climbedRamp || walker.reachedPlateau) {
      std::printf("character %u CLIMBED the steep ramp\n", walker.id);
      ++failures;
    }
    if (walker.toPlateau) {
      std::printf(
          "character %u did not reach its target on the plateau, as it must not: the "
          "only way up is the %.0f degree ramp, steeper than its %.0f degree limit; it "
          "ended %.1f m short, %s, after %d detours\n",
          walker.id, double(kRampAngle / kDegree), double(PfxCharacterParam().maxSlope / kDegree),
          double(left), pfxGetCharacterStateName(status.state), walker.detours);
      continue;
    }
    if (walker.arrived) {
      ++reached;
      latest = std::max(latest, walker.arrivalTime);
      continue;
    }
    std::printf(
        "character %u DID NOT REACH its target: %.1f m short at (%.1f, %.1f, %.1f), "
        "%s, after %d detours\n",
        walker.id, double(left), double(status.footPosition.x()), double(status.footPosition.y()),
        double(status.footPosition.z()), pfxGetCharacterStateName(status.state), walker.detours);
    ++failures;
  }
  std::printf("%d of %d reached their targets (the last after %.1f s); %u steps climbed\n", reached,
              numCharacters - 1, double(latest), stepsClimbed);
  std::printf("highest foot over the steep ramp %.2f m (its top %.2f m)\n", double(highestOverRamp),
              double(kPlateauHeight));
  std::printf(
      "%d rode the moving platform; %d of %zu loose boxes were pushed further than "
      "0.1 m, the ragdoll's pelvis %.2f m\n",
      riders, boxesPushed, course.looseBoxes.size(), double(ragdollMoved));
  std::printf("processor time per step: controller %.3f ms, world %.3f ms (%u bodies)\n",
              1e3 * controllerSeconds / steps, 1e3 * worldSeconds / steps,
              world.getNumRigidBodies());
  std::printf("%s\n", failures == 0 ? "every character reached its target or said why not"
                                    : "SOME CHARACTERS FAILED");
  return failures == 0 ? 0 : 1;
}
