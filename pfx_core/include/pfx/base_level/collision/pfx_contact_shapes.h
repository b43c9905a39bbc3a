// Narrow phase for one pair of shapes: the points where they touch, overlap, or come
// within `contactThreshold` of each other (speculative contacts).
#pragma once

#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/collision/pfx_shape.h"

namespace pfx {

// At most this many candidates come out of one pair of convex shapes (clipped polygons);
// the manifold keeps the best four.
constexpr PfxUInt32 PFX_MAX_CONTACT_CANDIDATES = 16;

// Contact candidates between two convex shapes placed at `transformA` and `transformB`
// (world poses of the shapes, their offsets already applied). Normals point from A to B.
// Returns how many candidates were written to `out` (at most `maxOut`); zero when the
// shapes are further apart than `contactThreshold`. Large meshes are not convex and are
// not handled here.
PfxUInt32 pfxContactConvexShapes(const PfxShape& shapeA, const PfxTransform3& transformA,
                                 const PfxShape& shapeB, const PfxTransform3& transformB,
                                 PfxFloat contactThreshold, PfxContactCandidate* out,
                                 PfxUInt32 maxOut);

// Candidates between two whole collidables (every pair of their shapes whose bounds come
// within the threshold), with shape indices filled in. A large mesh meets every convex
// shape, in either order (see pfx_large_tri_mesh.h); two large meshes do not collide.
// Points on a mesh carry their triangle and corner weights.
PfxUInt32 pfxContactCollidables(const class PfxCollidable& collidableA,
                                const PfxTransform3& transformA,
                                const class PfxCollidable& collidableB,
                                const PfxTransform3& transformB, PfxFloat contactThreshold,
                                PfxContactCandidate* out, PfxUInt32 maxOut);

}  // namespace pfx
