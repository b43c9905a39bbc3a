// Contact information between two rigid bodies: at most four points (seed chapter 2,
// "Collision Information" and chapter 10, "Compose Contact Points").
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/solver/pfx_constraint_row.h"

namespace pfx {

// m_triangleIndex of a contact point that does not lie on a large mesh.
constexpr PfxUInt32 PFX_CONTACT_NO_TRIANGLE = 0xFFFFFFFFu;

// One contact point. The normal points from body A to body B; m_distance is the
// separation along it (negative when the shapes overlap, positive for a speculative
// contact that only stops the bodies from closing the gap within the step).
struct PfxContactPoint {
  PfxConstraintRow m_constraintRow[3];  // normal, then two friction directions
  PfxVector3 m_localPointA;             // in the frame of body A
  PfxVector3 m_localPointB;             // in the frame of body B
  PfxVector3 m_armA;                    // world offset from A's centre, set up for the solver
  PfxVector3 m_armB;
  PfxFloat m_distance;
  PfxFloat m_approachVelocity;  // normal velocity before solving, for restitution
  PfxFloat m_maxImpulse;        // largest normal impulse of the last solve
  PfxFloat m_pushRhs;           // split impulse that would push the overlap out, from rest
  PfxFloat m_pushImpulse;       // accumulated split impulse of this step
  PfxUInt32 m_duration;         // frames this point has persisted
  PfxUInt8 m_shapeIdA;          // which shape of a compound
  PfxUInt8 m_shapeIdB;
  PfxUInt16 m_padding;
  // On a large mesh (the shape of A or B that is one): the triangle, as the mesh stores it
  // (PfxLargeTriMesh::m_triangleSourceIds gives the caller's index), and the weights of its
  // three corners at the point, so that the point follows the triangle when the mesh
  // deforms. The solver does not read them.
  PfxUInt32 m_triangleIndex;
  PfxFloat m_barycentric[3];

  const PfxVector3& getNormal() const { return m_constraintRow[0].m_normal; }
};

// A new point as narrow phase reports it, before it joins a manifold.
struct PfxContactCandidate {
  PfxVector3 m_normal;       // world, from A to B
  PfxVector3 m_pointA;       // world, on the surface of A
  PfxVector3 m_pointB;       // world, on the surface of B
  PfxFloat m_distance;
  PfxUInt8 m_shapeIdA;
  PfxUInt8 m_shapeIdB;
  PfxUInt32 m_triangleIndex = PFX_CONTACT_NO_TRIANGLE;  // as in PfxContactPoint
  PfxFloat m_barycentric[3] = {0, 0, 0};
};

// The points live apart from the manifold: a manifold made with no arguments (or copied)
// holds room of its own for four, as the seed's arrays of manifolds expect; PfxWorld keeps
// the points of its manifolds in pools by size (pfx_contact_point_pool.h), one point for a
// sphere on the ground, four for a box on a box.
class PfxContactManifold {
 public:
  PfxContactManifold();
  // Points kept in `points`, room for `capacity` (at most four) that the caller owns and
  // keeps in place while the manifold uses it; (nullptr, 0) for a manifold with no room,
  // which holds no points.
  PfxContactManifold(PfxContactPoint* points, PfxUInt32 capacity);
  // A copy has room of its own for four points (or the room it had, when they fit).
  PfxContactManifold(const PfxContactManifold& other);
  PfxContactManifold& operator=(const PfxContactManifold& other);
  PfxContactManifold(PfxContactManifold&& other) noexcept;
  PfxContactManifold& operator=(PfxContactManifold&& other) noexcept;
  ~PfxContactManifold();

  // Empties the manifold for a new pair; its room stays.
  void reset(PfxUInt32 rigidBodyIdA, PfxUInt32 rigidBodyIdB);

