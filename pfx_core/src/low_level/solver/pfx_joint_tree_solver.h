// Direct solver for the locked axes of joints that link bodies into trees (a robot arm, a
// chain, a ragdoll), after Baraff, "Linear-Time Dynamics using Lagrange Multipliers"
// (SIGGRAPH 1996). The system [M J^T; J -eps] over bodies and joints has the sparsity of
// the tree, so eliminating leaves first factors it in time linear in the number of bodies,
// with no fill-in. Solving it makes every locked axis hold exactly in one go, whatever the
// mass ratios: a 1000:1 payload on a light chain stays put, which iterating one row at a
// time cannot do in a few iterations. Joints that close a loop are left to the iterative
// solver; rows that are one-sided (limits) or bounded (drives, friction) are iterated, but
// each update moves the whole tree as the tree answers it (prepareBoundedRows).

#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"
#include "low_level/solver/pfx_block_tree.h"
#include "low_level/solver/pfx_joint_row.h"

namespace pfx {

class PfxJointTreeSolver {
 public:
  static PfxUInt32 getWorkBytes(PfxUInt32 numRigidBodies, PfxUInt32 numJointPairs);

  // When build() factors the trees: all at once, or each on its first solve of any kind,
  // for a solve that may leave most trees alone (the position correction once most joints
  // hold).
  enum class Factoring { kNow, kOnFirstSolve };

  // Picks the joints that form a forest, orders and factors the system (the trees in
  // parallel with a task manager). False when the work buffer is too small.
  bool build(void* workBuff, PfxUInt32 workBytes, const PfxConstraintPair* jointPairs,
             PfxUInt32 numJointPairs, PfxJoint* joints, PfxSolverBody* solverBodies,
             PfxUInt32 numRigidBodies, PfxTaskManager* taskManager = nullptr,
             Factoring factoring = Factoring::kNow);

  // Whether the locked axes of the i-th joint pair are solved here (and not iteratively).
  bool contains(PfxUInt32 jointPairIndex) const {
    return m_jointNode && m_jointNode[jointPairIndex] >= 0;
  }
  // Whether an axis is locked, and so solved here when its joint is in the forest.
  static bool isLockedRow(const PfxJointConstraint& c) {
    return c.m_rowType == kPfxJointRowEquality && c.m_weight == 1;
  }

  // The bounded rows (limits, drives, friction, damping) of the joints in the forest.
  // An impulse on one moves the whole tree, as the locked axes hold it together, so its
  // effective mass is the tree's, not that of its two bodies. That answer is linear and
  // fixed for the solve: prepareBoundedRows() solves the tree once per row for a unit
  // impulse and keeps the velocity change of every body of the tree, so that an update
  // during the iterations is one scaled addition over the tree's bodies instead of a tree
  // solve. Rows beyond the work buffer's share (trees far larger than robots) give the
  // impulse to their two bodies and solve the tree at each update.
  static PfxUInt32 getBoundedRowWorkBytes(PfxUInt32 numRigidBodies, PfxUInt32 numJointPairs);
  // After build(), once the rows are set up.
  bool prepareBoundedRows(void* workBuff, PfxUInt32 workBytes,
                          PfxTaskManager* taskManager = nullptr);
  // The row's slot for applyBoundedRowImpulse, or -1 for a row not prepared (unused, or
  // moving no body). `drive` picks m_driveRow over m_constraintRow.
  PfxInt32 getBoundedRow(PfxUInt32 jointPairIndex, PfxUInt32 axis, bool drive) const {
    return m_boundedRowSlot ? m_boundedRowSlot[(jointPairIndex * 6 + axis) * 2 + (drive ? 1 : 0)]
                            : -1;
  }
  // The row's velocity change per unit impulse, its tree's locked axes held.
  PfxFloat getBoundedRowResponse(PfxInt32 slot) const;
  // Moves the row's tree as it answers `impulse` on the row, its locked axes held.
  void applyBoundedRowImpulse(PfxInt32 slot, PfxFloat impulse);
  // Marks the trees that something besides their own rows moves during a solve: a body
  // of theirs held by a joint outside the forest (it closes a loop, or is one-way) or by a
  // joint coupling, and, from markTreesMovedByContacts, touched by a contact that acts.
  // The other trees' locked axes, once solved, stay held through the iterations: their
  // bounded rows' updates keep them so.
  void markTreesMovedFromOutside(const PfxJointCoupling* couplings, PfxUInt32 numCouplings);
  // After each sweep of the contacts, before solveVelocitiesBeforeSweep: marks the trees
  // of the bodies of contacts with an impulse (normal or friction), and keeps them marked
  // for the rest of the solve, since an impulse that returns to zero moves its bodies back
  // on the way. A contact whose impulses have stayed zero (a speculative point that never
  // closed, such as the arm's forearm 2 cm from its palm, every step) has moved nothing,
  // and its tree needs no solve before and after every sweep for it: two tree solves a
  // sweep on the arm.
  void markTreesMovedByContacts(const PfxConstraintPair* contactPairs, PfxUInt32 numContactPairs,
                                const PfxContactManifold* manifolds);
  // A velocity solve of a tree adds to its locked rows' impulses and its bodies' velocity
  // changes what makes every locked axis move at its target velocity (m_rhs). Trees are
  // solved in parallel with a task manager; they share no moving body, so the result is
  // the same.
  // Before a sweep of the joints: a velocity solve of the trees with bounded rows whose
  // locked axes may not hold, since a row reads its velocity where they hold. Before the
  // first sweep that is every such tree (the warm start gave each row's impulse to its
  // two bodies alone), before the others only those moved from outside.
  void solveVelocitiesBeforeSweep(bool firstSweep, PfxTaskManager* taskManager = nullptr);
  // After a sweep: a velocity solve of the trees whose locked axes may not hold. Those
  // moved from outside, the trees without bounded rows after the first sweep (they have
  // not been solved yet), and the trees with bounded rows after the last, which takes out
  // what rounding in their updates' stored velocity changes has left on the locked axes.
  void solveVelocitiesAfterSweep(bool firstSweep, bool lastSweep,
                                 PfxTaskManager* taskManager = nullptr);
  // The locked axes' share of the bounded rows' impulses, which applyBoundedRowImpulse
  // moves the bodies by but does not add to the locked rows' impulses: one tree solve for
  // all the updates of the solve, once they are done.
  void addLockedImpulsesOfBoundedRows(PfxTaskManager* taskManager = nullptr);

