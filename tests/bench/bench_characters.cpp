#include "bench_characters.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "bench_run.h"

namespace pfxbench {

namespace {

constexpr double kDegree = kPi / 180;
constexpr int kLanes = 20;
constexpr int kRowsPerBlock = 5;
constexpr double kLaneWidth = 1.44;
constexpr double kRowSpacing = 1.2;
constexpr double kBlockHalfWidth = kLanes * kLaneWidth / 2;

// The steep ramp of a block: 50 degrees from x = kRampStart up to the plateau's edge.
constexpr double kRampAngle = 50 * kDegree;
constexpr double kRampStart = -1;
constexpr double kPlateauHeight = 2.5;
constexpr double kRampZ = -2, kRampHalfWidth = 1.5;
// A foot this high over the ramp has got up it (the sample's threshold).
constexpr double kUpTheRamp = kPlateauHeight - 0.1;
constexpr double kFellThrough = -0.3;

// The platform of a block at time 0, and how far and how fast it moves.
constexpr double kPlatformX = 6, kPlatformZ = 6, kPlatformHalf = 2, kPlatformHalfHeight = 0.1;
constexpr double kPlatformSlide = 2, kPlatformSlidePeriod = 8;
constexpr double kPlatformTurn = 0.5, kPlatformTurnPeriod = 10;

// Points sampled along a capsule's axis for the penetration metric.
constexpr int kAxisSamples = 17;

double rampRun() { return kPlateauHeight / std::tan(kRampAngle); }

Quat aboutY(double angle) { return Quat(Eigen::AngleAxisd(angle, Vec3::UnitY())); }

// A block's obstacles, its centre line at z = `zc`.
void addBlock(CharacterCourse& course, double zc, std::mt19937& rng) {
  auto fixed = [&](const Vec3& center, const Vec3& half, const Quat& q = Quat::Identity()) {
    course.fixedBoxes.push_back({center + Vec3(0, 0, zc), half, q});
  };
  // Staircase for z in [-12, -6]: four 0.25 m steps up to a 1 m landing, four down.
  for (int i = 0; i < 4; ++i) {
    const double top = 0.25 * (i + 1), depth = 0.4;
    fixed(Vec3(-8 + depth * (i + 0.5), top / 2, -9), Vec3(depth / 2, top / 2, 3));
    fixed(Vec3(-3.2 - depth * (i + 0.5), top / 2, -9), Vec3(depth / 2, top / 2, 3));
  }
  fixed(Vec3(-5.6, 0.5, -9), Vec3(0.8, 0.5, 3));
  // The steep ramp, 0.2 m thick, leaning on the plateau's west face.
  const Vec3 along(std::cos(kRampAngle), std::sin(kRampAngle), 0);
  const Vec3 normal(-std::sin(kRampAngle), std::cos(kRampAngle), 0);
  const double length = kPlateauHeight / std::sin(kRampAngle);
  fixed(Vec3(kRampStart, 0, kRampZ) + along * (length / 2) - normal * 0.1,
        Vec3(length / 2, 0.1, kRampHalfWidth), Quat(Eigen::AngleAxisd(kRampAngle, Vec3::UnitZ())));
  const double plateauX = kRampStart + rampRun() + 1;
  fixed(Vec3(plateauX, kPlateauHeight / 2, kRampZ), Vec3(1, kPlateauHeight / 2, kRampHalfWidth));
  course.rampAreas.push_back({kRampStart, plateauX + 1, zc + kRampZ - kRampHalfWidth,
                              zc + kRampZ + kRampHalfWidth, kUpTheRamp});
  for (const double z : {-4.5, 1.5, 4.5, 10.5}) {
    fixed(Vec3(-6 + std::abs(z) * 0.3, 1, z), Vec3(0.5, 1, 0.5));
  }
  course.platforms.push_back({Vec3(kPlatformX, kPlatformHalfHeight, kPlatformZ + zc),
                              Vec3(kPlatformHalf, kPlatformHalfHeight, kPlatformHalf)});
  // Loose boxes east of the plateau, none where the platform sweeps.
  std::uniform_real_distribution<double> unit(0, 1);
  const double sweep = kPlatformHalf * std::sqrt(2.0) + 0.5;
  for (int placed = 0; placed < 20;) {
    const double half = 0.2 + 0.1 * unit(rng);
    const double x = 4 + 8 * unit(rng);
    const double z = -kBlockHalfWidth + 2 * kBlockHalfWidth * unit(rng);
    const bool onPlatform =
        std::abs(z - kPlatformZ) < sweep && std::abs(x - kPlatformX) < kPlatformSlide + sweep;
    if (onPlatform) continue;
    course.looseBoxes.push_back({Vec3(x, half, z + zc), Vec3(half, half, half)});
    ++placed;
  }
}

// Distance from `p` to the box, negative inside (then minus the depth to the nearest face).
double signedDistance(const CourseBox& box, const Vec3& p) {
  const Vec3 local = box.orientation.conjugate() * (p - box.center);
  const Vec3 d = local.cwiseAbs() - box.half;
  const Vec3 outside = d.cwiseMax(0.0);
  return outside.norm() + std::min(d.maxCoeff(), 0.0);
}

// How deep a character's capsule (its foot at `foot`) overlaps the box; 0 when apart.
double capsulePenetration(const CourseBox& box, const Vec3& foot) {
  const Vec3 bottom = foot + Vec3(0, kCharacterRadius, 0);
  const double axis = kCharacterHeight - 2 * kCharacterRadius;
  double nearest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kAxisSamples; ++i) {
    const Vec3 p = bottom + Vec3(0, axis * i / (kAxisSamples - 1), 0);
    nearest = std::min(nearest, signedDistance(box, p));
  }
  return std::max(0.0, kCharacterRadius - nearest);
}

// A fixed box's bounds, grown by a capsule's radius, for a quick rejection.
struct Bounds {
  Vec3 lo, hi;
};
Bounds grownBounds(const CourseBox& box) {
  const Vec3 extent = box.orientation.toRotationMatrix().cwiseAbs() * box.half;
  const Vec3 margin = Vec3::Constant(kCharacterRadius + 0.01);
  return {box.center - extent - margin, box.center + extent + margin};
}

// The walker of one character; the same for every engine.
struct Walker {
  bool arrived = false;
  double arrivalTime = 0;
  double lastDistance = 1e9;
  double nextCheck = 1;
  double detourEnd = 0;
  double detourSide = 1;
  int detours = 0;
  bool fell = false;
  bool climbed = false;
};

Vec3 horizontal(const Vec3& v) { return Vec3(v.x(), 0, v.z()); }

// Straight at the target; after a second without half a metre of progress, a hop and 1.5 s
// at 75 degrees to one side. Returns the desired velocity; sets `hop`.
Vec3 steerCharacter(int index, Walker& walker, const Vec3& foot, const Vec3& target, double time,
                    bool& hop) {
  hop = false;
  const Vec3 toTarget = horizontal(target - foot);
  const double distance = toTarget.norm();
  if (distance < kCharacterArrived) return Vec3::Zero();
  if (time >= walker.nextCheck) {
    if (walker.lastDistance - distance < 0.5 && time >= walker.detourEnd) {
      walker.detourEnd = time + 1.5;
      walker.detourSide = (index + walker.detours) % 2 == 0 ? 1.0 : -1.0;
      ++walker.detours;
      hop = true;
    }
    walker.lastDistance = distance;
    walker.nextCheck = time + 1;
  }
  Vec3 direction = toTarget / distance;
  if (time < walker.detourEnd) direction = aboutY(walker.detourSide * 75 * kDegree) * direction;
  return direction * std::min(kCharacterWalkSpeed, 2 * distance);
}

}  // namespace

