#include "pfx/low_level/solver/pfx_solve_constraints.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "low_level/pfx_param_checks.h"
#include "low_level/solver/pfx_constraint_batches.h"
#include "low_level/solver/pfx_constraint_row_solver.h"
#include "low_level/solver/pfx_contact_tree_solver.h"
#include "low_level/solver/pfx_joint_coupling_row.h"
#include "low_level/solver/pfx_joint_row.h"
#include "low_level/solver/pfx_joint_tree_solver.h"
#include "low_level/solver/pfx_normal_block.h"
#include "low_level/solver/pfx_shock_propagation.h"
#include "low_level/solver/pfx_solver_vec3.h"
#include "low_level/solver/pfx_tree_contact_rows.h"

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

// One manifold's two bodies as its solve sees them: the chosen velocities (the solved
// changes or the push velocities) and the inverse inertias held in registers from the
// first point to the last (pfx_solver_vec3.h), and written back once, by the bodies that
// take impulses only (a fixed body is shared by pairs solved at once on other threads).
class ManifoldBodies {
 public:
  ManifoldBodies(const PairBodies& p, PfxVector3 PfxSolverBody::*linear,
                 PfxVector3 PfxSolverBody::*angular)
      : m_a(p.a),
        m_b(p.b),
        m_linear(linear),
        m_angular(angular),
        m_movesA(pfxTakesImpulse(p.a, p.receivesA)),
        m_movesB(pfxTakesImpulse(p.b, p.receivesB)),
        m_linearA(pfxLoadVec3(p.a.*linear)),
        m_angularA(pfxLoadVec3(p.a.*angular)),
        m_linearB(pfxLoadVec3(p.b.*linear)),
        m_angularB(pfxLoadVec3(p.b.*angular)),
        m_inertiaInvA(pfxLoadMat3(p.a.m_inertiaInv)),
        m_inertiaInvB(pfxLoadMat3(p.b.m_inertiaInv)) {}

  ~ManifoldBodies() {
    if (m_movesA) {
      pfxStoreVec3(m_a.*m_linear, m_linearA);
      pfxStoreVec3(m_a.*m_angular, m_angularA);
    }
    if (m_movesB) {
      pfxStoreVec3(m_b.*m_linear, m_linearB);
      pfxStoreVec3(m_b.*m_angular, m_angularB);
    }
  }

  ManifoldBodies(const ManifoldBodies&) = delete;
  ManifoldBodies& operator=(const ManifoldBodies&) = delete;

  // Velocity of B's point at armB relative to A's point at armA.
  PfxSolverVec3 relativeVelocity(PfxSolverVec3 armA, PfxSolverVec3 armB) const {
    return m_linearB + pfxCross(m_angularB, armB) - m_linearA - pfxCross(m_angularA, armA);
  }

  PfxFloat normalVelocity(const PfxContactPoint& cp) const {
    return pfxDot(pfxLoadVec3(cp.getNormal()),
                  relativeVelocity(pfxLoadVec3(cp.m_armA), pfxLoadVec3(cp.m_armB)));
  }

  // B takes `impulse` at armB, A its opposite at armA.
  void applyImpulse(PfxSolverVec3 impulse, PfxSolverVec3 armA, PfxSolverVec3 armB) {
    applyForceAndTorques(impulse, pfxCross(armA, impulse), pfxCross(armB, impulse));
  }

  // Normal impulses `delta` at the manifold's points, summed into one push and two moments.
  void applyNormalImpulses(const PfxContactManifold& manifold, const PfxFloat* delta) {
    PfxSolverVec3 force = pfxZeroVec3();
    PfxSolverVec3 torqueA = pfxZeroVec3();
    PfxSolverVec3 torqueB = pfxZeroVec3();
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      const PfxContactPoint& cp = manifold.getContactPoint(i);
      const PfxSolverVec3 impulse = pfxLoadVec3(cp.getNormal()) * delta[i];
      force = force + impulse;
      torqueA = torqueA + pfxCross(pfxLoadVec3(cp.m_armA), impulse);
      torqueB = torqueB + pfxCross(pfxLoadVec3(cp.m_armB), impulse);
    }
    applyForceAndTorques(force, torqueA, torqueB);
  }

 private:
  void applyForceAndTorques(PfxSolverVec3 force, PfxSolverVec3 torqueA, PfxSolverVec3 torqueB) {
    if (m_movesA) {
      m_linearA = m_linearA - m_a.m_massInv * force;
      m_angularA = m_angularA - m_inertiaInvA * torqueA;
    }
    if (m_movesB) {
      m_linearB = m_linearB + m_b.m_massInv * force;
      m_angularB = m_angularB + m_inertiaInvB * torqueB;
    }
  }

  PfxSolverBody& m_a;
  PfxSolverBody& m_b;
  PfxVector3 PfxSolverBody::*m_linear;
  PfxVector3 PfxSolverBody::*m_angular;
  bool m_movesA;
  bool m_movesB;
  PfxSolverVec3 m_linearA;
  PfxSolverVec3 m_angularA;
  PfxSolverVec3 m_linearB;
  PfxSolverVec3 m_angularB;
  PfxSolverMat3 m_inertiaInvA;
  PfxSolverMat3 m_inertiaInvB;
};

