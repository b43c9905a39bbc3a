// Debug rendering (seed chapter 8): the world's shapes and debug information handed to the
// application's drawing callbacks, so that the core depends on no rendering API. The
// picture of pfx_sim (cairo) and the node's rviz markers are both drawn through it.
#pragma once

#include <functional>
#include <vector>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

// The seed's callback types; std::function so that a callback can carry its own context.
using PfxDebugRenderPointFunc = std::function<void(const PfxVector3& position, const PfxVector3& color)>;
using PfxDebugRenderLineFunc = std::function<void(const PfxVector3& position1, const PfxVector3& position2,
                                                  const PfxVector3& color)>;
using PfxDebugRenderArcFunc =
    std::function<void(const PfxVector3& position, const PfxVector3& axis, const PfxVector3& dir,
                       PfxFloat radius, PfxFloat startRad, PfxFloat endRad, const PfxVector3& color)>;
using PfxDebugRenderAabbFunc = std::function<void(const PfxVector3& center, const PfxVector3& halfExtent,
                                                  const PfxVector3& color)>;
using PfxDebugRenderBoxFunc = std::function<void(const PfxTransform3& transform, const PfxVector3& halfExtent,
                                                 const PfxVector3& color)>;
// Beyond the seed: filled triangles (counter-clockwise seen from outside), so that shapes can
// be drawn solid. The body id says which body a triangle belongs to.
using PfxDebugRenderTriangleFunc =
    std::function<void(const PfxVector3& p0, const PfxVector3& p1, const PfxVector3& p2,
                       const PfxVector3& color, PfxUInt32 rigidBodyId)>;

// Flags of renderLargeMeshByFlag (seed's SCE_PFX_DRENDER_MESH_FLG_*).
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_ISLAND = 1u << 0;
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_EDGE = 1u << 1;
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_FACET_AABB = 1u << 2;
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_NORMAL = 1u << 3;
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_THICKNESS = 1u << 4;
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_ALL = 0x1f;

class PfxDebugRender {
 public:
  void setDebugRenderPointFunc(PfxDebugRenderPointFunc f) { m_point = std::move(f); }
  void setDebugRenderLineFunc(PfxDebugRenderLineFunc f) { m_line = std::move(f); }
  void setDebugRenderArcFunc(PfxDebugRenderArcFunc f) { m_arc = std::move(f); }
  void setDebugRenderAabbFunc(PfxDebugRenderAabbFunc f) { m_aabb = std::move(f); }
  void setDebugRenderBoxFunc(PfxDebugRenderBoxFunc f) { m_box = std::move(f); }
  void setDebugRenderTriangleFunc(PfxDebugRenderTriangleFunc f) { m_triangle = std::move(f); }

  // Bodies whose visibility flag is off are skipped by every render method.
  void resetVisible(PfxUInt32 numRigidBodies);
  void setVisible(PfxUInt32 rigidBodyId, bool visible);
  bool isVisible(PfxUInt32 rigidBodyId) const;

  // The methods of seed chapter 8, plus renderShapes (every collision shape, as triangles
  // through the triangle callback, or as edges through the line callback without one).
  void renderShapes(const PfxWorld& world);
  void renderWorld(const PfxWorld& world);
  void renderAabb(const PfxWorld& world);
  void renderLocalAxis(const PfxWorld& world, PfxFloat scale = PfxFloat(0.1));
  void renderIsland(const PfxWorld& world);
  void renderContact(const PfxWorld& world);
  void renderJoint(const PfxWorld& world);
  void renderLargeMesh(const PfxWorld& world);
  // Only the islands of large meshes whose bounds meet the frustum given by its six planes
  // (inward normal xyz, distance w: inside when dot(n, p) + w >= 0).
  void renderLargeMeshInFrustum(const PfxWorld& world, const PfxVector4 planes[6]);
  void setLargeMeshFlag(PfxUInt32 rigidBodyId, PfxUInt32 islandId, PfxUInt32 triangleId, PfxUInt32 flags);
  void clearLargeMeshFlags();
  void renderLargeMeshByFlag(const PfxWorld& world);

 private:
  PfxDebugRenderPointFunc m_point;
  PfxDebugRenderLineFunc m_line;
  PfxDebugRenderArcFunc m_arc;
  PfxDebugRenderAabbFunc m_aabb;
  PfxDebugRenderBoxFunc m_box;
  PfxDebugRenderTriangleFunc m_triangle;
  std::vector<PfxUInt8> m_visible;
  struct LargeMeshFlag {
    PfxUInt32 rigidBodyId, islandId, triangleId, flags;
  };
  std::vector<LargeMeshFlag> m_largeMeshFlags;
};

}  // namespace pfx