CharacterCourse makeCharacterCourse(int count) {
  CharacterCourse course;
  const int perBlock = kLanes * kRowsPerBlock;
  const int blocks = std::max(1, (count + perBlock - 1) / perBlock);
  const double halfZ = blocks * kBlockHalfWidth;
  course.halfExtent = Vec3(40, 20, halfZ + 10);
  course.fixedBoxes.push_back({Vec3(0, -0.5, 0), Vec3(35, 0.5, halfZ + 5)});
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> laneShift(-3, 3);
  for (int b = 0; b < blocks; ++b) {
    const double zc = -halfZ + kBlockHalfWidth * (2 * b + 1);
    addBlock(course, zc, rng);
  }
  for (int i = 0; i < count; ++i) {
    const int block = i / perBlock, row = (i % perBlock) / kLanes, lane = i % kLanes;
    const double zc = -halfZ + kBlockHalfWidth * (2 * block + 1);
    auto laneZ = [&](int l) { return zc - kBlockHalfWidth + kLaneWidth * (l + 0.5); };
    course.starts.push_back(Vec3(-14 - kRowSpacing * row, 0, laneZ(lane)));
    const int targetLane = std::clamp(lane + laneShift(rng), 0, kLanes - 1);
    course.targets.push_back(Vec3(18 + 2.0 * (kRowsPerBlock - 1 - row), 0, laneZ(targetLane)));
  }
  return course;
}