void warmStart(PfxContactManifold& manifold, const PairBodies& p) {
  ManifoldBodies bodies(p, &PfxSolverBody::m_deltaLinearVelocity,
                        &PfxSolverBody::m_deltaAngularVelocity);
  for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
    const PfxContactPoint& cp = manifold.getContactPoint(c);
    const PfxSolverVec3 armA = pfxLoadVec3(cp.m_armA);
    const PfxSolverVec3 armB = pfxLoadVec3(cp.m_armB);
    for (const PfxConstraintRow& row : cp.m_constraintRow) {
      // A row without impulse (half the points of a pile of ragdolls, a gap apart) moves
      // nothing.
      if (row.m_accumImpulse == 0) continue;
      bodies.applyImpulse(pfxLoadVec3(row.m_normal) * row.m_accumImpulse, armA, armB);
    }
  }
}

// How far short of its target a contact on a tree may end the step (m per step): far
// below the contact slop.
constexpr PfxFloat kNegligibleTreeContactShortfall = PfxFloat(1e-4);

// The manifold's coupling matrix, read once: the block sweeps are the solver's innermost loop.
// All of it, a fixed 64 bytes that the compiler copies inline, where copying the rows in use
// called memcpy for each (a row of one float, for most manifolds of a pile); the rows and
// columns past the count are never read.
void solveNormalBlock(const PfxContactManifold& manifold, const PfxFloat* residual,
                      PfxFloat* impulse, PfxFloat* delta) {
  const PfxUInt32 n = manifold.getNumContacts();
  PfxNormalCoupling k;
  for (PfxUInt32 i = 0; i < PFX_NUM_CONTACTS_PER_MANIFOLD; ++i) {
    for (PfxUInt32 j = 0; j < PFX_NUM_CONTACTS_PER_MANIFOLD; ++j) {
      k[i][j] = manifold.getNormalCoupling(i, j);
    }
  }
  pfxSolveNormalBlock(n, k, residual, impulse, delta);
}

void solveContacts(PfxContactManifold& manifold, const PairBodies& p) {
  const PfxUInt32 n = manifold.getNumContacts();
  PfxFloat residual[PFX_NUM_CONTACTS_PER_MANIFOLD] = {};
  PfxFloat impulse[PFX_NUM_CONTACTS_PER_MANIFOLD] = {};
  PfxFloat delta[PFX_NUM_CONTACTS_PER_MANIFOLD] = {};
  ManifoldBodies bodies(p, &PfxSolverBody::m_deltaLinearVelocity,
                        &PfxSolverBody::m_deltaAngularVelocity);

  // Velocities: each row's rhs is (target - initial velocity) scaled by its effective mass.
  bool idle = true;
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    const PfxConstraintRow& row = cp.m_constraintRow[0];
    const PfxFloat target = row.m_jacDiagInv > 0 ? row.m_rhs / row.m_jacDiagInv : 0;
    residual[i] = target - bodies.normalVelocity(cp);
    impulse[i] = row.m_accumImpulse;
    idle = idle && impulse[i] == 0 && residual[i] <= 0;
  }
  // Points that do not push and need no push (a gap that no approach closes) keep their
  // impulses at zero through the block's sweeps, which change nothing.
  if (!idle) {
    solveNormalBlock(manifold, residual, impulse, delta);
    bodies.applyNormalImpulses(manifold, delta);
  }
  bool pushing = false;
  for (PfxUInt32 i = 0; i < n; ++i) {
    PfxContactPoint& cp = manifold.getContactPoint(i);
    cp.m_constraintRow[0].m_accumImpulse = impulse[i];
    cp.m_maxImpulse = std::max(cp.m_maxImpulse, impulse[i]);
    pushing = pushing || cp.m_pushRhs > 0 || cp.m_pushImpulse > 0;
  }

  // Split impulses push overlaps apart through the push velocities only.
  if (pushing) {
    ManifoldBodies pushed(p, &PfxSolverBody::m_pushLinearVelocity,
                          &PfxSolverBody::m_pushAngularVelocity);
    for (PfxUInt32 i = 0; i < n; ++i) {
      const PfxContactPoint& cp = manifold.getContactPoint(i);
      const PfxFloat jacDiagInv = cp.m_constraintRow[0].m_jacDiagInv;
      const PfxFloat target = jacDiagInv > 0 ? cp.m_pushRhs / jacDiagInv : 0;
      residual[i] = target - pushed.normalVelocity(cp);
      impulse[i] = cp.m_pushImpulse;
    }
    solveNormalBlock(manifold, residual, impulse, delta);
    pushed.applyNormalImpulses(manifold, delta);
    for (PfxUInt32 i = 0; i < n; ++i) manifold.getContactPoint(i).m_pushImpulse = impulse[i];
  }

  // Friction in both tangent directions at once, clamped to the friction circle: two rows
  // clamped separately would allow sqrt(2) times the friction when sliding diagonally.
  const PfxFloat friction = manifold.getCompositeFriction();
  for (PfxUInt32 i = 0; i < n; ++i) {
    PfxContactPoint& cp = manifold.getContactPoint(i);
    PfxConstraintRow& row1 = cp.m_constraintRow[1];
    PfxConstraintRow& row2 = cp.m_constraintRow[2];
    const PfxFloat limit = friction * cp.m_constraintRow[0].m_accumImpulse;
    // Without a limit the friction is clamped to nothing, which a point without friction
    // impulse already has: a point that does not push (a speculative point a gap apart,
    // half of a ragdoll pile's manifolds) has nothing to do here.
    if (limit == 0 && row1.m_accumImpulse == 0 && row2.m_accumImpulse == 0) continue;
    const PfxSolverVec3 armA = pfxLoadVec3(cp.m_armA);
    const PfxSolverVec3 armB = pfxLoadVec3(cp.m_armB);
    const PfxSolverVec3 tangent1 = pfxLoadVec3(row1.m_normal);
    const PfxSolverVec3 tangent2 = pfxLoadVec3(row2.m_normal);
    const PfxSolverVec3 dv = bodies.relativeVelocity(armA, armB);
    const PfxFloat old1 = row1.m_accumImpulse;
    const PfxFloat old2 = row2.m_accumImpulse;
    PfxFloat new1 = old1 + row1.m_rhs - row1.m_jacDiagInv * pfxDot(tangent1, dv);
    PfxFloat new2 = old2 + row2.m_rhs - row2.m_jacDiagInv * pfxDot(tangent2, dv);
    const PfxFloat magnitudeSq = new1 * new1 + new2 * new2;
    if (magnitudeSq > limit * limit) {
      const PfxFloat scale = limit / std::sqrt(magnitudeSq);
      new1 *= scale;
      new2 *= scale;
    }
    row1.m_accumImpulse = new1;
    row2.m_accumImpulse = new2;
    bodies.applyImpulse(tangent1 * (new1 - old1) + tangent2 * (new2 - old2), armA, armB);
  }
}

