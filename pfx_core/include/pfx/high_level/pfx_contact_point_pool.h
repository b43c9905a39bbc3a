// The room in which PfxWorld keeps its manifolds' contact points: blocks of one size (one
// point, or four), taken and given back through a free list, so that a manifold holds only
// the room its points need (a sphere on the ground one point, 188 bytes, not four).
#pragma once

#include <vector>

#include "pfx/base_level/collision/pfx_contact_manifold.h"

namespace pfx {

class PfxContactPointPool {
 public:
  explicit PfxContactPointPool(PfxUInt32 pointsPerBlock) : m_pointsPerBlock(pointsPerBlock) {}

  PfxUInt32 getPointsPerBlock() const { return m_pointsPerBlock; }

  // Room to take `numBlocks` more blocks without allocating: an eighth more than needed,
  // or half as many again as there are, whichever is more. When the blocks move, the
  // manifolds among `manifolds` that hold one are pointed at its new place.
  void reserve(PfxUInt32 numBlocks, PfxContactManifold* manifolds, PfxUInt32 numManifolds);
  // A block; reserve() made room for it.
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
