// Stage: the contact points between one collidable placed anywhere and the bodies of a
// scene, without adding it to the scene: "would a capsule fit here, and what would it
// touch?" (an overlap query). A character controller asks it where the ground is, which
// walls it touches and whether a step up leaves room; an application may ask it where to
// drop a body without overlap.
//
// The bodies are found through the hierarchy over proxies that rays descend
// (pfx_build_ray_bvh.h), so a query costs a descent of about log2(bodies) levels plus the
// narrow phase (pfxContactCollidables) against each body whose bounds come within the
// threshold; it needs no step of the world and changes nothing.
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_proxy.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/low_level/raycast/pfx_build_ray_bvh.h"

namespace pfx {

// PfxContactQueryInput::ignoreRigidBodyId when every body may be reported.
constexpr PfxUInt32 PFX_QUERY_IGNORE_NONE = 0xffffffffu;

// What to query: a collidable (a capsule, a compound, anything a body may hold but a large
// mesh) at a world pose.
struct PfxContactQueryInput {
  const PfxCollidable* collidable = nullptr;
  PfxTransform3 transform = PfxTransform3::Identity();
  // Bodies up to this far from the collidable are reported, with their (positive) distance.
  PfxFloat contactThreshold = 0;
  // A body is tested only when the filters match (pfxContactFiltersMatch), as for rays.
  PfxUInt32 contactFilterSelf = 0xffffffffu;
  PfxUInt32 contactFilterTarget = 0xffffffffu;
  // A body not to report, usually the body whose own shape is being queried.
  PfxUInt32 ignoreRigidBodyId = PFX_QUERY_IGNORE_NONE;
};

// One contact point of the query. The candidate's side A is the queried collidable, side B
// the body: the normal points from the queried collidable to the body, and m_distance is
// negative where they overlap.
struct PfxQueryContact {
  PfxContactCandidate m_contact;
  PfxUInt32 m_rigidBodyId;
};

struct PfxQueryContactsParam {
  // Indexed by the rigid body ids stored in the proxies.
  const PfxRigidState* offsetRigidStates = nullptr;
  const PfxCollidable* offsetCollidables = nullptr;
  // A hierarchy that pfxBuildRayBvh built over bvhProxies (numProxies of them), from proxies
  // quantized in rangeCenter +- rangeExtent with static bounds (timeStep 0).
  const PfxRayBvhNode* bvhNodes = nullptr;
  const PfxBroadphaseProxy* bvhProxies = nullptr;
  PfxUInt32 numProxies = 0;
  PfxVector3 rangeCenter = PfxVector3::Zero();
  PfxVector3 rangeExtent = PfxVector3::Constant(1000);
};

struct PfxQueryContactsResult {
  PfxUInt32 numContacts = 0;  // written to the output array
  // More points were found than the output holds; those beyond it were dropped.
  bool truncated = false;
};

// Writes the contact points of the query to out[0..maxContacts-1], body by body in the
// order the hierarchy visits them (up to PFX_MAX_CONTACT_CANDIDATES per body). Rejects a
// null collidable, a collidable without shapes or holding a large mesh, a non-finite or
// non-rigid transform, a negative or non-finite threshold (PFX_ERR_INVALID_VALUE), a null
// output with maxContacts > 0 and, when there are proxies, null states, collidables,
// hierarchy or proxies (PFX_ERR_NULL_POINTER); the output and result are then untouched.
// Allocates nothing; safe to call from several threads at once.
PfxInt32 pfxQueryContacts(const PfxContactQueryInput& query, const PfxQueryContactsParam& param,
                          PfxQueryContact* out, PfxUInt32 maxContacts,
                          PfxQueryContactsResult& result);

}  // namespace pfx