void platformPose(const CourseBox& base, double t, Vec3& position, Quat& orientation) {
  position =
      base.center + Vec3(kPlatformSlide * std::sin(2 * kPi * t / kPlatformSlidePeriod), 0, 0);
  orientation = aboutY(kPlatformTurn * std::sin(2 * kPi * t / kPlatformTurnPeriod));
}

bool runCharacterCourse(CharacterEngine& engine, const CharacterCourse& course, double dt,
                        double seconds, CharacterFigures& figures, std::string& error) {
  if (!engine.build(course, dt, error)) return false;
  const int count = int(course.starts.size());
  std::vector<Walker> walkers(count);
  std::vector<Bounds> bounds;
  for (const CourseBox& box : course.fixedBoxes) bounds.push_back(grownBounds(box));
  const int steps = int(std::lround(seconds / dt));
  std::vector<double> stepSeconds;
  stepSeconds.reserve(steps);
  figures = CharacterFigures();
  double time = 0;
  for (int step = 0; step < steps; ++step) {
    time = (step + 1) * dt;
    for (std::size_t p = 0; p < course.platforms.size(); ++p) {
      Vec3 position;
      Quat orientation;
      platformPose(course.platforms[p], time, position, orientation);
      engine.movePlatform(int(p), position, orientation);
    }
    for (int i = 0; i < count; ++i) {
      bool hop = false;
      const Vec3 desired =
          steerCharacter(i, walkers[i], engine.foot(i), course.targets[i], time, hop);
      if (!walkers[i].arrived && desired.isZero()) {
        walkers[i].arrived = true;
        walkers[i].arrivalTime = time;
      }
      engine.setDesiredVelocity(i, desired);
      if (hop) engine.jump(i);
    }
    const double start = processCpuSeconds();
    if (!engine.step(error)) return false;
    stepSeconds.push_back(processCpuSeconds() - start);
    for (int i = 0; i < count; ++i) {
      const Vec3 foot = engine.foot(i);
      if (!foot.allFinite()) {
        error = "character " + std::to_string(i) + " has a non-finite position";
        return false;
      }
      Walker& walker = walkers[i];
      walker.fell = walker.fell || foot.y() < kFellThrough;
      for (const RampArea& ramp : course.rampAreas) {
        if (foot.x() > ramp.xMin && foot.x() < ramp.xMax && foot.z() > ramp.zMin &&
            foot.z() < ramp.zMax && foot.y() > ramp.height) {
          walker.climbed = true;
        }
      }
      const Vec3 lo = foot, hi = foot + Vec3(0, kCharacterHeight, 0);
      for (std::size_t b = 0; b < bounds.size(); ++b) {
        if ((hi.array() < bounds[b].lo.array()).any() ||
            (lo.array() > bounds[b].hi.array()).any()) {
          continue;
        }
        figures.penetrationMax =
            std::max(figures.penetrationMax, capsulePenetration(course.fixedBoxes[b], foot));
      }
    }
  }
  int arrived = 0;
  for (const Walker& walker : walkers) {
    if (walker.arrived) {
      ++arrived;
      figures.lastArrival = std::max(figures.lastArrival, walker.arrivalTime);
    }
    if (walker.fell) ++figures.fellThrough;
    if (walker.climbed) ++figures.climbedRamp;
  }
  figures.arrivedShare = count > 0 ? double(arrived) / count : 1;
  double total = 0;
  for (const double s : stepSeconds) total += s;
  figures.msPerStepMean = stepSeconds.empty() ? 0 : 1e3 * total / double(stepSeconds.size());
  if (!stepSeconds.empty()) {
    std::nth_element(stepSeconds.begin(), stepSeconds.begin() + stepSeconds.size() / 2,
                     stepSeconds.end());
    figures.msPerStepMedian = 1e3 * stepSeconds[stepSeconds.size() / 2];
  }
  return true;
}

