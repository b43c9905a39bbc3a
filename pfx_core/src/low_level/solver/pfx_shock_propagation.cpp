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

// Approach (and leaving) speeds the pass leaves to the iterations (m/s): a resting stack's
// residue, which pushed at one corner of a box turns it; with none left, three-box stacks
// crept 2 mm sideways before falling asleep, and at 1 mm/s the benchmark's pyramid drifted
// 0.068 m (0.028 m at 1e-4). A sinking pile approaches at about g dt (0.16 m/s at 1/60).
constexpr PfxFloat kShockIgnoredApproach = PfxFloat(1e-4);

// Points of a body's support, at most four per contact; a body held by more contacts than
// fit is not tested for its turn.
constexpr int kMaxSupportPoints = 64;

// Whether the body's centre lies over the support its contact points span: the directions
// from the centre to the points, across `up`, leave no gap of half a turn or more. A body
// whose centre lies beyond the edge of its support tips, and is not held from turning.
bool centreOverSupport(const PfxVector3* arms, int count, const PfxVector3& up) {
  PfxVector3 across1, across2;
  pfxGetPlaneSpace(up, across1, across2);
  PfxFloat angles[kMaxSupportPoints];
  int numAngles = 0;
  for (int i = 0; i < count; ++i) {
    const PfxFloat x = across1.dot(arms[i]), y = across2.dot(arms[i]);
    if (x == 0 && y == 0) return true;
    angles[numAngles++] = std::atan2(y, x);
  }
  if (numAngles < 3) return false;
  std::sort(angles, angles + numAngles);
  const PfxFloat halfTurn = PfxFloat(3.14159265358979);
  PfxFloat widestGap = angles[0] + 2 * halfTurn - angles[numAngles - 1];
  for (int i = 1; i < numAngles; ++i) widestGap = std::max(widestGap, angles[i] - angles[i - 1]);
  return widestGap < halfTurn * PfxFloat(0.999);
}

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
  m_states = states;
  m_solverBodies = solverBodies;
  m_up = up;
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
      const PfxContactManifold& manifold =
          m_manifolds[pfxGetContactId(m_pairs[m_contacts[c].pair])];
      for (PfxUInt32 i = 0; i < PFX_NUM_CONTACTS_PER_MANIFOLD; ++i) {
        const bool iterated = !push && i < manifold.getNumContacts();
        m_contacts[c].impulse[i] =
            iterated ? manifold.getContactPoint(i).m_constraintRow[0].m_accumImpulse : PfxFloat(0);
      }
    }
    const int sweeps = end - begin > 1 ? kSweepsPerBody : 1;
    for (int sweep = 0; sweep < sweeps; ++sweep) {
      for (PfxUInt32 c = begin; c < end; ++c) solveContact(m_contacts[c], push);
    }
    if (!push) holdUpperBody(m_contacts + begin, m_contacts + end);
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
  // Short of the target, or past it while still pushing.
  bool offTarget = false;
  for (PfxUInt32 i = 0; i < n; ++i) {
    offTarget = offTarget || residual[i] > kShockIgnoredApproach ||
                (residual[i] < -kShockIgnoredApproach && contact.impulse[i] > 0);
  }
  if (!offTarget) return;
  PfxNormalCoupling k;  // of the upper body alone
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxVector3& ni = manifold.getContactPoint(i).getNormal();
    for (PfxUInt32 j = i; j < n; ++j) {
      k[i][j] = k[j][i] = ni.dot(manifold.getContactPoint(j).getNormal()) * upper.m_massInv +
                          torque[i].dot(upper.m_inertiaInv * torque[j]);
    }
  }
  // The impulse is kept at zero or above: on the push the pass only pushes, on the
  // velocities it takes back at most what the iterations pushed.
  pfxSolveNormalBlock(n, k, residual, contact.impulse, delta);
  pfxApplyNormalImpulses(manifold, delta, a, contact.lowerIsA ? 0 : 1, b,
                         contact.lowerIsA ? 1 : 0, linear, angular);
}

