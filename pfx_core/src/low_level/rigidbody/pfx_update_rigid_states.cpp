#include "pfx/low_level/rigidbody/pfx_update_rigid_states.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

// Rotation by the rotation vector `v` (exact exponential map).
PfxQuat rotationFromVector(const PfxVector3& v) {
  const PfxFloat angle = v.norm();
  if (angle < PfxFloat(1e-12)) {
    return PfxQuat(PfxFloat(1), v[0] * PfxFloat(0.5), v[1] * PfxFloat(0.5), v[2] * PfxFloat(0.5))
        .normalized();
  }
  return PfxQuat(Eigen::AngleAxis<PfxFloat>(angle, v / angle));
}

// See pfxIntegrate: the largest angle one part of the splitting turns a body by, and a
// cap on the parts so that a body spun absurdly fast costs a bounded time.
constexpr PfxFloat kMaxSplitAngle = PfxFloat(0.2);
constexpr int kMaxSplitParts = 64;

constexpr PfxUInt32 kIntegratedBodiesPerTask = 256;

bool isDiagonal(const PfxMatrix3& m) {
  return m(0, 1) == 0 && m(0, 2) == 0 && m(1, 2) == 0 && m(1, 0) == 0 && m(2, 0) == 0 &&
         m(2, 1) == 0;
}

// The free rigid body in its principal frame, advanced by h and split into exact rotations
// about the principal axes, 0 (h/2), 1 (h/2), 2 (h), 1 (h/2), 0 (h/2): each keeps |momentum|
// and the world momentum exactly, and the symmetric composition is second order and
// time-reversible. The frame's turn accumulates in `turn` and the body momentum's change in
// `momentumChange`, both kept as increments: the caller adds them to a state far larger
// than they are, and a step that recomputed the whole state from rotated copies of it
// would round it afresh every step.
void advanceFreeRotation(PfxQuat& turn, PfxVector3& momentumChange,
                         const PfxVector3& momentum, const PfxVector3& principalInertia,
                         PfxFloat h) {
  static constexpr int kAxes[5] = {0, 1, 2, 1, 0};
  static constexpr PfxFloat kFractions[5] = {0.5f, 0.5f, 1.0f, 0.5f, 0.5f};
  for (int s = 0; s < 5; ++s) {
    const int axis = kAxes[s], next = (axis + 1) % 3, last = (axis + 2) % 3;
    const PfxVector3 current = momentum + momentumChange;
    const PfxFloat halfAngle =
        h * kFractions[s] * current[axis] / principalInertia[axis] * PfxFloat(0.5);
    const PfxFloat sinHalf = std::sin(halfAngle), cosHalf = std::cos(halfAngle);
    PfxQuat step(cosHalf, 0, 0, 0);
    step.vec()[axis] = sinHalf;
    turn = turn * step;
    // The momentum seen from the turned frame, as its change: 1 - cos(angle) written as
    // 2 sin^2(angle / 2), which keeps its digits where cos(angle) rounds to 1.
    const PfxFloat sine = 2 * sinHalf * cosHalf, oneMinusCosine = 2 * sinHalf * sinHalf;
    momentumChange[next] += sine * current[last] - oneMinusCosine * current[next];
    momentumChange[last] -= sine * current[next] + oneMinusCosine * current[last];
  }
}

// q v q^-1 - v for a unit q, without forming v first.
PfxVector3 rotationChange(const PfxQuat& q, const PfxVector3& v) {
  const PfxVector3 twice = 2 * q.vec().cross(v);
  return q.w() * twice + q.vec().cross(twice);
}

// value + (change + carry), rounded into `value`, with what that rounding left out in
// `carry` (Knuth's two-sum, exact whatever the magnitudes). A step's change to a spinning body is
// small beside its state, and the rounding of each sum, one half unit in the last place,
// would otherwise pile up over the steps: more of them, the smaller the step.
template <typename Value, typename Carry, typename Change>
void addCompensated(Value& value, Carry& carry, const Change& change) {
  for (Eigen::Index i = 0; i < value.size(); ++i) {
    const PfxFloat added = change[i] + carry[i];
    const PfxFloat sum = value[i] + added;
    const PfxFloat addedPart = sum - value[i];
    const PfxFloat valuePart = sum - addedPart;
    carry[i] = (value[i] - valuePart) + (added - addedPart);
    value[i] = sum;
  }
}

}  // namespace

