#include "pfx/base_level/collision/pfx_collidable.h"

#include <cstring>

namespace pfx {

void PfxCollidable::reset() {
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  m_shape.reset();
  m_center.setZero();
  m_half.setZero();
  m_maxShapes = 1;
}

PfxInt32 PfxCollidable::reset(PfxShape* shapes, const PfxUInt16* shapeIds, PfxUInt32 maxShapes) {
  if (!shapes || !shapeIds) return PFX_ERR_NULL_POINTER;
  if (maxShapes == 0 || maxShapes > PFX_MAX_SHAPES_PER_COLLIDABLE) return PFX_ERR_OUT_OF_RANGE;
  reset();
  m_shapeBase = shapes;
  m_shapeIds = shapeIds;
  m_maxShapes = static_cast<PfxUInt16>(maxShapes);
  return PFX_OK;
}

PfxInt32 PfxCollidable::addShape(const PfxShape& shape) {
  if (m_numShapes >= m_maxShapes) return PFX_ERR_OUT_OF_RANGE;
  const PfxInt32 err = shape.validate();
  if (err != PFX_OK) return err;
  if (m_shapeIds) {
    m_shapeBase[m_shapeIds[m_numShapes]] = shape;
  } else {
    m_shape = shape;
  }
  ++m_numShapes;
  return PFX_OK;
}

PfxInt32 PfxCollidable::finish() {
  if (m_numShapes == 0) return PFX_ERR_OUT_OF_RANGE;
  PfxVector3 center, half;
  getShape(0).getAabb(center, half);
  PfxVector3 lo = center - half;
  PfxVector3 hi = center + half;
  for (PfxUInt32 i = 1; i < m_numShapes; ++i) {
    getShape(i).getAabb(center, half);
    lo = lo.cwiseMin(center - half);
    hi = hi.cwiseMax(center + half);
  }
  m_center = (lo + hi) * PfxFloat(0.5);
  m_half = (hi - lo) * PfxFloat(0.5);
  return PFX_OK;
}

void PfxCollidable::getWorldAabb(const PfxTransform3& transform, PfxVector3& center,
                                 PfxVector3& half) const {
  center = transform * m_center;
  half = transform.linear().cwiseAbs() * m_half;
}

}  // namespace pfx
