#include "low_level/solver/pfx_joint_tree_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "low_level/solver/pfx_block_tree.h"
#include "low_level/solver/pfx_joint_row.h"

namespace pfx {

namespace {

// Compliance added to each locked row, relative to its effective mass: small enough to
// leave the answer unchanged, large enough to keep redundant rows (two joints holding the
// same axis) from making the system singular.
constexpr double kJointTreeRelativeCompliance = 1e-9;

// A joint picked for the forest but not yet given a node.
constexpr PfxInt32 kJointTreeChosen = -2;

constexpr PfxUInt32 kJointTreesPerTask = 8;

// Room for the bounded rows' velocity changes in the work buffer, per joint pair: three
// rows on a tree of 24 bodies each (a ragdoll's ball joints have three limit rows, a URDF
// humanoid has about 20 links). Rows past it solve their tree at each update.
constexpr std::size_t kBoundedRowsPerJoint = 3;
constexpr std::size_t kBodiesPerTreeWithRoom = 24;
constexpr std::size_t kVelocityChangesPerJoint = kBoundedRowsPerJoint * kBodiesPerTreeWithRoom * 6;

// Per joint pair: a slot for each of its six axes' two rows.
constexpr std::size_t kRowSlotsPerJoint = 12;

// When the locked axes take nearly the whole impulse of a row (it is almost one of
// theirs), scaling the impulse up to the tree's response would only amplify rounding:
// below this fraction of the two bodies' response, the row's impulse is sized by the two
// bodies' response and the tree takes most of it.
constexpr double kSmallestRelativeResponse = 1e-4;

// Nodes from a body to its root beyond which getImpulseResponse solves the whole tree.
constexpr int kMaxResponsePath = 64;

// A locked row whose velocity is this close to its target (m/s, or rad/s) holds to the
// rounding of the velocities (1 µm/s in float, scaled by the precision's epsilon): a solve
// would move the tree by no more than that. Of the piled ragdolls' tree solves in the
// velocity solve, 45 % (dt 1/60) to 55 % (1/240) met every row within 1e-6 and the others
// missed some row by 1e-4 or more; most of the first are the solves after a sweep of the
// joints, whose bounded rows' updates leave the locked axes held but for rounding. Only
// the solves between the first sweep and the last are skipped so: skipping the last too
// left the arm of `pfx_bench --scene urdf` at dt 1/240 with twice the joint gap (2.4e-7
// against 1.2e-7 m, two steps of a float at 1 m instead of one).
constexpr double kHeldLockedRowVelocity =
    1e-6 * (double(std::numeric_limits<PfxFloat>::epsilon()) /
            double(std::numeric_limits<float>::epsilon()));

}  // namespace

// One node of the forest: a body, or a joint with up to 6 locked rows.
struct PfxJointTreeSolver::Node : PfxBlockTreeNode {
  PfxInt32 body;       // rigid body id, or -1 for a joint node
  PfxInt32 jointPair;  // joint pair index, or -1 for a body node
  PfxUInt8 axes[6];    // joint node: the joint axis of each row
  PfxUInt8 numRows;
  // Joint node: each row's Jacobian, fixed for the solve, so that a tree solve's
  // right-hand side does not rebuild it.
  PfxJointRowJacobian jacobians[6];
  PfxUInt32 tree;
  // solveTreeForRowImpulses(): the node is a loaded body or one of its ancestors.
  bool loaded;
  bool leaf;  // no node has it for parent
  // Unknowns of the node in the sized elimination (pfxFactorSizedBlockTree).
  int blockSize() const { return body >= 0 ? 6 : numRows; }
  // A leaf body's pivot is its mass matrix alone, whose inverse the solver body holds: set
  // up inverted, it saves a 3 x 3 and a 6 x 6 inversion (a ragdoll's head, hands and feet,
  // an arm's last link).
  bool pivotInverted() const { return body >= 0 && leaf; }
};

// A bounded row of a joint in the forest, prepared by prepareBoundedRows().
struct PfxJointTreeSolver::BoundedRow {
  PfxUInt32 jointPair;
  PfxUInt32 tree;
  PfxUInt8 axis;
  PfxUInt8 drive;  // m_driveRow, else m_constraintRow
  bool hasRoom;    // its velocity changes are kept, from velocityChanges on
  std::size_t velocityChanges;
  PfxFloat response;  // the row's own velocity change per unit impulse
};

namespace {
std::size_t maxBodiesInTrees(PfxUInt32 numRigidBodies, PfxUInt32 numJointPairs) {
  return std::min(std::size_t(numRigidBodies), 2 * std::size_t(numJointPairs));
}
}  // namespace

PfxUInt32 PfxJointTreeSolver::getWorkBytes(PfxUInt32 numRigidBodies, PfxUInt32 numJointPairs) {
  const std::size_t numNodes = std::size_t(numRigidBodies) + numJointPairs;
  const std::size_t bytes =
      PfxWorkCarver::bytesFor(alignof(Node), sizeof(Node) * numNodes) +
      PfxWorkCarver::bytesFor(alignof(PfxInt32), sizeof(PfxInt32) *
                                                     (numJointPairs +           // joint nodes
                                                      2 * numRigidBodies + 1 +  // nodes, sets
                                                      numRigidBodies + 1 +      // adjacency offsets
                                                      2 * numJointPairs +       // adjacency
                                                      numRigidBodies + 1 +      // tree starts
                                                      numRigidBodies +          // trees' bodies
                                                      numNodes)) +  // response slots
      PfxWorkCarver::bytesFor(alignof(PfxTreeBlock),
                              sizeof(PfxTreeBlock) * maxBodiesInTrees(numRigidBodies, numJointPairs)) +
      3 * PfxWorkCarver::bytesFor(alignof(PfxUInt8), numRigidBodies + 1);  // per tree: moved
                                                                            // from outside,
                                                                            // factored, held
  return static_cast<PfxUInt32>(bytes);
}

bool PfxJointTreeSolver::build(void* workBuff, PfxUInt32 workBytes,
                               const PfxConstraintPair* jointPairs, PfxUInt32 numJointPairs,
                               PfxJoint* joints, PfxSolverBody* solverBodies,
                               PfxUInt32 numRigidBodies, PfxTaskManager* taskManager,
                               Factoring factoring) {
  m_numNodes = 0;
  m_numTrees = 0;
  m_bodyNode = nullptr;
  m_boundedRowSlot = nullptr;
  m_numJointPairs = numJointPairs;
  m_numRigidBodies = numRigidBodies;
  m_joints = joints;
  m_jointPairs = jointPairs;
  m_solverBodies = solverBodies;
  PfxWorkCarver carver(workBuff, workBytes);
  const std::size_t maxNodes = std::size_t(numRigidBodies) + numJointPairs;
  m_nodes = carver.take<Node>(maxNodes);
  m_jointNode = carver.take<PfxInt32>(numJointPairs);
  PfxInt32* bodyNode = carver.take<PfxInt32>(numRigidBodies);
  PfxInt32* sets = carver.take<PfxInt32>(numRigidBodies + 1);
  PfxInt32* adjacencyStart = carver.take<PfxInt32>(numRigidBodies + 1);
  PfxInt32* adjacency = carver.take<PfxInt32>(2 * std::size_t(numJointPairs));
  m_treeStarts = carver.take<PfxUInt32>(std::size_t(numRigidBodies) + 1);
  m_bodyTreeBody = carver.take<PfxInt32>(numRigidBodies);
  m_responseSlot = carver.take<PfxInt32>(maxNodes);
  m_bodyResponses = carver.take<PfxTreeBlock>(maxBodiesInTrees(numRigidBodies, numJointPairs));
  m_numBodyResponses = 0;
  m_treeMovedFromOutside = carver.take<PfxUInt8>(std::size_t(numRigidBodies) + 1);
  m_treeFactored = carver.take<PfxUInt8>(std::size_t(numRigidBodies) + 1);
  m_treeHeld = carver.take<PfxUInt8>(std::size_t(numRigidBodies) + 1);
  if (maxNodes == 0) return true;
  if (!m_nodes || !bodyNode || !sets || !adjacencyStart || !m_treeStarts || !m_bodyTreeBody ||
      !m_responseSlot || !m_treeMovedFromOutside || !m_treeFactored || !m_treeHeld ||
      (numJointPairs > 0 && (!m_jointNode || !adjacency))) {
    return false;
  }
  m_bodyNode = bodyNode;
  for (std::size_t n = 0; n < maxNodes; ++n) m_responseSlot[n] = -1;

  auto movable = [&](PfxUInt32 id, bool receives) {
    return receives && solverBodies[id].m_massInv > 0;
  };
  // Everything that does not move is one "ground" in the search for loops: two joints that
  // hold one chain to the ground close a loop through it.
  const PfxInt32 ground = static_cast<PfxInt32>(numRigidBodies);
  for (PfxUInt32 b = 0; b <= numRigidBodies; ++b) {
    if (b < numRigidBodies) bodyNode[b] = m_bodyTreeBody[b] = -1;
    sets[b] = static_cast<PfxInt32>(b);
    adjacencyStart[b] = 0;
  }

  // Joints with locked rows, acting on a body that moves, and not closing a loop.
  for (PfxUInt32 i = 0; i < numJointPairs; ++i) {
    m_jointNode[i] = -1;
    const PfxConstraintPair& pair = jointPairs[i];
    if (!pfxGetActive(pair)) continue;
    const PfxJoint& joint = joints[pfxGetConstraintId(pair)];
    bool hasRows = false;
    for (const PfxJointConstraint& c : joint.m_constraints) hasRows = hasRows || isLockedRow(c);
    const PfxUInt32 a = pfxGetObjectIdA(pair), b = pfxGetObjectIdB(pair);
    const bool moveA = movable(a, pfxGetReceivesA(pair));
    const bool moveB = movable(b, pfxGetReceivesB(pair));
    // A body that moves but takes nothing from this joint (one-way) cannot be both inside
    // and outside the system: such a joint stays iterative.
    const bool oneWay = (!moveA && solverBodies[a].m_massInv > 0) ||
                        (!moveB && solverBodies[b].m_massInv > 0);
    if (!hasRows || oneWay || (!moveA && !moveB)) continue;
    const PfxInt32 ra = pfxFindTreeRoot(sets, moveA ? static_cast<PfxInt32>(a) : ground);
    const PfxInt32 rb = pfxFindTreeRoot(sets, moveB ? static_cast<PfxInt32>(b) : ground);
    if (ra == rb) continue;
    sets[ra] = rb;
    m_jointNode[i] = kJointTreeChosen;
    if (moveA) ++adjacencyStart[a];
    if (moveB) ++adjacencyStart[b];
  }
  // Adjacency of each body: the chosen joints acting on it.
  PfxInt32 running = 0;
  for (PfxUInt32 b = 0; b <= numRigidBodies; ++b) {
    const PfxInt32 count = b < numRigidBodies ? adjacencyStart[b] : 0;
    adjacencyStart[b] = running;
    running += count;
  }
  for (PfxUInt32 b = 0; b < numRigidBodies; ++b) sets[b] = adjacencyStart[b];  // fill cursors
  for (PfxUInt32 i = 0; i < numJointPairs; ++i) {
    if (m_jointNode[i] != kJointTreeChosen) continue;
    const PfxConstraintPair& pair = jointPairs[i];
    const PfxUInt32 a = pfxGetObjectIdA(pair), b = pfxGetObjectIdB(pair);
    if (movable(a, pfxGetReceivesA(pair))) adjacency[sets[a]++] = static_cast<PfxInt32>(i);
    if (movable(b, pfxGetReceivesB(pair))) adjacency[sets[b]++] = static_cast<PfxInt32>(i);
  }

  // Breadth first from the roots. A tree held to the ground is rooted at the joint that
  // holds it, so that every leaf is a body: a joint eliminated as a leaf would have a
  // pivot of nearly zero (its compliance), and the factorization would lose its precision.
  auto addNode = [&](PfxInt32 parent, PfxInt32 body, PfxInt32 jointPair) {
    Node& node = m_nodes[m_numNodes];
    node.parent = parent;
    node.body = body;
    node.jointPair = jointPair;
    node.numRows = 0;
    node.loaded = false;
    node.leaf = true;
    if (parent >= 0) m_nodes[parent].leaf = false;
    return static_cast<PfxInt32>(m_numNodes++);
  };
  auto grow = [&](std::size_t head) {
    const std::size_t root = head;
    while (head < m_numNodes) {
      const Node& current = m_nodes[head];
      const PfxInt32 self = static_cast<PfxInt32>(head++);
      if (current.body >= 0) {
        for (PfxInt32 k = adjacencyStart[current.body]; k < adjacencyStart[current.body + 1]; ++k) {
          const PfxInt32 pairIndex = adjacency[k];
          if (m_jointNode[pairIndex] != kJointTreeChosen) continue;  // already in the forest
          m_jointNode[pairIndex] = addNode(self, -1, pairIndex);
        }
      } else {
        const PfxConstraintPair& pair = jointPairs[current.jointPair];
        if (movable(pfxGetObjectIdA(pair), pfxGetReceivesA(pair)) &&
            bodyNode[pfxGetObjectIdA(pair)] < 0) {
          bodyNode[pfxGetObjectIdA(pair)] =
              addNode(self, static_cast<PfxInt32>(pfxGetObjectIdA(pair)), -1);
        }
        if (movable(pfxGetObjectIdB(pair), pfxGetReceivesB(pair)) &&
            bodyNode[pfxGetObjectIdB(pair)] < 0) {
          bodyNode[pfxGetObjectIdB(pair)] =
              addNode(self, static_cast<PfxInt32>(pfxGetObjectIdB(pair)), -1);
        }
      }
    }
    for (std::size_t n = root; n < m_numNodes; ++n) m_nodes[n].tree = m_numTrees - 1;
  };
  for (PfxUInt32 i = 0; i < numJointPairs; ++i) {
    if (m_jointNode[i] != kJointTreeChosen) continue;
    const PfxConstraintPair& pair = jointPairs[i];
    const bool moveA = movable(pfxGetObjectIdA(pair), pfxGetReceivesA(pair));
    const bool moveB = movable(pfxGetObjectIdB(pair), pfxGetReceivesB(pair));
    if (moveA == moveB) continue;
    const std::size_t head = m_numNodes;
    m_treeStarts[m_numTrees++] = m_numNodes;
    m_jointNode[i] = addNode(-1, -1, static_cast<PfxInt32>(i));
    grow(head);
  }
  for (PfxUInt32 i = 0; i < numJointPairs; ++i) {
    if (m_jointNode[i] != kJointTreeChosen) continue;
    const PfxUInt32 a = pfxGetObjectIdA(jointPairs[i]);
    const std::size_t head = m_numNodes;
    m_treeStarts[m_numTrees++] = m_numNodes;
    bodyNode[a] = addNode(-1, static_cast<PfxInt32>(a), -1);
    grow(head);
  }

  m_treeStarts[m_numTrees] = m_numNodes;
  for (PfxUInt32 t = 0; t < m_numTrees; ++t) {
    // A tree's first node is a body or a joint whose first child is a body.
    std::size_t firstBody = m_treeStarts[t];
    while (m_nodes[firstBody].body < 0) ++firstBody;
    for (std::size_t n = firstBody; n < m_treeStarts[t + 1]; ++n) {
      if (m_nodes[n].body >= 0) m_bodyTreeBody[m_nodes[n].body] = m_nodes[firstBody].body;
    }
    m_treeFactored[t] = 0;
    m_treeHeld[t] = 0;
  }
  if (factoring == Factoring::kNow) {
    pfxParallelFor(taskManager, m_numTrees, kJointTreesPerTask,
                   [&](PfxUInt32 first, PfxUInt32 last) {
                     for (PfxUInt32 t = first; t < last; ++t) factorTree(t);
                   });
  }
  return true;
}

// Trees share no node, and a tree's nodes are set up in order, since a body node reads the
// rows its parent joint node was given, so tree after tree on any thread, and in any order,
// gives the same bits as one pass over the forest.
void PfxJointTreeSolver::factorTree(PfxUInt32 tree) {
  for (std::size_t n = m_treeStarts[tree]; n < m_treeStarts[tree + 1]; ++n) {
    Node& node = m_nodes[n];
    if (node.body >= 0) {
      const PfxSolverBody& body = m_solverBodies[node.body];
      node.diagonalInverse =
          node.pivotInverted() ? pfxTreeBodyMassInverse(body) : pfxTreeBodyMass(body);
    } else {
      const PfxJoint& joint = m_joints[pfxGetConstraintId(m_jointPairs[node.jointPair])];
      node.numRows = 0;
      for (PfxUInt8 axis = 0; axis < 6; ++axis) {
        const PfxJointConstraint& c = joint.m_constraints[axis];
        if (!isLockedRow(c) || c.m_constraintRow.m_jacDiagInv <= 0) continue;
        const PfxUInt8 row = node.numRows++;
        node.axes[row] = axis;
        node.jacobians[row] = pfxJointRowJacobian(joint, axis, c.m_constraintRow.m_normal);
        for (PfxUInt8 k = 0; k < row; ++k) node.diagonalInverse(row, k) = 0;
        node.diagonalInverse(row, row) =
            -kJointTreeRelativeCompliance / double(c.m_constraintRow.m_jacDiagInv);
      }
    }
    if (node.parent < 0) continue;
    // H(node, parent) couples a joint's rows with one of its bodies' velocities: rows x
    // velocities for a joint node, the transpose for a body node. Nodes come parents
    // first, so a joint parent already has its rows.
    const Node& parent = m_nodes[node.parent];
    const Node& jointNode = node.body >= 0 ? parent : node;
    const PfxInt32 body = node.body >= 0 ? node.body : parent.body;
    const PfxConstraintPair& pair = m_jointPairs[jointNode.jointPair];
    const bool isA = PfxUInt32(body) == pfxGetObjectIdA(pair);
    for (PfxUInt8 row = 0; row < jointNode.numRows; ++row) {
      const PfxJointRowJacobian& j = jointNode.jacobians[row];
      const PfxVector3& linear = isA ? j.linearA : j.linearB;
      const PfxVector3& angular = isA ? j.angularA : j.angularB;
      for (int k = 0; k < 3; ++k) {
        double& toLinear = node.body >= 0 ? node.toParent(k, row) : node.toParent(row, k);
        double& toAngular = node.body >= 0 ? node.toParent(k + 3, row) : node.toParent(row, k + 3);
        toLinear = double(linear[k]);
        toAngular = double(angular[k]);
      }
    }
  }
  pfxFactorSizedBlockTree(m_nodes, m_treeStarts[tree], m_treeStarts[tree + 1]);
  m_treeFactored[tree] = 1;
}

void PfxJointTreeSolver::solvePush(PfxTaskManager* taskManager) { solve(true, taskManager); }

void PfxJointTreeSolver::refactorTreeOf(PfxUInt32 rigidBodyId) {
  const PfxInt32 node = nodeOfBody(rigidBodyId);
  if (node < 0) return;
  const PfxUInt32 tree = m_nodes[node].tree;
  if (!m_treeFactored[tree]) return;
  m_treeFactored[tree] = 0;
  for (PfxUInt32 n = m_treeStarts[tree]; n < m_treeStarts[tree + 1]; ++n) {
    if (m_responseSlot[n] >= 0) m_responseSlot[n] = -2 - m_responseSlot[n];
  }
}

PfxUInt32 PfxJointTreeSolver::getBoundedRowWorkBytes(PfxUInt32 numRigidBodies,
                                                     PfxUInt32 numJointPairs) {
  const std::size_t slots = kRowSlotsPerJoint * numJointPairs;
  const std::size_t bytes =
      PfxWorkCarver::bytesFor(alignof(PfxInt32), sizeof(PfxInt32) * slots) +
      PfxWorkCarver::bytesFor(alignof(BoundedRow), sizeof(BoundedRow) * slots) +
      PfxWorkCarver::bytesFor(alignof(double), sizeof(double) * slots) +
      PfxWorkCarver::bytesFor(alignof(PfxUInt32),
                              sizeof(PfxUInt32) * (4 * std::size_t(numRigidBodies) + 3)) +
      PfxWorkCarver::bytesFor(alignof(PfxFloat),
                              sizeof(PfxFloat) * kVelocityChangesPerJoint * numJointPairs);
  return static_cast<PfxUInt32>(bytes);
}

bool PfxJointTreeSolver::prepareBoundedRows(void* workBuff, PfxUInt32 workBytes,
                                            PfxTaskManager* taskManager) {
  m_boundedRowSlot = nullptr;
  if (m_numNodes == 0) return true;
  PfxWorkCarver carver(workBuff, workBytes);
  const std::size_t slots = kRowSlotsPerJoint * m_numJointPairs;
  PfxInt32* rowSlot = carver.take<PfxInt32>(slots);
  m_boundedRows = carver.take<BoundedRow>(slots);
  m_rowImpulseSums = carver.take<double>(slots);
  m_treeRowStarts = carver.take<PfxUInt32>(std::size_t(m_numTrees) + 1);
  m_treeBodyStarts = carver.take<PfxUInt32>(std::size_t(m_numTrees) + 1);
  m_treeBodies = carver.take<PfxUInt32>(m_numRigidBodies);
  m_treesToSolve = carver.take<PfxUInt32>(m_numRigidBodies);
  const std::size_t room = kVelocityChangesPerJoint * m_numJointPairs;
  m_rowVelocityChanges = carver.take<PfxFloat>(room);
  if (!rowSlot || !m_boundedRows || !m_rowImpulseSums || !m_treeRowStarts ||
      !m_treeBodyStarts || !m_treeBodies || !m_treesToSolve || !m_rowVelocityChanges) {
    return false;
  }
  for (std::size_t i = 0; i < slots; ++i) rowSlot[i] = -1;
  PfxUInt32 numBodies = 0, numRows = 0;
  std::size_t used = 0;
  for (PfxUInt32 t = 0; t < m_numTrees; ++t) {
    m_treeBodyStarts[t] = numBodies;
    for (PfxUInt32 n = m_treeStarts[t]; n < m_treeStarts[t + 1]; ++n) {
      if (m_nodes[n].body >= 0) m_treeBodies[numBodies++] = PfxUInt32(m_nodes[n].body);
    }
    const std::size_t changesPerRow = 6 * std::size_t(numBodies - m_treeBodyStarts[t]);
    m_treeRowStarts[t] = numRows;
    for (PfxUInt32 n = m_treeStarts[t]; n < m_treeStarts[t + 1]; ++n) {
      const Node& node = m_nodes[n];
      if (node.jointPair < 0) continue;
      const PfxJoint& joint = m_joints[pfxGetConstraintId(m_jointPairs[node.jointPair])];
      for (PfxUInt8 axis = 0; axis < 6; ++axis) {
        const PfxJointConstraint& c = joint.m_constraints[axis];
        for (PfxUInt8 drive = 0; drive < 2; ++drive) {
          const bool iterated = drive ? c.m_driveRowUsed != 0
                                      : c.m_rowType != kPfxJointRowNone && !isLockedRow(c);
          const PfxConstraintRow& row = drive ? c.m_driveRow : c.m_constraintRow;
          if (!iterated || row.m_jacDiagInv <= 0) continue;
          const bool hasRoom = used + changesPerRow <= room;
          m_boundedRows[numRows] = {PfxUInt32(node.jointPair), t, axis, drive, hasRoom, used, 0};
          if (hasRoom) used += changesPerRow;
          m_rowImpulseSums[numRows] = 0;
          rowSlot[(std::size_t(node.jointPair) * 6 + axis) * 2 + drive] = PfxInt32(numRows++);
        }
      }
    }
  }
  m_treeBodyStarts[m_numTrees] = numBodies;
  m_treeRowStarts[m_numTrees] = numRows;
  m_boundedRowSlot = rowSlot;

  pfxParallelFor(taskManager, m_numTrees, kJointTreesPerTask, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 t = first; t < last; ++t) {
      for (PfxUInt32 r = m_treeRowStarts[t]; r < m_treeRowStarts[t + 1]; ++r) {
        const BoundedRow& boundedRow = m_boundedRows[r];
        // A drive and a limit on one axis mostly share a direction (or its opposite), so
        // the last row's solve, the nodes' values, answers this one too, exactly.
        const double sign =
            r > m_treeRowStarts[t] ? sameJacobianSign(m_boundedRows[r - 1], boundedRow) : 0;
        if (sign == 0) {
          solveTreeForRowImpulses(t, r, r + 1, nullptr);
        } else if (sign < 0) {
          for (PfxUInt32 n = m_treeStarts[t]; n < m_treeStarts[t + 1]; ++n) {
            m_nodes[n].value = -m_nodes[n].value;
          }
        }
        // The row's own velocity change per unit impulse.
        const PfxJointRowJacobian j = boundedRowJacobian(boundedRow);
        const PfxConstraintPair& pair = m_jointPairs[boundedRow.jointPair];
        double response = 0;
        for (const bool isA : {true, false}) {
          const PfxInt32 n = m_bodyNode[isA ? pfxGetObjectIdA(pair) : pfxGetObjectIdB(pair)];
          if (n < 0) continue;
          const PfxTreeVector& change = m_nodes[n].value;
          response += (isA ? j.linearA : j.linearB).cast<double>().dot(change.head<3>()) +
                      (isA ? j.angularA : j.angularB).cast<double>().dot(change.tail<3>());
        }
        const PfxJointConstraint& c =
            m_joints[pfxGetConstraintId(pair)].m_constraints[boundedRow.axis];
        const PfxConstraintRow& row = boundedRow.drive ? c.m_driveRow : c.m_constraintRow;
        const double twoBodyResponse = double(c.m_weight) / double(row.m_jacDiagInv);
        m_boundedRows[r].response = static_cast<PfxFloat>(
            response > kSmallestRelativeResponse * twoBodyResponse ? response
                                                                   : twoBodyResponse);
        if (!boundedRow.hasRoom) continue;
        PfxFloat* changes = m_rowVelocityChanges + boundedRow.velocityChanges;
        for (PfxUInt32 k = m_treeBodyStarts[t]; k < m_treeBodyStarts[t + 1]; ++k, changes += 6) {
          const PfxTreeVector& change = m_nodes[m_bodyNode[m_treeBodies[k]]].value;
          for (int i = 0; i < 6; ++i) changes[i] = static_cast<PfxFloat>(change[i]);
        }
      }
    }
  });
  return true;
}

