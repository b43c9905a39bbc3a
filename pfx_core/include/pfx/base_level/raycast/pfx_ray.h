// A ray and what it hit (seed chapter 5). A ray is a start point and a direction whose
// length is the ray's length: it covers start + t * direction for t in [0, 1]. The answer
// is the hit closest to the start.
//
// What counts as a hit. Spheres, boxes, capsules, cylinders and convex meshes are solids:
// closed sets, their surface included. The line of the ray meets such a shape in one
// interval [tIn, tOut]; the ray hits the shape at tIn when 0 <= tIn <= 1, where it enters.
// From that follow the answers to the corner cases:
//   - A ray that starts inside a solid (or on its surface, heading out) does not hit it: it
//     passes out and reports what lies beyond. This is what a range sensor needs, whose
//     origin usually sits inside the robot's own collision shapes: it must measure the room,
//     not read zero (Bullet's and Embree's rays behave the same way). A ray that starts on
//     the surface heading in hits at fraction 0, within rounding.
//   - A grazing ray, tangent to a curved surface or touching only an edge or a corner,
//     meets the closed shape in one point and hits there; its normal is the surface normal
//     at that point, perpendicular to the ray. Within float rounding of exact tangency a
//     grazing ray may hit or miss.
//   - A ray that runs along an edge or a face (parallel to it, on it) hits where it first
//     meets the shape, with the normal of the face it meets head-on.
//   - Where the entry point lies on an edge or corner of several flat faces, the normal is
//     that of one of them: for a box the first of the X, Y, Z faces, for a cylinder's rim
//     the cap, for a convex mesh the first face in the mesh's order.
// Large triangle meshes are surfaces, not solids: a ray hits either side of a triangle,
// also from inside a closed mesh, and the normal is the face normal turned against the ray.
//
// Rays that cannot be cast: a start or direction with a NaN or infinite component is
// rejected with PFX_ERR_INVALID_VALUE, and so is a direction whose squared length overflows
// (a length beyond about 1.8e19); a zero-length direction, or one whose squared length
// underflows (a length below about 1.1e-19), with PFX_ERR_DEGENERATE. The output is then left
// as it was. The limits are float's also in the double build (a component beyond 3.4e38 is
// as infinite as in float), so a ray castable in one precision is castable in the other.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

// m_objectId and m_triangleIndex when there is nothing to name.
constexpr PfxUInt32 PFX_RAY_NO_OBJECT = 0xffffffffu;
constexpr PfxUInt32 PFX_RAY_NO_TRIANGLE = 0xffffffffu;

struct PfxRayInput {
  PfxVector3 m_startPosition;
  PfxVector3 m_direction;  // end point minus start point
  // A body is tested only when (m_contactFilterTarget & body's self) != 0 and
  // (m_contactFilterSelf & body's target) != 0: the rule bodies follow among themselves,
  // with the ray as one side (pfxContactFiltersMatch).
  PfxUInt32 m_contactFilterSelf;
  PfxUInt32 m_contactFilterTarget;

  // Start and direction zero (not castable until set), filters that admit every body.
  void reset();
};

struct PfxRayOutput {
  PfxVector3 m_contactPoint;   // world frame: start + m_variable * direction
  PfxVector3 m_contactNormal;  // world frame, unit, outward from the surface hit
  PfxFloat m_variable;         // fraction of the ray's length in [0, 1]; 1 on a miss
  PfxUInt32 m_objectId;        // rigid body id, PFX_RAY_NO_OBJECT on a miss
  PfxUInt32 m_triangleIndex;   // large meshes: the triangle in the creator's list
  PfxUInt8 m_shapeId;          // index of the shape in the body's collidable
  bool m_contactFlag = false;  // whether anything was hit
  // A particle group's hit (PfxWorld): the group and the particle, m_objectId then being
  // PFX_RAY_NO_OBJECT and m_triangleIndex the cloth's triangle; PFX_RAY_NO_OBJECT when a
  // body was hit or nothing.
  PfxUInt32 m_particleGroupId = PFX_RAY_NO_OBJECT;
  PfxUInt32 m_particleIndex = PFX_RAY_NO_OBJECT;

  // The answer for a ray that hits nothing: no contact, fraction 1, point at the end of the
  // ray, zero normal.
  void setMiss(const PfxRayInput& ray);
};

// PFX_OK when the ray can be cast, otherwise why not (see the header comment).
PfxInt32 pfxCheckRayInput(const PfxRayInput& ray);

}  // namespace pfx
