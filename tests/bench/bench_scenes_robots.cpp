// The `robots` scene: many copies of the `urdf` scene's arm, each driven by its motors as
// there, with ragdolls (the `ragdoll` scene's) dropped onto them, in one world on a ground.
// Variants by the number of arms: 1, 4, 16 and 64, with a quarter as many ragdolls (one for
// a lone arm). The arms stand on a square grid; every second block of 2 x 2 arms, like the
// black squares of a chess board, gets a stack of two ragdolls lying flat across it, the
// lower one along one diagonal of the block and the upper one along the other, so that
// each falls on two arms and the upper one on the lower one too.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bench_scene.h"

namespace pfxbench {

namespace {

constexpr double kArmSpacing = 1.2;  // m between neighbouring arms' bases
// Centre heights of the lying ragdolls in a stack: the arm stands 1.13 m tall.
constexpr double kStackHeights[] = {1.6, 2.1};
// A ragdoll's middle between its soles and the top of its head, in its own frame.
constexpr double kRagdollMiddle = 0.86;
constexpr int kArmCounts[] = {1, 4, 16, 64};

Scene makeRobots(const Scene& arm, int arms) {
  Scene scene;
  scene.name = "robots";
  scene.variant = "arms" + std::to_string(arms);
  scene.duration = 4;
  scene.motorGain = arm.motorGain;
  scene.robots = arms;
  // No position_error: the ragdolls make every arm's path chaotic, and the reference run
  // (dt / 16, four times the iterations) would cost 64 times the run.
  scene.metrics = {Metric::JointGapMax, Metric::PenetrationMax, Metric::Escaped,
                   Metric::MsPerStep, Metric::MsPerStepPerRobot, Metric::CpuMsPerStepPerRobot};
  scene.speedLimit = 30;

  const int side = static_cast<int>(std::lround(std::sqrt(arms)));
  const double halfWidth = 0.5 * (side - 1) * kArmSpacing;
  scene.bodies.push_back(
      makeFixedBody(ShapeDesc::box(Vec3(halfWidth + 5, 1, halfWidth + 5)), Vec3(0, -1, 0)));
  for (int row = 0; row < side; ++row) {
    for (int column = 0; column < side; ++column) {
      appendScene(scene, arm,
                  Vec3(column * kArmSpacing - halfWidth, 0, row * kArmSpacing - halfWidth));
    }
  }

  const int ragdolls = std::max(1, arms / 4);
  const int blocks = std::max(1, side / 2);
  const Quat lieDown(Eigen::AngleAxisd(-0.5 * kPi, Vec3::UnitX()));
  int placed = 0;
  for (int row = 0; row < blocks; ++row) {
    for (int column = 0; column < blocks; ++column) {
      if ((row + column) % 2 != 0) continue;
      // Between the block's four arms; over the arm itself when it is alone.
      auto middleOf = [&](int block) {
        return side == 1 ? 0.0 : (2 * block + 0.5) * kArmSpacing - halfWidth;
      };
      const Vec3 centre(middleOf(column), 0, middleOf(row));
      for (int level = 0; level < 2 && placed < ragdolls; ++level, ++placed) {
        const Quat yaw(Eigen::AngleAxisd(0.25 * kPi + 0.5 * kPi * level, Vec3::UnitY()));
        const Quat turn = yaw * lieDown;
        const Vec3 middle = centre + Vec3(0, kStackHeights[level], 0);
        addRagdoll(scene, middle - turn * Vec3(0, kRagdollMiddle, 0), turn);
      }
    }
  }
  scene.keepInside.min = Vec3(-halfWidth - 4, -0.5, -halfWidth - 4);
  scene.keepInside.max = Vec3(halfWidth + 4, 10, halfWidth + 4);
  return scene;
}

}  // namespace

void buildRobotsScene(std::vector<Scene>& variants) {
  std::vector<Scene> urdf;
  buildUrdfScene(urdf);
  if (urdf.empty()) return;  // buildUrdfScene said why
  for (int arms : kArmCounts) variants.push_back(makeRobots(urdf.front(), arms));
}

}  // namespace pfxbench
