#include "pfx/low_level/solver/pfx_solve_constraints.h"

#include "low_level/solver/pfx_constraint_row_solver.h"

namespace pfx {

namespace {

struct PairBodies {
  PfxSolverBody& a;
  PfxSolverBody& b;
  PfxFloat receivesA;
  PfxFloat receivesB;
};

PairBodies bodiesOf(const PfxConstraintPair& pair, PfxSolverBody* solverBodies) {
  return {solverBodies[pfxGetObjectIdA(pair)], solverBodies[pfxGetObjectIdB(pair)],
          pfxGetReceivesA(pair) ? PfxFloat(1) : PfxFloat(0),
          pfxGetReceivesB(pair) ? PfxFloat(1) : PfxFloat(0)};
}

void warmStart(PfxContactManifold& manifold, const PairBodies& p) {
  for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
    PfxContactPoint& cp = manifold.getContactPoint(c);
    for (const PfxConstraintRow& row : cp.m_constraintRow) {
      pfxApplyRowImpulse(row.m_normal, row.m_accumImpulse, p.a, cp.m_armA, p.receivesA, p.b,
                         cp.m_armB, p.receivesB);
    }
  }
}

void solveContacts(PfxContactManifold& manifold, const PairBodies& p) {
  const PfxFloat friction = manifold.getCompositeFriction();
  for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
    PfxContactPoint& cp = manifold.getContactPoint(c);
    PfxConstraintRow& normalRow = cp.m_constraintRow[0];
    pfxSolveRow(normalRow, p.a, cp.m_armA, p.receivesA, p.b, cp.m_armB, p.receivesB);
    cp.m_maxImpulse = std::max(cp.m_maxImpulse, normalRow.m_accumImpulse);
    const PfxFloat limit = friction * normalRow.m_accumImpulse;
    for (int k = 1; k < 3; ++k) {
      PfxConstraintRow& row = cp.m_constraintRow[k];
      row.m_lowerLimit = -limit;
      row.m_upperLimit = limit;
      pfxSolveRow(row, p.a, cp.m_armA, p.receivesA, p.b, cp.m_armB, p.receivesB);
    }
  }
}

// After the iterations, points that were hit faster than the threshold and did push get
// the restitution target: a normal velocity of -e times the approach velocity.
void applyRestitution(PfxContactManifold& manifold, const PairBodies& p, PfxFloat threshold) {
  const PfxFloat restitution = manifold.getCompositeRestitution();
  if (restitution <= 0) return;
  for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
    PfxContactPoint& cp = manifold.getContactPoint(c);
    if (cp.m_approachVelocity > -threshold || cp.m_maxImpulse <= 0) continue;
    PfxConstraintRow& row = cp.m_constraintRow[0];
    const PfxFloat normalVelocity =
        cp.m_approachVelocity +
        row.m_normal.dot(pfxRelativeDeltaVelocity(p.a, cp.m_armA, p.b, cp.m_armB));
    const PfxFloat target = -restitution * cp.m_approachVelocity;
    const PfxFloat previous = row.m_accumImpulse;
    row.m_accumImpulse =
        std::max(previous + (target - normalVelocity) * row.m_jacDiagInv, PfxFloat(0));
    pfxApplyRowImpulse(row.m_normal, row.m_accumImpulse - previous, p.a, cp.m_armA, p.receivesA,
                       p.b, cp.m_armB, p.receivesB);
  }
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfSolveConstraints(PfxUInt32, PfxUInt32, PfxUInt32, PfxUInt32) {
  return 0;
}

PfxInt32 pfxSolveConstraints(const PfxSolveConstraintsParam& param) {
  if (param.numContactPairs > 0 && (!param.contactPairs || !param.offsetContactManifolds)) {
    return PFX_ERR_NULL_POINTER;
  }
  if (param.numRigidBodies > 0 && (!param.offsetRigidStates || !param.offsetSolverBodies)) {
    return PFX_ERR_NULL_POINTER;
  }
  if (!(param.restitutionThreshold >= 0) || !pfxIsFinite(param.restitutionThreshold)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (!pfxPairsInRange(param.contactPairs, param.numContactPairs, param.numRigidBodies,
                       param.numContactManifolds)) {
    return PFX_ERR_OUT_OF_RANGE;
  }

  auto forEachContact = [&](auto&& work) {
    for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
      const PfxConstraintPair& pair = param.contactPairs[i];
      if (!pfxGetActive(pair)) continue;
      PfxContactManifold& manifold = param.offsetContactManifolds[pfxGetContactId(pair)];
      if (manifold.getNumContacts() == 0) continue;
      work(manifold, bodiesOf(pair, param.offsetSolverBodies));
    }
  };

  forEachContact([](PfxContactManifold& m, const PairBodies& p) { warmStart(m, p); });
  for (PfxUInt32 iteration = 0; iteration < param.iteration; ++iteration) {
    forEachContact([](PfxContactManifold& m, const PairBodies& p) { solveContacts(m, p); });
  }
  forEachContact([&](PfxContactManifold& m, const PairBodies& p) {
    applyRestitution(m, p, param.restitutionThreshold);
  });

  for (PfxUInt32 i = 0; i < param.numRigidBodies; ++i) {
    PfxRigidState& state = param.offsetRigidStates[i];
    const PfxSolverBody& solverBody = param.offsetSolverBodies[i];
    if (solverBody.m_massInv == 0) continue;
    state.setLinearVelocity(state.getLinearVelocity() + solverBody.m_deltaLinearVelocity);
    state.setAngularVelocity(state.getAngularVelocity() + solverBody.m_deltaAngularVelocity);
  }
  return PFX_OK;
}

}  // namespace pfx
