#include "base_level/collision/contact/pfx_contact_sink.h"

namespace pfx {

void PfxContactSink::add(const PfxVector3& normal, const PfxVector3& pointA,
                         const PfxVector3& pointB, PfxFloat distance) {
  // The negated comparison also drops a NaN distance.
  if (!(distance < m_threshold) || m_capacity == 0) return;
  if (!pfxIsFinite(normal) || !pfxIsFinite(pointA) || !pfxIsFinite(pointB)) return;

  PfxUInt32 slot = m_count;
  if (m_count == m_capacity) {
    slot = 0;
    for (PfxUInt32 i = 1; i < m_count; ++i) {
      if (m_out[i].m_distance > m_out[slot].m_distance) slot = i;
    }
    if (!(distance < m_out[slot].m_distance)) return;
  } else {
    ++m_count;
  }

  PfxContactCandidate& c = m_out[slot];
  if (m_swapped) {
    c.m_normal = -normal;
    c.m_pointA = pointB;
    c.m_pointB = pointA;
  } else {
    c.m_normal = normal;
    c.m_pointA = pointA;
    c.m_pointB = pointB;
  }
  c.m_distance = distance;
  c.m_shapeIdA = m_shapeIdA;
  c.m_shapeIdB = m_shapeIdB;
  c.m_triangleIndex = m_triangleIndex;
  for (int k = 0; k < 3; ++k) c.m_barycentric[k] = m_barycentric[k];
}

}  // namespace pfx