double PfxJointTreeSolver::sameJacobianSign(const BoundedRow& first,
                                            const BoundedRow& second) const {
  if (first.jointPair != second.jointPair || first.axis != second.axis) return 0;
  const PfxJointConstraint& c =
      m_joints[pfxGetConstraintId(m_jointPairs[first.jointPair])].m_constraints[first.axis];
  const PfxVector3& a = (first.drive ? c.m_driveRow : c.m_constraintRow).m_normal;
  const PfxVector3& b = (second.drive ? c.m_driveRow : c.m_constraintRow).m_normal;
  if (a == b) return 1;
  if (a == -b) return -1;
  return 0;
}

PfxJointRowJacobian PfxJointTreeSolver::boundedRowJacobian(const BoundedRow& row) const {
  const PfxJoint& joint = m_joints[pfxGetConstraintId(m_jointPairs[row.jointPair])];
  const PfxJointConstraint& c = joint.m_constraints[row.axis];
  return pfxJointRowJacobian(joint, row.axis,
                             (row.drive ? c.m_driveRow : c.m_constraintRow).m_normal);
}

void PfxJointTreeSolver::solveTreeForRowImpulses(PfxUInt32 tree, PfxUInt32 firstRow,
                                                 PfxUInt32 lastRow, const double* impulses) {
  factorIfNeeded(tree);
  const std::size_t begin = m_treeStarts[tree], end = m_treeStarts[tree + 1];
  for (std::size_t n = begin; n < end; ++n) m_nodes[n].value.setZero();
  auto load = [&](PfxInt32 bodyNode, const PfxVector3& linear, const PfxVector3& angular,
                  double impulse) {
    m_nodes[bodyNode].value.head<3>() += impulse * linear.cast<double>();
    m_nodes[bodyNode].value.tail<3>() += impulse * angular.cast<double>();
    for (PfxInt32 n = bodyNode; n >= 0 && !m_nodes[n].loaded; n = m_nodes[n].parent) {
      m_nodes[n].loaded = true;
    }
  };
  for (PfxUInt32 r = firstRow; r < lastRow; ++r) {
    const double impulse = impulses ? impulses[r] : 1.0;
    if (impulse == 0) continue;
    const PfxJointRowJacobian j = boundedRowJacobian(m_boundedRows[r]);
    const PfxConstraintPair& pair = m_jointPairs[m_boundedRows[r].jointPair];
    // A body of a joint in the forest has a node exactly when it moves.
    if (const PfxInt32 a = m_bodyNode[pfxGetObjectIdA(pair)]; a >= 0) {
      load(a, j.linearA, j.angularA, impulse);
    }
    if (const PfxInt32 b = m_bodyNode[pfxGetObjectIdB(pair)]; b >= 0) {
      load(b, j.linearB, j.angularB, impulse);
    }
  }
  pfxSolveSizedBlockTree(m_nodes, begin, end, [&](std::size_t n) { return m_nodes[n].loaded; });
  for (std::size_t n = begin; n < end; ++n) m_nodes[n].loaded = false;
}

