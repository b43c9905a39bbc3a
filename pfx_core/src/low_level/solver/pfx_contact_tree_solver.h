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

#include <cstddef>

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"
#include "low_level/solver/pfx_block_tree.h"

namespace pfx {

class PfxContactTreeSolver {
 public:
  // Work for picking and ordering the forest: a few words per body and pair, a node per
  // body and face, a face's rows; no blocks (see solve).
  static PfxUInt32 getWorkBytes(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs);
  // The nodes of a forest over every body, the most any step can have.
  static PfxUInt32 getMaxNodes(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs);
  // Scratch that holds the blocks of numNodes nodes.
  static std::size_t getScratchBytes(PfxUInt32 numNodes);

  // Picks the touching contact pairs that form a forest and orders it. Trees with a body
  // held by one of the joints are left out. False when the work buffer is too small.
  bool build(void* workBuff, PfxUInt32 workBytes, const PfxConstraintPair* contactPairs,
             PfxUInt32 numContactPairs, const PfxConstraintPair* jointPairs,
             PfxUInt32 numJointPairs, PfxContactManifold* manifolds,
             PfxSolverBody* solverBodies, PfxUInt32 numRigidBodies,
             PfxTaskManager* taskManager = nullptr);
  // The nodes of the largest tree built: what solve's scratch must hold at least.
  PfxUInt32 getLargestTreeNodes() const { return m_largestTreeNodes; }

  // Adds to the points' normal and friction impulses, and to the bodies' velocity changes,
  // what makes every face of the forest move at its points' target velocities (m_rhs of
  // the normal and friction rows), each point's normal impulse kept at zero or above and
  // its friction within its circle; then the same for the split impulses and the push
  // velocities (m_pushRhs). The blocks of a tree are needed only while it is factored and
  // solved, so the trees go through the scratch a batch at a time, as many whole trees as
  // it holds, and the trees of a batch in parallel with a task manager: they share no
  // moving body, so the result is the same. False when the scratch cannot hold the
  // largest tree (nothing is then changed).
  bool solve(void* scratch, std::size_t scratchBytes, PfxTaskManager* taskManager = nullptr);

 private:
  struct Node;
  struct Face;
  // Sets the blocks of a tree's nodes in the scratch and factors them, with the faces'
  // friction rows (the velocity solve) or without (the split impulses').
  void factorTree(PfxBlockTreeNode* blocks, PfxUInt32 begin, PfxUInt32 end, bool withFriction);
  void solveTree(PfxBlockTreeNode* blocks, PfxUInt32 begin, PfxUInt32 end, bool push);

  Node* m_nodes = nullptr;  // breadth first: parents before children, tree after tree
  PfxUInt32 m_numNodes = 0;
  Face* m_faces = nullptr;  // a face node's rows
  PfxUInt32* m_treeStarts = nullptr;  // first node of each tree, then m_numNodes
  PfxUInt32 m_numTrees = 0;
  PfxUInt32 m_largestTreeNodes = 0;
  const PfxConstraintPair* m_contactPairs = nullptr;
  PfxContactManifold* m_manifolds = nullptr;
  PfxSolverBody* m_solverBodies = nullptr;
};

}  // namespace pfx