// After the iterations, points that were hit faster than the threshold and did push get
// the restitution target: a normal velocity of -e times the approach velocity.
// A speculative point bounces from where it is, a gap d short of the surface; in truth
// the bodies would have closed that gap first and left again, ending (1 + e) d nearer.
// That displacement goes to the push velocities, so the bounce keeps its height.
void applyRestitution(PfxContactManifold& manifold, const PairBodies& p, PfxFloat threshold,
                      PfxFloat timeStep) {
  const PfxFloat restitution = manifold.getCompositeRestitution();
  if (restitution <= 0) return;
  for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
    PfxContactPoint& cp = manifold.getContactPoint(c);
    if (cp.m_approachVelocity > -threshold || cp.m_maxImpulse <= 0) continue;
    PfxConstraintRow& row = cp.m_constraintRow[0];
    const PfxFloat velocity =
        cp.m_approachVelocity +
        row.m_normal.dot(pfxRelativeDeltaVelocity(p.a, cp.m_armA, p.b, cp.m_armB));
    const PfxFloat target = -restitution * cp.m_approachVelocity;
    const PfxFloat previous = row.m_accumImpulse;
    row.m_accumImpulse = std::max(previous + (target - velocity) * row.m_jacDiagInv, PfxFloat(0));
    pfxApplyRowImpulse(row.m_normal, row.m_accumImpulse - previous, p.a, cp.m_armA, p.receivesA,
                       p.b, cp.m_armB, p.receivesB);
    if (cp.m_distance <= 0) continue;
    const PfxFloat pushVelocity = pfxContactNormalVelocity(cp, p.a, p.b, &PfxSolverBody::m_pushLinearVelocity,
                                                 &PfxSolverBody::m_pushAngularVelocity);
    const PfxFloat closing = -(1 + restitution) * cp.m_distance / timeStep;
    const PfxFloat impulse = std::min((closing - pushVelocity) * row.m_jacDiagInv, PfxFloat(0));
    pfxApplyRowImpulse(row.m_normal, impulse, p.a, cp.m_armA, p.receivesA, p.b, cp.m_armB,
                       p.receivesB, &PfxSolverBody::m_pushLinearVelocity,
                       &PfxSolverBody::m_pushAngularVelocity);
  }
}

void warmStartJoint(PfxJoint& joint, const PairBodies& p) {
  for (PfxUInt32 axis = 0; axis < 6; ++axis) {
    PfxJointConstraint& c = joint.m_constraints[axis];
    // The tree is factored anew for every solve; a row takes its tree's response again
    // at its first update sized by it (solveTreeJointRow).
    c.m_treeResponse[0] = c.m_treeResponse[1] = 0;
    for (const PfxConstraintRow* row : {&c.m_constraintRow, &c.m_driveRow}) {
      if (row->m_accumImpulse == 0) continue;
      pfxApplyJointRowImpulse(pfxJointRowJacobian(joint, axis, row->m_normal),
                              row->m_accumImpulse, p.a, p.receivesA, p.b, p.receivesB,
                              &PfxSolverBody::m_deltaLinearVelocity,
                              &PfxSolverBody::m_deltaAngularVelocity);
    }
  }
}