PfxFloat PfxJointTreeSolver::getBoundedRowResponse(PfxInt32 slot) const {
  return m_boundedRows[slot].response;
}

void PfxJointTreeSolver::applyBoundedRowImpulse(PfxInt32 slot, PfxFloat impulse) {
  const BoundedRow& row = m_boundedRows[slot];
  if (!row.hasRoom) {
    // The two bodies take the impulse, and the tree solve spreads it (and adds the locked
    // rows' share to their impulses).
    const PfxConstraintPair& pair = m_jointPairs[row.jointPair];
    pfxApplyJointRowImpulse(boundedRowJacobian(row), impulse,
                            m_solverBodies[pfxGetObjectIdA(pair)], pfxGetReceivesA(pair) ? 1 : 0,
                            m_solverBodies[pfxGetObjectIdB(pair)], pfxGetReceivesB(pair) ? 1 : 0,
                            &PfxSolverBody::m_deltaLinearVelocity,
                            &PfxSolverBody::m_deltaAngularVelocity);
    solveTree(false, m_treeStarts[row.tree], m_treeStarts[row.tree + 1]);
    return;
  }
  const PfxFloat* changes = m_rowVelocityChanges + row.velocityChanges;
  for (PfxUInt32 k = m_treeBodyStarts[row.tree]; k < m_treeBodyStarts[row.tree + 1];
       ++k, changes += 6) {
    PfxSolverBody& body = m_solverBodies[m_treeBodies[k]];
    body.m_deltaLinearVelocity += impulse * PfxVector3(changes[0], changes[1], changes[2]);
    body.m_deltaAngularVelocity += impulse * PfxVector3(changes[3], changes[4], changes[5]);
  }
  m_rowImpulseSums[slot] += impulse;
}

