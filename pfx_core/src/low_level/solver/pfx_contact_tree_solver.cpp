#include "low_level/solver/pfx_contact_tree_solver.h"

#include <algorithm>
#include <cmath>

#include "low_level/solver/pfx_block_tree.h"
#include "low_level/solver/pfx_constraint_row_solver.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kMaxPoints = PFX_NUM_CONTACTS_PER_MANIFOLD;

// Compliance added to each face row, relative to its effective mass: it leaves the answer
// unchanged and keeps a row that the others nearly repeat from making the system singular.
constexpr double kContactTreeRelativeCompliance = 1e-9;

// A moment row is kept only where the points spread along its axis by more than this
// fraction of their spread along the other (squared): points on a line hold no moment
// across it.
constexpr PfxFloat kMinSpreadRatio = PfxFloat(1e-4);
constexpr PfxFloat kMinSpread = PfxFloat(1e-12);  // m^2: points that all coincide
// ... and only where they spread by more than this fraction of their distance from the
// centre of the smaller body (squared): a row of short lever asks for a large turn from it,
// that is large point impulses of opposite sign, and the clamp to pushing keeps only the
// positive ones. Two points of a cylinder's rim a few millimetres apart on a box landing on
// it did that in a falling pile (test_world_threads): 75 N s on a 1 kg box, thrown out at
// 35 m/s; across that pile such faces gave pushes of up to 484 N s that the sweeps had to
// take back. Without their moment rows the iterations turn such faces, as they turn the
// faces outside the forest.
constexpr PfxFloat kMinLeverFraction = PfxFloat(0.05);

// A face of the forest was picked but not yet given a node.
constexpr PfxInt32 kContactTreeChosen = -2;

constexpr PfxUInt32 kContactTreesPerTask = 8;
constexpr PfxUInt32 kTreeSolvedPairsPerTask = 256;

// What a pair is to the forest.
constexpr PfxUInt8 kEligible = 1;
constexpr PfxUInt8 kMovesA = 2;
constexpr PfxUInt8 kMovesB = 4;

// The points that hold a face up: those that overlap, and those that pushed in the last
// step (which carry their impulse into this one). A resting face's points hover around
// zero distance, and choosing by distance alone would make the face flicker between one,
// two and four points from step to step. A speculative point that has not pushed stays
// free to close its gap and no more, which the iterations handle.
bool touches(const PfxContactPoint& cp) {
  return cp.m_distance <= 0 || cp.m_constraintRow[0].m_accumImpulse > 0;
}

// Whether a body takes the pair's impulses and moves with them.
bool movesWith(const PfxSolverBody& body, bool receives) { return receives && body.m_massInv > 0; }

// Touching points whose normals lie further apart than this (cosine) do not make one face.
// A compound's shapes can meet another body at points pushed in opposite directions (two
// shapes that both overlap a box through its whole height); their pressures are no affine
// field over a plane, and a face's first moment across such points can be no push at all:
// a zero row that left the factorization dividing by zero.
constexpr PfxFloat kFaceNormalsCos = PfxFloat(0.9);

// Whether the pair's touching points make a face: there is one, and they share a normal.
bool touchesAsAFace(const PfxContactManifold& manifold) {
  const PfxContactPoint* first = nullptr;
  for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    if (!touches(cp)) continue;
    if (!first) {
      first = &cp;
    } else if (cp.getNormal().dot(first->getNormal()) < kFaceNormalsCos) {
      return false;
    }
  }
  return first != nullptr;
}

}  // namespace

// A body node or a face node of the forest. Its blocks live in the scratch while its tree
// is factored and solved.
struct PfxContactTreeSolver::Node {
  PfxInt32 parent;  // node index, -1 at a root
  PfxInt32 body;    // rigid body id, or -1 for a face
  PfxInt32 face;    // index in m_faces, or -1 for a body
};

// A face's rows: up to three pressure rows, each a weighted sum of the manifold's touching
// points' normal rows, and, in the velocity solve, up to three friction rows: the face's
// slip along its two tangents and its twist about its normal.
struct PfxContactTreeSolver::Face {
  PfxInt32 pairIndex;
  PfxUInt8 numRows;  // the pressure rows, then the friction rows if the solve holds them
  PfxUInt8 numPressureRows;
  PfxUInt8 numFrictionRows;  // 0 without friction, 2 for one point, else 3
  PfxFloat weights[3][kMaxPoints];  // row k's weight of each point (0: point left out)
  // The face's plane, its touching points' centre (from body B's position), and the weights
  // of the slip rows (each point's share) and of the twist row (per metre of lever).
  PfxVector3 normal;
  PfxVector3 tangents[2];
  PfxVector3 centre;
  PfxFloat slipWeight;
  PfxFloat twistWeight;
};