// Velocities here are the state's plus the solved change. The load of each point is its
// normal impulse after the pass; the friction the iterations already applied counts
// against the friction the load allows.
void PfxShockPropagation::holdUpperBody(const Contact* begin, const Contact* end) const {
  PfxSolverBody& upper = m_solverBodies[begin->upper];
  const PfxRigidState& upperState = m_states[begin->upper];
  PfxFloat load = 0, frictionLimit = 0;
  PfxVector3 applied = PfxVector3::Zero();       // the iterations' friction on the upper body
  PfxVector3 carrierVelocity = PfxVector3::Zero();  // of the carrying bodies, by load
  PfxVector3 carrierTurn = PfxVector3::Zero();
  PfxVector3 arms[kMaxSupportPoints];
  int numArms = 0;
  bool countedAll = true;
  for (const Contact* contact = begin; contact != end; ++contact) {
    const PfxConstraintPair& pair = m_pairs[contact->pair];
    const PfxContactManifold& manifold = m_manifolds[pfxGetContactId(pair)];
    const PfxUInt32 lowerId = contact->lowerIsA ? pfxGetObjectIdA(pair) : pfxGetObjectIdB(pair);
    const PfxSolverBody& lower = m_solverBodies[lowerId];
    const PfxVector3 lowerVelocity =
        m_states[lowerId].getLinearVelocity() + lower.m_deltaLinearVelocity;
    const PfxVector3 lowerTurn =
        m_states[lowerId].getAngularVelocity() + lower.m_deltaAngularVelocity;
    // Friction rows push B along their direction and A against it.
    const PfxFloat onUpper = contact->lowerIsA ? 1 : -1;
    const PfxFloat friction = manifold.getCompositeFriction();
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      const PfxContactPoint& cp = manifold.getContactPoint(i);
      const PfxFloat pointLoad = contact->impulse[i];
      load += pointLoad;
      frictionLimit += friction * pointLoad;
      applied += onUpper * (cp.m_constraintRow[1].m_normal * cp.m_constraintRow[1].m_accumImpulse +
                            cp.m_constraintRow[2].m_normal * cp.m_constraintRow[2].m_accumImpulse);
      carrierVelocity += lowerVelocity * pointLoad;
      carrierTurn += lowerTurn * pointLoad;
      if (numArms < kMaxSupportPoints) {
        arms[numArms++] = contact->lowerIsA ? cp.m_armB : cp.m_armA;
      } else {
        countedAll = false;
      }
    }
  }
  if (load <= 0) return;
  carrierVelocity /= load;
  carrierTurn /= load;

  // The centre's slide against the carriers, taken away within the friction circle of the
  // whole load.
  const PfxVector3 slide =
      upperState.getLinearVelocity() + upper.m_deltaLinearVelocity - carrierVelocity;
  const PfxVector3 slideAcross = slide - m_up * m_up.dot(slide);
  PfxVector3 friction = applied - slideAcross / upper.m_massInv;
  if (friction.squaredNorm() > frictionLimit * frictionLimit) {
    friction *= frictionLimit / friction.norm();
  }
  upper.m_deltaLinearVelocity += (friction - applied) * upper.m_massInv;

  // Its turn against the carriers, taken away within the moment the load can hold at the
  // support's furthest point (tipping) and the friction's moment there (twisting).
  // A body with a locked turn (no inverse inertia to invert) is held by its slide alone.
  if (!countedAll || !(upper.m_inertiaInv.trace() > 0) ||
      !centreOverSupport(arms, numArms, m_up)) {
    return;
  }
  PfxVector3 centre = PfxVector3::Zero();
  for (int i = 0; i < numArms; ++i) centre += arms[i];
  centre /= PfxFloat(numArms);
  PfxFloat reach = 0;
  for (int i = 0; i < numArms; ++i) {
    const PfxVector3 offset = arms[i] - centre;
    reach = std::max(reach, (offset - m_up * m_up.dot(offset)).norm());
  }
  const PfxVector3 turn =
      upperState.getAngularVelocity() + upper.m_deltaAngularVelocity - carrierTurn;
  const PfxVector3 momentum = -(pfxInverseDefinite(upper.m_inertiaInv) * turn);
  const PfxFloat twist = m_up.dot(momentum);
  PfxVector3 tipping = momentum - m_up * twist;
  const PfxFloat tippingLimit = reach * load, twistLimit = reach * frictionLimit;
  if (tipping.norm() > tippingLimit) tipping *= tippingLimit / tipping.norm();
  const PfxFloat heldTwist = std::clamp(twist, -twistLimit, twistLimit);
  upper.m_deltaAngularVelocity += upper.m_inertiaInv * (tipping + m_up * heldTwist);
}

}  // namespace pfx
