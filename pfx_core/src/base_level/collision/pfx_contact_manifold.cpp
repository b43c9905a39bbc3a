#include "pfx/base_level/collision/pfx_contact_manifold.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

namespace {

// Points are compared where they lie in the contact plane of the deepest candidate, so
// that the gap between the two surfaces (pointA against pointB, or a speculative
// distance) does not count as covered area.
PfxVector3 projectOntoPlane(const PfxVector3& p, const PfxVector3& normal) {
  return p - normal * normal.dot(p);
}

PfxFloat triangleAreaTwice(const PfxVector3& a, const PfxVector3& b, const PfxVector3& c) {
  return (b - a).cross(c - a).norm();
}

// Twice the area of the convex hull of four coplanar points. If they are in convex
// position one of the three ways of pairing them into diagonals gives the hull
// (|d1 x d2| is twice a quadrilateral's area); if one lies inside the triangle of the
// others, the largest triangle is the hull. Every other candidate value is smaller, so the
// maximum of all seven is the hull.
PfxFloat hullAreaTwice(const PfxVector3& p0, const PfxVector3& p1, const PfxVector3& p2,
                       const PfxVector3& p3) {
  PfxFloat area = (p2 - p0).cross(p3 - p1).norm();
  area = std::max(area, (p1 - p0).cross(p3 - p2).norm());
  area = std::max(area, (p1 - p0).cross(p2 - p3).norm());
  area = std::max(area, triangleAreaTwice(p0, p1, p2));
  area = std::max(area, triangleAreaTwice(p0, p1, p3));
  area = std::max(area, triangleAreaTwice(p0, p2, p3));
  area = std::max(area, triangleAreaTwice(p1, p2, p3));
  return area;
}

bool isChosen(const PfxUInt32* chosen, PfxUInt32 numChosen, PfxUInt32 i) {
  for (PfxUInt32 k = 0; k < numChosen; ++k) {
    if (chosen[k] == i) return true;
  }
  return false;
}

void zeroContactPoint(PfxContactPoint& point) {
  std::memset(static_cast<void*>(&point), 0, sizeof(point));
}

// Copying no points touches neither pointer: either may be null (a manifold without room).
void copyPoints(const PfxContactPoint* from, PfxUInt32 count, PfxContactPoint* to) {
  if (count > 0) std::copy(from, from + count, to);
}

}  // namespace

PfxUInt32 pfxReduceContactCandidates(const PfxContactCandidate* candidates, PfxUInt32 count,
                                     PfxUInt32 chosen[PFX_NUM_CONTACTS_PER_MANIFOLD]) {
  if (!candidates || !chosen || count == 0) return 0;
  if (count <= PFX_NUM_CONTACTS_PER_MANIFOLD) {
    for (PfxUInt32 i = 0; i < count; ++i) chosen[i] = i;
    return count;
  }

  // Strict comparisons while scanning in index order make every tie go to the lower index.
  PfxUInt32 deepest = 0;
  for (PfxUInt32 i = 1; i < count; ++i) {
    if (candidates[i].m_distance < candidates[deepest].m_distance) deepest = i;
  }
  const PfxVector3& normal = candidates[deepest].m_normal;
  auto planar = [&](PfxUInt32 i) { return projectOntoPlane(candidates[i].m_pointA, normal); };

  // Greedy growth of the covered polygon: the point farthest from the deepest, then the one
  // that makes the largest triangle, then the one that makes the largest quadrilateral.
  // A point that adds no length or area is not taken, so a line contact keeps two points
  // and a point contact one.
  PfxUInt32 numChosen = 0;
  chosen[numChosen++] = deepest;
  const PfxVector3 p0 = planar(deepest);

  PfxUInt32 best = count;
  PfxFloat bestValue = 0;
  for (PfxUInt32 i = 0; i < count; ++i) {
    if (isChosen(chosen, numChosen, i)) continue;
    const PfxFloat value = (planar(i) - p0).squaredNorm();
    if (value > bestValue) { bestValue = value; best = i; }
  }
  if (best == count) return numChosen;
  chosen[numChosen++] = best;
  const PfxVector3 p1 = planar(best);

  best = count;
  bestValue = 0;
  for (PfxUInt32 i = 0; i < count; ++i) {
    if (isChosen(chosen, numChosen, i)) continue;
    const PfxFloat value = triangleAreaTwice(p0, p1, planar(i));
    if (value > bestValue) { bestValue = value; best = i; }
  }
  if (best == count) return numChosen;
  chosen[numChosen++] = best;
  const PfxVector3 p2 = planar(best);

  const PfxFloat triangleArea = triangleAreaTwice(p0, p1, p2);
  best = count;
  bestValue = triangleArea;
  for (PfxUInt32 i = 0; i < count; ++i) {
    if (isChosen(chosen, numChosen, i)) continue;
    const PfxFloat value = hullAreaTwice(p0, p1, p2, planar(i));
    if (value > bestValue) { bestValue = value; best = i; }
  }
  if (best == count) return numChosen;
  chosen[numChosen++] = best;
  return numChosen;
}