PfxUInt32 PfxContactTreeSolver::getMaxNodes(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs) {
  // A forest over n bodies has fewer than n + 1 edges, however many pairs there are.
  return numRigidBodies + std::min(numRigidBodies, numContactPairs);
}

std::size_t PfxContactTreeSolver::getScratchBytes(PfxUInt32 numNodes) {
  return PfxWorkCarver::bytesFor(alignof(PfxBlockTreeNode), sizeof(PfxBlockTreeNode) * numNodes);
}

PfxUInt32 PfxContactTreeSolver::getWorkBytes(PfxUInt32 numRigidBodies,
                                             PfxUInt32 numContactPairs) {
  const std::size_t maxFaces = std::min(numRigidBodies, numContactPairs);
  const std::size_t bytes =
      PfxWorkCarver::bytesFor(alignof(Node),
                              sizeof(Node) * getMaxNodes(numRigidBodies, numContactPairs)) +
      PfxWorkCarver::bytesFor(alignof(Face), sizeof(Face) * maxFaces) +
      PfxWorkCarver::bytesFor(alignof(PfxInt32), sizeof(PfxInt32) *
                                                     (2 * maxFaces +            // pair, state
                                                      3 * numRigidBodies +      // nodes, sets, loops
                                                      numRigidBodies + 1 +      // adjacency offsets
                                                      2 * maxFaces +            // adjacency
                                                      numRigidBodies + 1)) +    // tree starts
      PfxWorkCarver::bytesFor(1, numContactPairs);  // each pair's flags
  return static_cast<PfxUInt32>(bytes);
}

namespace {

// A face whose touching points slip faster than this at the start of the step (m/s) is
// sliding: its friction is Coulomb's, which the iterations give it, and solving it as if
// it stuck, then cutting it to the points' circles, upsets the face's pressures (a box
// sliding down a slope took 3 % less friction than Coulomb's).
constexpr PfxFloat kSlidingSpeed = PfxFloat(0.01);

bool slides(const PfxContactManifold& manifold) {
  for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    if (!touches(cp)) continue;
    PfxFloat slipSq = 0;
    for (int k = 1; k < 3; ++k) {
      const PfxConstraintRow& row = cp.m_constraintRow[k];
      const PfxFloat slip = row.m_jacDiagInv > 0 ? row.m_rhs / row.m_jacDiagInv : 0;
      slipSq += slip * slip;
    }
    if (slipSq > kSlidingSpeed * kSlidingSpeed) return true;
  }
  return false;
}

// The rows of a face: the total push of its touching points and their first moments along
// the principal axes of the points in the contact plane, each of unit length; then, with
// friction, their total slip along the plane's two tangents and their twist about its normal.
template <typename Face>
void setFaceRows(const PfxContactManifold& manifold, Face& face) {
  PfxFloat (*weights)[kMaxPoints] = face.weights;
  const PfxUInt32 n = manifold.getNumContacts();
  PfxVector3 normal = PfxVector3::Zero();
  PfxVector3 centre = PfxVector3::Zero();
  PfxFloat count = 0;
  PfxFloat reachA = 0, reachB = 0;  // the points' squared distances from each centre
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    if (!touches(cp)) continue;
    normal += cp.getNormal();
    centre += cp.m_armB;
    count += 1;
    reachA += cp.m_armA.squaredNorm();
    reachB += cp.m_armB.squaredNorm();
  }
  const PfxFloat minMomentSpread =
      std::max(kMinSpread, kMinLeverFraction * kMinLeverFraction * std::min(reachA, reachB));
  centre /= count;
  normal = normal.norm() > 0 ? PfxVector3(normal.normalized())
                             : manifold.getContactPoint(0).getNormal();
  PfxVector3 t1, t2;
  pfxGetPlaneSpace(normal, t1, t2);
  PfxFloat x[kMaxPoints] = {}, y[kMaxPoints] = {};
  PfxFloat xx = 0, xy = 0, yy = 0;
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    if (!touches(cp)) continue;
    const PfxVector3 d = cp.m_armB - centre;
    x[i] = d.dot(t1);
    y[i] = d.dot(t2);
    xx += x[i] * x[i];
    xy += x[i] * y[i];
    yy += y[i] * y[i];
  }
  const PfxFloat angle = PfxFloat(0.5) * std::atan2(2 * xy, xx - yy);
  const PfxFloat c = std::cos(angle), s = std::sin(angle);
  PfxFloat major[kMaxPoints] = {}, minor[kMaxPoints] = {};
  PfxFloat majorSpread = 0, minorSpread = 0;
  for (PfxUInt32 i = 0; i < n; ++i) {
    major[i] = c * x[i] + s * y[i];
    minor[i] = -s * x[i] + c * y[i];
    majorSpread += major[i] * major[i];
    minorSpread += minor[i] * minor[i];
  }
  if (minorSpread > majorSpread) {
    std::swap(major, minor);
    std::swap(majorSpread, minorSpread);
  }
  PfxUInt8 rows = 0;
  auto addRow = [&](const PfxFloat* w, PfxFloat lengthSq) {
    const PfxFloat scale = PfxFloat(1) / std::sqrt(lengthSq);
    for (PfxUInt32 i = 0; i < kMaxPoints; ++i) weights[rows][i] = i < n ? w[i] * scale : 0;
    ++rows;
  };
  PfxFloat ones[kMaxPoints] = {};
  for (PfxUInt32 i = 0; i < n; ++i) ones[i] = touches(manifold.getContactPoint(i)) ? 1 : 0;
  addRow(ones, count);
  if (majorSpread > minMomentSpread) {
    addRow(major, majorSpread);
    if (minorSpread > std::max(kMinSpreadRatio * majorSpread, minMomentSpread)) {
      addRow(minor, minorSpread);
    }
  }
  face.numPressureRows = rows;
  face.normal = normal;
  face.tangents[0] = t1;
  face.tangents[1] = t2;
  face.centre = centre;
  face.slipWeight = PfxFloat(1) / std::sqrt(count);
  // A single point, or points a short lever apart, hold no twist (as no moment above).
  const PfxFloat spread = majorSpread + minorSpread;
  face.twistWeight = spread > minMomentSpread ? PfxFloat(1) / std::sqrt(spread) : 0;
  face.numFrictionRows = manifold.getCompositeFriction() <= 0 || slides(manifold)
                             ? 0
                             : face.twistWeight > 0 ? 3 : 2;
}