  // Adds to the rows' push impulses and the bodies' push velocities what makes every
  // locked axis move at its position correction (m_pushRhs), as a velocity solve does
  // for the velocity changes and m_rhs.
  void solvePush(PfxTaskManager* taskManager = nullptr);
  // One body of the tree that holds body `rigidBodyId`, the same for every body of that
  // tree, or -1 for a body in no tree: a joint row that moves its tree
  // (applyBoundedRowImpulse) touches every body of the tree.
  PfxInt32 getTreeBody(PfxUInt32 rigidBodyId) const;
  // Whether the tree that holds body `rigidBodyId` is joined to a body that does not move
  // (an arm on its base); false for a body in no tree.
  bool isTreeHeldByGround(PfxUInt32 rigidBodyId) const;
  // How fast the generalized impulse (linear, angular) on body `rigidBodyId` moves it
  // along itself per unit, its tree's locked axes held (j^T M^-1 j over the tree): the
  // effective inverse mass of a contact on a body of a tree. -1 for a body in no tree. The
  // body's 6 x 6 answer is solved for on first use, six tree solves, and kept until the
  // next build(). Uses the tree's nodes as scratch, so not while a solve of it runs.
  PfxFloat getImpulseResponse(PfxUInt32 rigidBodyId, const PfxVector3& linear,
                              const PfxVector3& angular);
  // solveVelocities() (or solvePush()) for the one tree that holds body `rigidBodyId`, if
  // any.
  void solveTreeOf(PfxUInt32 rigidBodyId, bool push);
  // Moves the tree that holds body `rigidBodyId` as it answers the generalized impulse
  // (linear, angular) on that body, its locked axes held: the body's velocity change and
  // every other body's, and the locked rows' impulses. Where the tree's locked axes held
  // before (holdsTreeOf), that is what giving the body the impulse and solving the tree
  // (solveTreeOf) gives, but the right-hand side is one body's and the elimination runs
  // along its path to the root alone: half the work of a solve for a foot of a ragdoll,
  // one contact update of many on the ground.
  void applyImpulseThroughTree(PfxUInt32 rigidBodyId, const PfxVector3& linear,
                               const PfxVector3& angular, bool push);
  // Whether the locked axes of the tree of body `rigidBodyId` hold, as far as this solver
  // knows: a tree solve makes them hold, and forgetHeldTrees() and forgetHeldTreeOf()
  // forget it. Velocities changed elsewhere are not seen, so a caller trusts it only over
  // a stretch of work where every change to the trees' bodies goes through here or is
  // forgotten (a sweep of pfxSweepTreeContacts).
  bool holdsTreeOf(PfxUInt32 rigidBodyId) const;
  void forgetHeldTrees();
  void forgetHeldTreeOf(PfxUInt32 rigidBodyId);
  // Drops the factors of the tree that holds body `rigidBodyId`, and the impulse responses
  // kept from them: its next solve factors it again, from the bodies' masses and the joints'
  // rows as they are then.
  void refactorTreeOf(PfxUInt32 rigidBodyId);

