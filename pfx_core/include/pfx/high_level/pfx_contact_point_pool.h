// The room in which PfxWorld keeps its manifolds' contact points: blocks of one size (one
// point, or four), taken and given back through a free list, so that a manifold holds only
// the room its points need (a sphere on the ground one point, 188 bytes, not four). The
// owner decides how much room to keep; taking and giving back never allocate.
#pragma once

#include <vector>

#include "pfx/base_level/collision/pfx_contact_manifold.h"

namespace pfx {

class PfxContactPointPool {
 public:
  explicit PfxContactPointPool(PfxUInt32 pointsPerBlock) : m_pointsPerBlock(pointsPerBlock) {}

  PfxUInt32 getPointsPerBlock() const { return m_pointsPerBlock; }
  // Blocks that take() can hand out in all, those in use included.
  PfxUInt32 getCapacity() const {
    return static_cast<PfxUInt32>(m_points.size() / m_pointsPerBlock);
  }
  // Blocks handed out and not given back.
  PfxUInt32 getNumBlocksInUse() const {
    return m_numBlocks - static_cast<PfxUInt32>(m_freeBlocks.size());
  }

  // Room for `numBlocks` blocks in all (never less than there is). When the blocks move,
  // the manifolds among `manifolds` that hold one are pointed at its new place.
  void reserve(PfxUInt32 numBlocks, PfxContactManifold* manifolds, PfxUInt32 numManifolds);
  // A block; there must be room for one more in use (reserve).
  PfxContactPoint* take();
  // Takes back a block that take() gave.
  void give(const PfxContactPoint* block);
  bool holds(const PfxContactManifold& manifold) const;
  void clear();

 private:
  PfxUInt32 m_pointsPerBlock;
  std::vector<PfxContactPoint> m_points;
  PfxUInt32 m_numBlocks = 0;  // blocks handed out so far, in use or free
  std::vector<PfxUInt32> m_freeBlocks;
};

}  // namespace pfx
