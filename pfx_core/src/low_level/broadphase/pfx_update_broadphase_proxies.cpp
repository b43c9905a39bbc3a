#include "pfx/low_level/broadphase/pfx_update_broadphase_proxies.h"

#include <cmath>

#include "pfx/low_level/sort/pfx_parallel_sort.h"
#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

constexpr double kQuantizedMax = 65535.0;
constexpr int kNumProxyArrays = 6;
constexpr PfxUInt32 kProxyBodiesPerTask = 256;
constexpr PfxUInt32 kKnownOutOfWorldFlags =
    PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION | PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY;

// The world's lower corner and the grid cells per metre, in double so that the floor and
// ceil below round the float bounds themselves and not an error of the conversion.
struct WorldGrid {
  double origin[3];
  double cellsPerMetre[3];
};

bool isValidWorld(const PfxVector3& worldCenter, const PfxVector3& worldExtent) {
  return pfxIsFinite(worldCenter) && pfxIsFinite(worldExtent) && worldExtent.minCoeff() > 0;
}

bool isValidCollidable(const PfxCollidable& collidable) {
  return collidable.getNumShapes() > 0 && pfxIsFinite(collidable.getCenter()) &&
         pfxIsFinite(collidable.getHalf());
}

bool isValidTimeStep(PfxFloat timeStep) { return pfxIsFinite(timeStep) && timeStep >= 0; }

WorldGrid makeWorldGrid(const PfxVector3& worldCenter, const PfxVector3& worldExtent) {
  WorldGrid grid;
  for (int a = 0; a < 3; ++a) {
    grid.origin[a] = double(worldCenter[a]) - double(worldExtent[a]);
    grid.cellsPerMetre[a] = kQuantizedMax / (2.0 * double(worldExtent[a]));
  }
  return grid;
}

// Written so that NaN (from an overflowing sweep) widens the box instead of reaching the
// integer conversion.
PfxUInt16 quantizeDown(double cells) {
  if (!(cells > 0)) return 0;
  if (cells >= kQuantizedMax) return 0xffff;
  return static_cast<PfxUInt16>(std::floor(cells));
}

PfxUInt16 quantizeUp(double cells) {
  if (!(cells < kQuantizedMax)) return 0xffff;
  if (cells <= 0) return 0;
  return static_cast<PfxUInt16>(std::ceil(cells));
}

// Fills every field of the proxy but the sort value; returns whether the box lies
// entirely outside the world. A box that only pokes out is clamped: clamping keeps
// overlapping intervals overlapping, so no pair inside the world is lost.
bool buildProxy(PfxBroadphaseProxy& proxy, const PfxRigidState& state,
                const PfxCollidable& collidable, const WorldGrid& grid, PfxFloat timeStep) {
  PfxVector3 center, half;
  collidable.getWorldAabb(state.getTransform(), center, half);
  const PfxVector3& velocity = state.getLinearVelocity();

  proxy.key = 0;
  for (PfxUInt32& word : proxy.data) word = 0;
  bool outOfWorld = false;
  for (int a = 0; a < 3; ++a) {
    // In double, where the sum of two floats of similar magnitude is exact: a float sum
    // could round the box inward by half an ulp and lose a touching pair.
    double lo = double(center[a]) - double(half[a]);
    double hi = double(center[a]) + double(half[a]);
    if (timeStep > 0) {
      const double travel = double(velocity[a]) * double(timeStep);
      if (travel < 0) {
        lo += travel;
      } else {
        hi += travel;
      }
    }
    const double loCells = (lo - grid.origin[a]) * grid.cellsPerMetre[a];
    const double hiCells = (hi - grid.origin[a]) * grid.cellsPerMetre[a];
    if (hiCells < 0 || loCells > kQuantizedMax) outOfWorld = true;
    pfxSetXMin(proxy, a, quantizeDown(loCells));
    pfxSetXMax(proxy, a, quantizeUp(hiCells));
  }
  pfxSetIdentity(proxy, state.getRigidBodyId(), state.getMotionType(), state.isAsleep());
  pfxSetSelf(proxy, state.getContactFilterSelf());
  pfxSetTarget(proxy, state.getContactFilterTarget());
  return outOfWorld;
}

// Arrays 0..2 ascend by minimum along X, Y, Z; arrays 3..5 descend by maximum, which an
// ascending sort gives when the value is stored as its complement.
PfxUInt16 sortValueOfArray(const PfxBroadphaseProxy& proxy, int array) {
  return array < 3 ? pfxGetXMin(proxy, array)
                   : static_cast<PfxUInt16>(0xffff - pfxGetXMax(proxy, array - 3));
}

}  // namespace

