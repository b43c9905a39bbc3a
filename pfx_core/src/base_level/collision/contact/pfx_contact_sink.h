// Collects the contact candidates of the pair routines. Each routine speaks of its own
// first shape as A; when the dispatcher swapped the shapes to reach a routine, the sink
// turns normals and points back into the caller's order.
#pragma once

#include "pfx/base_level/collision/pfx_contact_manifold.h"

namespace pfx {

class PfxContactSink {
 public:
  PfxContactSink(PfxContactCandidate* out, PfxUInt32 capacity, PfxFloat threshold)
      : m_out(out), m_capacity(capacity), m_threshold(threshold) {}

  PfxFloat getThreshold() const { return m_threshold; }
  PfxUInt32 getCount() const { return m_count; }

  void setSwapped(bool swapped) { m_swapped = swapped; }
  void setShapeIds(PfxUInt8 shapeIdA, PfxUInt8 shapeIdB) {
    m_shapeIdA = shapeIdA;
    m_shapeIdB = shapeIdB;
  }

  // Contacts added from now on lie on this large-mesh triangle at these corner weights
  // (they belong to the mesh side whichever order the shapes are in).
  void setTriangle(PfxUInt32 triangleIndex, const PfxFloat barycentric[3]) {
    m_triangleIndex = triangleIndex;
    for (int k = 0; k < 3; ++k) m_barycentric[k] = barycentric[k];
  }
  void clearTriangle() { m_triangleIndex = PFX_CONTACT_NO_TRIANGLE; }

  // Records a contact given in the routine's order (normal from its A to its B), if it
  // lies within the threshold. Once full, a new contact replaces the shallowest one when
  // it is deeper, so that the deepest contacts survive.
  void add(const PfxVector3& normal, const PfxVector3& pointA, const PfxVector3& pointB,
           PfxFloat distance);

 private:
  PfxContactCandidate* m_out;
  PfxUInt32 m_capacity;
  PfxUInt32 m_count = 0;
  PfxFloat m_threshold;
  bool m_swapped = false;
  PfxUInt8 m_shapeIdA = 0;
  PfxUInt8 m_shapeIdB = 0;
  PfxUInt32 m_triangleIndex = PFX_CONTACT_NO_TRIANGLE;
  PfxFloat m_barycentric[3] = {0, 0, 0};
};

}  // namespace pfx