// The impulse at point i of a face per unit of its row k: along the point's normal for a
// pressure row, along a tangent of the face for a slip row, across the lever from the
// face's centre for the twist row. Zero for a point that does not touch.
template <typename Face>
PfxVector3 rowDirection(const Face& face, const PfxContactPoint& cp, PfxUInt32 i, PfxUInt8 k) {
  if (face.weights[0][i] == 0) return PfxVector3::Zero();
  if (k < face.numPressureRows) return face.weights[k][i] * cp.getNormal();
  const PfxUInt8 friction = k - face.numPressureRows;
  if (friction < 2) return face.slipWeight * face.tangents[friction];
  return face.twistWeight * face.normal.cross(cp.m_armB - face.centre);
}

// What a point's velocities lack, as a vector: its normal row's target minus its normal
// velocity along the normal, and, for the velocity solve, the same for its friction rows
// along their tangents.
PfxVector3 pointDeficit(const PfxContactPoint& cp, const PfxSolverBody& a, const PfxSolverBody& b,
                        bool push) {
  PfxVector3 linear = PfxVector3::Zero();
  const PfxVector3 relative =
      push ? PfxVector3(b.m_pushLinearVelocity + b.m_pushAngularVelocity.cross(cp.m_armB) -
                        a.m_pushLinearVelocity - a.m_pushAngularVelocity.cross(cp.m_armA))
           : pfxRelativeDeltaVelocity(a, cp.m_armA, b, cp.m_armB);
  for (int r = 0; r < (push ? 1 : 3); ++r) {
    const PfxConstraintRow& row = cp.m_constraintRow[r];
    const PfxFloat rhs = push && r == 0 ? cp.m_pushRhs : row.m_rhs;
    const PfxFloat target = row.m_jacDiagInv > 0 ? rhs / row.m_jacDiagInv : 0;
    linear += (target - row.m_normal.dot(relative)) * row.m_normal;
  }
  return linear;
}

// The face's rows against one of its bodies' velocities (linear, then angular), as the
// points push that body: along the normal for B, against it for A.
template <typename Face>
PfxTreeBlock faceJacobian(const PfxContactManifold& manifold, const Face& face, bool bodyB) {
  PfxTreeBlock rows = PfxTreeBlock::Zero();
  for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    if (face.weights[0][i] == 0) continue;
    const PfxVector3& arm = bodyB ? cp.m_armB : cp.m_armA;
    for (PfxUInt8 k = 0; k < face.numRows; ++k) {
      const PfxVector3 direction = rowDirection(face, cp, i, k);
      const PfxVector3 linear = bodyB ? direction : PfxVector3(-direction);
      rows.block<1, 3>(k, 0) += linear.cast<double>().transpose();
      rows.block<1, 3>(k, 3) += arm.cross(linear).cast<double>().transpose();
    }
  }
  return rows;
}

