#include "pfx/low_level/raycast/pfx_cast_rays.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pfx/base_level/raycast/pfx_ray_shapes.h"
#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

constexpr double kQuantizedMax = 65535.0;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

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

PfxInt32 checkParam(const PfxRayCastParam& param) {
  if (!pfxIsFinite(param.rangeCenter) || !pfxIsFinite(param.rangeExtent) ||
      !(param.rangeExtent.minCoeff() > 0)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (param.numProxies > 0 && (!param.offsetRigidStates || !param.offsetCollidables ||
                               (param.bvhNodes && !param.bvhProxies))) {
    return PFX_ERR_NULL_POINTER;
  }
  return PFX_OK;
}

PfxInt32 checkRay(const PfxRayInput& ray, const PfxRayCastParam& param) {
  if (const PfxInt32 err = pfxCheckRayInput(ray); err != PFX_OK) return err;
  if (param.numProxies > 0 && !param.bvhNodes &&
      !proxiesFor(param, chooseWalk(ray.m_direction))) {
    return PFX_ERR_NULL_POINTER;
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

RayInCells toCells(const PfxRayInput& ray, const PfxRayCastParam& param) {
  RayInCells cells;
  for (int a = 0; a < 3; ++a) {
    const double extent = param.rangeExtent[a];
    const double cellsPerMetre = kQuantizedMax / (2.0 * extent);
    const double origin = double(param.rangeCenter[a]) - extent;
    cells.start[a] = (double(ray.m_startPosition[a]) - origin) * cellsPerMetre;
    cells.direction[a] = double(ray.m_direction[a]) * cellsPerMetre;
    cells.inverse[a] = cells.direction[a] != 0 ? 1.0 / cells.direction[a] : 0.0;
  }
  return cells;
}

// A 16-bit box in cells, one cell wider on each side against rounding; a side clamped to
// the edge of the range stands for everything beyond it.
double lowerCell(PfxUInt16 v) { return v == 0 ? -kInfinity : double(v) - 1.0; }
double upperCell(PfxUInt16 v) { return v == 0xffff ? kInfinity : double(v) + 1.0; }

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
    const RayInCells cells = toCells(ray, param);
    if (param.bvhNodes) {
      descendBvh(ray, cells, param, closest);
    } else {
      walkSortedProxies(ray, cells, param, closest);
    }
  }
  out = closest;
}

}  // namespace

PfxInt32 pfxCastSingleRay(const PfxRayInput& in, PfxRayOutput& out, const PfxRayCastParam& param) {
  if (const PfxInt32 err = checkParam(param); err != PFX_OK) return err;
  if (const PfxInt32 err = checkRay(in, param); err != PFX_OK) return err;
  castCheckedRay(in, out, param);
  return PFX_OK;
}

PfxInt32 pfxCastRays(const PfxRayInput* in, PfxRayOutput* out, PfxUInt32 numRays,
                     const PfxRayCastParam& param) {
  if (const PfxInt32 err = checkParam(param); err != PFX_OK) return err;
  if (numRays == 0) return PFX_OK;
  if (!in || !out) return PFX_ERR_NULL_POINTER;
  if (pfxRangesOverlap(in, PfxUInt64(sizeof(PfxRayInput)) * numRays, out,
                       PfxUInt64(sizeof(PfxRayOutput)) * numRays)) {
    return PFX_ERR_INVALID_VALUE;
  }
  for (PfxUInt32 i = 0; i < numRays; ++i) {
    if (const PfxInt32 err = checkRay(in[i], param); err != PFX_OK) return err;
  }
  for (PfxUInt32 i = 0; i < numRays; ++i) castCheckedRay(in[i], out[i], param);
  return PFX_OK;
}

}  // namespace pfx
