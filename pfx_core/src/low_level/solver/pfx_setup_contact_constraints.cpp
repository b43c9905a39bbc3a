#include "pfx/low_level/solver/pfx_setup_contact_constraints.h"

#include <cmath>
#include <limits>

#include "low_level/solver/pfx_constraint_row_solver.h"

namespace pfx {

namespace {

PfxVector3 pointVelocity(const PfxRigidState& s, const PfxVector3& arm) {
  return s.getLinearVelocity() + s.getAngularVelocity().cross(arm);
}

void setupPoint(PfxContactPoint& cp, const PfxRigidState& stateA, const PfxSolverBody& bodyA, PfxFloat receivesA,
                const PfxRigidState& stateB, const PfxSolverBody& bodyB, PfxFloat receivesB,
                const PfxSetupContactConstraintsParam& param) {
  cp.m_armA = stateA.getOrientation() * cp.m_localPointA;
  cp.m_armB = stateB.getOrientation() * cp.m_localPointB;
  const PfxVector3 relativeVelocity =
      pointVelocity(stateB, cp.m_armB) - pointVelocity(stateA, cp.m_armA);

  PfxConstraintRow& normalRow = cp.m_constraintRow[0];
  const PfxVector3 normal = normalRow.m_normal;
  const PfxFloat normalVelocity = normal.dot(relativeVelocity);
  cp.m_approachVelocity = normalVelocity;
  cp.m_maxImpulse = 0;

  // A speculative contact lets the bodies close the gap within the step but no further;
  // an overlap beyond the slop is pushed out by a fraction per step.
  const PfxFloat targetVelocity =
      cp.m_distance > 0
          ? -cp.m_distance / param.timeStep
          : param.separateBias * std::max(PfxFloat(0), -cp.m_distance - param.contactSlop) /
                param.timeStep;
  normalRow.m_jacDiagInv =
      pfxCalcJacDiagInv(normal, bodyA, cp.m_armA, receivesA, bodyB, cp.m_armB, receivesB);
  normalRow.m_rhs = (targetVelocity - normalVelocity) * normalRow.m_jacDiagInv;
  normalRow.m_lowerLimit = 0;
  normalRow.m_upperLimit = std::numeric_limits<PfxFloat>::max();
  normalRow.m_accumImpulse *= param.warmStartFactor;

  PfxVector3 tangents[2];
  pfxGetPlaneSpace(normal, tangents[0], tangents[1]);
  for (int k = 0; k < 2; ++k) {
    PfxConstraintRow& row = cp.m_constraintRow[1 + k];
    row.m_normal = tangents[k];
    row.m_jacDiagInv =
        pfxCalcJacDiagInv(tangents[k], bodyA, cp.m_armA, receivesA, bodyB, cp.m_armB, receivesB);
    row.m_rhs = -tangents[k].dot(relativeVelocity) * row.m_jacDiagInv;
    // The friction limits follow the normal impulse during the iterations.
    row.m_lowerLimit = 0;
    row.m_upperLimit = 0;
    row.m_accumImpulse *= param.warmStartFactor;
  }
}

}  // namespace

PfxInt32 pfxSetupContactConstraints(const PfxSetupContactConstraintsParam& param) {
  if (param.numContactPairs > 0 &&
      (!param.contactPairs || !param.offsetContactManifolds || !param.offsetRigidStates ||
       !param.offsetRigidBodies || !param.offsetSolverBodies)) {
    return PFX_ERR_NULL_POINTER;
  }
  if (!(param.timeStep > 0) || !pfxIsFinite(param.timeStep) || !(param.separateBias >= 0) ||
      !(param.contactSlop >= 0) || !(param.warmStartFactor >= 0)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (!pfxPairsInRange(param.contactPairs, param.numContactPairs, param.numRigidBodies,
                       param.numContactManifolds)) {
    return PFX_ERR_OUT_OF_RANGE;
  }

  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    const PfxConstraintPair& pair = param.contactPairs[i];
    if (!pfxGetActive(pair)) continue;
    PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
    if (manifold.getNumContacts() == 0) continue;
    const PfxUInt32 idA = pfxGetObjectIdA(pair);
    const PfxUInt32 idB = pfxGetObjectIdB(pair);
    const PfxRigidBody& bodyA = param.offsetRigidBodies[idA];
    const PfxRigidBody& bodyB = param.offsetRigidBodies[idB];
    manifold.setCompositeFriction(std::sqrt(bodyA.getFriction() * bodyB.getFriction()));
    manifold.setCompositeRestitution(std::max(bodyA.getRestitution(), bodyB.getRestitution()));
    const PfxFloat receivesA = pfxGetReceivesA(pair) ? 1 : 0;
    const PfxFloat receivesB = pfxGetReceivesB(pair) ? 1 : 0;
    for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
      setupPoint(manifold.getContactPoint(c), param.offsetRigidStates[idA],
                 param.offsetSolverBodies[idA], receivesA, param.offsetRigidStates[idB],
                 param.offsetSolverBodies[idB], receivesB, param);
    }
  }
  return PFX_OK;
}

}  // namespace pfx