// The smallest change (m/s or rad/s) of a tree joint row's velocity, as its two bodies
// alone would answer the update, for which the update is sized by the tree's response:
// 1 mm/s in float, scaled by the precision's epsilon. Smaller updates, those of limit,
// drive and friction rows that are nearly met, are sized by the two bodies' response, a
// fraction of what the tree would want: a ragdoll at rest at dt 1/30, its limit rows
// holding its limbs, twitched at 3 mm/s now and then when those rows took their full
// updates. (In double the same 1 mm/s left too many rows of that ragdoll under-relaxed,
// and it did not come to rest in 10 s.)
constexpr PfxFloat kMinTreeSizedUpdate =
    PfxFloat(1e-3 * (double(std::numeric_limits<PfxFloat>::epsilon()) /
                     double(std::numeric_limits<float>::epsilon())));

// A bounded row (limit, drive, friction, damping) of a joint in the direct solve's forest:
// its impulse is sized by the tree's response (the row's velocity change per unit impulse
// with the tree's locked axes held) and moves the whole tree, so a motor at an arm's
// shoulder carries the arm in one update. A row sized so once keeps that for the rest of
// the solve (`response`, 0 until then). The row reads its velocity where the locked axes
// hold (solveVelocitiesBeforeSweep), and the updates of the tree's rows
// keep them held.
void solveTreeJointRow(PfxConstraintRow& row, PfxFloat& response, const PfxJointConstraint& c,
                       bool dampingOnly, const PfxJoint& joint, PfxUInt32 axis,
                       const PairBodies& p, PfxJointTreeSolver& tree, PfxInt32 slot) {
  const PfxJointRowJacobian j = pfxJointRowJacobian(joint, axis, row.m_normal);
  const PfxFloat before =
      pfxJointRowVelocity(j, p.a.m_deltaLinearVelocity, p.a.m_deltaAngularVelocity,
                          p.b.m_deltaLinearVelocity, p.b.m_deltaAngularVelocity);
  const PfxFloat previous = row.m_accumImpulse;
  // The accumulated impulse wanted, given the row velocity per unit impulse.
  const auto wanted = [&](PfxFloat velocityPerImpulse) {
    if (dampingOnly) {
      // Implicit damping: the impulse takes the fraction c.m_damping of the velocity the
      // joint would have without it. (Aiming at a fraction of the velocity before the
      // solve, as the two-body row does, would hold a joint that starts from rest there,
      // whatever pulls it.) The row's target, -m_damping times the velocity before the
      // solve, gives that velocity back; `before` is what the solve has added to it.
      const PfxFloat atSetup = -(row.m_rhs / row.m_jacDiagInv) / c.m_damping;
      return -c.m_damping * (atSetup + before - previous * velocityPerImpulse) /
             velocityPerImpulse;
    }
    const PfxFloat missing = row.m_rhs / row.m_jacDiagInv - before;
    return std::clamp(previous + c.m_weight * missing / velocityPerImpulse, row.m_lowerLimit,
                      row.m_upperLimit);
  };
  PfxFloat impulse;
  if (response > 0) {
    impulse = wanted(response);
  } else {
    // A damping row's update is its damping fraction of the row's velocity, 1 - exp(-c h /
    // I) for a viscous coefficient c, small at small steps however fast the joint turns
    // (0.5 mrad/s for an arm turning at 1 rad/s at dt 1/1000): sized by the two bodies, it
    // would lose nearly all the damping, as they answer a thousand times more than the arm.
    const PfxFloat twoBodyResponse = c.m_weight / row.m_jacDiagInv;
    impulse = wanted(twoBodyResponse);
    if (dampingOnly || std::abs(impulse - previous) * twoBodyResponse >= kMinTreeSizedUpdate) {
      response = tree.getBoundedRowResponse(slot);
      impulse = wanted(response);
    }
  }
  if (impulse != previous) tree.applyBoundedRowImpulse(slot, impulse - previous);
  row.m_accumImpulse = impulse;
}

// Whether the iterations solve a row of an axis: its drive row, or its constraint row
// unless the direct solve holds it (a locked axis of a joint in the forest).
bool isIteratedRow(const PfxJointConstraint& c, bool drive, bool inTree) {
  if (drive) return c.m_driveRowUsed != 0;
  return c.m_rowType != kPfxJointRowNone && !(inTree && PfxJointTreeSolver::isLockedRow(c));
}

bool hasIteratedRow(const PfxJoint& joint, bool inTree) {
  for (const PfxJointConstraint& c : joint.m_constraints) {
    if (isIteratedRow(c, false, inTree) || isIteratedRow(c, true, inTree)) return true;
  }
  return false;
}