PfxInt32 pfxUpdateBroadphaseProxy(PfxBroadphaseProxy& proxy, const PfxRigidState& state,
                                  const PfxCollidable& collidable, const PfxVector3& worldCenter,
                                  const PfxVector3& worldExtent, int axis, PfxFloat timeStep) {
  const PfxParamNames at{"pfxUpdateBroadphaseProxy", ""};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckValue(at, "axis", axis, axis >= 0 && axis <= 2, "0, 1 or 2")) != PFX_OK ||
      (err = pfxCheckValue(at, "timeStep", timeStep, isValidTimeStep(timeStep),
                           "finite and not negative")) != PFX_OK) {
    return err;
  }
  if (!isValidWorld(worldCenter, worldExtent)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxUpdateBroadphaseProxy: worldCenter and worldExtent must be finite, "
                          "the extent positive");
  }
  if (!state.isValid()) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxUpdateBroadphaseProxy: state fails PfxRigidState::isValid()");
  }
  if (!isValidCollidable(collidable)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxUpdateBroadphaseProxy: collidable has no shape or a non-finite box");
  }
  const WorldGrid grid = makeWorldGrid(worldCenter, worldExtent);
  const bool outOfWorld = buildProxy(proxy, state, collidable, grid, timeStep);
  pfxSetSortValue(proxy, pfxGetXMin(proxy, axis));
  return outOfWorld ? PFX_ERR_OUT_OF_WORLD : PFX_OK;
}

PfxUInt32 pfxGetWorkBytesOfUpdateBroadphaseProxies(PfxUInt32 numRigidBodies) {
  return static_cast<PfxUInt32>(pfxAlignBytes(sizeof(PfxBroadphaseProxy) * numRigidBodies));
}

