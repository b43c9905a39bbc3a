#include "pfx/base_level/raycast/pfx_ray.h"

#include <limits>

namespace pfx {

void PfxRayInput::reset() {
  m_startPosition.setZero();
  m_direction.setZero();
  m_contactFilterSelf = 0xffffffffu;
  m_contactFilterTarget = 0xffffffffu;
}

void PfxRayOutput::setMiss(const PfxRayInput& ray) {
  m_contactPoint = ray.m_startPosition + ray.m_direction;
  m_contactNormal.setZero();
  m_variable = 1;
  m_objectId = PFX_RAY_NO_OBJECT;
  m_triangleIndex = PFX_RAY_NO_TRIANGLE;
  m_shapeId = 0;
  m_contactFlag = false;
  m_particleGroupId = PFX_RAY_NO_OBJECT;
  m_particleIndex = PFX_RAY_NO_OBJECT;
}

namespace {

// A ray is castable within float's range in both precisions. The shape tests work in
// double and multiply squared lengths together (a sphere's discriminant is the squared
// length times the squared radius); from float's range these stay far inside double's, but
// from double's own range they overflow and a long ray hits a large sphere at fraction 0.
constexpr PfxFloat kLargestValue = PfxFloat(std::numeric_limits<float>::max());
constexpr PfxFloat kSmallestLengthSq = PfxFloat(std::numeric_limits<float>::min());

// False for NaN as well.
bool withinFloatRange(const PfxVector3& v) { return (v.array().abs() <= kLargestValue).all(); }

}  // namespace

PfxInt32 pfxCheckRayInput(const PfxRayInput& ray) {
  if (!withinFloatRange(ray.m_startPosition) || !withinFloatRange(ray.m_direction)) {
    return PFX_ERR_INVALID_VALUE;
  }
  // The shape tests divide by the squared length; one that overflows or underflows would
  // turn a finite ray into NaN there.
  const PfxFloat lengthSq = ray.m_direction.squaredNorm();
  if (!(lengthSq <= kLargestValue)) return PFX_ERR_INVALID_VALUE;
  if (!(lengthSq >= kSmallestLengthSq)) return PFX_ERR_DEGENERATE;
  return PFX_OK;
}

}  // namespace pfx
