// Debug rendering (seed chapter 8): shapes and debug information handed to the
// application's drawing callbacks, so that the core depends on no rendering API. The
// picture of pfx_sim (cairo) and the node's rviz markers are both drawn through it.
//
// Every method takes the low-level arrays, as the seed's do (renderLocalAxis(states,
// numRigidBodies)): the states, collidables, joints, pairs and manifolds of a pipeline driven
// stage by stage, bodies numbered 0 .. numRigidBodies - 1. Each also takes a PfxWorld, and
// then draws the world's own arrays through the array form. An array form checks its
// arguments before it draws anything: a null array with a count (PFX_ERR_NULL_POINTER), an id
// beyond a count (PFX_ERR_OUT_OF_RANGE), a size or time step that is not finite and positive
// (PFX_ERR_INVALID_VALUE) draw nothing.
//
// Every method draws only through the callbacks that are set; one that would need a callback
// that is not set falls back to lines where it can (boxes, AABBs and arcs become line
// segments, shapes become their edges), and otherwise draws nothing. Colours are RGB in
// [0, 1]. Nothing here changes the world.
#pragma once

#include <functional>
#include <vector>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

// The seed's callback types; std::function so that a callback can carry its own context.
using PfxDebugRenderPointFunc = std::function<void(const PfxVector3& position, const PfxVector3& color)>;
using PfxDebugRenderLineFunc = std::function<void(const PfxVector3& position1, const PfxVector3& position2,
                                                  const PfxVector3& color)>;
// The arc of the circle of `radius` about `axis` through `position`, from angle startRad to
// endRad, where angle a is the point position + radius * (cos a * dir + sin a * axis x dir);
// `axis` and `dir` are unit vectors and perpendicular.
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
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_ISLAND = 1u << 0;       // the island's bounds and edges
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_EDGE = 1u << 1;         // the triangle's edges
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_FACET_AABB = 1u << 2;   // the triangle's bounds
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_NORMAL = 1u << 3;       // its normal, from the centroid
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_THICKNESS = 1u << 4;    // its prism below the face
constexpr PfxUInt32 PFX_DRENDER_MESH_FLG_ALL = 0x1f;

// The rigid body id the triangle callback receives for a particle group's triangles.
constexpr PfxUInt32 PFX_PARTICLE_DRAW_ID = 0xffffffffu;

class PfxDebugRender {
 public:
  void setDebugRenderPointFunc(PfxDebugRenderPointFunc f) { m_point = std::move(f); }
  void setDebugRenderLineFunc(PfxDebugRenderLineFunc f) { m_line = std::move(f); }
  void setDebugRenderArcFunc(PfxDebugRenderArcFunc f) { m_arc = std::move(f); }
  void setDebugRenderAabbFunc(PfxDebugRenderAabbFunc f) { m_aabb = std::move(f); }
  void setDebugRenderBoxFunc(PfxDebugRenderBoxFunc f) { m_box = std::move(f); }
  void setDebugRenderTriangleFunc(PfxDebugRenderTriangleFunc f) { m_triangle = std::move(f); }

  // Bodies whose visibility flag is off are skipped by every render method. Bodies start
  // visible; resetVisible makes the first numRigidBodies visible again, and setVisible
  // grows the flags as needed. The calls that take a world also hide its removed bodies'
  // slots (PfxWorld::removeRigidBody).
  void resetVisible(PfxUInt32 numRigidBodies);
  void setVisible(PfxUInt32 rigidBodyId, bool visible);
  bool isVisible(PfxUInt32 rigidBodyId) const;

  // Sizes of what is drawn. Each rejects a value that is not finite and positive (the force
  // scale may be 0) with PFX_ERR_INVALID_VALUE and keeps the old one.
  // Segments around a circle of spheres, capsules and cylinders (3..256; default 16).
  PfxInt32 setCircleSegments(PfxUInt32 segments);
  // Length of contact normals and of joint axes and limit arcs (m; default 0.1).
  PfxInt32 setDrawLength(PfxFloat length);
  // Length per newton of the line showing a contact's force (m/N; default 0.01; 0 draws
  // no force lines).
  PfxInt32 setForceScale(PfxFloat metresPerNewton);

