#include "low_level/solver/pfx_shock_propagation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "low_level/solver/pfx_constraint_row_solver.h"
#include "low_level/solver/pfx_normal_block.h"

namespace pfx {

namespace {

// cos 45 degrees: a contact steeper than this holds its upper body up more than it holds
// it sideways. The faces between a pile's columns are left out.
constexpr PfxFloat kMinUpwardNormal = PfxFloat(0.70710678);

// Sweeps over the contacts that hold one body up (a box on a box and the edges of its
// diagonal neighbours), so that their pushes share the body between them: visited once
// each, the 5 x 5 x 20 pile's columns spread 1.10 m in 10 s instead of 0.92 m.
constexpr int kSweepsPerBody = 4;

// Approach speeds the pass leaves to the iterations (m/s): a resting stack's residue, which
// pushed at one corner of a box turns it; with none left, three-box stacks crept 2 mm
// sideways before falling asleep, and at 1 mm/s the benchmark's pyramid drifted 0.068 m
// (0.028 m now). A sinking pile approaches at about g dt (0.16 m/s at 1/60).
constexpr PfxFloat kShockIgnoredApproach = PfxFloat(1e-4);

}  // namespace

std::size_t PfxShockPropagation::getWorkBytes(PfxUInt32 numContactPairs) {
  return sizeof(Contact) * std::size_t(numContactPairs) + alignof(Contact);
}

void PfxShockPropagation::build(void* workBuff, const PfxConstraintPair* contactPairs,
                                PfxUInt32 numContactPairs, PfxContactManifold* manifolds,
                                const PfxRigidState* states, PfxSolverBody* solverBodies,
                                const PfxVector3& up) {
  m_contacts = reinterpret_cast<Contact*>(
      (reinterpret_cast<std::uintptr_t>(workBuff) + alignof(Contact) - 1) &
      ~std::uintptr_t(alignof(Contact) - 1));
  m_numContacts = 0;
  m_pairs = contactPairs;
  m_manifolds = manifolds;
  m_solverBodies = solverBodies;
  if (up.isZero(0)) return;
  for (PfxUInt32 i = 0; i < numContactPairs; ++i) {
    const PfxConstraintPair& pair = contactPairs[i];
    if (!pfxGetActive(pair)) continue;
    const PfxContactManifold& manifold = manifolds[pfxGetContactId(pair)];
    if (manifold.getNumContacts() == 0) continue;
    // The normal pushes B away from A.
    const PfxFloat upward = manifold.getContactPoint(0).getNormal().dot(up);
    if (std::abs(upward) < kMinUpwardNormal) continue;
    const bool lowerIsA = upward > 0;
    const PfxUInt32 upper = lowerIsA ? pfxGetObjectIdB(pair) : pfxGetObjectIdA(pair);
    const bool upperReceives = lowerIsA ? pfxGetReceivesB(pair) : pfxGetReceivesA(pair);
    if (!pfxTakesImpulse(solverBodies[upper], upperReceives ? 1 : 0)) continue;
    m_contacts[m_numContacts++] = {states[upper].getPosition().dot(up), upper, i, lowerIsA, {}};
  }
  // By the upper body's height, so that every contact holding a body up comes before those
  // it holds up; the contacts of one body together, in pair order.
  std::sort(m_contacts, m_contacts + m_numContacts, [](const Contact& x, const Contact& y) {
    if (x.upperHeight != y.upperHeight) return x.upperHeight < y.upperHeight;
    return x.upper < y.upper || (x.upper == y.upper && x.pair < y.pair);
  });
}

void PfxShockPropagation::propagate(bool push) const {
  for (PfxUInt32 begin = 0, end = 0; begin < m_numContacts; begin = end) {
    end = begin + 1;
    while (end < m_numContacts && m_contacts[end].upper == m_contacts[begin].upper) ++end;
    for (PfxUInt32 c = begin; c < end; ++c) {
      std::fill_n(m_contacts[c].impulse, PFX_NUM_CONTACTS_PER_MANIFOLD, PfxFloat(0));
    }
    const int sweeps = end - begin > 1 ? kSweepsPerBody : 1;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
      for (PfxUInt32 c = begin; c < end; ++c) solveContact(m_contacts[c], push);
    }
  }
}

void PfxShockPropagation::solveContact(Contact& contact, bool push) const {
  PfxVector3 PfxSolverBody::*linear =
      push ? &PfxSolverBody::m_pushLinearVelocity : &PfxSolverBody::m_deltaLinearVelocity;
  PfxVector3 PfxSolverBody::*angular =
      push ? &PfxSolverBody::m_pushAngularVelocity : &PfxSolverBody::m_deltaAngularVelocity;
  const PfxConstraintPair& pair = m_pairs[contact.pair];
  const PfxContactManifold& manifold = m_manifolds[pfxGetContactId(pair)];
  PfxSolverBody& a = m_solverBodies[pfxGetObjectIdA(pair)];
  PfxSolverBody& b = m_solverBodies[pfxGetObjectIdB(pair)];
  const PfxSolverBody& upper = contact.lowerIsA ? b : a;
  const PfxUInt32 n = manifold.getNumContacts();
  PfxVector3 torque[PFX_NUM_CONTACTS_PER_MANIFOLD];
  PfxFloat residual[PFX_NUM_CONTACTS_PER_MANIFOLD] = {};
  PfxFloat delta[PFX_NUM_CONTACTS_PER_MANIFOLD];
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    const PfxConstraintRow& row = cp.m_constraintRow[0];
    torque[i] = (contact.lowerIsA ? cp.m_armB : cp.m_armA).cross(cp.getNormal());
    const PfxFloat rhs = push ? cp.m_pushRhs : row.m_rhs;
    const PfxFloat target = row.m_jacDiagInv > 0 ? rhs / row.m_jacDiagInv : 0;
    residual[i] = target - pfxContactNormalVelocity(cp, a, b, linear, angular);
  }
  bool approaching = false;
  for (PfxUInt32 i = 0; i < n; ++i) approaching = approaching || residual[i] > kShockIgnoredApproach;
  if (!approaching) return;
  PfxNormalCoupling k;  // of the upper body alone
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxVector3& ni = manifold.getContactPoint(i).getNormal();
    for (PfxUInt32 j = i; j < n; ++j) {
      k[i][j] = k[j][i] = ni.dot(manifold.getContactPoint(j).getNormal()) * upper.m_massInv +
                          torque[i].dot(upper.m_inertiaInv * torque[j]);
    }
  }
  // The pass's own impulse is kept at zero or above: it only stops what the iterations
  // left sinking. Let it take back the iterations' impulse too and the pile, pulled down
  // wherever a warm start threw a box up, slid apart within 7 s instead of 15.
  pfxSolveNormalBlock(n, k, residual, contact.impulse, delta);
  pfxApplyNormalImpulses(manifold, delta, a, contact.lowerIsA ? 0 : 1, b,
                         contact.lowerIsA ? 1 : 0, linear, angular);
}

}  // namespace pfx