// Whether joints hold every body that moves (a pile of ragdolls, robots): the trees of
// such bodies are left to the iterations (see build), so the forest is empty, and
// looking for it, which reads every pair's manifold, can be skipped. `jointed` is scratch
// of numRigidBodies entries.
bool everyMovingBodyJointed(const PfxConstraintPair* jointPairs, PfxUInt32 numJointPairs,
                            const PfxSolverBody* solverBodies, PfxUInt32 numRigidBodies,
                            PfxInt32* jointed) {
  for (PfxUInt32 b = 0; b < numRigidBodies; ++b) jointed[b] = 0;
  for (PfxUInt32 i = 0; i < numJointPairs; ++i) {
    const PfxConstraintPair& pair = jointPairs[i];
    if (!pfxGetActive(pair)) continue;
    for (const PfxUInt32 id : {pfxGetObjectIdA(pair), pfxGetObjectIdB(pair)}) {
      if (id < numRigidBodies) jointed[id] = 1;
    }
  }
  for (PfxUInt32 b = 0; b < numRigidBodies; ++b) {
    if (solverBodies[b].m_massInv > 0 && !jointed[b]) return false;
  }
  return true;
}

}  // namespace

bool PfxContactTreeSolver::build(void* workBuff, PfxUInt32 workBytes,
                                 const PfxConstraintPair* contactPairs, PfxUInt32 numContactPairs,
                                 const PfxConstraintPair* jointPairs, PfxUInt32 numJointPairs,
                                 PfxContactManifold* manifolds, PfxSolverBody* solverBodies,
                                 PfxUInt32 numRigidBodies, PfxTaskManager* taskManager) {
  m_numNodes = 0;
  m_numTrees = 0;
  m_largestTreeNodes = 0;
  m_contactPairs = contactPairs;
  m_manifolds = manifolds;
  m_solverBodies = solverBodies;
  PfxWorkCarver carver(workBuff, workBytes);
  const std::size_t maxFaces = std::min(numRigidBodies, numContactPairs);
  m_nodes = carver.take<Node>(getMaxNodes(numRigidBodies, numContactPairs));
  m_faces = carver.take<Face>(maxFaces);
  PfxInt32* facePair = carver.take<PfxInt32>(maxFaces);
  PfxInt32* faceState = carver.take<PfxInt32>(maxFaces);
  PfxInt32* bodyNode = carver.take<PfxInt32>(numRigidBodies);
  PfxInt32* sets = carver.take<PfxInt32>(numRigidBodies);
  PfxInt32* unsolvedFaces = carver.take<PfxInt32>(numRigidBodies);  // per set
  PfxInt32* adjacencyStart = carver.take<PfxInt32>(numRigidBodies + 1);
  PfxInt32* adjacency = carver.take<PfxInt32>(2 * maxFaces);
  m_treeStarts = carver.take<PfxUInt32>(std::size_t(numRigidBodies) + 1);
  PfxUInt8* pairFlags = carver.take<PfxUInt8>(numContactPairs);
  if (maxFaces == 0) return true;
  if (!m_nodes || !m_faces || !facePair || !faceState || !bodyNode || !sets || !unsolvedFaces ||
      !adjacencyStart || !adjacency || !m_treeStarts || !pairFlags) {
    return false;
  }

  if (numJointPairs > 0 &&
      everyMovingBodyJointed(jointPairs, numJointPairs, solverBodies, numRigidBodies, sets)) {
    return true;
  }
  auto movable = [&](PfxUInt32 id, bool receives) { return movesWith(solverBodies[id], receives); };
  // Faces that touch and act on a body that moves. A body that moves but takes nothing
  // from the pair (one-way) cannot be both inside and outside the system: such a pair
  // stays iterative. Found for every pair at once, in parallel, since it reads each
  // manifold; the forest is then picked from these flags in pair order.
  pfxParallelFor(taskManager, numContactPairs, kTreeSolvedPairsPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     const PfxConstraintPair& pair = contactPairs[i];
                     pairFlags[i] = 0;
                     if (!pfxGetActive(pair) || !touchesAsAFace(manifolds[pfxGetContactId(pair)]))
                       continue;
                     const PfxUInt32 a = pfxGetObjectIdA(pair), b = pfxGetObjectIdB(pair);
                     const bool moveA = movable(a, pfxGetReceivesA(pair));
                     const bool moveB = movable(b, pfxGetReceivesB(pair));
                     const bool oneWay = (!moveA && solverBodies[a].m_massInv > 0) ||
                                         (!moveB && solverBodies[b].m_massInv > 0);
                     if (oneWay || (!moveA && !moveB)) continue;
                     pairFlags[i] = kEligible | (moveA ? kMovesA : 0) | (moveB ? kMovesB : 0);
                   }
                 });
  auto eligible = [&](PfxUInt32 pairIndex, bool& moveA, bool& moveB) {
    const PfxUInt8 flags = pairFlags[pairIndex];
    moveA = (flags & kMovesA) != 0;
    moveB = (flags & kMovesB) != 0;
    return (flags & kEligible) != 0;
  };
  auto movingRoot = [&](const PfxConstraintPair& pair, bool moveA) {
    return pfxFindTreeRoot(sets, static_cast<PfxInt32>(moveA ? pfxGetObjectIdA(pair)
                                                             : pfxGetObjectIdB(pair)));
  };
  PfxInt32* grounded = bodyNode;  // per set, until the nodes are numbered
  for (PfxUInt32 b = 0; b < numRigidBodies; ++b) {
    sets[b] = static_cast<PfxInt32>(b);
    unsolvedFaces[b] = 0;
    grounded[b] = 0;
    adjacencyStart[b] = 0;
  }
  adjacencyStart[numRigidBodies] = 0;

  // The forest: faces between moving bodies that join two trees, then one face per tree on
  // what does not move.
  PfxUInt32 numFaces = 0;
  bool moveA = false, moveB = false;
  for (PfxUInt32 i = 0; i < numContactPairs; ++i) {
    const PfxConstraintPair& pair = contactPairs[i];
    if (!eligible(i, moveA, moveB) || !moveA || !moveB || numFaces == maxFaces) continue;
    const PfxInt32 ra = pfxFindTreeRoot(sets, static_cast<PfxInt32>(pfxGetObjectIdA(pair)));
    const PfxInt32 rb = pfxFindTreeRoot(sets, static_cast<PfxInt32>(pfxGetObjectIdB(pair)));
    if (ra == rb) continue;
    sets[ra] = rb;
    facePair[numFaces++] = static_cast<PfxInt32>(i);
  }
  for (PfxUInt32 i = 0; i < numContactPairs; ++i) {
    const PfxConstraintPair& pair = contactPairs[i];
    if (!eligible(i, moveA, moveB) || moveA == moveB || numFaces == maxFaces) continue;
    const PfxInt32 root = movingRoot(pair, moveA);
    if (grounded[root]) continue;
    grounded[root] = 1;
    facePair[numFaces++] = static_cast<PfxInt32>(i);
  }
  // Only trees whose every face is in the forest are solved directly. Where faces close a
  // loop (a box on two others in a pyramid, a pile, a box against a wall and the floor),
  // the load splits between faces in a way the forest cannot know: solved over the forest
  // alone, a box on two supports is hung on one of them, its pressure clamped where the
  // support ends, and a pyramid topples. Those are left to the iterations.
  for (PfxUInt32 i = 0; i < numContactPairs; ++i) {
    const PfxConstraintPair& pair = contactPairs[i];
    if (eligible(i, moveA, moveB)) ++unsolvedFaces[movingRoot(pair, moveA)];
  }
  // A body held by a joint does not answer a push with its own mass alone: solved as if it
  // were free, a ragdoll's foot on the ground took thousands of newton-seconds in one step.
  // Trees holding such bodies are left to the iterations, which see the joints.
  for (PfxUInt32 i = 0; i < numJointPairs; ++i) {
    const PfxConstraintPair& pair = jointPairs[i];
    if (!pfxGetActive(pair)) continue;
    for (const PfxUInt32 id : {pfxGetObjectIdA(pair), pfxGetObjectIdB(pair)}) {
      if (id < numRigidBodies && solverBodies[id].m_massInv > 0) {
        ++unsolvedFaces[pfxFindTreeRoot(sets, static_cast<PfxInt32>(id))];
      }
    }
  }
  for (PfxUInt32 f = 0; f < numFaces; ++f) {
    const PfxConstraintPair& pair = contactPairs[facePair[f]];
    eligible(PfxUInt32(facePair[f]), moveA, moveB);
    --unsolvedFaces[movingRoot(pair, moveA)];
  }
  PfxUInt32 kept = 0;
  for (PfxUInt32 f = 0; f < numFaces; ++f) {
    const PfxConstraintPair& pair = contactPairs[facePair[f]];
    eligible(PfxUInt32(facePair[f]), moveA, moveB);
    if (unsolvedFaces[movingRoot(pair, moveA)] != 0) continue;
    facePair[kept] = facePair[f];
    faceState[kept++] = kContactTreeChosen;
    if (moveA) ++adjacencyStart[pfxGetObjectIdA(pair)];
    if (moveB) ++adjacencyStart[pfxGetObjectIdB(pair)];
  }
  numFaces = kept;
  for (PfxUInt32 b = 0; b < numRigidBodies; ++b) bodyNode[b] = -1;
  PfxInt32 running = 0;
  for (PfxUInt32 b = 0; b <= numRigidBodies; ++b) {
    const PfxInt32 count = b < numRigidBodies ? adjacencyStart[b] : 0;
    adjacencyStart[b] = running;
    running += count;
  }
  for (PfxUInt32 b = 0; b < numRigidBodies; ++b) sets[b] = adjacencyStart[b];  // fill cursors
  for (PfxUInt32 f = 0; f < numFaces; ++f) {
    const PfxConstraintPair& pair = contactPairs[facePair[f]];
    const PfxUInt32 a = pfxGetObjectIdA(pair), b = pfxGetObjectIdB(pair);
    if (movable(a, pfxGetReceivesA(pair))) adjacency[sets[a]++] = static_cast<PfxInt32>(f);
    if (movable(b, pfxGetReceivesB(pair))) adjacency[sets[b]++] = static_cast<PfxInt32>(f);
  }

  // Breadth first from the roots. A tree that rests on the ground is rooted at a face that
  // holds it, so that every leaf is a body: a face eliminated as a leaf would have a pivot
  // of nearly zero (its compliance), and the factorization would lose its precision.
  auto addNode = [&](PfxInt32 parent, PfxInt32 body, PfxInt32 face) {
    Node& node = m_nodes[m_numNodes];
    node.parent = parent;
    node.body = body;
    node.face = face;
    if (face >= 0) {
      m_faces[face].pairIndex = facePair[face];
      m_faces[face].numRows = 0;
    }
    return static_cast<PfxInt32>(m_numNodes++);
  };
  auto grow = [&](std::size_t head) {
    while (head < m_numNodes) {
      const Node& current = m_nodes[head];
      const PfxInt32 self = static_cast<PfxInt32>(head++);
      if (current.body >= 0) {
        for (PfxInt32 k = adjacencyStart[current.body]; k < adjacencyStart[current.body + 1];
             ++k) {
          const PfxInt32 face = adjacency[k];
          if (faceState[face] != kContactTreeChosen) continue;  // already in the forest
          faceState[face] = addNode(self, -1, face);
        }
        continue;
      }
      const PfxConstraintPair& pair = contactPairs[m_faces[current.face].pairIndex];
      for (const bool isA : {true, false}) {
        const PfxUInt32 id = isA ? pfxGetObjectIdA(pair) : pfxGetObjectIdB(pair);
        if (movable(id, isA ? pfxGetReceivesA(pair) : pfxGetReceivesB(pair)) &&
            bodyNode[id] < 0) {
          bodyNode[id] = addNode(self, static_cast<PfxInt32>(id), -1);
        }
      }
    }
  };
  for (PfxUInt32 f = 0; f < numFaces; ++f) {
    const PfxConstraintPair& pair = contactPairs[facePair[f]];
    if (faceState[f] != kContactTreeChosen ||
        movable(pfxGetObjectIdA(pair), pfxGetReceivesA(pair)) ==
            movable(pfxGetObjectIdB(pair), pfxGetReceivesB(pair))) {
      continue;
    }
    const std::size_t head = m_numNodes;
    m_treeStarts[m_numTrees++] = m_numNodes;
    faceState[f] = addNode(-1, -1, static_cast<PfxInt32>(f));
    grow(head);
  }
  for (PfxUInt32 f = 0; f < numFaces; ++f) {
    if (faceState[f] != kContactTreeChosen) continue;
    const PfxUInt32 a = pfxGetObjectIdA(contactPairs[facePair[f]]);
    const std::size_t head = m_numNodes;
    m_treeStarts[m_numTrees++] = m_numNodes;
    bodyNode[a] = addNode(-1, static_cast<PfxInt32>(a), -1);
    grow(head);
  }

  for (std::size_t n = 0; n < m_numNodes; ++n) {
    const Node& node = m_nodes[n];
    if (node.face < 0) continue;
    Face& face = m_faces[node.face];
    setFaceRows(manifolds[pfxGetContactId(contactPairs[face.pairIndex])], face);
  }
  m_treeStarts[m_numTrees] = m_numNodes;
  for (PfxUInt32 t = 0; t < m_numTrees; ++t) {
    m_largestTreeNodes = std::max(m_largestTreeNodes, m_treeStarts[t + 1] - m_treeStarts[t]);
  }
  return true;
}

