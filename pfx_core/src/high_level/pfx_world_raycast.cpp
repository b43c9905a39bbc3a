// PfxWorld's raycasts: the six proxy arrays of seed chapter 5, built on demand.
#include "pfx/high_level/pfx_world.h"

namespace pfx {

namespace {

constexpr std::size_t kNumRayProxyArrays = 6;

}  // namespace

PfxInt32 PfxWorld::updateRayProxies() {
  if (!m_rayProxiesStale) return PFX_OK;
  const PfxUInt32 numBodies = getNumRigidBodies();
  // Sized by the bodies' capacity, as the other buffers are, so that casts between body
  // additions do not allocate.
  if (m_rayProxyStride < m_states.capacity()) {
    m_rayProxyStride = m_states.capacity();
    m_rayProxies.resize((kNumRayProxyArrays + 1) * m_rayProxyStride);
  }
  m_numRayProxies = 0;
  if (numBodies > 0) {
    PfxBroadphaseProxy* arrays = m_rayProxies.data();
    PfxUpdateBroadphaseProxiesParam param;
    param.workBuff = arrays + kNumRayProxyArrays * m_rayProxyStride;
    param.workBytes = pfxGetWorkBytesOfUpdateBroadphaseProxies(numBodies);
    param.offsetRigidStates = m_states.data();
    param.offsetCollidables = m_collidables.data();
    param.numRigidBodies = numBodies;
    param.proxiesX = arrays;
    param.proxiesY = arrays + m_rayProxyStride;
    param.proxiesZ = arrays + 2 * m_rayProxyStride;
    param.proxiesXb = arrays + 3 * m_rayProxyStride;
    param.proxiesYb = arrays + 4 * m_rayProxyStride;
    param.proxiesZb = arrays + 5 * m_rayProxyStride;
    param.worldCenter = m_param.worldCenter;
    param.worldExtent = m_param.worldExtent;
    // Rays see every body as it is: none is dropped or fixed for lying outside the world,
    // and bounds are not swept along velocities.
    param.outOfWorldBehavior = 0;
    param.timeStep = 0;
    PfxUpdateBroadphaseProxiesResult result;
    // Fails only on a body whose state went bad (a simulation that blew up to NaN); the
    // arrays then stay stale and the cast reports it.
    if (const PfxInt32 err = pfxUpdateBroadphaseProxies(param, result); err != PFX_OK) {
      return err;
    }
    m_numRayProxies = result.numProxies;
  }
  m_rayProxiesStale = false;
  return PFX_OK;
}

PfxRayCastParam PfxWorld::rayCastParam() const {
  const PfxBroadphaseProxy* arrays = m_rayProxies.data();
  PfxRayCastParam param;
  param.offsetRigidStates = m_states.data();
  param.offsetCollidables = m_collidables.data();
  if (m_numRayProxies > 0) {
    param.proxiesX = arrays;
    param.proxiesY = arrays + m_rayProxyStride;
    param.proxiesZ = arrays + 2 * m_rayProxyStride;
    param.proxiesXb = arrays + 3 * m_rayProxyStride;
    param.proxiesYb = arrays + 4 * m_rayProxyStride;
    param.proxiesZb = arrays + 5 * m_rayProxyStride;
  }
  param.numProxies = m_numRayProxies;
  param.rangeCenter = m_param.worldCenter;
  param.rangeExtent = m_param.worldExtent;
  return param;
}

PfxInt32 PfxWorld::castRay(const PfxRayInput& in, PfxRayOutput& out) {
  if (const PfxInt32 err = updateRayProxies(); err != PFX_OK) return err;
  return pfxCastSingleRay(in, out, rayCastParam());
}

PfxInt32 PfxWorld::castRays(const PfxRayInput* in, PfxRayOutput* out, PfxUInt32 numRays) {
  if (const PfxInt32 err = updateRayProxies(); err != PFX_OK) return err;
  return pfxCastRays(in, out, numRays, rayCastParam());
}

}  // namespace pfx