void PfxJointTreeSolver::markTreeOfBody(PfxUInt32 rigidBodyId) {
  const PfxInt32 node = m_bodyNode[rigidBodyId];
  if (node >= 0) m_treeMovedFromOutside[m_nodes[node].tree] = 1;
}

void PfxJointTreeSolver::markTreesMovedFromOutside(const PfxJointCoupling* couplings,
                                                   PfxUInt32 numCouplings) {
  if (m_numNodes == 0) return;
  for (PfxUInt32 t = 0; t < m_numTrees; ++t) m_treeMovedFromOutside[t] = 0;
  for (PfxUInt32 i = 0; i < m_numJointPairs; ++i) {
    const PfxConstraintPair& pair = m_jointPairs[i];
    if (!pfxGetActive(pair) || contains(i)) continue;
    markTreeOfBody(pfxGetObjectIdA(pair));
    markTreeOfBody(pfxGetObjectIdB(pair));
  }
  for (PfxUInt32 i = 0; i < numCouplings; ++i) {
    for (PfxUInt32 b = 0; b < couplings[i].m_numBodies; ++b) {
      markTreeOfBody(couplings[i].m_bodies[b].m_rigidBodyId);
    }
  }
}

void PfxJointTreeSolver::markTreesMovedByContacts(const PfxConstraintPair* contactPairs,
                                                  PfxUInt32 numContactPairs,
                                                  const PfxContactManifold* manifolds) {
  if (m_numNodes == 0) return;
  for (PfxUInt32 i = 0; i < numContactPairs; ++i) {
    const PfxConstraintPair& pair = contactPairs[i];
    if (!pfxGetActive(pair)) continue;
    const PfxContactManifold& manifold = manifolds[pfxGetContactId(pair)];
    bool acted = false;
    for (PfxUInt32 c = 0; c < manifold.getNumContacts() && !acted; ++c) {
      for (const PfxConstraintRow& row : manifold.getContactPoint(c).m_constraintRow) {
        acted = acted || row.m_accumImpulse != 0;
      }
    }
    if (!acted) continue;
    markTreeOfBody(pfxGetObjectIdA(pair));
    markTreeOfBody(pfxGetObjectIdB(pair));
  }
}