  PfxUInt32 getRigidBodyIdA() const { return m_rigidBodyIdA; }
  PfxUInt32 getRigidBodyIdB() const { return m_rigidBodyIdB; }
  PfxUInt32 getNumContacts() const { return m_numContacts; }
  // How many points the manifold has room for.
  PfxUInt32 getCapacity() const { return m_capacity; }
  PfxContactPoint& getContactPoint(PfxUInt32 i) { return m_contactPoints[i]; }
  const PfxContactPoint& getContactPoint(PfxUInt32 i) const { return m_contactPoints[i]; }
  // The room the points are kept in (getCapacity() points); null without room.
  const PfxContactPoint* getContactPoints() const { return m_contactPoints; }
  // Moves the points to `points`, room for `capacity` that the caller owns as above (those
  // that do not fit are dropped; (nullptr, 0) leaves no room and no points). Room the
  // manifold had of its own goes back to the heap.
  void moveContactPoints(PfxContactPoint* points, PfxUInt32 capacity);
  PfxFloat getCompositeFriction() const { return m_compositeFriction; }
  PfxFloat getCompositeRestitution() const { return m_compositeRestitution; }
  void setCompositeFriction(PfxFloat f) { m_compositeFriction = f; }
  // J_i M^-1 J_j^T between the normal rows of points i and j, set up for the solver,
  // which solves the points of a manifold together (they rock against each other).
  PfxFloat getNormalCoupling(PfxUInt32 i, PfxUInt32 j) const { return m_normalCoupling[i][j]; }
  void setNormalCoupling(PfxUInt32 i, PfxUInt32 j, PfxFloat k) { m_normalCoupling[i][j] = k; }
  void setCompositeRestitution(PfxFloat e) { m_compositeRestitution = e; }

  // Replaces the points by the best four of `candidates` (the deepest, then those that
  // maximise the covered area). A new point close to a point of the previous frame on the
  // same shapes inherits its accumulated impulses and age, so warm starting carries over;
  // `matchDistanceSq` bounds how far (squared, in A's frame) such a point may have moved.
  // Returns how many points it chose; when they do not fit in the manifold's room, the
  // manifold is left as it was, for the caller to give it more room and update it again.
  PfxUInt32 update(const PfxContactCandidate* candidates, PfxUInt32 numCandidates,
                   const PfxTransform3& transformA, const PfxTransform3& transformB,
                   PfxFloat matchDistanceSq);

  // Recomputes each point's distance from its anchors and the current poses, and drops
  // points whose bodies moved apart along the normal by more than `breakDistance` or slid
  // sideways by more than `breakDistance` (seed chapter 4, pfxRefreshContacts).
  void refresh(const PfxTransform3& transformA, const PfxTransform3& transformB,
               PfxFloat breakDistance);

  // Moves the anchor of every point that lies on a large-mesh triangle to where its
  // barycentric weights put it on the triangle's current corners, in the frame of the body
  // that holds the mesh. Run before refresh() after a mesh has deformed; a point whose
  // triangle is gone is dropped. The collidables are those of bodies A and B.
  void carryMeshContacts(const class PfxCollidable& collidableA,
                         const class PfxCollidable& collidableB);

  void removeContactPoint(PfxUInt32 i);
  void clearContacts() { m_numContacts = 0; }

  // Deepest penetration among the points (0 when none overlap).
  PfxFloat getPenetrationDepth() const;

 private:
  // The serializer (pfx_serialize.h) restores a manifold as it was, points and all.
  friend class PfxSerializeAccess;

  void copyFrom(const PfxContactManifold& other);
  void releaseOwnPoints();

  PfxContactPoint* m_contactPoints;
  PfxFloat m_normalCoupling[PFX_NUM_CONTACTS_PER_MANIFOLD][PFX_NUM_CONTACTS_PER_MANIFOLD];
  PfxUInt32 m_rigidBodyIdA;
  PfxUInt32 m_rigidBodyIdB;
  PfxFloat m_compositeFriction;
  PfxFloat m_compositeRestitution;
  PfxUInt32 m_numContacts;
  PfxUInt8 m_capacity;
  PfxUInt8 m_ownsContactPoints;  // 1 when m_contactPoints came from the heap for it alone
};

// Chooses at most four of `count` candidates: the deepest first, then the ones that make
// the covered polygon largest. Writes their indices to `chosen` and returns how many.
PfxUInt32 pfxReduceContactCandidates(const PfxContactCandidate* candidates, PfxUInt32 count,
                                     PfxUInt32 chosen[PFX_NUM_CONTACTS_PER_MANIFOLD]);

}  // namespace pfx
