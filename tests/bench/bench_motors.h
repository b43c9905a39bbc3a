// The commands of a scene's joint motors (JointMotorDesc), worked out by the benchmark from
// the body states an engine reports, so that every engine is driven by the same controller
// with the same gains and only its motor differs.
#pragma once

#include <vector>

#include "bench_engine.h"
#include "bench_scene.h"

namespace pfxbench {

class MotorController {
 public:
  explicit MotorController(const Scene& scene);

  // The target rate (rad/s) of every motor, in the order of Scene::motors, for the states
  // at `time` seconds into the run.
  void commands(double time, const std::vector<BodyState>& states, std::vector<double>& rates) const;

 private:
  struct Hinge {
    int bodyA;         // kWorld or a body
    int bodyB;
    Vec3 axisInA;      // the axis in A's frame (the world's for kWorld)
    Quat initialBInA;  // B's orientation in A's frame in the initial poses
  };
  Quat orientationOf(int body, const std::vector<BodyState>& states) const;
  // The angle (JointDesc's sign) of the hinge of a motor in the given states.
  double angle(int motor, const std::vector<BodyState>& states) const;

  const Scene& m_scene;
  std::vector<Hinge> m_hinges;  // one per motor
};

}  // namespace pfxbench