bool PfxContactTreeSolver::solve(void* scratch, std::size_t scratchBytes,
                                 PfxTaskManager* taskManager) {
  if (m_numTrees == 0) return true;
  std::size_t capacity = 0;
  PfxBlockTreeNode* const blocks =
      PfxWorkCarver(scratch, scratchBytes).takeRest<PfxBlockTreeNode>(capacity);
  if (capacity < m_largestTreeNodes) return false;
  for (PfxUInt32 first = 0; first < m_numTrees;) {
    PfxUInt32 last = first + 1;
    while (last < m_numTrees && m_treeStarts[last + 1] - m_treeStarts[first] <= capacity) ++last;
    const PfxUInt32 batchStart = m_treeStarts[first];
    pfxParallelFor(taskManager, last - first, kContactTreesPerTask,
                   [&](PfxUInt32 begin, PfxUInt32 end) {
                     for (PfxUInt32 t = first + begin; t < first + end; ++t) {
                       const PfxUInt32 treeBegin = m_treeStarts[t], treeEnd = m_treeStarts[t + 1];
                       PfxBlockTreeNode* const treeBlocks = blocks + (treeBegin - batchStart);
                       // With the faces' friction, then over their pressures alone: a face
                       // that slides keeps the friction it had, and its pressures, solved
                       // with the friction it would have needed to stick (and that
                       // friction's moment), are set right for the friction it has. The
                       // split impulses have no friction.
                       factorTree(treeBlocks, treeBegin, treeEnd, true);
                       solveTree(treeBlocks, treeBegin, treeEnd, false);
                       factorTree(treeBlocks, treeBegin, treeEnd, false);
                       solveTree(treeBlocks, treeBegin, treeEnd, false);
                       solveTree(treeBlocks, treeBegin, treeEnd, true);
                     }
                   });
    first = last;
  }
  return true;
}