int runCharactersScene(const Options& options, std::vector<ResultRow>& rows) {
  struct EngineSide {
    const char* name;
    std::unique_ptr<CharacterEngine> (*make)();
  };
  std::vector<EngineSide> engines;
  for (const EngineSide& side : {EngineSide{"pfx", makePfxCharacterEngine},
                                 EngineSide{"bullet", makeBulletCharacterEngine}}) {
    const bool asked = options.engines.empty() ||
                       std::find(options.engines.begin(), options.engines.end(), side.name) !=
                           options.engines.end();
    if (!asked) continue;
    if (!side.make()) {
      std::fprintf(stderr, "characters %s: skipped, its library was not found\n", side.name);
      continue;
    }
    engines.push_back(side);
  }
  if (engines.empty()) {
    std::fprintf(stderr, "characters: skipped, it runs pfx and bullet only\n");
    return 0;
  }
  const std::vector<double> timeSteps =
      options.timeStepsGiven ? options.timeSteps : std::vector<double>{1.0 / 60};
  const double seconds = options.seconds > 0 ? options.seconds : kCharacterSceneSeconds;

  struct Column {
    std::string label;
    CharacterFigures figures;
  };
  std::vector<Column> columns;
  int failures = 0;
  for (const int count : options.characterCounts) {
    const CharacterCourse course = makeCharacterCourse(count);
    for (const double dt : timeSteps) {
      for (const EngineSide& side : engines) {
        std::unique_ptr<CharacterEngine> engine = side.make();
        CharacterFigures figures;
        std::string error;
        char label[96];
        std::snprintf(label, sizeof(label), "%s %d dt=%.4g", side.name, count, dt);
        std::fprintf(stderr, "characters %s: running %.0f s...\n", label, seconds);
        if (!runCharacterCourse(*engine, course, dt, seconds, figures, error)) {
          std::fprintf(stderr, "characters %s: FAILED: %s\n", label, error.c_str());
          ++failures;
          continue;
        }
        // pfx's aim on this course: everyone arrives, nobody falls through or climbs the
        // ramp. The peer's figures are reported as they are.
        const bool pfxMissed =
            std::string(side.name) == "pfx" &&
            (figures.arrivedShare < 1 || figures.fellThrough > 0 || figures.climbedRamp > 0);
        if (pfxMissed) {
          std::fprintf(stderr, "characters %s: NOT every character arrived safely\n", label);
          ++failures;
        }
        const std::string variant = std::to_string(count);
        const double wallPerSim = figures.msPerStepMean * 1e-3 / dt;
        auto row = [&](const char* metric, double value) {
          rows.push_back(
              {kCharactersSceneName, side.name, variant, dt, 1, 10, 1, wallPerSim, metric, value});
        };
        row("arrived_share", figures.arrivedShare);
        row("last_arrival_s", figures.lastArrival);
        row("penetration_max", figures.penetrationMax);
        row("fell_through", figures.fellThrough);
        row("climbed_ramp", figures.climbedRamp);
        row("ms_per_step", figures.msPerStepMean);
        row("ms_per_step_median", figures.msPerStepMedian);
        columns.push_back({label, figures});
      }
    }
  }

  // The table: one column per run.
  if (columns.empty()) return failures;
  std::fprintf(stderr, "\ncharacters, %.0f s simulated, one thread\n%-26s", seconds, "");
  for (const Column& c : columns) std::fprintf(stderr, " %18s", c.label.c_str());
  std::fprintf(stderr, "\n");
  auto line = [&](const char* name, auto value, const char* format) {
    std::fprintf(stderr, "%-26s", name);
    for (const Column& c : columns) std::fprintf(stderr, format, value(c.figures));
    std::fprintf(stderr, "\n");
  };
  line(
      "reached target (share)", [](const CharacterFigures& f) { return f.arrivedShare; },
      " %18.3f");
  line(
      "last arrival (s)", [](const CharacterFigures& f) { return f.lastArrival; }, " %18.1f");
  line(
      "deepest penetration (m)", [](const CharacterFigures& f) { return f.penetrationMax; },
      " %18.4f");
  line(
      "fell through floor", [](const CharacterFigures& f) { return f.fellThrough; }, " %18d");
  line(
      "climbed steep ramp", [](const CharacterFigures& f) { return f.climbedRamp; }, " %18d");
  line(
      "CPU ms per step (mean)", [](const CharacterFigures& f) { return f.msPerStepMean; },
      " %18.3f");
  line(
      "CPU ms per step (median)", [](const CharacterFigures& f) { return f.msPerStepMedian; },
      " %18.3f");
  return failures;
}

}  // namespace pfxbench