template <typename TreePredicate>
void PfxJointTreeSolver::solveVelocitiesOf(TreePredicate solves, bool skipHeld,
                                           PfxTaskManager* taskManager) {
  // Listed first: most sweeps solve the few trees that contacts moved, and a parallel loop
  // over every tree handed the threads next to nothing for the cost of starting them (on
  // the 64 arms of the robots scene two threads took longer over these solves than one).
  PfxUInt32 count = 0;
  for (PfxUInt32 t = 0; t < m_numTrees; ++t) {
    if (solves(t)) m_treesToSolve[count++] = t;
  }
  pfxParallelFor(taskManager, count, kJointTreesPerTask, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 k = first; k < last; ++k) {
      const PfxUInt32 t = m_treesToSolve[k];
      solveTree(false, m_treeStarts[t], m_treeStarts[t + 1], skipHeld);
    }
  });
}

void PfxJointTreeSolver::solveVelocitiesBeforeSweep(bool firstSweep, PfxTaskManager* taskManager) {
  if (!m_boundedRowSlot) return;
  solveVelocitiesOf(
      [&](PfxUInt32 t) {
        return hasBoundedRows(t) && (firstSweep || m_treeMovedFromOutside[t]);
      },
      !firstSweep, taskManager);
}

void PfxJointTreeSolver::solveVelocitiesAfterSweep(bool firstSweep, bool lastSweep,
                                                   PfxTaskManager* taskManager) {
  if (!m_boundedRowSlot) {
    // Trees and their bounded rows not prepared: every tree, every sweep.
    solve(false, taskManager);
    return;
  }
  solveVelocitiesOf(
      [&](PfxUInt32 t) {
        return m_treeMovedFromOutside[t] || (firstSweep && !hasBoundedRows(t)) ||
               (lastSweep && hasBoundedRows(t));
      },
      !lastSweep, taskManager);
}

