// The narrow phase for a caller that checks its input once rather than at every call: the
// particles' contact detection and refresh meet thousands of particles with the same few
// bodies, and the public entry points' own checks of the poses and shapes cost as much as
// the contacts.
#pragma once

#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

// A finite rotation and translation: what pfxContactCollidables asks of a pose.
bool pfxIsRigidTransform(const PfxTransform3& transform);

// A shape pfxContactCollidables meets: a valid convex shape, or a large mesh with a tree.
bool pfxIsContactShape(const PfxShape& shape);

// pfxContactCollidables for poses that pass pfxIsRigidTransform, collidables whose every
// shape passes pfxIsContactShape, a finite threshold of at least 0 and room in `out`.
PfxUInt32 pfxContactCheckedCollidables(const PfxCollidable& collidableA,
                                       const PfxTransform3& transformA,
                                       const PfxCollidable& collidableB,
                                       const PfxTransform3& transformB, PfxFloat contactThreshold,
                                       PfxContactCandidate* out, PfxUInt32 maxOut);

// pfxContactConvexShapes for two shapes that pass pfxIsContactShape and are not large
// meshes, poses that pass pfxIsRigidTransform, a finite threshold of at least 0 and room in
// `out`: what the particles' contact refresh calls each sub-step, its shapes and poses
// checked once for the many contacts that share them.
PfxUInt32 pfxContactCheckedConvexShapes(const PfxShape& shapeA, const PfxTransform3& transformA,
                                        const PfxShape& shapeB, const PfxTransform3& transformB,
                                        PfxFloat contactThreshold, PfxContactCandidate* out,
                                        PfxUInt32 maxOut);

}  // namespace pfx