 private:
  struct Node;
  struct BoundedRow;
  void solve(bool push, PfxTaskManager* taskManager);
  // A velocity solve of the trees t with solves(t); with `skipHeld`, of those only whose
  // locked axes do not hold (solveTree).
  template <typename TreePredicate>
  void solveVelocitiesOf(TreePredicate solves, bool skipHeld, PfxTaskManager* taskManager);
  bool hasBoundedRows(PfxUInt32 tree) const {
    return m_treeRowStarts[tree] != m_treeRowStarts[tree + 1];
  }
  void markTreeOfBody(PfxUInt32 rigidBodyId);
  // The node of body `rigidBodyId`, or -1 for a body in no tree (or any body before build()).
  PfxInt32 nodeOfBody(PfxUInt32 rigidBodyId) const {
    return m_bodyNode && rigidBodyId < m_numRigidBodies ? m_bodyNode[rigidBodyId] : -1;
  }
  // Sets up the blocks of the tree's nodes from the rows and the bodies, and factors them.
  void factorTree(PfxUInt32 tree);
  void factorIfNeeded(PfxUInt32 tree) {
    if (!m_treeFactored[tree]) factorTree(tree);
  }
  // With `skipHeld`, a tree whose locked axes already hold but for rounding
  // (kHeldLockedRowVelocity) is left as it is; the solves that end the velocity solve and
  // those of the position correction take that rounding out as well.
  void solveTree(bool push, std::size_t begin, std::size_t end, bool skipHeld = false);
  // Adds the solved values of nodes [begin, end) to their bodies' velocities (the push
  // velocities with `push`) and their locked rows' impulses.
  void takeSolution(bool push, std::size_t begin, std::size_t end);
  // Adds a joint node's negated multipliers to its locked rows' impulses.
  void addLockedRowImpulses(const Node& node, bool push);
  PfxJointRowJacobian boundedRowJacobian(const BoundedRow& row) const;
  // 1 when two rows have the same Jacobian, -1 when opposite ones, else 0.
  double sameJacobianSign(const BoundedRow& first, const BoundedRow& second) const;
  // Solves tree t with the generalized impulse of each row of [firstRow, lastRow), times
  // `impulses` (1 when null), on its bodies and no velocity error: the bodies' values are
  // the velocity change, the joints' the locked rows' negated impulses.
  void solveTreeForRowImpulses(PfxUInt32 tree, PfxUInt32 firstRow, PfxUInt32 lastRow,
                               const double* impulses);

  Node* m_nodes = nullptr;  // breadth first: parents before children, tree after tree
  PfxInt32* m_jointNode = nullptr;
  PfxUInt32 m_numNodes = 0;
  PfxUInt32* m_treeStarts = nullptr;  // first node of each tree, then m_numNodes
  PfxUInt32 m_numTrees = 0;
  PfxUInt8* m_treeMovedFromOutside = nullptr;  // per tree, by markTreesMovedFromOutside
  PfxUInt8* m_treeFactored = nullptr;          // per tree
  PfxUInt8* m_treeHeld = nullptr;              // per tree, holdsTreeOf()
  PfxInt32* m_bodyNode = nullptr;  // each body's node, or -1
  PfxInt32* m_bodyTreeBody = nullptr;  // getTreeBody() of each body
  // getImpulseResponse(): per node, its slot in m_bodyResponses once solved for, else -1;
  // -2 - slot once refactorTreeOf dropped it.
  PfxInt32* m_responseSlot = nullptr;
  PfxTreeBlock* m_bodyResponses = nullptr;  // room for every body a joint can hold
  PfxUInt32 m_numBodyResponses = 0;
  PfxUInt32 m_numRigidBodies = 0;
  PfxUInt32 m_numJointPairs = 0;
  PfxJoint* m_joints = nullptr;
  const PfxConstraintPair* m_jointPairs = nullptr;
  PfxSolverBody* m_solverBodies = nullptr;

  // prepareBoundedRows(): the rows tree by tree, each tree's bodies, and for each row with
  // room the velocity change of those bodies per unit impulse (6 numbers a body).
  PfxInt32* m_boundedRowSlot = nullptr;  // 12 per joint pair: (pair * 6 + axis) * 2 + drive
  BoundedRow* m_boundedRows = nullptr;
  PfxUInt32* m_treeRowStarts = nullptr;   // per tree, then the number of rows
  PfxUInt32* m_treeBodyStarts = nullptr;  // per tree, into m_treeBodies
  PfxUInt32* m_treeBodies = nullptr;
  PfxUInt32* m_treesToSolve = nullptr;  // solveVelocitiesOf's list
  PfxFloat* m_rowVelocityChanges = nullptr;
  double* m_rowImpulseSums = nullptr;  // per row: the impulses applied with its changes
};

}  // namespace pfx
