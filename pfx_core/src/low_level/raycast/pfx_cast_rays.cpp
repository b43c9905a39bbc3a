#include "pfx/low_level/raycast/pfx_cast_rays.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pfx/base_level/base/pfx_sort_data.h"
#include "pfx/base_level/raycast/pfx_ray_shapes.h"
#include "pfx/low_level/sort/pfx_parallel_sort.h"
#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

constexpr double kRayQuantizedMax = 65535.0;
constexpr double kRayInfinity = std::numeric_limits<double>::infinity();

// The axis along which the ray moves fastest, and whether it moves towards +.
struct WalkDirection {
  int axis;
  bool forward;
};

WalkDirection chooseWalk(const PfxVector3& direction) {
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (std::abs(direction[a]) > std::abs(direction[axis])) axis = a;
  }
  return {axis, direction[axis] > 0};
}

const PfxBroadphaseProxy* proxiesFor(const PfxRayCastParam& param, WalkDirection walk) {
  const PfxBroadphaseProxy* const arrays[6] = {param.proxiesX,  param.proxiesY,
                                               param.proxiesZ,  param.proxiesXb,
                                               param.proxiesYb, param.proxiesZb};
  return arrays[walk.axis + (walk.forward ? 0 : 3)];
}

PfxInt32 checkRayParam(const PfxParamNames& at, const PfxRayCastParam& param) {
  if (!pfxIsFinite(param.rangeCenter) || !pfxIsFinite(param.rangeExtent) ||
      !(param.rangeExtent.minCoeff() > 0)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "%s: PfxRayCastParam::rangeCenter and rangeExtent must be finite, the "
                          "extent positive",
                          at.stage);
  }
  if (param.numProxies > 0 && param.bvhNodes && !param.bvhProxies) {
    return pfxRejectParam(PFX_ERR_NULL_POINTER,
                          "%s: PfxRayCastParam::bvhProxies is null, but bvhNodes is set", at.stage);
  }
  return pfxCheckRequired(at,
                          {{param.offsetRigidStates, "offsetRigidStates"},
                           {param.offsetCollidables, "offsetCollidables"}},
                          "numProxies", param.numProxies);
}

PfxInt32 checkRay(const PfxParamNames& at, const PfxRayInput& ray, PfxUInt32 index,
                  const PfxRayCastParam& param) {
  if (const PfxInt32 err = pfxCheckRayInput(ray); err != PFX_OK) {
    return pfxRejectParam(err,
                          "%s: ray %u has a non-finite start or direction, or a zero direction",
                          at.stage, index);
  }
  if (param.numProxies > 0 && !param.bvhNodes &&
      !proxiesFor(param, chooseWalk(ray.m_direction))) {
    static const char* const arrayFields[6] = {"proxiesX",  "proxiesY",  "proxiesZ",
                                               "proxiesXb", "proxiesYb", "proxiesZb"};
    const WalkDirection walk = chooseWalk(ray.m_direction);
    return pfxRejectParam(PFX_ERR_NULL_POINTER,
                          "%s: PfxRayCastParam::%s is null, but ray %u walks it", at.stage,
                          arrayFields[walk.axis + (walk.forward ? 0 : 3)], index);
  }
  return PFX_OK;
}

// The ray in the grid of the quantized bounds, in double so that a ray starting far
// outside the range keeps its cell coordinates exact enough for the one-cell margin.
struct RayInCells {
  double start[3];
  double direction[3];
  double inverse[3];
};

RayInCells rayToCells(const PfxRayInput& ray, const PfxRayCastParam& param) {
  RayInCells cells;
  for (int a = 0; a < 3; ++a) {
    const double extent = param.rangeExtent[a];
    const double cellsPerMetre = kRayQuantizedMax / (2.0 * extent);
    const double origin = double(param.rangeCenter[a]) - extent;
    cells.start[a] = (double(ray.m_startPosition[a]) - origin) * cellsPerMetre;
    cells.direction[a] = double(ray.m_direction[a]) * cellsPerMetre;
    cells.inverse[a] = cells.direction[a] != 0 ? 1.0 / cells.direction[a] : 0.0;
  }
  return cells;
}

// A 16-bit box in cells, one cell wider on each side against rounding; a side clamped to
// the edge of the range stands for everything beyond it.
double lowerCell(PfxUInt16 v) { return v == 0 ? -kRayInfinity : double(v) - 1.0; }
double upperCell(PfxUInt16 v) { return v == 0xffff ? kRayInfinity : double(v) + 1.0; }

