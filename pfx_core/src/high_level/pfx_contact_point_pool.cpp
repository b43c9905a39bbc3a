#include "pfx/high_level/pfx_contact_point_pool.h"

namespace pfx {

bool PfxContactPointPool::holds(const PfxContactManifold& manifold) const {
  const PfxContactPoint* points = manifold.getContactPoints();
  return manifold.getCapacity() == m_pointsPerBlock && points >= m_points.data() &&
         points < m_points.data() + m_points.size();
}

void PfxContactPointPool::reserve(PfxUInt32 numBlocks, PfxContactManifold* manifolds,
                                  PfxUInt32 numManifolds) {
  if (numBlocks <= getCapacity()) return;
  std::vector<PfxContactPoint> points(std::size_t(numBlocks) * m_pointsPerBlock);
  for (PfxUInt32 i = 0; i < numManifolds; ++i) {
    PfxContactManifold& manifold = manifolds[i];
    if (!holds(manifold)) continue;
    manifold.moveContactPoints(points.data() + (manifold.getContactPoints() - m_points.data()),
                               m_pointsPerBlock);
  }
  m_points.swap(points);
  // Every block can be given back without the free list growing.
  m_freeBlocks.reserve(numBlocks);
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
