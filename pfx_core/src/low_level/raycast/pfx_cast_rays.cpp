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
  if (param.numProxies > 0 && (!param.offsetRigidStates || !param.offsetCollidables)) {
    return PFX_ERR_NULL_POINTER;
  }
  return PFX_OK;
}

PfxInt32 checkRay(const PfxRayInput& ray, const PfxRayCastParam& param) {
  if (const PfxInt32 err = pfxCheckRayInput(ray); err != PFX_OK) return err;
  if (param.numProxies > 0 && !proxiesFor(param, chooseWalk(ray.m_direction))) {
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

// A proxy's box in cells, one cell wider on each side against rounding; a side clamped to
// the edge of the range stands for everything beyond it.
double lowerCell(const PfxBroadphaseProxy& proxy, int axis) {
  const PfxUInt16 v = pfxGetXMin(proxy, axis);
  return v == 0 ? -kInfinity : double(v) - 1.0;
}

double upperCell(const PfxBroadphaseProxy& proxy, int axis) {
  const PfxUInt16 v = pfxGetXMax(proxy, axis);
  return v == 0xffff ? kInfinity : double(v) + 1.0;
}

// Whether the ray passes through the proxy's box at a fraction in [0, maxFraction].
bool rayMeetsProxy(const RayInCells& ray, const PfxBroadphaseProxy& proxy, double maxFraction) {
  double tEnter = 0;
  double tExit = maxFraction;
  for (int a = 0; a < 3; ++a) {
    const double lo = lowerCell(proxy, a);
    const double hi = upperCell(proxy, a);
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
  return true;
}

// The walk itself, for a ray and parameters already checked.
void castCheckedRay(const PfxRayInput& ray, PfxRayOutput& out, const PfxRayCastParam& param) {
  PfxRayOutput closest;
  closest.setMiss(ray);
  if (param.numProxies > 0) {
    const WalkDirection walk = chooseWalk(ray.m_direction);
    const PfxBroadphaseProxy* proxies = proxiesFor(param, walk);
    const RayInCells cells = toCells(ray, param);
    const int axis = walk.axis;
    for (PfxUInt32 i = 0; i < param.numProxies; ++i) {
      const PfxBroadphaseProxy& proxy = proxies[i];
      // Where the ray reaches the proxy's near side along the walk axis; the arrays are
      // sorted by that side, so every later proxy starts at least as far along.
      const double nearSide = walk.forward ? lowerCell(proxy, axis) : upperCell(proxy, axis);
      const double reach = (nearSide - cells.start[axis]) * cells.inverse[axis];
      if (reach > double(closest.m_variable)) break;
      if (!rayMeetsProxy(cells, proxy, closest.m_variable)) continue;
      if (!pfxContactFiltersMatch(ray.m_contactFilterSelf, ray.m_contactFilterTarget,
                                  pfxGetSelf(proxy), pfxGetTarget(proxy))) {
        continue;
      }
      const PfxUInt32 id = pfxGetObjectId(proxy);
      PfxRayOutput hit;
      if (!pfxRayCastCollidable(ray, param.offsetCollidables[id],
                                param.offsetRigidStates[id].getTransform(), closest.m_variable,
                                hit)) {
        continue;
      }
      const bool closer = !closest.m_contactFlag || hit.m_variable < closest.m_variable ||
                          (hit.m_variable == closest.m_variable && id < closest.m_objectId);
      if (!closer) continue;
      closest = hit;
      closest.m_objectId = id;
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
