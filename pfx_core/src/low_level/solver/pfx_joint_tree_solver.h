// Direct solver for the locked axes of joints that link bodies into trees (a robot arm, a
// chain, a ragdoll), after Baraff, "Linear-Time Dynamics using Lagrange Multipliers"
// (SIGGRAPH 1996). The system [M J^T; J -eps] over bodies and joints has the sparsity of
// the tree, so eliminating leaves first factors it in time linear in the number of bodies,
// with no fill-in. Solving it makes every locked axis hold exactly in one go, whatever the
// mass ratios: a 1000:1 payload on a light chain stays put, which iterating one row at a
// time cannot do in a few iterations. Joints that close a loop are left to the iterative
// solver; rows that are one-sided (limits) or bounded (drives, friction) are iterated, but
// each update asks this solver how the whole tree answers it (solveVelocitiesOfTree).

#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

class PfxJointTreeSolver {
 public:
  static PfxUInt32 getWorkBytes(PfxUInt32 numRigidBodies, PfxUInt32 numJointPairs);

  // Picks the joints that form a forest, orders and factors the system (the trees in
  // parallel with a task manager). False when the work buffer is too small.
  bool build(void* workBuff, PfxUInt32 workBytes, const PfxConstraintPair* jointPairs,
             PfxUInt32 numJointPairs, PfxJoint* joints, PfxSolverBody* solverBodies,
             PfxUInt32 numRigidBodies, PfxTaskManager* taskManager = nullptr);

  // Whether the locked axes of the i-th joint pair are solved here (and not iteratively).
  bool contains(PfxUInt32 jointPairIndex) const {
    return m_jointNode && m_jointNode[jointPairIndex] >= 0;
  }

  // Adds to the rows' impulses and the bodies' velocity changes what makes every locked
  // axis move at its target velocity (m_rhs). Trees are solved in parallel with a task
  // manager; they share no moving body, so the result is the same.
  void solveVelocities(PfxTaskManager* taskManager = nullptr);
  // The same for the push velocities and the rows' position corrections (m_pushRhs).
  void solvePush(PfxTaskManager* taskManager = nullptr);
  // solveVelocities() for the one tree that holds the i-th joint pair (contained), after
  // an impulse on that tree: its cost is the tree's size, not the forest's.
  void solveVelocitiesOfTree(PfxUInt32 jointPairIndex);
  // One body of the tree that holds body `rigidBodyId`, the same for every body of that
  // tree, or -1 for a body in no tree: a joint row that asks its tree how it answers
  // (solveVelocitiesOfTree) touches every body of the tree.
  PfxInt32 getTreeBody(PfxUInt32 rigidBodyId) const;

 private:
  struct Node;
  void solve(bool push, PfxTaskManager* taskManager);
  void solveTree(bool push, std::size_t begin, std::size_t end);

  Node* m_nodes = nullptr;  // breadth first: parents before children, tree after tree
  PfxInt32* m_jointNode = nullptr;
  PfxUInt32 m_numNodes = 0;
  PfxUInt32* m_treeStarts = nullptr;  // first node of each tree, then m_numNodes
  PfxUInt32 m_numTrees = 0;
  PfxInt32* m_bodyNode = nullptr;  // each body's node, or -1
  PfxUInt32 m_numRigidBodies = 0;
  PfxJoint* m_joints = nullptr;
  const PfxConstraintPair* m_jointPairs = nullptr;
  PfxSolverBody* m_solverBodies = nullptr;
};

}  // namespace pfx