PfxContactManifold::PfxContactManifold()
    : PfxContactManifold(new PfxContactPoint[PFX_NUM_CONTACTS_PER_MANIFOLD],
                         PFX_NUM_CONTACTS_PER_MANIFOLD) {
  m_ownsContactPoints = 1;
}

PfxContactManifold::PfxContactManifold(PfxContactPoint* points, PfxUInt32 capacity)
    : m_contactPoints(points),
      m_capacity(static_cast<PfxUInt8>(points ? capacity : 0)),
      m_ownsContactPoints(0) {
  reset(0, 0);
}

PfxContactManifold::PfxContactManifold(const PfxContactManifold& other) : PfxContactManifold() {
  *this = other;
}

PfxContactManifold& PfxContactManifold::operator=(const PfxContactManifold& other) {
  if (this == &other) return *this;
  if (other.m_numContacts > m_capacity) {
    releaseOwnPoints();
    m_contactPoints = new PfxContactPoint[PFX_NUM_CONTACTS_PER_MANIFOLD];
    m_capacity = PFX_NUM_CONTACTS_PER_MANIFOLD;
    m_ownsContactPoints = 1;
  }
  copyFrom(other);
  copyPoints(other.m_contactPoints, other.m_numContacts, m_contactPoints);
  return *this;
}

PfxContactManifold::PfxContactManifold(PfxContactManifold&& other) noexcept
    : m_contactPoints(nullptr), m_capacity(0), m_ownsContactPoints(0) {
  *this = std::move(other);
}

PfxContactManifold& PfxContactManifold::operator=(PfxContactManifold&& other) noexcept {
  if (this == &other) return *this;
  releaseOwnPoints();
  copyFrom(other);
  m_contactPoints = other.m_contactPoints;
  m_capacity = other.m_capacity;
  m_ownsContactPoints = other.m_ownsContactPoints;
  other.m_contactPoints = nullptr;
  other.m_capacity = other.m_ownsContactPoints = 0;
  other.m_numContacts = 0;
  return *this;
}

PfxContactManifold::~PfxContactManifold() { releaseOwnPoints(); }

void PfxContactManifold::releaseOwnPoints() {
  if (m_ownsContactPoints) delete[] m_contactPoints;
  m_contactPoints = nullptr;
  m_capacity = m_ownsContactPoints = 0;
}

// Everything but the points and the room they are kept in.
void PfxContactManifold::copyFrom(const PfxContactManifold& other) {
  std::memcpy(m_normalCoupling, other.m_normalCoupling, sizeof(m_normalCoupling));
  m_rigidBodyIdA = other.m_rigidBodyIdA;
  m_rigidBodyIdB = other.m_rigidBodyIdB;
  m_compositeFriction = other.m_compositeFriction;
  m_compositeRestitution = other.m_compositeRestitution;
  m_numContacts = other.m_numContacts;
}

void PfxContactManifold::moveContactPoints(PfxContactPoint* points, PfxUInt32 capacity) {
  if (!points) capacity = 0;
  m_numContacts = std::min(m_numContacts, capacity);
  copyPoints(m_contactPoints, m_numContacts, points);
  releaseOwnPoints();
  m_contactPoints = points;
  m_capacity = static_cast<PfxUInt8>(capacity);
}

void PfxContactManifold::reset(PfxUInt32 rigidBodyIdA, PfxUInt32 rigidBodyIdB) {
  // Zeroing the room and the couplings keeps unused slots deterministic, which a bit-exact
  // serialization of the world relies on.
  // A manifold without room (the world's shared empty one) has no pointer to give memset.
  if (m_capacity > 0) {
    std::memset(static_cast<void*>(m_contactPoints), 0, sizeof(PfxContactPoint) * m_capacity);
  }
  std::memset(m_normalCoupling, 0, sizeof(m_normalCoupling));
  m_rigidBodyIdA = rigidBodyIdA;
  m_rigidBodyIdB = rigidBodyIdB;
  m_compositeFriction = m_compositeRestitution = 0;
  m_numContacts = 0;
}