// Whether the ray passes through the box at a fraction in [0, maxFraction], and where it
// enters it.
bool rayMeetsBox(const RayInCells& ray, const PfxUInt16 min[3], const PfxUInt16 max[3],
                 double maxFraction, double& entry) {
  double tEnter = 0;
  double tExit = maxFraction;
  for (int a = 0; a < 3; ++a) {
    const double lo = lowerCell(min[a]);
    const double hi = upperCell(max[a]);
    if (ray.direction[a] == 0) {
      if (ray.start[a] < lo || ray.start[a] > hi) return false;
      continue;
    }
    double t0 = (lo - ray.start[a]) * ray.inverse[a];
    double t1 = (hi - ray.start[a]) * ray.inverse[a];
    if (t0 > t1) std::swap(t0, t1);
    tEnter = std::max(tEnter, t0);
    tExit = std::min(tExit, t1);
    if (tEnter > tExit) return false;
  }
  entry = tEnter;
  return true;
}

bool rayMeetsProxy(const RayInCells& ray, const PfxBroadphaseProxy& proxy, double maxFraction) {
  const PfxUInt16 min[3] = {pfxGetXMin(proxy, 0), pfxGetXMin(proxy, 1), pfxGetXMin(proxy, 2)};
  const PfxUInt16 max[3] = {pfxGetXMax(proxy, 0), pfxGetXMax(proxy, 1), pfxGetXMax(proxy, 2)};
  double entry;
  return rayMeetsBox(ray, min, max, maxFraction, entry);
}

// Tests the body of a proxy whose box the ray meets, and keeps its hit if it is the
// closest so far (the lowest id among equals).
void testBody(const PfxRayInput& ray, const PfxBroadphaseProxy& proxy,
              const PfxRayCastParam& param, PfxRayOutput& closest) {
  if (!pfxContactFiltersMatch(ray.m_contactFilterSelf, ray.m_contactFilterTarget,
                              pfxGetSelf(proxy), pfxGetTarget(proxy))) {
    return;
  }
  const PfxUInt32 id = pfxGetObjectId(proxy);
  PfxRayOutput hit;
  if (!pfxRayCastCollidable(ray, param.offsetCollidables[id],
                            param.offsetRigidStates[id].getTransform(), closest.m_variable, hit)) {
    return;
  }
  const bool closer = !closest.m_contactFlag || hit.m_variable < closest.m_variable ||
                      (hit.m_variable == closest.m_variable && id < closest.m_objectId);
  if (!closer) return;
  closest = hit;
  closest.m_objectId = id;
}

// The seed's walk over the array sorted along the ray's dominant axis.
void walkSortedProxies(const PfxRayInput& ray, const RayInCells& cells,
                       const PfxRayCastParam& param, PfxRayOutput& closest) {
  const WalkDirection walk = chooseWalk(ray.m_direction);
  const PfxBroadphaseProxy* proxies = proxiesFor(param, walk);
  const int axis = walk.axis;
  for (PfxUInt32 i = 0; i < param.numProxies; ++i) {
    const PfxBroadphaseProxy& proxy = proxies[i];
    // Where the ray reaches the proxy's near side along the walk axis; the arrays are
    // sorted by that side, so every later proxy starts at least as far along.
    const double nearSide = walk.forward ? lowerCell(pfxGetXMin(proxy, axis))
                                         : upperCell(pfxGetXMax(proxy, axis));
    const double reach = (nearSide - cells.start[axis]) * cells.inverse[axis];
    if (reach > double(closest.m_variable)) break;
    if (rayMeetsProxy(cells, proxy, closest.m_variable)) testBody(ray, proxy, param, closest);
  }
}