  // The methods of seed chapter 8, plus renderShapes.
  // Every collision shape of the visible bodies: boxes, spheres, capsules and cylinders (along
  // X), convex meshes and large meshes, compounds at their offsets; as triangles through
  // the triangle callback, or, when none is set, as edges through the line callback.
  PfxInt32 renderShapes(const PfxRigidState* states, const PfxCollidable* collidables,
                        PfxUInt32 numRigidBodies);
  void renderShapes(const PfxWorld& world);
  // The world's bounds (PfxWorldParam::worldCenter, worldExtent, as given to the broad phase).
  PfxInt32 renderWorld(const PfxVector3& worldCenter, const PfxVector3& worldExtent);
  void renderWorld(const PfxWorld& world);
  // The world bounds of each visible body.
  PfxInt32 renderAabb(const PfxRigidState* states, const PfxCollidable* collidables,
                      PfxUInt32 numRigidBodies);
  void renderAabb(const PfxWorld& world);
  // Each visible body's frame: its X, Y and Z axes as red, green and blue lines of `scale`
  // metres.
  PfxInt32 renderLocalAxis(const PfxRigidState* states, PfxUInt32 numRigidBodies,
                           PfxFloat scale = PfxFloat(0.1));
  PfxInt32 renderLocalAxis(const PfxWorld& world, PfxFloat scale = PfxFloat(0.1));
  // Simulation islands (pfxGenerateIsland; for a world, those of its last step): the bounds
  // of the visible bodies that forces move in each group that contacts (pairs with at least
  // one point), joints and couplings connect; a fixed or keyframe body joins no group, as it
  // passes no motion on. One colour per island; a world's bodies added since its last step
  // are not drawn.
  PfxInt32 renderIsland(const PfxIsland& island, const PfxRigidState* states,
                        const PfxCollidable* collidables, PfxUInt32 numRigidBodies);
  void renderIsland(const PfxWorld& world);
  // Every contact point of the pairs (for a world, of its last step) between visible bodies:
  // a point on each surface (the manifold's points on A and on B), the normal from A's
  // point, and a line along the normal as long as the point's force (last impulse /
  // `timeStep`, the step it was solved over) times the force scale. Manifolds are those the
  // pairs name (pfxGetContactId), their body ids checked against numRigidBodies.
  PfxInt32 renderContact(const PfxConstraintPair* contactPairs, PfxUInt32 numContactPairs,
                         const PfxContactManifold* offsetContactManifolds,
                         const PfxRigidState* states, PfxUInt32 numRigidBodies,
                         PfxFloat timeStep);
  void renderContact(const PfxWorld& world);
  // Every joint with a visible body: both anchors and the line between them (the joint's
  // gap), the axes of its frame in body A, a line along each limited translation from its
  // lower to its upper limit, and an arc for each limited rotation (twist about X, swings
  // about Y and Z; a swing-twist joint's cone as two arcs), through the arc callback.
  PfxInt32 renderJoint(const PfxJoint* joints, PfxUInt32 numJoints, const PfxRigidState* states,
                       PfxUInt32 numRigidBodies);
  void renderJoint(const PfxWorld& world);
  // Large meshes of the visible bodies: the bounds of each island (box callback) and every
  // triangle's edges.
  PfxInt32 renderLargeMesh(const PfxRigidState* states, const PfxCollidable* collidables,
                           PfxUInt32 numRigidBodies);
  void renderLargeMesh(const PfxWorld& world);
  // Only the islands of large meshes whose bounds meet the frustum given by its six planes
  // (inward normal xyz, distance w: inside when dot(n, p) + w >= 0). Rejects NaN planes
  // (PFX_ERR_INVALID_VALUE) and a null array (PFX_ERR_NULL_POINTER) without drawing.
  PfxInt32 renderLargeMeshInFrustum(const PfxRigidState* states, const PfxCollidable* collidables,
                                    PfxUInt32 numRigidBodies, const PfxVector4 planes[6]);
  PfxInt32 renderLargeMeshInFrustum(const PfxWorld& world, const PfxVector4 planes[6]);
  // Marks triangle `triangleId` of island `islandId` of the large mesh(es) of a body for
  // renderLargeMeshByFlag; flags of the same triangle add up. Rejects unknown flags
  // (PFX_ERR_INVALID_FLAG) and no flags (PFX_ERR_INVALID_VALUE). Ids are checked when
  // drawing: marks naming no triangle draw nothing.
  PfxInt32 setLargeMeshFlag(PfxUInt32 rigidBodyId, PfxUInt32 islandId, PfxUInt32 triangleId, PfxUInt32 flags);
  void clearLargeMeshFlags();
  PfxInt32 renderLargeMeshByFlag(const PfxRigidState* states, const PfxCollidable* collidables,
                                 PfxUInt32 numRigidBodies);
  void renderLargeMeshByFlag(const PfxWorld& world);
  // Particles (seed sample 9): each particle as a point, each distance constraint as a line,
  // and the group's triangles filled through the triangle callback (rigid body id
  // PFX_PARTICLE_DRAW_ID), or as their edges when it is not set. A world draws every group,
  // awake groups in blue, sleeping ones in grey, and its pins as lines from the particle to
  // the anchor. Rejects null arrays with counts (PFX_ERR_NULL_POINTER) and indices beyond
  // numParticles (PFX_ERR_OUT_OF_RANGE) without drawing.
  PfxInt32 renderParticles(const PfxParticle* particles, PfxUInt32 numParticles,
                           const PfxParticleDistanceConstraint* distanceConstraints,
                           PfxUInt32 numDistanceConstraints, const PfxUInt32* triangleIndices,
                           PfxUInt32 numTriangles, const PfxVector3& color);
  void renderParticles(const PfxWorld& world);

