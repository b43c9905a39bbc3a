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
}

PfxInt32 pfxCheckRayInput(const PfxRayInput& ray) {
  if (!pfxIsFinite(ray.m_startPosition) || !pfxIsFinite(ray.m_direction)) {
    return PFX_ERR_INVALID_VALUE;
  }
  // The shape tests divide by the squared length; one that overflows or underflows would
  // turn a finite ray into NaN there.
  const PfxFloat lengthSq = ray.m_direction.squaredNorm();
  if (!pfxIsFinite(lengthSq)) return PFX_ERR_INVALID_VALUE;
  if (!(lengthSq >= std::numeric_limits<PfxFloat>::min())) return PFX_ERR_DEGENERATE;
  return PFX_OK;
}

}  // namespace pfx