PfxInt32 pfxUpdateBroadphaseProxies(const PfxUpdateBroadphaseProxiesParam& param,
                                    PfxUpdateBroadphaseProxiesResult& result,
                                    PfxTaskManager* taskManager) {
  PfxBroadphaseProxy* const arrays[kNumProxyArrays] = {param.proxiesX,  param.proxiesY,
                                                      param.proxiesZ,  param.proxiesXb,
                                                      param.proxiesYb, param.proxiesZb};
  static const char* const arrayFields[kNumProxyArrays] = {"proxiesX",  "proxiesY",  "proxiesZ",
                                                          "proxiesXb", "proxiesYb", "proxiesZb"};
  const PfxParamNames at{"pfxUpdateBroadphaseProxies", "PfxUpdateBroadphaseProxiesParam"};
  const PfxUInt32 n = param.numRigidBodies;
  if (const PfxInt32 err = pfxCheckRequired(at,
                                            {{param.offsetRigidStates, "offsetRigidStates"},
                                             {param.offsetCollidables, "offsetCollidables"}},
                                            "numRigidBodies", n);
      err != PFX_OK) {
    return err;
  }
  PfxBroadphaseProxy* primary = nullptr;
  for (int a = 0; a < kNumProxyArrays; ++a) {
    if (!arrays[a]) continue;
    if (!pfxIsAligned(arrays[a])) {
      return pfxRejectParam(PFX_ERR_INVALID_ALIGNMENT,
                            "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::%s is "
                            "not 16-byte aligned",
                            arrayFields[a]);
    }
    if (!primary) primary = arrays[a];
  }
  // Like every other array of the pipeline, the proxies may be null when there is no body
  // to give one (a world of particles alone has none).
  if (!primary && n > 0) {
    return pfxRejectParam(PFX_ERR_NULL_POINTER,
                          "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::proxiesX "
                          "to proxiesZb are all null, but numRigidBodies is %u; at least one "
                          "array is needed",
                          n);
  }
  if ((param.outOfWorldBehavior & ~kKnownOutOfWorldFlags) != 0) {
    return pfxRejectParam(PFX_ERR_INVALID_FLAG,
                          "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::"
                          "outOfWorldBehavior is 0x%x; known flags are "
                          "PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION and _REMOVE_PROXY",
                          param.outOfWorldBehavior);
  }
  if (!isValidWorld(param.worldCenter, param.worldExtent)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::"
                          "worldCenter and worldExtent must be finite, the extent positive");
  }
  if (const PfxInt32 err = pfxCheckValue(at, "timeStep", param.timeStep,
                                         isValidTimeStep(param.timeStep),
                                         "finite and not negative");
      err != PFX_OK) {
    return err;
  }
  const PfxUInt64 arrayBytes = PfxUInt64(sizeof(PfxBroadphaseProxy)) * n;
  if (const PfxInt32 err =
          pfxCheckBuffer(at, "workBuff", param.workBuff, param.workBytes, arrayBytes);
      err != PFX_OK) {
    return err;
  }
  // Each array is filled from the first and sorted through the work buffer, so none may
  // share bytes with another.
  auto bytesOf = [arrayBytes](const void* array) { return array ? arrayBytes : 0; };
  for (int a = 0; a < kNumProxyArrays; ++a) {
    if (pfxRangesOverlap(arrays[a], bytesOf(arrays[a]), param.workBuff, arrayBytes)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::%s "
                            "shares bytes with workBuff",
                            arrayFields[a]);
    }
    for (int b = a + 1; b < kNumProxyArrays; ++b) {
      if (pfxRangesOverlap(arrays[a], bytesOf(arrays[a]), arrays[b], bytesOf(arrays[b]))) {
        return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                              "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::%s "
                              "shares bytes with %s",
                              arrayFields[a], arrayFields[b]);
      }
    }
  }
  // Checked before anything is written, so that a rejected call leaves states and arrays
  // as they were.
  const auto skipped = [&param](PfxUInt32 i) { return param.skipBodies && param.skipBodies[i]; };
  for (PfxUInt32 i = 0; i < n; ++i) {
    if (skipped(i)) continue;
    if (!param.offsetRigidStates[i].isValid()) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::"
                            "offsetRigidStates[%u] fails PfxRigidState::isValid()",
                            i);
    }
    if (!isValidCollidable(param.offsetCollidables[i])) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxUpdateBroadphaseProxies: PfxUpdateBroadphaseProxiesParam::"
                            "offsetCollidables[%u] has no shape or a non-finite box",
                            i);
    }
  }

  const WorldGrid grid = makeWorldGrid(param.worldCenter, param.worldExtent);
  const bool fixOutside = (param.outOfWorldBehavior & PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION) != 0;
  const bool removeOutside =
      (param.outOfWorldBehavior & PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY) != 0;
  // Each body writes its own proxy at its own index; the sort value (rewritten below)
  // marks a body outside the world until the proxies are counted in body order.
  pfxParallelFor(taskManager, n, kProxyBodiesPerTask, [&](PfxUInt32 begin, PfxUInt32 end) {
    for (PfxUInt32 i = begin; i < end; ++i) {
      if (skipped(i)) continue;
      PfxRigidState& state = param.offsetRigidStates[i];
      PfxBroadphaseProxy& proxy = primary[i];
      const bool outOfWorld =
          buildProxy(proxy, state, param.offsetCollidables[i], grid, param.timeStep);
      if (outOfWorld && fixOutside) {
        // Stopped as well: a fixed body keeps the velocity it has, which the solver would
        // give whatever touched it, and which may be beyond the speed limits of a body
        // forces do not move (PfxRigidState::isValid) when forces had driven it out.
        state.setMotionType(kPfxMotionTypeFixed);
        state.setLinearVelocity(PfxVector3::Zero());
        state.setAngularVelocity(PfxVector3::Zero());
        pfxSetIdentity(proxy, state.getRigidBodyId(), kPfxMotionTypeFixed, state.isAsleep());
      }
      pfxSetSortValue(proxy, outOfWorld ? 1 : 0);
    }
  });
  PfxUInt32 numProxies = 0;
  PfxUInt32 numOutOfWorld = 0;
  for (PfxUInt32 i = 0; i < n; ++i) {
    if (skipped(i)) continue;
    const bool outOfWorld = pfxGetSortValue(primary[i]) != 0;
    numOutOfWorld += outOfWorld ? 1 : 0;
    if (outOfWorld && removeOutside) continue;
    if (numProxies != i) primary[numProxies] = primary[i];
    ++numProxies;
  }

  for (int a = 0; a < kNumProxyArrays; ++a) {
    PfxBroadphaseProxy* array = arrays[a];
    if (!array) continue;
    pfxParallelFor(taskManager, numProxies, kProxyBodiesPerTask,
                   [&](PfxUInt32 begin, PfxUInt32 end) {
                     for (PfxUInt32 i = begin; i < end; ++i) {
                       if (array != primary) array[i] = primary[i];
                       pfxSetSortValue(array[i], sortValueOfArray(array[i], a));
                     }
                   });
    pfxParallelSort(array, numProxies, param.workBuff, param.workBytes, taskManager);
  }

  result.numProxies = numProxies;
  result.numOutOfWorldProxies = numOutOfWorld;
  return PFX_OK;
}

int pfxChooseSweepAxis(const PfxRigidState* states, PfxUInt32 numRigidBodies) {
  if (!states || numRigidBodies == 0) return 0;
  // Two passes (mean, then squared deviations) in double: the one-pass sum of squares
  // cancels badly for bodies far from the origin.
  double mean[3] = {0, 0, 0};
  for (PfxUInt32 i = 0; i < numRigidBodies; ++i) {
    for (int a = 0; a < 3; ++a) mean[a] += states[i].getPosition()[a];
  }
  for (double& m : mean) m /= numRigidBodies;
  double spread[3] = {0, 0, 0};
  for (PfxUInt32 i = 0; i < numRigidBodies; ++i) {
    for (int a = 0; a < 3; ++a) {
      const double d = states[i].getPosition()[a] - mean[a];
      spread[a] += d * d;
    }
  }
  int axis = 0;
  if (spread[1] > spread[axis]) axis = 1;
  if (spread[2] > spread[axis]) axis = 2;
  return axis;
}

}  // namespace pfx