// The rows of a joint that the direct solve leaves to iteration: limits, drives, friction,
// and every row of a joint outside the forest. (Their position errors are corrected after
// the bodies have moved, by pfxCorrectJointPositions.)
void solveJoint(PfxJoint& joint, const PairBodies& p, PfxJointTreeSolver& tree,
                PfxUInt32 jointPairIndex) {
  const bool inTree = tree.contains(jointPairIndex);
  for (PfxUInt32 axis = 0; axis < 6; ++axis) {
    PfxJointConstraint& c = joint.m_constraints[axis];
    for (int which = 0; which < 2; ++which) {
      const bool drive = which == 1;
      PfxConstraintRow& row = drive ? c.m_driveRow : c.m_constraintRow;
      if (!isIteratedRow(c, drive, inTree)) continue;
      if (inTree) {
        // Rows that move neither body have no slot.
        const PfxInt32 slot = tree.getBoundedRow(jointPairIndex, axis, drive);
        if (slot < 0) continue;
        const bool dampingOnly = drive && !pfxDriveHasTarget(c.m_drive) &&
                                 c.m_friction <= 0 && c.m_damping > 0;
        solveTreeJointRow(row, c.m_treeResponse[which], c, dampingOnly, joint, axis, p, tree,
                          slot);
      } else {
        pfxSolveJointRow(row, joint, axis, p.a, p.receivesA, p.b, p.receivesB);
      }
    }
  }
}

constexpr PfxUInt32 kSolvedBodiesPerTask = 512;

// The contact pairs with points that touch a body of a joint tree: first, in their order,
// those sized through the trees (the pairs that pfxSweepTreeContacts takes with
// PfxTreeContactPairs::kOnTrees), then the others. Each
// iteration's sweep of those pairs through the trees, and its marking of the trees that
// contacts move, went through every pair the broad phase found, most of them without a
// point (three quarters of the piled ragdolls' pairs).
struct TreeContactPairs {
  const PfxConstraintPair* pairs;
  PfxUInt32 numThroughTrees;
  PfxUInt32 numPairs;
};

TreeContactPairs gatherTreeContactPairs(const PfxSolveConstraintsParam& param,
                                        const PfxJointTreeSolver& tree, PfxConstraintPair* pairs) {
  PfxUInt32 numThroughTrees = 0, numOthers = 0;
  // The others are gathered from the end backwards (their order does not matter), then
  // moved up behind the first.
  PfxConstraintPair* const others = pairs + param.numContactPairs;
  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    const PfxConstraintPair& pair = param.contactPairs[i];
    if (!pfxGetActive(pair) ||
        param.offsetContactManifolds[pfxGetContactId(pair)].getNumContacts() == 0) {
      continue;
    }
    const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
    if (tree.getTreeBody(idA) < 0 && tree.getTreeBody(idB) < 0) continue;
    if (pfxTreeContactSides(pair, param.offsetSolverBodies, tree).throughTrees) {
      pairs[numThroughTrees++] = pair;
    } else {
      *(others - ++numOthers) = pair;
    }
  }
  std::copy(others - numOthers, others, pairs + numThroughTrees);
  return {pairs, numThroughTrees, numThroughTrees + numOthers};
}

// The work buffer: the joints' forest and its bounded rows, the contacts' forest, the
// bodies' batch words, the batches of contacts, of joints and of the joints with rows to
// iterate (jointBatchBytes each), shock propagation's work
// (without joints) or the contact pairs on the trees' bodies (with them), then the scratch
// of the contacts' direct solve, whatever is left.
struct SolverWorkLayout {
  PfxUInt32 jointTreeBytes = 0;
  PfxUInt32 boundedRowBytes = 0;
  PfxUInt32 contactTreeBytes = 0;
  std::size_t bodyBatchBytes = 0;
  std::size_t contactBatchBytes = 0;
  std::size_t jointBatchBytes = 0;
  std::size_t shockOrTreeContactBytes = 0;

  SolverWorkLayout(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs, PfxUInt32 numJointPairs) {
    if (numJointPairs > 0) {
      jointTreeBytes = PfxJointTreeSolver::getWorkBytes(numRigidBodies, numJointPairs);
      boundedRowBytes = PfxJointTreeSolver::getBoundedRowWorkBytes(numRigidBodies, numJointPairs);
    }
    if (numContactPairs > 0) {
      contactTreeBytes = PfxContactTreeSolver::getWorkBytes(numRigidBodies, numContactPairs);
    }
    if (numContactPairs + numJointPairs > 0) {
      bodyBatchBytes = sizeof(PfxUInt32) * (std::size_t(numRigidBodies) + 1);
    }
    contactBatchBytes = PfxConstraintBatches::getWorkBytes(numContactPairs);
    jointBatchBytes = PfxConstraintBatches::getWorkBytes(numJointPairs);
    if (numContactPairs > 0) {
      shockOrTreeContactBytes =
          std::max(PfxShockPropagation::getWorkBytes(numContactPairs),
                   PfxWorkCarver::bytesFor(alignof(PfxConstraintPair),
                                           sizeof(PfxConstraintPair) * numContactPairs));
    }
  }
  // All but the contacts' scratch.
  std::size_t fixedBytes() const {
    return std::size_t(jointTreeBytes) + boundedRowBytes + contactTreeBytes + bodyBatchBytes +
           contactBatchBytes + 2 * jointBatchBytes + shockOrTreeContactBytes;
  }
};

}  // namespace