void PfxContactTreeSolver::factorTree(PfxBlockTreeNode* blocks, PfxUInt32 begin, PfxUInt32 end,
                                      bool withFriction) {
  // Diagonal blocks and couplings to the parent. Nodes come parents first, so a face
  // parent already has its rows.
  for (PfxUInt32 n = begin; n < end; ++n) {
    const Node& node = m_nodes[n];
    PfxBlockTreeNode& block = blocks[n - begin];
    block.parent = node.parent < 0 ? -1 : node.parent - PfxInt32(begin);
    block.toParent.setZero();
    if (node.body >= 0) {
      block.diagonalInverse = pfxTreeBodyMass(m_solverBodies[node.body]);
    } else {
      Face& face = m_faces[node.face];
      const PfxConstraintPair& pair = m_contactPairs[face.pairIndex];
      const PfxContactManifold& manifold = m_manifolds[pfxGetContactId(pair)];
      face.numRows = face.numPressureRows + (withFriction ? face.numFrictionRows : 0);
      block.diagonalInverse = -PfxTreeBlock::Identity();
      const PfxSolverBody* bodies[2] = {&m_solverBodies[pfxGetObjectIdA(pair)],
                                        &m_solverBodies[pfxGetObjectIdB(pair)]};
      const bool receives[2] = {movesWith(*bodies[0], pfxGetReceivesA(pair)),
                                movesWith(*bodies[1], pfxGetReceivesB(pair))};
      Eigen::Matrix<double, 6, 1> effectiveMass = Eigen::Matrix<double, 6, 1>::Zero();
      for (int side = 0; side < 2; ++side) {
        if (!receives[side]) continue;
        const PfxTreeBlock rows = faceJacobian(manifold, face, side == 1);
        const Eigen::Matrix3d inertiaInv = bodies[side]->m_inertiaInv.cast<double>();
        for (PfxUInt8 k = 0; k < face.numRows; ++k) {
          const Eigen::Vector3d linear = rows.block<1, 3>(k, 0).transpose();
          const Eigen::Vector3d angular = rows.block<1, 3>(k, 3).transpose();
          effectiveMass[k] += double(bodies[side]->m_massInv) * linear.squaredNorm() +
                              angular.dot(inertiaInv * angular);
        }
      }
      for (PfxUInt8 k = 0; k < face.numRows; ++k) {
        block.diagonalInverse(k, k) = -kContactTreeRelativeCompliance * effectiveMass[k];
      }
    }
    if (node.parent < 0) continue;
    const Node& parent = m_nodes[node.parent];
    const Face& face = m_faces[node.body >= 0 ? parent.face : node.face];
    const PfxInt32 body = node.body >= 0 ? node.body : parent.body;
    const PfxConstraintPair& pair = m_contactPairs[face.pairIndex];
    const PfxTreeBlock rows = faceJacobian(m_manifolds[pfxGetContactId(pair)], face,
                                           PfxUInt32(body) == pfxGetObjectIdB(pair));
    block.toParent = node.body >= 0 ? PfxTreeBlock(rows.transpose()) : rows;
  }
  pfxFactorBlockTree(blocks, 0, end - begin);
}