void PfxJointTreeSolver::addLockedImpulsesOfBoundedRows(PfxTaskManager* taskManager) {
  if (!m_boundedRowSlot) return;
  pfxParallelFor(taskManager, m_numTrees, kJointTreesPerTask, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 t = first; t < last; ++t) {
      bool applied = false;
      for (PfxUInt32 r = m_treeRowStarts[t]; r < m_treeRowStarts[t + 1]; ++r) {
        applied = applied || m_rowImpulseSums[r] != 0;
      }
      if (!applied) continue;
      solveTreeForRowImpulses(t, m_treeRowStarts[t], m_treeRowStarts[t + 1], m_rowImpulseSums);
      for (std::size_t n = m_treeStarts[t]; n < m_treeStarts[t + 1]; ++n) {
        addLockedRowImpulses(m_nodes[n], false);
      }
    }
  });
}

PfxInt32 PfxJointTreeSolver::getTreeBody(PfxUInt32 rigidBodyId) const {
  if (!m_bodyNode || rigidBodyId >= m_numRigidBodies) return -1;
  return m_bodyTreeBody[rigidBodyId];
}

bool PfxJointTreeSolver::isTreeHeldByGround(PfxUInt32 rigidBodyId) const {
  const PfxInt32 node = nodeOfBody(rigidBodyId);
  return node >= 0 && m_nodes[m_treeStarts[m_nodes[node].tree]].body < 0;
}