PfxUInt32 PfxContactManifold::update(const PfxContactCandidate* candidates,
                                     PfxUInt32 numCandidates, const PfxTransform3& transformA,
                                     const PfxTransform3& transformB, PfxFloat matchDistanceSq) {
  if (!candidates) numCandidates = 0;
  PfxUInt32 chosen[PFX_NUM_CONTACTS_PER_MANIFOLD];
  const PfxUInt32 numNew = pfxReduceContactCandidates(candidates, numCandidates, chosen);
  if (numNew > m_capacity) return numNew;

  // Of the old points only what matching reads and what a match carries over is kept,
  // about a sixth of a contact point.
  struct OldPoint {
    PfxVector3 localPointA;
    PfxFloat accumImpulse[3];
    PfxUInt32 duration;
    PfxUInt8 shapeIdA;
    PfxUInt8 shapeIdB;
  };
  OldPoint oldPoints[PFX_NUM_CONTACTS_PER_MANIFOLD];
  const PfxUInt32 numOld = matchDistanceSq > 0 ? m_numContacts : 0;
  for (PfxUInt32 i = 0; i < numOld; ++i) {
    const PfxContactPoint& point = m_contactPoints[i];
    OldPoint& old = oldPoints[i];
    old.localPointA = point.m_localPointA;
    for (int row = 0; row < 3; ++row) {
      old.accumImpulse[row] = point.m_constraintRow[row].m_accumImpulse;
    }
    old.duration = point.m_duration;
    old.shapeIdA = point.m_shapeIdA;
    old.shapeIdB = point.m_shapeIdB;
  }

  const PfxTransform3 inverseA = transformA.inverse(Eigen::Isometry);
  const PfxTransform3 inverseB = transformB.inverse(Eigen::Isometry);
  for (PfxUInt32 i = 0; i < numNew; ++i) {
    const PfxContactCandidate& candidate = candidates[chosen[i]];
    PfxContactPoint& point = m_contactPoints[i];
    zeroContactPoint(point);
    point.m_localPointA = inverseA * candidate.m_pointA;
    point.m_localPointB = inverseB * candidate.m_pointB;
    point.m_distance = candidate.m_distance;
    point.m_shapeIdA = candidate.m_shapeIdA;
    point.m_shapeIdB = candidate.m_shapeIdB;
    point.m_triangleIndex = candidate.m_triangleIndex;
    for (int k = 0; k < 3; ++k) point.m_barycentric[k] = candidate.m_barycentric[k];
    point.m_constraintRow[0].m_normal = candidate.m_normal;
    pfxGetPlaneSpace(candidate.m_normal, point.m_constraintRow[1].m_normal,
                     point.m_constraintRow[2].m_normal);
  }
  m_numContacts = numNew;

  if (numOld == 0 || numNew == 0) return numNew;

  // Each old point goes to at most one new point, the closest pairs first, so that two new
  // points near one old point do not both receive its impulse (which would double the
  // warm-start push). Ties resolve by new index, then old index.
  struct Match {
    PfxFloat distanceSq;
    PfxUInt32 newIndex;
    PfxUInt32 oldIndex;
  };
  Match matches[PFX_NUM_CONTACTS_PER_MANIFOLD * PFX_NUM_CONTACTS_PER_MANIFOLD];
  PfxUInt32 numMatches = 0;
  for (PfxUInt32 n = 0; n < numNew; ++n) {
    const PfxContactPoint& newPoint = m_contactPoints[n];
    for (PfxUInt32 o = 0; o < numOld; ++o) {
      const OldPoint& oldPoint = oldPoints[o];
      if (oldPoint.shapeIdA != newPoint.m_shapeIdA || oldPoint.shapeIdB != newPoint.m_shapeIdB) {
        continue;
      }
      const PfxFloat distanceSq = (newPoint.m_localPointA - oldPoint.localPointA).squaredNorm();
      if (distanceSq <= matchDistanceSq) matches[numMatches++] = {distanceSq, n, o};
    }
  }
  std::sort(matches, matches + numMatches, [](const Match& a, const Match& b) {
    if (a.distanceSq != b.distanceSq) return a.distanceSq < b.distanceSq;
    if (a.newIndex != b.newIndex) return a.newIndex < b.newIndex;
    return a.oldIndex < b.oldIndex;
  });

  bool newTaken[PFX_NUM_CONTACTS_PER_MANIFOLD] = {};
  bool oldTaken[PFX_NUM_CONTACTS_PER_MANIFOLD] = {};
  for (PfxUInt32 m = 0; m < numMatches; ++m) {
    const Match& match = matches[m];
    if (newTaken[match.newIndex] || oldTaken[match.oldIndex]) continue;
    newTaken[match.newIndex] = oldTaken[match.oldIndex] = true;
    PfxContactPoint& newPoint = m_contactPoints[match.newIndex];
    const OldPoint& oldPoint = oldPoints[match.oldIndex];
    for (int row = 0; row < 3; ++row) {
      newPoint.m_constraintRow[row].m_accumImpulse = oldPoint.accumImpulse[row];
    }
    newPoint.m_duration = oldPoint.duration + 1;
  }
  return numNew;
}