void PfxContactTreeSolver::solveTree(PfxBlockTreeNode* blocks, PfxUInt32 begin, PfxUInt32 end,
                                     bool push) {
  PfxVector3 PfxSolverBody::*linear =
      push ? &PfxSolverBody::m_pushLinearVelocity : &PfxSolverBody::m_deltaLinearVelocity;
  PfxVector3 PfxSolverBody::*angular =
      push ? &PfxSolverBody::m_pushAngularVelocity : &PfxSolverBody::m_deltaAngularVelocity;

  // Right-hand side: zero for bodies; for each face row, what its points' velocities lack
  // along the row's impulse at each point.
  bool anyResidual = false;
  for (PfxUInt32 n = begin; n < end; ++n) {
    PfxTreeVector& value = blocks[n - begin].value;
    value.setZero();
    if (m_nodes[n].body >= 0) continue;
    const Face& face = m_faces[m_nodes[n].face];
    const PfxConstraintPair& pair = m_contactPairs[face.pairIndex];
    const PfxContactManifold& manifold = m_manifolds[pfxGetContactId(pair)];
    const PfxSolverBody& a = m_solverBodies[pfxGetObjectIdA(pair)];
    const PfxSolverBody& b = m_solverBodies[pfxGetObjectIdB(pair)];
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      if (face.weights[0][i] == 0) continue;
      const PfxContactPoint& cp = manifold.getContactPoint(i);
      const PfxVector3 deficit = pointDeficit(cp, a, b, push);
      for (PfxUInt8 k = 0; k < face.numRows; ++k) {
        value[k] += double(rowDirection(face, cp, i, k).dot(deficit));
      }
    }
    anyResidual = anyResidual || !value.isZero(0);
  }
  if (!anyResidual) return;
  pfxSolveBlockTree(blocks, 0, end - begin);

  // Each face takes its pressure point by point, clamped to pushing only, and its friction
  // if every point keeps within its friction circle; the bodies take what the points apply,
  // so that velocities and impulses stay consistent after a clamp. A face that would slip
  // leaves its friction to the iterations (see kSlidingSpeed), and its pressures are
  // solved again without it (see solve).
  for (PfxUInt32 n = begin; n < end; ++n) {
    if (m_nodes[n].body >= 0) continue;
    const Face& face = m_faces[m_nodes[n].face];
    const PfxTreeVector& value = blocks[n - begin].value;
    const PfxConstraintPair& pair = m_contactPairs[face.pairIndex];
    PfxContactManifold& manifold = m_manifolds[pfxGetContactId(pair)];
    PfxSolverBody& a = m_solverBodies[pfxGetObjectIdA(pair)];
    PfxSolverBody& b = m_solverBodies[pfxGetObjectIdB(pair)];
    const PfxFloat receivesA = pfxGetReceivesA(pair) ? PfxFloat(1) : PfxFloat(0);
    const PfxFloat receivesB = pfxGetReceivesB(pair) ? PfxFloat(1) : PfxFloat(0);
    PfxFloat delta[kMaxPoints] = {};
    PfxFloat friction[kMaxPoints][2] = {};
    bool sticks = face.numRows > face.numPressureRows;
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      if (face.weights[0][i] == 0) continue;
      PfxContactPoint& cp = manifold.getContactPoint(i);
      PfxVector3 change = PfxVector3::Zero();  // the impulse is the negated multiplier
      for (PfxUInt8 k = 0; k < face.numRows; ++k) {
        change -= PfxFloat(value[k]) * rowDirection(face, cp, i, k);
      }
      PfxFloat& impulse = push ? cp.m_pushImpulse : cp.m_constraintRow[0].m_accumImpulse;
      const PfxFloat updated = std::max(impulse + cp.getNormal().dot(change), PfxFloat(0));
      delta[i] = updated - impulse;
      impulse = updated;
      if (push) continue;
      cp.m_maxImpulse = std::max(cp.m_maxImpulse, updated);
      for (int k = 0; k < 2; ++k) {
        const PfxConstraintRow& slip = cp.m_constraintRow[1 + k];
        friction[i][k] = slip.m_accumImpulse + slip.m_normal.dot(change);
      }
      const PfxFloat limit = manifold.getCompositeFriction() * updated;
      sticks = sticks && friction[i][0] * friction[i][0] + friction[i][1] * friction[i][1] <=
                             limit * limit;
    }
    pfxApplyNormalImpulses(manifold, delta, a, receivesA, b, receivesB, linear, angular);
    if (!sticks) continue;
    for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
      if (face.weights[0][i] == 0) continue;
      PfxContactPoint& cp = manifold.getContactPoint(i);
      PfxConstraintRow& slip1 = cp.m_constraintRow[1];
      PfxConstraintRow& slip2 = cp.m_constraintRow[2];
      pfxApplyRowImpulse(slip1.m_normal * (friction[i][0] - slip1.m_accumImpulse) +
                             slip2.m_normal * (friction[i][1] - slip2.m_accumImpulse),
                         1, a, cp.m_armA, receivesA, b, cp.m_armB, receivesB);
      slip1.m_accumImpulse = friction[i][0];
      slip2.m_accumImpulse = friction[i][1];
    }
  }
}

}  // namespace pfx