 private:
  struct LargeMeshFlag {
    PfxUInt32 rigidBodyId, islandId, triangleId, flags;
  };
  void hideRemovedBodies(const PfxWorld& world);
  void drawLine(const PfxVector3& a, const PfxVector3& b, const PfxVector3& color) const;
  void drawBox(const PfxTransform3& transform, const PfxVector3& half, const PfxVector3& color) const;
  void drawAabb(const PfxVector3& center, const PfxVector3& half, const PfxVector3& color) const;
  void drawArc(const PfxVector3& position, const PfxVector3& axis, const PfxVector3& dir,
               PfxFloat radius, PfxFloat start, PfxFloat end, const PfxVector3& color) const;
  void drawShape(const PfxShape& shape, const PfxTransform3& transform, const PfxVector3& color,
                 PfxUInt32 rigidBodyId) const;
  void drawLargeMeshIslands(const PfxRigidState* states, const PfxCollidable* collidables,
                            PfxUInt32 numRigidBodies, const PfxVector4* planes) const;
  void drawContacts(const PfxContactManifold& manifold, const PfxRigidState* states,
                    PfxFloat timeStep) const;

  PfxDebugRenderPointFunc m_point;
  PfxDebugRenderLineFunc m_line;
  PfxDebugRenderArcFunc m_arc;
  PfxDebugRenderAabbFunc m_aabb;
  PfxDebugRenderBoxFunc m_box;
  PfxDebugRenderTriangleFunc m_triangle;
  std::vector<PfxUInt8> m_visible;
  std::vector<LargeMeshFlag> m_largeMeshFlags;
  PfxUInt32 m_circleSegments = 16;
  PfxFloat m_drawLength = PfxFloat(0.1);
  PfxFloat m_forceScale = PfxFloat(0.01);
};

}  // namespace pfx