void PfxContactManifold::refresh(const PfxTransform3& transformA,
                                 const PfxTransform3& transformB, PfxFloat breakDistance) {
  PfxUInt32 numKept = 0;
  for (PfxUInt32 i = 0; i < m_numContacts; ++i) {
    PfxContactPoint& point = m_contactPoints[i];
    const PfxVector3& normal = point.getNormal();
    const PfxVector3 separation = transformB * point.m_localPointB - transformA * point.m_localPointA;
    const PfxFloat distance = separation.dot(normal);
    const PfxVector3 slip = separation - normal * distance;
    if (distance > breakDistance || slip.squaredNorm() > breakDistance * breakDistance) continue;
    point.m_distance = distance;
    if (numKept != i) m_contactPoints[numKept] = point;
    ++numKept;
  }
  m_numContacts = numKept;
}

void PfxContactManifold::carryMeshContacts(const PfxCollidable& collidableA,
                                           const PfxCollidable& collidableB) {
  PfxUInt32 numKept = 0;
  for (PfxUInt32 i = 0; i < m_numContacts; ++i) {
    PfxContactPoint& point = m_contactPoints[i];
    if (point.m_triangleIndex != PFX_CONTACT_NO_TRIANGLE) {
      const PfxLargeTriMesh* mesh = nullptr;
      PfxVector3* anchor = nullptr;
      PfxTransform3 offset = PfxTransform3::Identity();
      if (point.m_shapeIdA < collidableA.getNumShapes() &&
          collidableA.getShape(point.m_shapeIdA).getType() == kPfxShapeLargeTriMesh) {
        const PfxShape& shape = collidableA.getShape(point.m_shapeIdA);
        mesh = shape.getLargeTriMesh();
        anchor = &point.m_localPointA;
        offset = shape.getOffsetTransform();
      } else if (point.m_shapeIdB < collidableB.getNumShapes() &&
                 collidableB.getShape(point.m_shapeIdB).getType() == kPfxShapeLargeTriMesh) {
        const PfxShape& shape = collidableB.getShape(point.m_shapeIdB);
        mesh = shape.getLargeTriMesh();
        anchor = &point.m_localPointB;
        offset = shape.getOffsetTransform();
      }
      if (!mesh || point.m_triangleIndex >= mesh->m_numTriangles) continue;
      PfxVector3 v0, v1, v2;
      pfxGetLargeTriMeshTriangle(*mesh, point.m_triangleIndex, v0, v1, v2);
      *anchor = offset * (v0 * point.m_barycentric[0] + v1 * point.m_barycentric[1] +
                          v2 * point.m_barycentric[2]);
    }
    if (numKept != i) m_contactPoints[numKept] = point;
    ++numKept;
  }
  m_numContacts = numKept;
}

void PfxContactManifold::removeContactPoint(PfxUInt32 i) {
  if (i >= m_numContacts) return;
  // Shifting rather than swapping in the last point keeps the order, and with it the order
  // in which the solver visits the points, the same on every run.
  for (PfxUInt32 k = i + 1; k < m_numContacts; ++k) m_contactPoints[k - 1] = m_contactPoints[k];
  --m_numContacts;
}

PfxFloat PfxContactManifold::getPenetrationDepth() const {
  PfxFloat deepest = 0;
  for (PfxUInt32 i = 0; i < m_numContacts; ++i) {
    deepest = std::max(deepest, -m_contactPoints[i].m_distance);
  }
  return deepest;
}

}  // namespace pfx
