// The narrow phase for a caller that checks its input once rather than at every call: the
// particles' contact detection meets thousands of particles with the same few bodies, and
// pfxContactCollidables' own checks of the poses and shapes cost as much as the contacts.
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

}  // namespace pfx