PfxFloat PfxJointTreeSolver::getImpulseResponse(PfxUInt32 rigidBodyId, const PfxVector3& linear,
                                                const PfxVector3& angular) {
  const PfxInt32 bodyNode = nodeOfBody(rigidBodyId);
  if (bodyNode < 0) return -1;
  PfxInt32& slot = m_responseSlot[bodyNode];
  if (slot < 0) {
    factorIfNeeded(m_nodes[bodyNode].tree);
    // A unit impulse on the body moves the values of its path to the root only, and the
    // body's answer depends on them alone: the tree solve restricted to that path, in the
    // same order, gives the same numbers at a fraction of the cost (a foot of a ragdoll is
    // 7 of its 21 nodes from the root).
    PfxInt32 path[kMaxResponsePath];
    int length = 0;
    for (PfxInt32 n = bodyNode; n >= 0 && length < kMaxResponsePath; n = m_nodes[n].parent) {
      path[length++] = n;
    }
    // Deeper than the path's room (a long chain): the whole tree.
    if (m_nodes[path[length - 1]].parent >= 0) length = 0;
    const Node& node = m_nodes[bodyNode];
    // A response dropped by refactorTreeOf is solved again into its old place.
    const PfxInt32 target = slot == -1 ? PfxInt32(m_numBodyResponses++) : -2 - slot;
    PfxTreeBlock& response = m_bodyResponses[target];
    for (int axis = 0; axis < 6; ++axis) {
      if (length == 0) {
        for (std::size_t n = m_treeStarts[node.tree]; n < m_treeStarts[node.tree + 1]; ++n) {
          m_nodes[n].value.setZero();
        }
        m_nodes[bodyNode].value[axis] = 1;
        pfxSolveSizedBlockTree(m_nodes, m_treeStarts[node.tree], m_treeStarts[node.tree + 1]);
      } else {
        for (int i = 0; i < length; ++i) m_nodes[path[i]].value.setZero();
        m_nodes[bodyNode].value[axis] = 1;
        for (int i = 0; i + 1 < length; ++i) {
          pfxSizedBlockTreeForward(m_nodes[path[i]], m_nodes[path[i + 1]]);
        }
        for (int i = 0; i < length; ++i) pfxSizedBlockTreeDiagonal(m_nodes[path[i]]);
        for (int i = length - 1; i-- > 0;) {
          pfxSizedBlockTreeBackward(m_nodes[path[i]], m_nodes[path[i + 1]]);
        }
      }
      response.col(axis) = m_nodes[bodyNode].value;
    }
    slot = target;
  }
  PfxTreeVector impulse;
  impulse << linear.cast<double>(), angular.cast<double>();
  return static_cast<PfxFloat>(impulse.dot(m_bodyResponses[slot] * impulse));
}

void PfxJointTreeSolver::solveTreeOf(PfxUInt32 rigidBodyId, bool push) {
  const PfxInt32 bodyNode = nodeOfBody(rigidBodyId);
  if (bodyNode < 0) return;
  const Node& node = m_nodes[bodyNode];
  solveTree(push, m_treeStarts[node.tree], m_treeStarts[node.tree + 1]);
}

