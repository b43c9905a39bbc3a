// One ray against one shape, in the shape's own frame, and against one body's collidable.
// The rules for what counts as a hit are in pfx_ray.h. These are the inner loops of every
// raycast and take a ray already checked by pfxCheckRayInput (finite, non-zero direction);
// the stages and the world check it.
//
// Each shape test follows the same contract: `fraction` holds on input the furthest
// fraction of interest (1 for the whole ray, or the closest hit so far); the test returns
// true when the ray enters the shape at a fraction in [0, that value], and then writes the
// fraction and the outward unit normal (shape frame). On false nothing is written.
#pragma once

#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/raycast/pfx_ray.h"

namespace pfx {

// Sphere centred at the origin. The quadratic is solved in the form that keeps its digits
// for rays starting far from a small sphere.
bool pfxRayCastSphere(const PfxSphere& sphere, const PfxVector3& start,
                      const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal);

// Box centred at the origin, by slabs.
bool pfxRayCastBox(const PfxBox& box, const PfxVector3& start, const PfxVector3& direction,
                   PfxFloat& fraction, PfxVector3& normal);

// Capsule along X: the entry into the union of its side and its two end spheres.
bool pfxRayCastCapsule(const PfxCapsule& capsule, const PfxVector3& start,
                       const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal);

// Cylinder along X: the slab between the caps intersected with the infinite side.
bool pfxRayCastCylinder(const PfxCylinder& cylinder, const PfxVector3& start,
                        const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal);

// Convex mesh, as the intersection of its face planes' half-spaces: no triangle edges, so
// no ray can slip between two faces.
bool pfxRayCastConvexMesh(const PfxConvexMesh& mesh, const PfxVector3& start,
                          const PfxVector3& direction, PfxFloat& fraction, PfxVector3& normal);

// Any shape placed at `shapeTransform` (world pose, offset applied), with a world-frame ray
// and a world-frame normal. Large meshes go through pfxRayCastLargeTriMesh; for them
// `triangleIndex` is the triangle hit in the creator's list, for the others
// PFX_RAY_NO_TRIANGLE.
bool pfxRayCastShape(const PfxShape& shape, const PfxTransform3& shapeTransform,
                     const PfxVector3& start, const PfxVector3& direction, PfxFloat& fraction,
                     PfxVector3& normal, PfxUInt32& triangleIndex);

// The closest hit on any shape of a body placed at `bodyTransform`, at a fraction no
// further than `maxFraction`. On a hit writes every field of `out` but m_objectId and
// returns true; of shapes hit at the same fraction the lowest index wins. On a miss writes
// nothing.
bool pfxRayCastCollidable(const PfxRayInput& ray, const PfxCollidable& collidable,
                          const PfxTransform3& bodyTransform, PfxFloat maxFraction,
                          PfxRayOutput& out);

}  // namespace pfx
