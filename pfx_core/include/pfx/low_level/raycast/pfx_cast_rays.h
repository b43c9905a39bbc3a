// Stage: rays cast into a scene through the six sorted proxy arrays that
// pfxUpdateBroadphaseProxies writes (seed chapter 5, "Raycast"), or through the hierarchy
// of pfxBuildRayBvh over one of them, which finds the same hits about ten times faster
// among 1,000 bodies (pfx_build_ray_bvh.h).
//
// How a ray finds its body. The ray walks the array sorted along its dominant axis, in its
// own direction: the array by minimum ascending for a ray going +X, by maximum descending
// for -X, and likewise for Y and Z. A proxy whose quantized box the ray misses is skipped
// without touching the body; the walk stops at the first proxy whose box begins, along that
// axis, beyond the closest hit so far (or beyond the ray's end), since every later proxy
// begins further still. Quantized boxes are widened by one cell, and a box clamped to the
// edge of the range reaches on to infinity there, so that neither rounding nor a body
// poking out of the range hides a hit.
//
// Contact filters: a body is tested only when
//   (ray.m_contactFilterTarget & body's self) != 0 && (ray.m_contactFilterSelf & body's target) != 0,
// the rule bodies follow among themselves (pfxContactFiltersMatch), with the ray as one side.
// The filters are read from the proxies, as pfxUpdateBroadphaseProxies copied them. Every
// motion type is hit, triggers included; give bodies that rays should not see a filter that
// the rays' filters exclude.
//
// Of bodies hit at the same fraction the lowest id wins, so the answer does not depend on
// the order of the walk: it equals testing every body in turn.
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_proxy.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/raycast/pfx_ray.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"
#include "pfx/low_level/raycast/pfx_build_ray_bvh.h"

namespace pfx {

struct PfxRayCastParam {
  // Indexed by the rigid body ids stored in the proxies.
  const PfxRigidState* offsetRigidStates = nullptr;
  const PfxCollidable* offsetCollidables = nullptr;
  // The six arrays of pfxUpdateBroadphaseProxies, built with static bounds (timeStep 0) and
  // the world bounds given below. Only the arrays that the rays' directions need are read:
  // a scene cast only downward may pass proxiesYb alone.
  const PfxBroadphaseProxy* proxiesX = nullptr;
  const PfxBroadphaseProxy* proxiesY = nullptr;
  const PfxBroadphaseProxy* proxiesZ = nullptr;
  const PfxBroadphaseProxy* proxiesXb = nullptr;
  const PfxBroadphaseProxy* proxiesYb = nullptr;
  const PfxBroadphaseProxy* proxiesZb = nullptr;
  PfxUInt32 numProxies = 0;  // in each array
  // The worldCenter and worldExtent the proxies were quantized in.
  PfxVector3 rangeCenter = PfxVector3::Zero();
  PfxVector3 rangeExtent = PfxVector3::Constant(1000);
  // Optional and faster (pfx_build_ray_bvh.h): a hierarchy that pfxBuildRayBvh built over
  // bvhProxies, one proxy array of numProxies. When set, rays descend it instead of walking
  // the six arrays, which are then not read.
  const PfxRayBvhNode* bvhNodes = nullptr;
  const PfxBroadphaseProxy* bvhProxies = nullptr;
  // Optional, read by pfxCastRays only: scratch of pfxGetWorkBytesOfCastRays(numRays) bytes,
  // 16-byte aligned. With it a batch is cast in the Morton (Z-curve) order of the rays'
  // start points in the range (then of their directions), so that rays cast one after
  // another search the same parts of a large mesh while they are still in the cache:
  // 100,000 random rays on a 524,288-triangle terrain went 1.3 to 2.7 times as fast on a
  // shared machine, depending on how much of the mesh the other work left in the cache.
  // The outputs are the same, each in its ray's place.
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
};

// Largest batch that pfxCastRays casts in Morton order (a larger one with a work buffer is
// rejected), and the scratch that takes.
constexpr PfxUInt32 PFX_CAST_RAYS_MAX_ORDERED = 1u << 26;
PfxUInt32 pfxGetWorkBytesOfCastRays(PfxUInt32 numRays);

// Casts one ray and writes the closest hit, or a miss (PfxRayOutput::setMiss), to `out`.
// Rejects a ray that cannot be cast (pfxCheckRayInput: PFX_ERR_INVALID_VALUE,
// PFX_ERR_DEGENERATE), a non-finite range or one not larger than zero on every axis
// (PFX_ERR_INVALID_VALUE), and, when there are proxies, null states or collidables, a
// hierarchy without its proxies, or without a hierarchy a null array that the ray's
// direction needs (PFX_ERR_NULL_POINTER); `out` is then left as
// it was. `in` and `out` may be the same memory. Safe to call from several threads at once
// on the same parameters, which it does not change.
PfxInt32 pfxCastSingleRay(const PfxRayInput& in, PfxRayOutput& out, const PfxRayCastParam& param);

// Casts `numRays` rays, each as pfxCastSingleRay would. Every ray and the parameters are
// checked before any output is written, so a rejected batch writes nothing; null arrays
// with rays to cast (PFX_ERR_NULL_POINTER), output that shares bytes with the input or
// the work buffer (PFX_ERR_INVALID_VALUE), a misaligned or short work buffer
// (PFX_ERR_INVALID_ALIGNMENT, PFX_ERR_OUT_OF_BUFFER) and, with a work buffer, more than
// PFX_CAST_RAYS_MAX_ORDERED rays (PFX_ERR_OUT_OF_RANGE) are rejected as well. With a task
// manager the rays are cast in parallel, each writing only its own output.
PfxInt32 pfxCastRays(const PfxRayInput* in, PfxRayOutput* out, PfxUInt32 numRays,
                     const PfxRayCastParam& param, PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
