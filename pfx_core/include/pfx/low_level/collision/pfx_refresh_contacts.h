// Stage (3b): contact points kept from the last frame are brought up to date and those
// that no longer hold are dropped (seed chapter 4, "Update the Collision Information").
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxRefreshContactsParam {
  PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  PfxContactManifold* offsetContactManifolds = nullptr;
  // Length of offsetContactManifolds, to check the pairs' contact ids against; 0 (the
  // seed's programs give none) checks nothing, and each pair's id must index the array.
  PfxUInt32 numContactManifolds = 0;
  const PfxRigidState* offsetRigidStates = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxFloat breakDistance = 0.02f;  // how far apart or sideways a point may move and stay
  // Optional: the bodies' collidables. With them, points on a large mesh are first carried
  // to where their triangles are now (a deforming mesh); without, meshes count as rigid.
  const PfxCollidable* offsetCollidables = nullptr;
};

// Pairs run in parallel with a task manager; they must name distinct manifolds, but for an
// empty one, which is only read (pfxDetectCollision's shared empty manifold).
PfxInt32 pfxRefreshContacts(const PfxRefreshContactsParam& param,
                            PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
