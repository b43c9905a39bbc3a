// A convex shape as GJK and EPA see it: a core (a point, a segment, a box, a cylinder or the
// vertices of a mesh) with a radius swept around it (spheres and capsules), placed in the
// world. Keeping the radius out of the core keeps GJK exact on spheres and capsules.
#pragma once

#include "pfx/base_level/collision/pfx_shape.h"

namespace pfx {

// Points of the polygon that stands in for a cylinder's cap.
constexpr PfxUInt32 PFX_CYLINDER_CAP_POINTS = 12;
// Largest supporting face: a mesh face or a cylinder cap.
constexpr PfxUInt32 PFX_MAX_SUPPORTING_FACE_POINTS = PFX_CONVEX_MESH_MAX_VERTICES;

struct PfxConvexCore {
  PfxShapeType m_type;
  PfxVector3 m_size;  // box: half extents; capsule, cylinder: (half length, radius, 0)
  const PfxConvexMesh* m_mesh;
  PfxFloat m_radius;  // swept around the core: spheres and capsules only
  PfxMatrix3 m_rotation;
  PfxVector3 m_position;

  void set(const PfxShape& shape, const PfxTransform3& transform);

  // Largest distance of a point of the whole shape from its origin (radius included).
  PfxFloat boundingRadius() const;

  // The point of the core furthest along a world direction (need not be unit).
  PfxVector3 support(const PfxVector3& worldDir) const {
    return m_rotation * supportLocal(m_rotation.transpose() * worldDir) + m_position;
  }
  PfxVector3 supportLocal(const PfxVector3& dir) const;

  // The face of the whole shape (radius included) that touches a plane with outward normal
  // `worldDir` (unit): its world points and outward normal. Returns 2 for a segment (capsule
  // side, cylinder side), 3 or more for a polygon, 0 where the shape meets the plane in a
  // point only (sphere, a capsule's end, a cylinder's rim).
  PfxUInt32 supportingFace(const PfxVector3& worldDir, PfxVector3* points,
                           PfxVector3& faceNormal) const;
};

}  // namespace pfx