void PfxJointTreeSolver::solve(bool push, PfxTaskManager* taskManager) {
  // Trees share no body that moves, so they are solved at the same time.
  pfxParallelFor(taskManager, m_numTrees, kJointTreesPerTask, [&](PfxUInt32 first, PfxUInt32 last) {
    for (PfxUInt32 t = first; t < last; ++t) solveTree(push, m_treeStarts[t], m_treeStarts[t + 1]);
  });
}

void PfxJointTreeSolver::solveTree(bool push, std::size_t begin, std::size_t end,
                                   bool skipHeld) {
  if (begin == end) return;
  factorIfNeeded(m_nodes[begin].tree);
  PfxVector3 PfxSolverBody::*linear =
      push ? &PfxSolverBody::m_pushLinearVelocity : &PfxSolverBody::m_deltaLinearVelocity;
  PfxVector3 PfxSolverBody::*angular =
      push ? &PfxSolverBody::m_pushAngularVelocity : &PfxSolverBody::m_deltaAngularVelocity;

  // Right-hand side: zero for bodies; for each row, its target velocity minus its velocity.
  double largestMiss = 0;
  for (std::size_t n = begin; n < end; ++n) {
    Node& node = m_nodes[n];
    node.value.setZero();
    if (node.body >= 0) continue;
    const PfxConstraintPair& pair = m_jointPairs[node.jointPair];
    const PfxJoint& joint = m_joints[pfxGetConstraintId(pair)];
    const PfxSolverBody& a = m_solverBodies[pfxGetObjectIdA(pair)];
    const PfxSolverBody& b = m_solverBodies[pfxGetObjectIdB(pair)];
    for (PfxUInt8 row = 0; row < node.numRows; ++row) {
      const PfxJointConstraint& c = joint.m_constraints[node.axes[row]];
      const PfxConstraintRow& r = c.m_constraintRow;
      const PfxJointRowJacobian& j = node.jacobians[row];
      const PfxFloat target = (push ? c.m_pushRhs : r.m_rhs) / r.m_jacDiagInv;
      node.value[row] = double(target) - double(pfxJointRowVelocity(j, a.*linear, a.*angular,
                                                                    b.*linear, b.*angular));
      largestMiss = std::max(largestMiss, std::abs(node.value[row]));
    }
  }
  m_treeHeld[m_nodes[begin].tree] = 1;
  if (skipHeld && largestMiss <= kHeldLockedRowVelocity) return;
  pfxSolveSizedBlockTree(m_nodes, begin, end);
  takeSolution(push, begin, end);
}

void PfxJointTreeSolver::takeSolution(bool push, std::size_t begin, std::size_t end) {
  PfxVector3 PfxSolverBody::*linear =
      push ? &PfxSolverBody::m_pushLinearVelocity : &PfxSolverBody::m_deltaLinearVelocity;
  PfxVector3 PfxSolverBody::*angular =
      push ? &PfxSolverBody::m_pushAngularVelocity : &PfxSolverBody::m_deltaAngularVelocity;
  // Bodies take their velocity change; rows take the impulse (the negated multiplier).
  for (std::size_t n = begin; n < end; ++n) {
    const Node& node = m_nodes[n];
    if (node.body >= 0) {
      PfxSolverBody& sb = m_solverBodies[node.body];
      sb.*linear += node.value.head<3>().cast<PfxFloat>();
      sb.*angular += node.value.tail<3>().cast<PfxFloat>();
      continue;
    }
    addLockedRowImpulses(node, push);
  }
}

void PfxJointTreeSolver::forgetHeldTrees() {
  for (PfxUInt32 t = 0; t < m_numTrees; ++t) m_treeHeld[t] = 0;
}

bool PfxJointTreeSolver::holdsTreeOf(PfxUInt32 rigidBodyId) const {
  const PfxInt32 node = nodeOfBody(rigidBodyId);
  return node >= 0 && m_treeHeld[m_nodes[node].tree] != 0;
}

void PfxJointTreeSolver::forgetHeldTreeOf(PfxUInt32 rigidBodyId) {
  const PfxInt32 node = nodeOfBody(rigidBodyId);
  if (node >= 0) m_treeHeld[m_nodes[node].tree] = 0;
}

void PfxJointTreeSolver::applyImpulseThroughTree(PfxUInt32 rigidBodyId, const PfxVector3& linear,
                                                 const PfxVector3& angular, bool push) {
  const PfxInt32 bodyNode = m_bodyNode[rigidBodyId];
  const PfxUInt32 tree = m_nodes[bodyNode].tree;
  factorIfNeeded(tree);
  const std::size_t begin = m_treeStarts[tree], end = m_treeStarts[tree + 1];
  for (std::size_t n = begin; n < end; ++n) m_nodes[n].value.setZero();
  m_nodes[bodyNode].value << linear.cast<double>(), angular.cast<double>();
  for (PfxInt32 n = bodyNode; n >= 0; n = m_nodes[n].parent) m_nodes[n].loaded = true;
  pfxSolveSizedBlockTree(m_nodes, begin, end, [&](std::size_t n) { return m_nodes[n].loaded; });
  for (PfxInt32 n = bodyNode; n >= 0; n = m_nodes[n].parent) m_nodes[n].loaded = false;
  takeSolution(push, begin, end);
}

void PfxJointTreeSolver::addLockedRowImpulses(const Node& node, bool push) {
  if (node.body >= 0) return;
  PfxJoint& joint = m_joints[pfxGetConstraintId(m_jointPairs[node.jointPair])];
  for (PfxUInt8 row = 0; row < node.numRows; ++row) {
    PfxJointConstraint& c = joint.m_constraints[node.axes[row]];
    const PfxFloat impulse = static_cast<PfxFloat>(-node.value[row]);
    if (push) {
      c.m_pushImpulse += impulse;
    } else {
      c.m_constraintRow.m_accumImpulse += impulse;
    }
  }
}

}  // namespace pfx