PfxUInt32 pfxGetWorkBytesOfSolveConstraints(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs,
                                            PfxUInt32 numJointPairs, PfxUInt32,
                                            PfxUInt32 contactTreeNodes) {
  std::size_t bytes = SolverWorkLayout(numRigidBodies, numContactPairs, numJointPairs).fixedBytes();
  if (numContactPairs > 0) {
    bytes += PfxContactTreeSolver::getScratchBytes(std::min(
        contactTreeNodes, PfxContactTreeSolver::getMaxNodes(numRigidBodies, numContactPairs)));
  }
  return bytes > 0xffffffffu ? 0xffffffffu : static_cast<PfxUInt32>(bytes);
}

PfxInt32 pfxSolveConstraints(const PfxSolveConstraintsParam& param, PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxSolveConstraints", "PfxSolveConstraintsParam"};
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.contactPairs, "contactPairs"},
                               {param.offsetContactManifolds, "offsetContactManifolds"}},
                              "numContactPairs", param.numContactPairs)) != PFX_OK ||
      (err = pfxCheckRequired(at,
                              {{param.offsetRigidStates, "offsetRigidStates"},
                               {param.offsetSolverBodies, "offsetSolverBodies"}},
                              "numRigidBodies", param.numRigidBodies)) != PFX_OK ||
      (err = pfxCheckValue(at, "restitutionThreshold", param.restitutionThreshold,
                           param.restitutionThreshold >= 0 &&
                               pfxIsFinite(param.restitutionThreshold),
                           "finite and not negative")) != PFX_OK ||
      (err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckValue(at, "gravity", param.gravity.norm(), pfxIsFinite(param.gravity),
                           "finite")) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "contactPairs", param.contactPairs, param.numContactPairs,
                                  param.numRigidBodies, "numContactManifolds",
                                  param.numContactManifolds)) != PFX_OK ||
      (err = pfxCheckRequired(at,
                              {{param.jointPairs, "jointPairs"},
                               {param.offsetJoints, "offsetJoints"}},
                              "numJointPairs", param.numJointPairs)) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "jointPairs", param.jointPairs, param.numJointPairs,
                                  param.numRigidBodies, "numJoints", param.numJoints)) != PFX_OK ||
      (err = pfxCheckRequired(at,
                              {{param.offsetJointCouplings, "offsetJointCouplings"},
                               {param.offsetSolverBodies, "offsetSolverBodies"}},
                              "numJointCouplings", param.numJointCouplings)) != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
    const PfxJointCoupling& coupling = param.offsetJointCouplings[i];
    if (coupling.m_numBodies > PFX_JOINT_COUPLING_MAX_BODIES) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxSolveConstraints: PfxSolveConstraintsParam::"
                            "offsetJointCouplings[%u] has %u bodies, more than "
                            "PFX_JOINT_COUPLING_MAX_BODIES (%u)",
                            i, PfxUInt32(coupling.m_numBodies), PFX_JOINT_COUPLING_MAX_BODIES);
    }
    for (PfxUInt32 b = 0; b < coupling.m_numBodies; ++b) {
      if (coupling.m_bodies[b].m_rigidBodyId >= param.numRigidBodies) {
        return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                              "pfxSolveConstraints: PfxSolveConstraintsParam::"
                              "offsetJointCouplings[%u] names body %u, but numRigidBodies is %u",
                              i, coupling.m_bodies[b].m_rigidBodyId, param.numRigidBodies);
      }
    }
  }
  const SolverWorkLayout layout(param.numRigidBodies, param.numContactPairs, param.numJointPairs);
  if (layout.fixedBytes() > 0 && (!param.workBuff || param.workBytes < layout.fixedBytes())) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                          "pfxSolveConstraints: PfxSolveConstraintsParam::workBuff holds %u "
                          "bytes; pfxGetWorkBytesOfSolveConstraints asks %llu",
                          param.workBuff ? param.workBytes : 0,
                          static_cast<unsigned long long>(layout.fixedBytes()));
  }
  unsigned char* cursor = static_cast<unsigned char*>(param.workBuff);
  PfxJointTreeSolver tree;
  if (param.numJointPairs > 0) {
    tree.build(cursor, layout.jointTreeBytes, param.jointPairs, param.numJointPairs,
               param.offsetJoints, param.offsetSolverBodies, param.numRigidBodies, taskManager);
  }
  cursor += layout.jointTreeBytes;
  unsigned char* const boundedRowWork = cursor;
  cursor += layout.boundedRowBytes;
  PfxContactTreeSolver contactTree;
  contactTree.build(cursor, layout.contactTreeBytes, param.contactPairs, param.numContactPairs,
                    param.jointPairs, param.numJointPairs, param.offsetContactManifolds,
                    param.offsetSolverBodies, param.numRigidBodies, taskManager);
  if (param.outContactTreeNodes) *param.outContactTreeNodes = contactTree.getLargestTreeNodes();
  unsigned char* const contactTreeScratch =
      static_cast<unsigned char*>(param.workBuff) + layout.fixedBytes();
  const std::size_t contactTreeScratchBytes =
      param.workBuff ? param.workBytes - layout.fixedBytes() : 0;
  if (contactTree.getLargestTreeNodes() > 0 &&
      PfxContactTreeSolver::getScratchBytes(contactTree.getLargestTreeNodes()) >
          contactTreeScratchBytes) {
    // Nothing outside the work buffer has been written yet.
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                          "pfxSolveConstraints: PfxSolveConstraintsParam::workBuff holds %u "
                          "bytes; a contact tree of %u nodes needs "
                          "pfxGetWorkBytesOfSolveConstraints(..., %u)",
                          param.workBytes, contactTree.getLargestTreeNodes(),
                          contactTree.getLargestTreeNodes());
  }
  cursor += layout.contactTreeBytes;
  PfxUInt32* bodyBatches = reinterpret_cast<PfxUInt32*>(
      (reinterpret_cast<std::uintptr_t>(cursor) + alignof(PfxUInt32) - 1) &
      ~std::uintptr_t(alignof(PfxUInt32) - 1));
  cursor += layout.bodyBatchBytes;
  PfxConstraintBatches contactBatches;
  contactBatches.build(cursor, layout.contactBatchBytes, bodyBatches, param.contactPairs,
                       param.numContactPairs, param.offsetSolverBodies, param.numRigidBodies,
                       [&](PfxUInt32 i) {
                         const PfxConstraintPair& pair = param.contactPairs[i];
                         return pfxGetActive(pair) &&
                                param.offsetContactManifolds[pfxGetContactId(pair)]
                                        .getNumContacts() > 0;
                       },
                       [](PfxUInt32 id) { return id; }, taskManager);
  cursor += layout.contactBatchBytes;
  PfxConstraintBatches jointBatches;
  // A row of a joint in the direct solve's forest moves its whole tree (solveTreeJointRow),
  // so every joint on a tree's bodies counts as acting on one body of that tree.
  const auto jointActingOn = [&](PfxUInt32 id) {
    const PfxInt32 treeBody = tree.getTreeBody(id);
    return treeBody >= 0 ? PfxUInt32(treeBody) : id;
  };
  jointBatches.build(cursor, layout.jointBatchBytes, bodyBatches, param.jointPairs,
                     param.numJointPairs, param.offsetSolverBodies, param.numRigidBodies,
                     [&](PfxUInt32 i) { return pfxGetActive(param.jointPairs[i]); },
                     jointActingOn, taskManager);
  cursor += layout.jointBatchBytes;
  // The iterations visit only the joints with a row to solve: a chain of ball joints in the
  // forest has none, and going through its joints' twelve rows each to find so took a
  // tenth of its step.
  PfxConstraintBatches iteratedJointBatches;
  iteratedJointBatches.build(
      cursor, layout.jointBatchBytes, bodyBatches, param.jointPairs, param.numJointPairs,
      param.offsetSolverBodies, param.numRigidBodies,
      [&](PfxUInt32 i) {
        const PfxConstraintPair& pair = param.jointPairs[i];
        return pfxGetActive(pair) &&
               hasIteratedRow(param.offsetJoints[pfxGetConstraintId(pair)], tree.contains(i));
      },
      jointActingOn, taskManager);
  cursor += layout.jointBatchBytes;
  unsigned char* const shockOrTreeContactWork = cursor;

  // work(sweep, ...) over numSweeps sweeps of the contacts, or one of the joints' batches.
  auto sweepContacts = [&](PfxUInt32 numSweeps, auto&& work) {
    contactBatches.sweep(taskManager, numSweeps,
                         [&](PfxUInt32 sweep, const PfxConstraintPair& pair, PfxUInt32) {
                           work(sweep, param.offsetContactManifolds[pfxGetContactId(pair)],
                                bodiesOf(pair, param.offsetSolverBodies));
                         });
  };
  auto sweepJoints = [&](const PfxConstraintBatches& batches, auto&& work) {
    batches.sweep(taskManager, 1, [&](PfxUInt32, const PfxConstraintPair& pair, PfxUInt32 i) {
      work(param.offsetJoints[pfxGetConstraintId(pair)], bodiesOf(pair, param.offsetSolverBodies),
           i);
    });
  };
  auto restitution = [&](PfxContactManifold& m, const PairBodies& p) {
    applyRestitution(m, p, param.restitutionThreshold, param.timeStep);
  };
  // The contacts' direct solve once, after the first sweep has set the impulses of the
  // faces it leaves out, as a predictor that the remaining sweeps refine: it hands the
  // whole weight of a stack to every face at once, which the sweeps alone pass down one
  // body per sweep. Measured on a 30-box tower at 10 iterations, solving it before the
  // sweeps leaves the top drifting 9 cm in a minute, after the first 2 cm; as the last
  // word of every iteration it makes the tower explode, because its clamped face
  // pressures leave friction and the faces outside the forest far from balance, and one
  // sweep cannot restore that.
  auto solveContactTrees = [&] {
    contactTree.solve(contactTreeScratch, contactTreeScratchBytes, taskManager);
  };

  if (param.numJointPairs == 0 && param.numJointCouplings == 0) {
    // Only contacts: the warm start and the first sweep, then the trees, then the other
    // sweeps, shock propagation and the restitution pass, each run of sweeps in one
    // parallel loop.
    sweepContacts(2, [](PfxUInt32 sweep, PfxContactManifold& m, const PairBodies& p) {
      if (sweep == 0) {
        warmStart(m, p);
      } else {
        solveContacts(m, p);
      }
    });
    solveContactTrees();
    PfxShockPropagation shock;
    shock.build(shockOrTreeContactWork, param.contactPairs, param.numContactPairs,
                param.offsetContactManifolds, param.offsetRigidStates, param.offsetSolverBodies,
                param.gravity.isZero(0) ? PfxVector3(PfxVector3::Zero())
                                        : PfxVector3(-param.gravity.normalized()));
    sweepContacts(param.iteration - 1, [](PfxUInt32, PfxContactManifold& m, const PairBodies& p) {
      solveContacts(m, p);
    });
    // Before restitution, which aims at bounces from the approach velocities alone.
    shock.propagate(false);
    shock.propagate(true);
    sweepContacts(1, [&](PfxUInt32, PfxContactManifold& m, const PairBodies& p) {
      restitution(m, p);
    });
  } else {
    sweepContacts(1, [](PfxUInt32, PfxContactManifold& m, const PairBodies& p) { warmStart(m, p); });
    sweepJoints(jointBatches,
                [](PfxJoint& j, const PairBodies& p, PfxUInt32) { warmStartJoint(j, p); });
    if (param.numJointPairs > 0) {
      tree.prepareBoundedRows(boundedRowWork, layout.boundedRowBytes, taskManager);
      tree.markTreesMovedFromOutside(param.offsetJointCouplings, param.numJointCouplings);
    }
    const TreeContactPairs treeContacts = gatherTreeContactPairs(
        param, tree,
        PfxWorkCarver(shockOrTreeContactWork, layout.shockOrTreeContactBytes)
            .take<PfxConstraintPair>(param.numContactPairs));
    for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
      const PfxJointCoupling& coupling = param.offsetJointCouplings[i];
      pfxApplyJointCouplingImpulse(coupling, coupling.m_row.m_accumImpulse,
                                   param.offsetSolverBodies, &PfxSolverBody::m_deltaLinearVelocity,
                                   &PfxSolverBody::m_deltaAngularVelocity);
    }
    // Joints last in each iteration, and their locked axes exactly: whatever the contacts
    // did, every iteration ends with the joints' velocities consistent (a tree that
    // nothing outside it moves stays so without a solve). Their positions are
    // corrected after the bodies have moved, by pfxCorrectJointPositions.
    for (PfxUInt32 iteration = 0; iteration < param.iteration; ++iteration) {
      sweepContacts(1, [](PfxUInt32, PfxContactManifold& m, const PairBodies& p) {
        solveContacts(m, p);
      });
      const bool first = iteration == 0, last = iteration + 1 == param.iteration;
      // The contacts on the trees' bodies again, as the trees answer them
      // (pfx_tree_contact_rows.h): the sweep above leaves a landing foot sinking with the
      // body's momentum. Before the joints' limits, which the trees' solve does not hold.
      pfxSweepTreeContacts(treeContacts.pairs, treeContacts.numThroughTrees,
                           param.offsetContactManifolds, param.offsetSolverBodies, tree,
                           PfxTreeContactVelocities::kVelocity, PfxTreeContactPairs::kOnTrees,
                           kNegligibleTreeContactShortfall / param.timeStep);
      tree.markTreesMovedByContacts(treeContacts.pairs, treeContacts.numPairs,
                                    param.offsetContactManifolds);
      tree.solveVelocitiesBeforeSweep(first, taskManager);
      sweepJoints(iteratedJointBatches, [&](PfxJoint& j, const PairBodies& p, PfxUInt32 index) {
        solveJoint(j, p, tree, index);
      });
      for (PfxUInt32 i = 0; i < param.numJointCouplings; ++i) {
        pfxSolveJointCouplingBlock(param.offsetJointCouplings[i], param.offsetJoints,
                                   param.offsetSolverBodies, false);
      }
      tree.solveVelocitiesAfterSweep(first, last, taskManager);
      if (first) solveContactTrees();
    }
    tree.addLockedImpulsesOfBoundedRows(taskManager);
    sweepContacts(1, [&](PfxUInt32, PfxContactManifold& m, const PairBodies& p) {
      restitution(m, p);
    });
  }

  // Velocities take the solved changes; positions take the split impulses' push over the
  // step, which is then forgotten.
  pfxParallelFor(taskManager, param.numRigidBodies, kSolvedBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     PfxRigidState& state = param.offsetRigidStates[i];
                     const PfxSolverBody& solverBody = param.offsetSolverBodies[i];
                     if (solverBody.m_massInv == 0) continue;
                     state.setLinearVelocity(state.getLinearVelocity() +
                                             solverBody.m_deltaLinearVelocity);
                     // A body the solver turns is held by its contacts and joints at the
                     // precision of its state as stored: the integrator's carries, there
                     // to keep free flight from drifting, would turn it by what those
                     // never see (a standing 30-box tower leaned 1.3 m in 60 s).
                     if (!solverBody.m_deltaAngularVelocity.isZero(0)) {
                       state.addAngularVelocity(solverBody.m_deltaAngularVelocity);
                       state.clearCarries();
                     }
                     pfxApplyPush(state, solverBody, param.timeStep);
                   }
                 });
  return PFX_OK;
}

}  // namespace pfx
