// The collision shapes of one rigid body (seed chapter 3, "Create Rigid Body Shapes").
// One shape is copied in; a compound of up to 64 shapes refers to an array of shapes that
// the application owns, through a list of indices into it.
#pragma once

#include "pfx/base_level/collision/pfx_shape.h"

namespace pfx {

class PfxCollidable {
 public:
  // Holds a single shape, copied in by addShape().
  void reset();
  // Holds up to `maxShapes` shapes in shapes[shapeIds[0..maxShapes-1]]; addShape() writes
  // them there. Rejects null arrays and more than PFX_MAX_SHAPES_PER_COLLIDABLE shapes.
  PfxInt32 reset(PfxShape* shapes, const PfxUInt16* shapeIds, PfxUInt32 maxShapes);

  // Rejects an invalid shape and a shape beyond capacity; nothing is added then.
  PfxInt32 addShape(const PfxShape& shape);
  // Computes the local bounding box. Fails on an empty collidable.
  PfxInt32 finish();

  PfxUInt32 getNumShapes() const { return m_numShapes; }
  const PfxShape& getShape(PfxUInt32 i) const {
    return m_shapeIds ? m_shapeBase[m_shapeIds[i]] : m_shape;
  }
  // Compounds refer to the application's array; after that array moves, point here again.
  void relocateShapes(PfxShape* shapes) { if (m_shapeIds) m_shapeBase = shapes; }

  // Local bounds of all shapes, computed by finish().
  const PfxVector3& getCenter() const { return m_center; }
  const PfxVector3& getHalf() const { return m_half; }

  // World bounds of the collidable for a body at `transform`.
  void getWorldAabb(const PfxTransform3& transform, PfxVector3& center, PfxVector3& half) const;

 private:
  PfxShape m_shape;
  PfxVector3 m_center;
  PfxVector3 m_half;
  PfxShape* m_shapeBase;
  const PfxUInt16* m_shapeIds;
  PfxUInt16 m_numShapes;
  PfxUInt16 m_maxShapes;
};

}  // namespace pfx
