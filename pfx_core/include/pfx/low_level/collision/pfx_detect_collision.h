// Stage (3a): narrow phase over the pairs of the broad phase (seed chapter 4).
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

// PfxDetectCollisionParam::sharedEmptyContactId when no manifold is shared.
constexpr PfxUInt32 PFX_NO_SHARED_CONTACT = 0xFFFFFFFFu;

struct PfxDetectCollisionParam {
  PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  PfxContactManifold* offsetContactManifolds = nullptr;  // indexed by pfxGetContactId(pair)
  // Length of offsetContactManifolds, to check the pairs' contact ids against; 0 (the
  // seed's programs give none) checks nothing, and each pair's id must index the array.
  PfxUInt32 numContactManifolds = 0;
  const PfxRigidState* offsetRigidStates = nullptr;
  const PfxCollidable* offsetCollidables = nullptr;
  PfxUInt32 numRigidBodies = 0;
  // Points up to this far apart are kept as speculative contacts, plus the distance the
  // two bodies can close within timeStep at their current velocities; that is what keeps
  // fast bodies from passing through thin walls.
  PfxFloat contactMargin = 0.02f;
  PfxFloat timeStep = 0;
  // Squared distance within which a new point takes over an old point's impulses: what
  // carries the solver's work from one frame to the next (warm starting, the stable
  // pipeline). 0 starts every point afresh, as if the manifold had just been reset.
  PfxFloat matchDistanceSq = PfxFloat(0.02 * 0.02);
  // A manifold that pairs without points may share, so that they cost no manifold of their
  // own (most pairs of a pile or a floor of spheres are neighbours that do not touch). A
  // pair naming it is tested into a manifold of the stage's own; the shared one is only
  // read, and stays empty. When such a pair finds points, its number of constraints says
  // how many while its id still names the shared manifold: the caller gives it one of its
  // own, reset for its bodies, and detects it again. PFX_NO_SHARED_CONTACT: none.
  PfxUInt32 sharedEmptyContactId = PFX_NO_SHARED_CONTACT;
  // One byte per body from pfxCheckContactBodies, or none. A pair of two bodies it passed
  // skips the checks of their poses and shapes that the narrow phase makes at every call
  // otherwise: a body of a pile is checked once, not once for each of its pairs.
  const PfxUInt8* checkedBodies = nullptr;
};

// Writes 1 to checked[i] where body i's pose is a rigid transform and every shape of its
// collidable meets the narrow phase (a shape that passes PfxShape::validate, whose convex
// mesh is whole or whose large mesh has a tree), else 0; bodies in parallel with a task
// manager. For PfxDetectCollisionParam::checkedBodies, at the poses of that detection.
void pfxCheckContactBodies(const PfxRigidState* states, const PfxCollidable* collidables,
                           PfxUInt32 numRigidBodies, PfxUInt8* checked,
                           PfxTaskManager* taskManager = nullptr);

// Writes each pair's manifold and sets its number of constraints (pfxGetNumConstraints);
// pairs run in parallel with a task manager. Pairs must name distinct manifolds, but for
// the shared empty one. A manifold with room for fewer points than its pair found (see
// PfxContactManifold::getCapacity; a manifold made with no arguments has room for four)
// is left as it was, and the pair's number of constraints says how many were found: the
// caller gives it more room and detects it again.
PfxInt32 pfxDetectCollision(const PfxDetectCollisionParam& param,
                            PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
