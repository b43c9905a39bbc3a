#include "bench_motors.h"

#include <algorithm>
#include <cmath>

namespace pfxbench {

MotorController::MotorController(const Scene& scene) : m_scene(scene) {
  for (const JointMotorDesc& motor : scene.motors) {
    const JointDesc& joint = scene.joints[motor.joint];
    const Quat a =
        joint.bodyA == kWorld ? Quat::Identity() : scene.bodies[joint.bodyA].orientation;
    const Quat b = scene.bodies[joint.bodyB].orientation;
    m_hinges.push_back({joint.bodyA, joint.bodyB, a.conjugate() * joint.axis.normalized(),
                        a.conjugate() * b});
  }
}

Quat MotorController::orientationOf(int body, const std::vector<BodyState>& states) const {
  return body == kWorld ? Quat::Identity() : states[body].orientation.normalized();
}

// B's turn in A's frame since the start is a rotation about the axis while the hinge holds;
// its twist about the axis is the angle even when the hinge has opened a little.
double MotorController::angle(int motor, const std::vector<BodyState>& states) const {
  const Hinge& h = m_hinges[motor];
  const Quat bInA = orientationOf(h.bodyA, states).conjugate() * orientationOf(h.bodyB, states);
  Quat turn = bInA * h.initialBInA.conjugate();
  if (turn.w() < 0) turn.coeffs() = -turn.coeffs();
  return 2 * std::atan2(turn.vec().dot(h.axisInA), turn.w());
}

void MotorController::commands(double time, const std::vector<BodyState>& states,
                               std::vector<double>& rates) const {
  rates.resize(m_scene.motors.size());
  for (std::size_t i = 0; i < m_scene.motors.size(); ++i) {
    const JointMotorDesc& motor = m_scene.motors[i];
    const double phase = motor.angularFrequency * time;
    const double reference = motor.amplitude * (1 - std::cos(phase));
    const double referenceRate = motor.amplitude * motor.angularFrequency * std::sin(phase);
    const double wanted =
        referenceRate + m_scene.motorGain * (reference - angle(static_cast<int>(i), states));
    rates[i] = std::clamp(wanted, -motor.maxSpeed, motor.maxSpeed);
  }
}

}  // namespace pfxbench
