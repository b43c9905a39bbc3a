// Direct solve of the normal impulses of contacts that link bodies into trees: stacks,
// towers, a heavy load on a light part. Projected Gauss-Seidel passes the weight of a stack
// down one body per sweep and, where a light body sits between heavy ones, corrects it by
// only 1 / (1 + ratio) per sweep: a 30-box tower at 10 iterations leaves the lower boxes
// sinking unevenly, which feeds back into a sway that grows until the tower falls, and a
// 1 kg box under 1000 kg is squeezed out sideways. Treating each touching face as an
// equality for one solve over the forest of such faces (the same linear-time factorization
// as the joints' tree solve) gives every face of a stack its exact share at once, whatever
// the masses; one-sidedness is restored by clamping each point's accumulated impulse at
// zero, and whatever the clamp leaves over, the iterations take up. Bodies whose faces
// close loops (a pyramid, a pile) are left to the iterations alone.
//
// A face is not given its points' rows, which are redundant (four coplanar points hold
// three degrees of freedom), but up to three combinations of them: the total push and
// its first moments along the principal axes of the points. The impulse that comes back
// is an affine pressure over the face, which is what a rigid face carries. In the velocity
// solve a face also holds its slip along its two tangents and its twist about its normal,
// each point's share then clamped to its friction circle: iterated alone, friction passes
// a sideways disturbance between a 1 kg box and the 10 kg box on it by a tenth per sweep,
// and a 1, 10, 100, 1000 kg stack (lightest at the bottom) slid apart after 5 s when one
// contact point was replaced. The split impulses, which carry no friction, are solved
// over the pressure rows alone, from a second factorization.
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

class PfxContactTreeSolver {
 public:
  static PfxUInt32 getWorkBytes(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs);

  // Picks the touching contact pairs that form a forest, orders and factors the system.
  // Trees with a body held by one of the joints are left out. False when the work buffer
  // is too small. The trees are factored in parallel with a task manager.
  bool build(void* workBuff, PfxUInt32 workBytes, const PfxConstraintPair* contactPairs,
             PfxUInt32 numContactPairs, const PfxConstraintPair* jointPairs,
             PfxUInt32 numJointPairs, PfxContactManifold* manifolds,
             PfxSolverBody* solverBodies, PfxUInt32 numRigidBodies,
             PfxTaskManager* taskManager = nullptr);

  // Adds to the points' normal and friction impulses, and to the bodies' velocity changes,
  // what makes every face of the forest move at its points' target velocities (m_rhs of
  // the normal and friction rows), each point's normal impulse kept at zero or above and
  // its friction within its circle. Trees are solved in parallel with a task
  // manager; they share no moving body, so the result is the same.
  void solveVelocities(PfxTaskManager* taskManager = nullptr);
  // The same for the split impulses and the push velocities (m_pushRhs).
  void solvePush(PfxTaskManager* taskManager = nullptr);

 private:
  struct Node;
  // Sets the blocks of every node and factors the trees, with the faces' friction rows
  // (the velocity solve) or without (the split impulses').
  void factor(bool withFriction, PfxTaskManager* taskManager);
  void solve(bool push, PfxTaskManager* taskManager);
  void solveTree(bool push, PfxUInt32 begin, PfxUInt32 end);

  Node* m_nodes = nullptr;  // breadth first: parents before children, tree after tree
  PfxUInt32 m_numNodes = 0;
  PfxUInt32* m_treeStarts = nullptr;  // first node of each tree, then m_numNodes
  PfxUInt32 m_numTrees = 0;
  bool m_factoredWithFriction = false;
  const PfxConstraintPair* m_contactPairs = nullptr;
  PfxContactManifold* m_manifolds = nullptr;
  PfxSolverBody* m_solverBodies = nullptr;
};

}  // namespace pfx
