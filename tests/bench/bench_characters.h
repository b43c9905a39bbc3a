// The `characters` scene: the same course walked by pfx's PfxCharacterController and by
// Bullet's btKinematicCharacterController (Debian's libbullet-dev), for 100 and 1,000
// characters.
//
// The course (makeCharacterCourse) is one block per 100 characters, blocks side by side
// along Z on one floor, so that 1,000 characters walk ten copies of what 100 walk at the
// same density. A block, 28.8 m wide, holds what sample 10_character_ctrl holds: a
// staircase of four 0.25 m steps up to a 1 m landing and four down, a 50 degree ramp (too
// steep: the characters' limit is 45) leaning on a 2.5 m plateau, four pillars, a keyframe
// platform 0.2 m high (a step up) that slides 2 m to and fro and turns a quarter turn and
// back, and 20 loose 10 kg boxes. The sample's ragdoll is left out: Bullet would need its
// own ragdoll built from constraints, and the two would not be the same obstacle.
//
// Characters: capsules 1.8 m tall of radius 0.3 m, step height 0.35 m, maximum slope 45
// degrees, jump speed 5 m/s, fall speed at most 50 m/s, gravity 9.80665 m/s^2, walking at 3
// m/s. They start in a grid of 20 lanes 1.44 m apart and 5 rows 1.2 m apart west of the
// course, and each walks to a target east of it, in a lane up to three places to either
// side of its own; the first row takes the furthest targets, so that nobody has to pass
// through those who arrived. Lanes lead straight through the stairs, the pillars, the
// platform and the loose boxes, and three of them into the steep ramp; no target needs it.
// Characters block each other in both engines (Bullet's ghost objects see each other).
//
// Both engines get the same steering, once per step (steerCharacter): the velocity towards
// the target at 3 m/s (slower within 1.5 m, so as not to overshoot); after a second without
// half a metre of progress, a hop and 1.5 s at 75 degrees to one side, the side alternating.
// Bullet's controller takes the velocity as this step's walk (setWalkDirection(v dt)).
//
// Measured the same way for both engines, from the foot positions they report:
//   arrived_share    share of characters that came within 0.5 m of their target
//                    (horizontally) within the simulated time (30 s by default)
//   penetration_max  deepest overlap of a character's capsule with the course's fixed boxes
//                    (floor, stairs, ramp, plateau, pillars) at any step, m: the capsule's
//                    radius less the distance from its axis to the box (sampled at 17
//                    points along the axis, exact for the flat faces characters stand on)
//   fell_through     characters whose foot went below -0.3 m (the floor's top is at 0)
//   climbed_ramp     characters whose foot got over the steep ramp higher than 2.4 m or onto
//                    the plateau
//   ms_per_step      processor time of one step (pfx: controller update and world step;
//                    Bullet: stepSimulation, which runs the controllers), mean over the run,
//                    one thread
//   ms_per_step_median  its median
// The steering and the measuring are outside the timed part.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "bench_cli.h"
#include "bench_report.h"
#include "bench_scene.h"

namespace pfxbench {

constexpr const char* kCharactersSceneName = "characters";

constexpr double kCharacterRadius = 0.3;
constexpr double kCharacterHeight = 1.8;
constexpr double kCharacterStepHeight = 0.35;
constexpr double kCharacterMaxSlopeDegrees = 45;
constexpr double kCharacterJumpSpeed = 5;
constexpr double kCharacterMaxFallSpeed = 50;
constexpr double kCharacterWalkSpeed = 3;
constexpr double kCharacterGravity = 9.80665;
constexpr double kCharacterArrived = 0.5;
constexpr double kLooseBoxMass = 10;
constexpr double kCharacterSceneSeconds = 30;

struct CourseBox {
  Vec3 center = Vec3::Zero();
  Vec3 half = Vec3::Ones();
  Quat orientation = Quat::Identity();
};

// An area on the floor (X, Z) where a foot higher than `height` has climbed the steep ramp.
struct RampArea {
  double xMin = 0, xMax = 0, zMin = 0, zMax = 0, height = 0;
};

struct CharacterCourse {
  std::vector<CourseBox> fixedBoxes;  // the floor first
  std::vector<CourseBox> platforms;   // keyframe, at time 0
  std::vector<CourseBox> looseBoxes;  // kLooseBoxMass each
  std::vector<RampArea> rampAreas;    // the ramps and the plateaus behind them
  std::vector<Vec3> starts;           // feet, on the floor
  std::vector<Vec3> targets;
  Vec3 halfExtent = Vec3::Ones();  // a box about the origin that holds everything
};

// The course for `count` characters: one block per 100 (the last one partly filled).
CharacterCourse makeCharacterCourse(int count);

// Where platform `base` (its pose at time 0) is at time `t`: position and turn about Y.
void platformPose(const CourseBox& base, double t, Vec3& position, Quat& orientation);

// One engine's side of the scene: the course built, then stepped with the steering's
// commands. Each returns false with `error` when the engine rejected something.
class CharacterEngine {
 public:
  virtual ~CharacterEngine() = default;
  virtual bool build(const CharacterCourse& course, double dt, std::string& error) = 0;
  // The pose platform `index` is to reach over the next step.
  virtual void movePlatform(int index, const Vec3& position, const Quat& orientation) = 0;
  virtual void setDesiredVelocity(int character, const Vec3& velocity) = 0;
  virtual void jump(int character) = 0;
  // One step of dt: the controllers and the world; timed by the caller.
  virtual bool step(std::string& error) = 0;
  virtual Vec3 foot(int character) const = 0;
};

std::unique_ptr<CharacterEngine> makePfxCharacterEngine();
std::unique_ptr<CharacterEngine> makeBulletCharacterEngine();  // null without Bullet

struct CharacterFigures {
  double arrivedShare = 0;
  double lastArrival = 0;  // s, of those that arrived
  double penetrationMax = 0;
  int fellThrough = 0;
  int climbedRamp = 0;
  double msPerStepMean = 0;
  double msPerStepMedian = 0;
};

// Runs one engine on the course for `seconds` at `dt`.
bool runCharacterCourse(CharacterEngine& engine, const CharacterCourse& course, double dt,
                        double seconds, CharacterFigures& figures, std::string& error);

// Runs the scene for each count of --characters (100 and 1,000 by default), each engine of
// --engine that it knows (pfx and bullet by default) and each --dt (1/60 unless given) for
// --seconds (30 by default); appends its rows and prints a table on stderr. Returns the
// number of failed runs.
int runCharactersScene(const Options& options, std::vector<ResultRow>& rows);

}  // namespace pfxbench