// Front to back through the hierarchy: of two children the nearer is entered first, and a
// node left for later is dropped when the closest hit has come before its entry.
void descendBvh(const PfxRayInput& ray, const RayInCells& cells, const PfxRayCastParam& param,
                PfxRayOutput& closest) {
  const PfxRayBvhNode* nodes = param.bvhNodes;
  // Median splits keep the depth within log2(2^31) + 1 = 32 levels, one waiting node each.
  PfxUInt32 stackNode[64];
  double stackEntry[64];
  int top = 0;
  double entry;
  if (!rayMeetsBox(cells, nodes[0].m_min, nodes[0].m_max, closest.m_variable, entry)) return;
  PfxUInt32 index = 0;
  for (;;) {
    const PfxRayBvhNode& node = nodes[index];
    if (node.m_link & PFX_RAY_BVH_LEAF) {
      testBody(ray, param.bvhProxies[node.m_link & ~PFX_RAY_BVH_LEAF], param, closest);
    } else {
      const PfxUInt32 first = index + 1;
      const PfxUInt32 second = node.m_link;
      double entryFirst, entrySecond;
      const bool meetsFirst = rayMeetsBox(cells, nodes[first].m_min, nodes[first].m_max,
                                          closest.m_variable, entryFirst);
      const bool meetsSecond = rayMeetsBox(cells, nodes[second].m_min, nodes[second].m_max,
                                           closest.m_variable, entrySecond);
      if (meetsFirst && meetsSecond) {
        const bool firstNearer = entryFirst <= entrySecond;
        stackNode[top] = firstNearer ? second : first;
        stackEntry[top] = firstNearer ? entrySecond : entryFirst;
        ++top;
        index = firstNearer ? first : second;
        continue;
      }
      if (meetsFirst || meetsSecond) {
        index = meetsFirst ? first : second;
        continue;
      }
    }
    // Inclusive: a body entered exactly at the closest fraction may still win on its id.
    while (top > 0 && stackEntry[top - 1] > double(closest.m_variable)) --top;
    if (top == 0) return;
    index = stackNode[--top];
  }
}

// The search itself, for a ray and parameters already checked.
void castCheckedRay(const PfxRayInput& ray, PfxRayOutput& out, const PfxRayCastParam& param) {
  PfxRayOutput closest;
  closest.setMiss(ray);
  if (param.numProxies > 0) {
    const RayInCells cells = rayToCells(ray, param);
    if (param.bvhNodes) {
      descendBvh(ray, cells, param, closest);
    } else {
      walkSortedProxies(ray, cells, param, closest);
    }
  }
  out = closest;
}

// Spreads the low 16 bits of x to every third bit.
PfxUInt64 spreadBits3(PfxUInt64 x) {
  x &= 0xFFFF;
  x = (x | (x << 16)) & 0x0000FF0000FFull;
  x = (x | (x << 8)) & 0x00F00F00F00Full;
  x = (x | (x << 4)) & 0x0C30C30C30C3ull;
  x = (x | (x << 2)) & 0x249249249249ull;
  return x;
}

PfxUInt64 interleave3(PfxUInt64 x, PfxUInt64 y, PfxUInt64 z) {
  return spreadBits3(x) | (spreadBits3(y) << 1) | (spreadBits3(z) << 2);
}

// Bits of each direction cell in the key, below the 48 of the start point: rays from one
// point (a range sensor) then go round it in order.
constexpr int kDirectionBits = 5;

// The sort key of a ray: its start point's cell of the range, 16 bits per axis, clamped at
// the range's faces; then its direction in 2^5 cells per axis of [-1, 1].
PfxUInt64 mortonKey(const PfxRayInput& ray, const PfxRayCastParam& param) {
  const RayInCells cells = rayToCells(ray, param);
  PfxUInt64 start[3], direction[3];
  const double length = double(ray.m_direction.norm());
  for (int a = 0; a < 3; ++a) {
    start[a] = static_cast<PfxUInt64>(std::min(std::max(cells.start[a], 0.0), kRayQuantizedMax));
    const double unit = length > 0 ? double(ray.m_direction[a]) / length : 0.0;
    const double cell = (unit + 1) * 0.5 * ((1 << kDirectionBits) - 1) + 0.5;
    direction[a] = static_cast<PfxUInt64>(std::min(std::max(cell, 0.0), double((1 << kDirectionBits) - 1)));
  }
  return (interleave3(start[0], start[1], start[2]) << (3 * kDirectionBits)) |
         interleave3(direction[0], direction[1], direction[2]);
}

