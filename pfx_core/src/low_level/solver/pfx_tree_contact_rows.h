// The normal rows of contacts on the bodies of joint trees, solved as the trees answer them.
// Sized by its own two bodies, an update that stops a ragdoll's foot is handed back to the
// foot by the tree's solve that follows: a 1 kg foot under a 70 kg ragdoll keeps about a
// seventieth of it per iteration, and at dt 1/30 a landing foot went 3 cm into the ground
// in the velocity solve, and 10 cm once the joints' position correction had closed the
// ankle by moving the foot. Here each update is sized by the tree's effective mass at the
// point and followed at once by the tree's solve, a Gauss-Seidel sweep on the contacts'
// coupling through the tree: sized so but applied together before one solve, the updates
// of two feet and a hand overshoot each other and the ragdoll was flung.
#pragma once

#include <algorithm>
#include <cmath>

#include "low_level/solver/pfx_constraint_row_solver.h"
#include "low_level/solver/pfx_joint_tree_solver.h"
#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"

namespace pfx {

// Below this fraction of what its two bodies alone give, a contact's response through the
// trees is taken for none.
constexpr PfxFloat kPfxSmallestTreeContactResponse = PfxFloat(1e-3);

// The velocities a sweep works on: the velocity changes and the accumulated normal
// impulses towards each row's target, or the push velocities and the push impulses towards
// no approach.
enum class PfxTreeContactVelocities { kVelocity, kPush };

// The velocity change along a contact's normal per unit impulse, a body of a tree answering
// as its tree does; 0 where the trees cannot move that way (a contact that contradicts the
// joints, as on a chain folded onto itself), which the ordinary sweeps are left to.
inline PfxFloat pfxTreeContactResponse(const PfxContactPoint& cp, PfxUInt32 idA,
                                       const PfxSolverBody& a, PfxFloat receivesA,
                                       PfxUInt32 idB, const PfxSolverBody& b,
                                       PfxFloat receivesB, PfxJointTreeSolver& tree) {
  const PfxVector3& normal = cp.m_constraintRow[0].m_normal;
  PfxFloat response = 0;
  auto side = [&](PfxUInt32 id, const PfxSolverBody& body, PfxFloat receives,
                  const PfxVector3& arm, const PfxVector3& direction) {
    if (!pfxTakesImpulse(body, receives)) return;
    const PfxVector3 torque = arm.cross(direction);
    const PfxFloat throughTree = tree.getImpulseResponse(id, direction, torque);
    response += throughTree >= 0 ? throughTree
                                 : body.m_massInv + torque.dot(body.m_inertiaInv * torque);
  };
  side(idA, a, receivesA, cp.m_armA, -normal);
  side(idB, b, receivesB, cp.m_armB, normal);
  const PfxFloat twoBodies = cp.m_constraintRow[0].m_jacDiagInv > 0
                                 ? 1 / cp.m_constraintRow[0].m_jacDiagInv
                                 : 0;
  return response > kPfxSmallestTreeContactResponse * twoBodies ? response : 0;
}

// Which pairs a sweep takes: those sized through the trees (a body of a tree against one
// that does not move, a foot on the ground, or against a body of another tree held by the
// ground, a ragdoll's head on an arm's palm), and also the others (each with its two
// bodies' response), or not. A pair within one tree (a limb on a limb) is not sized by the
// tree: its response there may be next to none, and the impulses that bought it pushed the
// tree through the joints' limits, which the tree's solve does not hold. Nor is a pair of
// two free trees (ragdolls in a pile): sizing those too took the pile's deepest overlap
// from 4.1 to 1.4 mm but cost 55 % more, where a head on a palm, sized by its two bodies,
// sank 5 cm into it at dt 1/60 (0.5 kg of palm held by the arm's motors and base).
enum class PfxTreeContactPairs { kOnTrees, kAll };

// A pair's two sides as the trees see them: how each receives impulses, its tree's body
// (-1 for none, or a side that receives nothing), and whether the pair is one a kOnTrees
// sweep takes, sized through the trees.
struct PfxTreeContactSides {
  PfxFloat receivesA, receivesB;
  PfxInt32 treeA, treeB;
  bool throughTrees;
};

inline PfxTreeContactSides pfxTreeContactSides(const PfxConstraintPair& pair,
                                               const PfxSolverBody* solverBodies,
                                               const PfxJointTreeSolver& tree) {
  const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
  PfxTreeContactSides sides;
  sides.receivesA = pfxGetReceivesA(pair) ? 1 : 0;
  sides.receivesB = pfxGetReceivesB(pair) ? 1 : 0;
  sides.treeA = sides.receivesA != 0 ? tree.getTreeBody(idA) : -1;
  sides.treeB = sides.receivesB != 0 ? tree.getTreeBody(idB) : -1;
  const bool fixedA = !pfxTakesImpulse(solverBodies[idA], sides.receivesA);
  const bool fixedB = !pfxTakesImpulse(solverBodies[idB], sides.receivesB);
  sides.throughTrees = (sides.treeA >= 0 && fixedB) || (sides.treeB >= 0 && fixedA);
  // Two trees, one of them held by the ground: the trees' answer at the point is far from
  // the two bodies' (a ragdoll's head on an arm's palm).
  sides.throughTrees |= sides.treeA >= 0 && sides.treeB >= 0 && sides.treeA != sides.treeB &&
                        (tree.isTreeHeldByGround(idA) || tree.isTreeHeldByGround(idB));
  return sides;
}

// A sweep over every pair it is given.
struct PfxSweepWholeWorld {
  bool takes(PfxUInt32, PfxUInt32) const { return true; }
  void impulseChanged(PfxUInt32, PfxUInt32, bool, bool) {}
};

// One sweep over the normal rows of those pairs; a row within `negligible` (m/s) of its
// target is left as it is. `region` limits the sweep to the pairs it takes(idA, idB), and
// hears of each pair whose impulse changed: impulseChanged(idA, idB, whether the row was
// short of its target by more than the negligible, whether its bodies' trees were solved
// since).
template <typename Region = PfxSweepWholeWorld>
inline void pfxSweepTreeContacts(const PfxConstraintPair* pairs, PfxUInt32 numPairs,
                                 PfxContactManifold* manifolds, PfxSolverBody* solverBodies,
                                 PfxJointTreeSolver& tree, PfxTreeContactVelocities which,
                                 PfxTreeContactPairs taken, PfxFloat negligible,
                                 Region&& region = Region()) {
  const bool push = which == PfxTreeContactVelocities::kPush;
  PfxVector3 PfxSolverBody::*linear =
      push ? &PfxSolverBody::m_pushLinearVelocity : &PfxSolverBody::m_deltaLinearVelocity;
  PfxVector3 PfxSolverBody::*angular =
      push ? &PfxSolverBody::m_pushAngularVelocity : &PfxSolverBody::m_deltaAngularVelocity;
  // Whether a tree's locked axes hold is known only from what this sweep did to it: the
  // first update of a tree through it solves the tree, and the later ones move it as it
  // answers their impulse alone, until an update outside the trees touches it.
  tree.forgetHeldTrees();
  // A side moves as its tree answers the impulse, or as its body alone outside the trees.
  auto moveSide = [&](PfxUInt32 id, PfxSolverBody& body, PfxFloat receives, PfxInt32 treeOf,
                      const PfxVector3& arm, const PfxVector3& impulse) {
    if (!pfxTakesImpulse(body, receives)) return;
    if (treeOf >= 0 && tree.holdsTreeOf(id)) {
      tree.applyImpulseThroughTree(id, impulse, arm.cross(impulse), push);
      return;
    }
    pfxApplyBodyImpulse(body, impulse, arm.cross(impulse), linear, angular);
    if (treeOf >= 0) tree.solveTreeOf(id, push);
  };
  for (PfxUInt32 i = 0; i < numPairs; ++i) {
    const PfxConstraintPair& pair = pairs[i];
    if (!pfxGetActive(pair)) continue;
    const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
    if (!region.takes(idA, idB)) continue;
    const auto [receivesA, receivesB, treeA, treeB, throughTrees] =
        pfxTreeContactSides(pair, solverBodies, tree);
    if (!throughTrees && taken == PfxTreeContactPairs::kOnTrees) continue;
    PfxContactManifold& manifold = manifolds[pfxGetContactId(pair)];
    PfxSolverBody& a = solverBodies[idA];
    PfxSolverBody& b = solverBodies[idB];
    for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
      PfxContactPoint& cp = manifold.getContactPoint(c);
      const PfxConstraintRow& row = cp.m_constraintRow[0];
      if (row.m_jacDiagInv <= 0) continue;
      const PfxFloat target = push ? 0 : row.m_rhs / row.m_jacDiagInv;
      PfxFloat& impulse = push ? cp.m_pushImpulse : cp.m_constraintRow[0].m_accumImpulse;
      const PfxFloat shortfall = target - pfxContactNormalVelocity(cp, a, b, linear, angular);
      // Rows within the negligible are left as the sweeps before left them: a resting
      // ragdoll's contacts, moved about by each tree solve, twitched it through its limits.
      if (std::abs(shortfall) <= negligible || (shortfall < 0 && impulse == 0)) continue;
      const PfxFloat response =
          throughTrees ? pfxTreeContactResponse(cp, idA, a, receivesA, idB, b, receivesB, tree)
                       : 1 / row.m_jacDiagInv;
      if (response <= 0) continue;
      const PfxFloat previous = impulse;
      impulse = std::max(previous + shortfall / response, PfxFloat(0));
      if (impulse == previous) continue;
      region.impulseChanged(idA, idB, shortfall > 0, throughTrees);
      const PfxFloat change = impulse - previous;
      if (!throughTrees) {
        pfxApplyRowImpulse(row.m_normal, change, a, cp.m_armA, receivesA, b, cp.m_armB,
                           receivesB, linear, angular);
        tree.forgetHeldTreeOf(idA);
        tree.forgetHeldTreeOf(idB);
        continue;
      }
      const PfxVector3 onB = row.m_normal * change;
      moveSide(idA, a, receivesA, treeA, cp.m_armA, -onB);
      moveSide(idB, b, receivesB, treeB, cp.m_armB, onB);
    }
  }
}

}  // namespace pfx
