#include "pfx/high_level/pfx_contact_point_pool.h"

#include <algorithm>

namespace pfx {

bool PfxContactPointPool::holds(const PfxContactManifold& manifold) const {
  const PfxContactPoint* points = manifold.getContactPoints();
  return manifold.getCapacity() == m_pointsPerBlock && points >= m_points.data() &&
         points < m_points.data() + m_points.size();
}

void PfxContactPointPool::reserve(PfxUInt32 numBlocks, PfxContactManifold* manifolds,
                                  PfxUInt32 numManifolds) {
  const std::size_t free = m_freeBlocks.size();
  const std::size_t needed = m_numBlocks + (numBlocks > free ? numBlocks - free : 0);
  const std::size_t capacity = m_points.size() / m_pointsPerBlock;
  if (needed <= capacity) return;
  const std::size_t newCapacity = std::max(needed + needed / 8, capacity * 3 / 2);
  std::vector<PfxContactPoint> points(newCapacity * m_pointsPerBlock);
  for (PfxUInt32 i = 0; i < numManifolds; ++i) {
    PfxContactManifold& manifold = manifolds[i];
    if (!holds(manifold)) continue;
    manifold.moveContactPoints(points.data() + (manifold.getContactPoints() - m_points.data()),
                               m_pointsPerBlock);
  }
  m_points.swap(points);
  m_freeBlocks.reserve(newCapacity);
}

PfxContactPoint* PfxContactPointPool::take() {
  PfxUInt32 block = m_numBlocks;
  if (m_freeBlocks.empty()) {
    ++m_numBlocks;
  } else {
    block = m_freeBlocks.back();
    m_freeBlocks.pop_back();
  }
  return m_points.data() + std::size_t(block) * m_pointsPerBlock;
}

void PfxContactPointPool::give(const PfxContactPoint* block) {
  m_freeBlocks.push_back(static_cast<PfxUInt32>((block - m_points.data()) / m_pointsPerBlock));
}

void PfxContactPointPool::clear() {
  m_points.clear();
  m_numBlocks = 0;
  m_freeBlocks.clear();
}

}  // namespace pfx
