// Stage (2a): rigid bodies become broadphase proxies (seed chapters 4 and 5).
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_proxy.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

// What becomes of a body outside the world's bounds.
enum : PfxUInt32 {
  PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION = 1 << 0,    // its motion type becomes fixed
  PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY = 1 << 1,  // it gets no proxy
};

// One body. The box is swept along the body's linear velocity over `timeStep` (0: not
// swept), so that the pair of a fast body is found before it passes something; then it is
// quantized (min rounded down, max up) in [worldCenter - worldExtent, worldCenter + worldExtent].
// The sort value is the minimum along `axis`. Returns PFX_ERR_OUT_OF_WORLD for a body
// outside those bounds, and still writes the proxy, clamped (seed chapter 4).
PfxInt32 pfxUpdateBroadphaseProxy(PfxBroadphaseProxy& proxy, const PfxRigidState& state,
                                  const PfxCollidable& collidable, const PfxVector3& worldCenter,
                                  const PfxVector3& worldExtent, int axis,
                                  PfxFloat timeStep = 0);

struct PfxUpdateBroadphaseProxiesParam {
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  PfxRigidState* offsetRigidStates = nullptr;
  const PfxCollidable* offsetCollidables = nullptr;
  PfxUInt32 numRigidBodies = 0;
  // Optional, one entry per body: a body whose entry is not 0 gets no proxy, as if it were
  // not there (the slot of a body PfxWorld removed). Null: every body gets one.
  const PfxUInt8* skipBodies = nullptr;
  // Sorted by minimum along X, Y, Z, and by maximum along X, Y, Z in descending order
  // ("b" for backward), for rays that travel in either direction. Any array may be null
  // when not needed; the simulation needs only the one of its sweep axis.
  PfxBroadphaseProxy* proxiesX = nullptr;
  PfxBroadphaseProxy* proxiesY = nullptr;
  PfxBroadphaseProxy* proxiesZ = nullptr;
  PfxBroadphaseProxy* proxiesXb = nullptr;
  PfxBroadphaseProxy* proxiesYb = nullptr;
  PfxBroadphaseProxy* proxiesZb = nullptr;
  PfxVector3 worldCenter = PfxVector3::Zero();
  PfxVector3 worldExtent = PfxVector3::Constant(1000);
  PfxUInt32 outOfWorldBehavior = 0;
  PfxFloat timeStep = 0;  // sweep bounds over this time; 0 for static bounds (raycasts)
};

struct PfxUpdateBroadphaseProxiesResult {
  PfxUInt32 numProxies = 0;            // written to each array
  PfxUInt32 numOutOfWorldProxies = 0;  // bodies found outside the world
};

PfxUInt32 pfxGetWorkBytesOfUpdateBroadphaseProxies(PfxUInt32 numRigidBodies);

// With a task manager, bodies are turned into proxies in parallel and the arrays sorted
// in parallel; the arrays come out the same.
PfxInt32 pfxUpdateBroadphaseProxies(const PfxUpdateBroadphaseProxiesParam& param,
                                    PfxUpdateBroadphaseProxiesResult& result,
                                    PfxTaskManager* taskManager = nullptr);

// The axis (0, 1, 2) along which body centres spread the most: the best one to sweep.
int pfxChooseSweepAxis(const PfxRigidState* states, PfxUInt32 numRigidBodies);

}  // namespace pfx
