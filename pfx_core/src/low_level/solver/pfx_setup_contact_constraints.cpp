#include "pfx/low_level/solver/pfx_setup_contact_constraints.h"

#include <cmath>
#include <limits>

#include "low_level/pfx_param_checks.h"
#include "low_level/solver/pfx_constraint_row_solver.h"

namespace pfx {

namespace {

PfxVector3 pointVelocity(const PfxRigidState& s, const PfxVector3& arm) {
  return s.getLinearVelocity() + s.getAngularVelocity().cross(arm);
}

void setupPoint(PfxContactPoint& cp, const PfxRigidState& stateA, const PfxSolverBody& bodyA, PfxFloat receivesA,
                const PfxRigidState& stateB, const PfxSolverBody& bodyB, PfxFloat receivesB,
                const PfxSetupContactConstraintsParam& param) {
  // Both bodies are pushed at one point, midway between their surfaces: impulses at two
  // different points would form a couple and create angular momentum from nothing.
  const PfxVector3 pointA = stateA.getPosition() + stateA.getOrientation() * cp.m_localPointA;
  const PfxVector3 pointB = stateB.getPosition() + stateB.getOrientation() * cp.m_localPointB;
  const PfxVector3 midpoint = PfxFloat(0.5) * (pointA + pointB);
  cp.m_armA = midpoint - stateA.getPosition();
  cp.m_armB = midpoint - stateB.getPosition();
  // The separation at the current poses, which may have moved since the points were found
  // (sub-steps share one collision detection).
  cp.m_distance = cp.getNormal().dot(pointB - pointA);
  const PfxVector3 relativeVelocity =
      pointVelocity(stateB, cp.m_armB) - pointVelocity(stateA, cp.m_armA);

  PfxConstraintRow& normalRow = cp.m_constraintRow[0];
  const PfxVector3 normal = normalRow.m_normal;
  const PfxFloat normalVelocity = normal.dot(relativeVelocity);
  cp.m_approachVelocity = normalVelocity;
  cp.m_maxImpulse = 0;

  // A speculative contact lets the bodies close the gap within the step but no further.
  // An overlap beyond the slop is pushed out by a fraction per step through the split
  // impulse, which moves the bodies but leaves their velocities alone.
  const PfxFloat targetVelocity = cp.m_distance > 0 ? -cp.m_distance / param.timeStep : 0;
  normalRow.m_jacDiagInv =
      pfxCalcJacDiagInv(normal, bodyA, cp.m_armA, receivesA, bodyB, cp.m_armB, receivesB);
  normalRow.m_rhs = (targetVelocity - normalVelocity) * normalRow.m_jacDiagInv;
  const PfxFloat overlap = std::max(PfxFloat(0), -cp.m_distance - param.contactSlop);
  cp.m_pushRhs = param.separateBias * overlap / param.timeStep * normalRow.m_jacDiagInv;
  cp.m_pushImpulse = 0;
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
    // The solver clamps both friction rows together to the friction circle.
    row.m_lowerLimit = 0;
    row.m_upperLimit = 0;
    row.m_accumImpulse *= param.warmStartFactor;
  }
}

// K_ij = J_i M^-1 J_j^T over the normal rows of one manifold.
void setupNormalCoupling(PfxContactManifold& manifold, const PfxSolverBody& a, PfxFloat receivesA,
                         const PfxSolverBody& b, PfxFloat receivesB) {
  const PfxUInt32 n = manifold.getNumContacts();
  PfxVector3 angularA[PFX_NUM_CONTACTS_PER_MANIFOLD];
  PfxVector3 angularB[PFX_NUM_CONTACTS_PER_MANIFOLD];
  PfxVector3 torqueA[PFX_NUM_CONTACTS_PER_MANIFOLD];
  PfxVector3 torqueB[PFX_NUM_CONTACTS_PER_MANIFOLD];
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    torqueA[i] = cp.m_armA.cross(cp.getNormal());
    torqueB[i] = cp.m_armB.cross(cp.getNormal());
    angularA[i] = receivesA * (a.m_inertiaInv * torqueA[i]);
    angularB[i] = receivesB * (b.m_inertiaInv * torqueB[i]);
  }
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxVector3& ni = manifold.getContactPoint(i).getNormal();
    for (PfxUInt32 j = i; j < n; ++j) {
      const PfxFloat linear = ni.dot(manifold.getContactPoint(j).getNormal()) *
                              (receivesA * a.m_massInv + receivesB * b.m_massInv);
      const PfxFloat k = linear + torqueA[i].dot(angularA[j]) + torqueB[i].dot(angularB[j]);
      manifold.setNormalCoupling(i, j, k);
      manifold.setNormalCoupling(j, i, k);
    }
  }
}

constexpr PfxUInt32 kSetUpPairsPerTask = 128;

void setupPair(const PfxSetupContactConstraintsParam& param, const PfxConstraintPair& pair) {
  if (!pfxGetActive(pair)) return;
  PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
  if (manifold.getNumContacts() == 0) return;
  const PfxUInt32 idA = pfxGetObjectIdA(pair);
  const PfxUInt32 idB = pfxGetObjectIdB(pair);
  const PfxRigidBody& bodyA = param.offsetRigidBodies[idA];
  const PfxRigidBody& bodyB = param.offsetRigidBodies[idB];
  manifold.setCompositeFriction(std::sqrt(bodyA.getFriction() * bodyB.getFriction()));
  manifold.setCompositeRestitution(std::max(bodyA.getRestitution(), bodyB.getRestitution()));
  const PfxFloat receivesA = pfxGetReceivesA(pair) ? 1 : 0;
  const PfxFloat receivesB = pfxGetReceivesB(pair) ? 1 : 0;
  const PfxSolverBody& solverA = param.offsetSolverBodies[idA];
  const PfxSolverBody& solverB = param.offsetSolverBodies[idB];
  for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
    setupPoint(manifold.getContactPoint(c), param.offsetRigidStates[idA], solverA, receivesA,
               param.offsetRigidStates[idB], solverB, receivesB, param);
  }
  setupNormalCoupling(manifold, solverA, receivesA, solverB, receivesB);
}

}  // namespace

PfxInt32 pfxSetupContactConstraints(const PfxSetupContactConstraintsParam& param,
                                    PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxSetupContactConstraints", "PfxSetupContactConstraintsParam"};
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.contactPairs, "contactPairs"},
                               {param.offsetContactManifolds, "offsetContactManifolds"},
                               {param.offsetRigidStates, "offsetRigidStates"},
                               {param.offsetRigidBodies, "offsetRigidBodies"},
                               {param.offsetSolverBodies, "offsetSolverBodies"}},
                              "numContactPairs", param.numContactPairs)) != PFX_OK ||
      (err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckValue(at, "separateBias", param.separateBias, param.separateBias >= 0,
                           "not negative")) != PFX_OK ||
      (err = pfxCheckValue(at, "contactSlop", param.contactSlop, param.contactSlop >= 0,
                           "not negative")) != PFX_OK ||
      (err = pfxCheckValue(at, "warmStartFactor", param.warmStartFactor,
                           param.warmStartFactor >= 0, "not negative")) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "contactPairs", param.contactPairs, param.numContactPairs,
                                  param.numRigidBodies, "numContactManifolds",
                                  param.numContactManifolds)) != PFX_OK) {
    return err;
  }

  pfxParallelFor(taskManager, param.numContactPairs, kSetUpPairsPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) setupPair(param, param.contactPairs[i]);
                 });
  return PFX_OK;
}

}  // namespace pfx