PfxUInt64 orderedWorkBytes(PfxUInt32 numRays) {
  // The records, then the sort's scratch of as many.
  return 2 * PfxUInt64(sizeof(PfxSortData16)) * numRays;
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfCastRays(PfxUInt32 numRays) {
  return static_cast<PfxUInt32>(orderedWorkBytes(std::min(numRays, PFX_CAST_RAYS_MAX_ORDERED)));
}

PfxInt32 pfxCastSingleRay(const PfxRayInput& in, PfxRayOutput& out, const PfxRayCastParam& param) {
  const PfxParamNames at{"pfxCastSingleRay", "PfxRayCastParam"};
  if (const PfxInt32 err = checkRayParam(at, param); err != PFX_OK) return err;
  if (const PfxInt32 err = checkRay(at, in, 0, param); err != PFX_OK) return err;
  castCheckedRay(in, out, param);
  return PFX_OK;
}

PfxInt32 pfxCastRays(const PfxRayInput* in, PfxRayOutput* out, PfxUInt32 numRays,
                     const PfxRayCastParam& param, PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxCastRays", "PfxRayCastParam"};
  if (const PfxInt32 err = checkRayParam(at, param); err != PFX_OK) return err;
  if (numRays == 0) return PFX_OK;
  if (!in || !out) {
    return pfxRejectParam(PFX_ERR_NULL_POINTER, "pfxCastRays: %s is null, but numRays is %u",
                          in ? "out" : "in", numRays);
  }
  const PfxUInt64 inBytes = PfxUInt64(sizeof(PfxRayInput)) * numRays;
  const PfxUInt64 outBytes = PfxUInt64(sizeof(PfxRayOutput)) * numRays;
  if (pfxRangesOverlap(in, inBytes, out, outBytes)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE, "pfxCastRays: in and out share bytes");
  }
  const bool ordered = param.workBuff != nullptr;
  if (ordered) {
    if (numRays > PFX_CAST_RAYS_MAX_ORDERED) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxCastRays: numRays is %u, more than PFX_CAST_RAYS_MAX_ORDERED "
                            "(%u) cast with PfxRayCastParam::workBuff",
                            numRays, PFX_CAST_RAYS_MAX_ORDERED);
    }
    const PfxUInt64 workBytes = orderedWorkBytes(numRays);
    if (const PfxInt32 err =
            pfxCheckBuffer(at, "workBuff", param.workBuff, param.workBytes, workBytes);
        err != PFX_OK) {
      return err;
    }
    if (pfxRangesOverlap(param.workBuff, workBytes, out, outBytes) ||
        pfxRangesOverlap(param.workBuff, workBytes, in, inBytes)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxCastRays: PfxRayCastParam::workBuff shares bytes with in or out");
    }
  }
  for (PfxUInt32 i = 0; i < numRays; ++i) {
    if (const PfxInt32 err = checkRay(at, in[i], i, param); err != PFX_OK) return err;
  }
  // Each ray writes only its own output, so tasks may take any of them.
  constexpr PfxUInt32 kRaysPerTask = 64;
  if (!ordered) {
    pfxParallelFor(taskManager, numRays, kRaysPerTask, [&](PfxUInt32 begin, PfxUInt32 end) {
      for (PfxUInt32 i = begin; i < end; ++i) castCheckedRay(in[i], out[i], param);
    });
    return PFX_OK;
  }
  PfxSortData16* order = static_cast<PfxSortData16*>(param.workBuff);
  pfxParallelFor(taskManager, numRays, 1024, [&](PfxUInt32 begin, PfxUInt32 end) {
    for (PfxUInt32 i = begin; i < end; ++i) {
      pfxSetKey(order[i], mortonKey(in[i], param));
      order[i].data[0] = i;
      order[i].data[1] = 0;
    }
  });
  const PfxUInt32 recordBytes = static_cast<PfxUInt32>(sizeof(PfxSortData16) * numRays);
  if (const PfxInt32 err =
          pfxParallelSort(order, numRays, order + numRays, recordBytes, taskManager);
      err != PFX_OK) {
    return err;
  }
  // In this order the rays and outputs are read and written all over their arrays; asking
  // for them a few rays ahead hides the wait for memory behind the casts in between.
  constexpr PfxUInt32 kLookAhead = 8;
  pfxParallelFor(taskManager, numRays, kRaysPerTask, [&](PfxUInt32 begin, PfxUInt32 end) {
    for (PfxUInt32 k = begin; k < end; ++k) {
#if defined(__GNUC__)
      if (k + kLookAhead < end) {
        const PfxUInt32 ahead = order[k + kLookAhead].data[0];
        __builtin_prefetch(&in[ahead]);
        __builtin_prefetch(&out[ahead], 1);
      }
#endif
      const PfxUInt32 i = order[k].data[0];
      castCheckedRay(in[i], out[i], param);
    }
  });
  return PFX_OK;
}

}  // namespace pfx