void pfxIntegrate(PfxRigidState& state, const PfxRigidBody& body, PfxFloat timeStep) {
  const PfxMotionType type = state.getMotionType();
  if (state.isAsleep() || type == kPfxMotionTypeFixed || type == kPfxMotionTypeTrigger) return;

  state.setPosition(state.getPosition() + state.getLinearVelocity() * timeStep);

  const PfxVector3& omega = state.getAngularVelocity();
  if (type == kPfxMotionTypeKeyframe) {
    state.setOrientation((rotationFromVector(omega * timeStep) * state.getOrientation()).normalized());
    return;
  }

  // Principal frame of the inertia: body = principal * axes. Shape inertias are usually
  // diagonal already, which saves the eigen-decomposition.
  const PfxMatrix3& inertia = body.getInertia();
  PfxVector3 principalInertia;
  PfxQuat axes = PfxQuat::Identity();
  if (isDiagonal(inertia)) {
    principalInertia = inertia.diagonal();
  } else {
    const Eigen::SelfAdjointEigenSolver<PfxMatrix3> eig(inertia);
    PfxMatrix3 vectors = eig.eigenvectors();
    if (vectors.determinant() < 0) vectors.col(2) = -vectors.col(2);
    principalInertia = eig.eigenvalues();
    axes = PfxQuat(vectors);
  }

  const PfxQuat frame = state.getOrientation() * axes;
  const PfxVector3 bodyOmega = frame.conjugate() * omega;
  const PfxVector3 momentum = principalInertia.cwiseProduct(bodyOmega);
  // The splitting's energy error is bounded but grows with the square of the angle turned
  // per step: a box tumbling at 100 rad/s turns 1.7 rad per 1/60 s step, and its energy
  // swings by -6 % to +26 % (without drifting) over 100 s. Splitting the step so that no
  // part turns more than kMaxSplitAngle keeps that swing near 0.1 %; bodies turning slower
  // (below 12 rad/s at 1/60 s) still take one part. The bound on the rate, |L| / I_min,
  // is kept by the free motion, so a tumbling body keeps its number of parts: parts that
  // changed from step to step as the spin moves between axes would break the symmetry of
  // the scheme, and the energy would drift (by 15 % in 100 s, measured).
  const PfxFloat stepAngle = momentum.norm() / principalInertia.minCoeff() * timeStep;
  // Compared before the conversion to int, which is undefined for a turn beyond int's range.
  const int parts = stepAngle < kMaxSplitParts * kMaxSplitAngle
                        ? std::max(1, int(std::ceil(stepAngle / kMaxSplitAngle)))
                        : kMaxSplitParts;
  PfxQuat turn = PfxQuat::Identity();
  PfxVector3 momentumChange = PfxVector3::Zero();
  for (int part = 0; part < parts; ++part) {
    advanceFreeRotation(turn, momentumChange, momentum, principalInertia,
                        timeStep / PfxFloat(parts));
    // rotationChange below takes `turn` as a unit quaternion; up to 320 products of a
    // fast spinner's parts would move it off by their round-off.
    turn.normalize();
  }

  // The new orientation, frame * turn * axes^-1, and the new velocity, frame * turn *
  // (bodyOmega + omegaChange), are added to the old ones as their differences from them,
  // with the carries of the last step's rounding (addCompensated): a spin that barely
  // changes keeps its bits instead of taking each step's round-off of a full rotation, and
  // the round-off of the sums does not pile up, so a spinner's momentum drift does not
  // grow with the number of steps.
  PfxQuat turnChange = turn;
  turnChange.w() -= 1;
  PfxQuat orientation = state.getOrientation();
  PfxQuat orientationCarry = state.getOrientationCarry();
  addCompensated(orientation.coeffs(), orientationCarry.coeffs(),
                 (frame * turnChange * axes.conjugate()).coeffs());
  // Back to unit length, as a change too. The length comes from the rounded value: its
  // error, as the rounding's, is a scale, which the next step measures and takes out again.
  const PfxVector4 toUnit = orientation.coeffs() * (1 / orientation.norm() - 1);
  addCompensated(orientation.coeffs(), orientationCarry.coeffs(), toUnit);

  const PfxVector3 omegaChange = momentumChange.cwiseQuotient(principalInertia);
  PfxVector3 angularVelocity = omega;
  PfxVector3 angularVelocityCarry = state.getAngularVelocityCarry();
  addCompensated(angularVelocity, angularVelocityCarry,
                 PfxVector3(frame * (rotationChange(turn, bodyOmega + omegaChange) + omegaChange)));
  state.setRotation(orientation, orientationCarry, angularVelocity, angularVelocityCarry);
}

PfxInt32 pfxUpdateRigidStates(const PfxUpdateRigidStatesParam& param,
                              PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxUpdateRigidStates", "PfxUpdateRigidStatesParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at, {{param.states, "states"}, {param.bodies, "bodies"}},
                              "numRigidBodies", param.numRigidBodies)) != PFX_OK ||
      (err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK) {
    return err;
  }
  pfxParallelFor(taskManager, param.numRigidBodies, kIntegratedBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     pfxIntegrate(param.states[i], param.bodies[i], param.timeStep);
                   }
                 });
  return PFX_OK;
}

}  // namespace pfx
