#include "pfx/high_level/pfx_debug_render.h"

#include <algorithm>
#include <cmath>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"

namespace pfx {

namespace {

const PfxVector3 kRed(1, 0, 0);
const PfxVector3 kGreen(0, 1, 0);
const PfxVector3 kBlue(0, 0, 1);
const PfxVector3 kYellow(1, 1, 0);
const PfxVector3 kCyan(0, 1, 1);
const PfxVector3 kMagenta(1, 0, 1);
const PfxVector3 kWhite(1, 1, 1);
const PfxVector3 kGrey(PfxFloat(0.55), PfxFloat(0.55), PfxFloat(0.55));
const PfxVector3 kOrange(1, PfxFloat(0.5), 0);

// A bright colour of its own for each index: hues a golden angle apart never repeat closely.
PfxVector3 indexColor(PfxUInt32 index) {
  const PfxFloat hue = std::fmod(PfxFloat(index) * PfxFloat(0.618033988749895), PfxFloat(1)) * 6;
  const PfxFloat f = hue - std::floor(hue);
  const PfxFloat low = PfxFloat(0.3), high = PfxFloat(0.95);
  const PfxFloat up = low + (high - low) * f, down = high - (high - low) * f;
  switch (static_cast<int>(hue)) {
    case 0: return PfxVector3(high, up, low);
    case 1: return PfxVector3(down, high, low);
    case 2: return PfxVector3(low, high, up);
    case 3: return PfxVector3(low, down, high);
    case 4: return PfxVector3(up, low, high);
    default: return PfxVector3(high, low, down);
  }
}

// Fixed bodies grey, keyframe bodies blue-grey, bodies that forces move a colour each;
// sleeping bodies darker.
PfxVector3 bodyColor(const PfxRigidState& state) {
  switch (state.getMotionType()) {
    case kPfxMotionTypeFixed: return kGrey;
    case kPfxMotionTypeKeyframe: return PfxVector3(PfxFloat(0.45), PfxFloat(0.55), PfxFloat(0.75));
    case kPfxMotionTypeTrigger: return PfxVector3(PfxFloat(0.9), PfxFloat(0.9), PfxFloat(0.6));
    default: break;
  }
  const PfxVector3 color = indexColor(state.getRigidBodyId());
  return state.isAsleep() ? PfxVector3(color * PfxFloat(0.5)) : color;
}

// Emits a surface as triangles through `triangle`, or as its edges through `line`.
struct ShapeSink {
  const PfxDebugRenderTriangleFunc& triangle;
  const PfxDebugRenderLineFunc& line;
  const PfxTransform3& transform;
  const PfxVector3& color;
  PfxUInt32 rigidBodyId;

  bool solid() const { return static_cast<bool>(triangle); }
  void addTriangle(const PfxVector3& a, const PfxVector3& b, const PfxVector3& c) const {
    triangle(transform * a, transform * b, transform * c, color, rigidBodyId);
  }
  void addEdge(const PfxVector3& a, const PfxVector3& b) const {
    line(transform * a, transform * b, color);
  }
};

void tessellateBox(const PfxBox& box, const ShapeSink& sink) {
  const PfxVector3& h = box.m_half;
  if (sink.solid()) {
    // Each face is spanned by the next two axes, u x v pointing out of the +axis face.
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (const PfxFloat sign : {PfxFloat(1), PfxFloat(-1)}) {
        PfxVector3 corners[4];
        const PfxFloat us[4] = {-1, 1, 1, -1}, vs[4] = {-1, -1, 1, 1};
        for (int k = 0; k < 4; ++k) {
          corners[k][axis] = sign * h[axis];
          corners[k][u] = us[k] * h[u];
          corners[k][v] = vs[k] * h[v];
        }
        if (sign > 0) {
          sink.addTriangle(corners[0], corners[1], corners[2]);
          sink.addTriangle(corners[0], corners[2], corners[3]);
        } else {
          sink.addTriangle(corners[0], corners[2], corners[1]);
          sink.addTriangle(corners[0], corners[3], corners[2]);
        }
      }
    }
    return;
  }
  auto corner = [&](int bits) {
    return PfxVector3((bits & 1) ? h[0] : -h[0], (bits & 2) ? h[1] : -h[1], (bits & 4) ? h[2] : -h[2]);
  };
  // Corners that differ in exactly one bit share an edge.
  for (int i = 0; i < 8; ++i) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      if ((i & bit) == 0) sink.addEdge(corner(i), corner(i | bit));
    }
  }
}

// A surface of revolution about X through the profile points (x, radius) in order, turned
// through `segments` steps. Points of radius 0 are poles: the band next to one is a fan.
void tessellateRevolution(const PfxFloat (*profile)[2], PfxUInt32 numProfile, PfxUInt32 segments,
                          const ShapeSink& sink) {
  auto at = [&](PfxUInt32 i, PfxUInt32 j) {
    const PfxFloat angle = 2 * PFX_PI * PfxFloat(j % segments) / PfxFloat(segments);
    return PfxVector3(profile[i][0], profile[i][1] * std::cos(angle), profile[i][1] * std::sin(angle));
  };
  for (PfxUInt32 i = 0; i + 1 < numProfile; ++i) {
    for (PfxUInt32 j = 0; j < segments; ++j) {
      const PfxVector3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (sink.solid()) {
        // Along the profile (+X) then around (+angle) is clockwise seen from outside.
        if (profile[i][1] > 0) sink.addTriangle(a, d, c);
        if (profile[i + 1][1] > 0) sink.addTriangle(a, c, b);
      } else {
        sink.addEdge(a, b);
        if (profile[i][1] > 0) sink.addEdge(a, d);
      }
    }
  }
  if (!sink.solid() && profile[numProfile - 1][1] > 0) {
    for (PfxUInt32 j = 0; j < segments; ++j) {
      sink.addEdge(at(numProfile - 1, j), at(numProfile - 1, j + 1));
    }
  }
}

// Profile of a sphere-swept segment of half length `halfLength` (0 for a sphere): a pole,
// half a circle's quarter-steps to the equator, the same on the other side.
void tessellateRoundedSegment(PfxFloat halfLength, PfxFloat radius, PfxUInt32 segments,
                              const ShapeSink& sink) {
  const PfxUInt32 quarter = std::max<PfxUInt32>(2, segments / 4);
  PfxFloat profile[2 * (256 / 4) + 2][2];
  PfxUInt32 n = 0;
  for (PfxUInt32 k = 0; k <= quarter; ++k) {
    const PfxFloat angle = PFX_PI / 2 * PfxFloat(k) / PfxFloat(quarter);
    profile[n][0] = -halfLength - radius * std::cos(angle);
    profile[n++][1] = k == 0 ? 0 : radius * std::sin(angle);
  }
  for (PfxUInt32 k = halfLength > 0 ? 0 : 1; k <= quarter; ++k) {
    const PfxFloat angle = PFX_PI / 2 * PfxFloat(k) / PfxFloat(quarter);
    profile[n][0] = halfLength + radius * std::sin(angle);
    profile[n++][1] = k == quarter ? 0 : radius * std::cos(angle);
  }
  tessellateRevolution(profile, n, segments, sink);
}

void tessellateCylinder(const PfxCylinder& cylinder, PfxUInt32 segments, const ShapeSink& sink) {
  const PfxFloat h = cylinder.m_halfLen, r = cylinder.m_radius;
  const PfxFloat profile[4][2] = {{-h, 0}, {-h, r}, {h, r}, {h, 0}};
  tessellateRevolution(profile, 4, segments, sink);
}

void tessellateConvexMesh(const PfxConvexMesh& mesh, const ShapeSink& sink) {
  if (sink.solid()) {
    for (PfxUInt32 f = 0; f < mesh.m_numFacets; ++f) {
      const PfxUInt8* ids = mesh.m_facetVertIds[f];
      sink.addTriangle(mesh.m_verts[ids[0]], mesh.m_verts[ids[1]], mesh.m_verts[ids[2]]);
    }
    return;
  }
  for (PfxUInt32 e = 0; e < mesh.m_numEdges; ++e) {
    sink.addEdge(mesh.m_verts[mesh.m_edgeVertIds[e][0]], mesh.m_verts[mesh.m_edgeVertIds[e][1]]);
  }
}

void tessellateLargeMesh(const PfxLargeTriMesh& mesh, const ShapeSink& sink) {
  for (PfxUInt32 t = 0; t < mesh.m_numTriangles; ++t) {
    PfxVector3 v[3];
    pfxGetLargeTriMeshTriangle(mesh, t, v[0], v[1], v[2]);
    if (sink.solid()) {
      sink.addTriangle(v[0], v[1], v[2]);
    } else {
      for (int k = 0; k < 3; ++k) sink.addEdge(v[k], v[(k + 1) % 3]);
    }
  }
}

// Local bounds of an island from its triangles.
void islandBounds(const PfxLargeTriMesh& mesh, const PfxLargeMeshIsland& island,
                  PfxVector3& lower, PfxVector3& upper) {
  lower = PfxVector3::Constant(std::numeric_limits<PfxFloat>::max());
  upper = -lower;
  for (PfxUInt32 t = 0; t < island.m_numTriangles; ++t) {
    PfxVector3 v[3];
    pfxGetLargeTriMeshTriangle(mesh, island.m_firstTriangle + t, v[0], v[1], v[2]);
    for (const PfxVector3& p : v) {
      lower = lower.cwiseMin(p);
      upper = upper.cwiseMax(p);
    }
  }
}

// Whether a box (transform, half extents) lies at least partly inside every plane.
bool boxMeetsFrustum(const PfxTransform3& transform, const PfxVector3& half,
                     const PfxVector4* planes) {
  const PfxVector3 center = transform.translation();
  const PfxMatrix3 rotation = transform.linear();
  for (int p = 0; p < 6; ++p) {
    const PfxVector3 normal = planes[p].head<3>();
    const PfxFloat reach = (rotation.transpose() * normal).cwiseAbs().dot(half);
    if (normal.dot(center) + planes[p][3] + reach < 0) return false;
  }
  return true;
}

// The arrays every body-wise method reads: both, or no bodies.
PfxInt32 checkBodies(const PfxRigidState* states, const PfxCollidable* collidables,
                     PfxUInt32 numRigidBodies) {
  return numRigidBodies > 0 && (!states || !collidables) ? PFX_ERR_NULL_POINTER : PFX_OK;
}

// A world keeps its collidables in one array, as it does its states.
const PfxCollidable* collidablesOf(const PfxWorld& world) {
  return world.getNumRigidBodies() > 0 ? &world.getCollidable(0) : nullptr;
}

}  // namespace

void PfxDebugRender::resetVisible(PfxUInt32 numRigidBodies) {
  m_visible.assign(numRigidBodies, 1);
}

void PfxDebugRender::setVisible(PfxUInt32 rigidBodyId, bool visible) {
  if (rigidBodyId >= m_visible.size()) m_visible.resize(std::size_t(rigidBodyId) + 1, 1);
  m_visible[rigidBodyId] = visible ? 1 : 0;
}

bool PfxDebugRender::isVisible(PfxUInt32 rigidBodyId) const {
  return rigidBodyId >= m_visible.size() || m_visible[rigidBodyId] != 0;
}

// A removed body's slot (PfxWorld::removeRigidBody) is not a body to show; it never comes
// back, so hiding it for good is right.
void PfxDebugRender::hideRemovedBodies(const PfxWorld& world) {
  if (world.getNumRemovedRigidBodies() == 0) return;
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    if (!world.hasRigidBody(id)) setVisible(id, false);
  }
}

PfxInt32 PfxDebugRender::setCircleSegments(PfxUInt32 segments) {
  if (segments < 3 || segments > 256) return PFX_ERR_INVALID_VALUE;
  m_circleSegments = segments;
  return PFX_OK;
}

PfxInt32 PfxDebugRender::setDrawLength(PfxFloat length) {
  if (!(length > 0) || !pfxIsFinite(length)) return PFX_ERR_INVALID_VALUE;
  m_drawLength = length;
  return PFX_OK;
}

PfxInt32 PfxDebugRender::setForceScale(PfxFloat metresPerNewton) {
  if (!(metresPerNewton >= 0) || !pfxIsFinite(metresPerNewton)) return PFX_ERR_INVALID_VALUE;
  m_forceScale = metresPerNewton;
  return PFX_OK;
}

void PfxDebugRender::drawLine(const PfxVector3& a, const PfxVector3& b,
                              const PfxVector3& color) const {
  if (m_line) m_line(a, b, color);
}

void PfxDebugRender::drawBox(const PfxTransform3& transform, const PfxVector3& half,
                             const PfxVector3& color) const {
  if (m_box) {
    m_box(transform, half, color);
    return;
  }
  if (!m_line) return;
  const PfxDebugRenderTriangleFunc none;
  const ShapeSink sink{none, m_line, transform, color, 0};
  tessellateBox(PfxBox(half), sink);
}

void PfxDebugRender::drawAabb(const PfxVector3& center, const PfxVector3& half,
                              const PfxVector3& color) const {
  if (m_aabb) {
    m_aabb(center, half, color);
    return;
  }
  PfxTransform3 transform = PfxTransform3::Identity();
  transform.translation() = center;
  if (m_box) {
    m_box(transform, half, color);
    return;
  }
  drawBox(transform, half, color);
}

void PfxDebugRender::drawArc(const PfxVector3& position, const PfxVector3& axis,
                             const PfxVector3& dir, PfxFloat radius, PfxFloat start, PfxFloat end,
                             const PfxVector3& color) const {
  if (m_arc) {
    m_arc(position, axis, dir, radius, start, end, color);
    return;
  }
  if (!m_line) return;
  const PfxVector3 side = axis.cross(dir);
  const PfxUInt32 chords = std::max<PfxUInt32>(
      1, static_cast<PfxUInt32>(std::ceil(std::abs(end - start) / (2 * PFX_PI) * m_circleSegments)));
  PfxVector3 previous = position + radius * (std::cos(start) * dir + std::sin(start) * side);
  for (PfxUInt32 i = 1; i <= chords; ++i) {
    const PfxFloat angle = start + (end - start) * PfxFloat(i) / PfxFloat(chords);
    const PfxVector3 next = position + radius * (std::cos(angle) * dir + std::sin(angle) * side);
    m_line(previous, next, color);
    previous = next;
  }
}

void PfxDebugRender::drawShape(const PfxShape& shape, const PfxTransform3& transform,
                               const PfxVector3& color, PfxUInt32 rigidBodyId) const {
  const ShapeSink sink{m_triangle, m_line, transform, color, rigidBodyId};
  switch (shape.getType()) {
    case kPfxShapeSphere:
      tessellateRoundedSegment(0, shape.getSphere().m_radius, m_circleSegments, sink);
      break;
    case kPfxShapeBox: tessellateBox(shape.getBox(), sink); break;
    case kPfxShapeCapsule: {
      const PfxCapsule capsule = shape.getCapsule();
      tessellateRoundedSegment(capsule.m_halfLen, capsule.m_radius, m_circleSegments, sink);
      break;
    }
    case kPfxShapeCylinder: tessellateCylinder(shape.getCylinder(), m_circleSegments, sink); break;
    case kPfxShapeConvexMesh:
      if (shape.getConvexMesh()) tessellateConvexMesh(*shape.getConvexMesh(), sink);
      break;
    case kPfxShapeLargeTriMesh:
      if (shape.getLargeTriMesh()) tessellateLargeMesh(*shape.getLargeTriMesh(), sink);
      break;
    default: break;
  }
}

PfxInt32 PfxDebugRender::renderShapes(const PfxRigidState* states,
                                      const PfxCollidable* collidables, PfxUInt32 numRigidBodies) {
  if (const PfxInt32 err = checkBodies(states, collidables, numRigidBodies); err != PFX_OK) {
    return err;
  }
  if (!m_triangle && !m_line) return PFX_OK;
  for (PfxUInt32 id = 0; id < numRigidBodies; ++id) {
    if (!isVisible(id)) continue;
    const PfxTransform3 transform = states[id].getTransform();
    const PfxVector3 color = bodyColor(states[id]);
    for (PfxUInt32 s = 0; s < collidables[id].getNumShapes(); ++s) {
      const PfxShape& shape = collidables[id].getShape(s);
      drawShape(shape, transform * shape.getOffsetTransform(), color, id);
    }
  }
  return PFX_OK;
}

void PfxDebugRender::renderShapes(const PfxWorld& world) {
  hideRemovedBodies(world);
  renderShapes(world.getRigidStates(), collidablesOf(world), world.getNumRigidBodies());
}

PfxInt32 PfxDebugRender::renderWorld(const PfxVector3& worldCenter,
                                     const PfxVector3& worldExtent) {
  if (!pfxIsFinite(worldCenter) || !pfxIsFinite(worldExtent) || !(worldExtent.minCoeff() > 0)) {
    return PFX_ERR_INVALID_VALUE;
  }
  drawAabb(worldCenter, worldExtent, kGrey);
  return PFX_OK;
}

void PfxDebugRender::renderWorld(const PfxWorld& world) {
  renderWorld(world.getParam().worldCenter, world.getParam().worldExtent);
}

PfxInt32 PfxDebugRender::renderAabb(const PfxRigidState* states, const PfxCollidable* collidables,
                                    PfxUInt32 numRigidBodies) {
  if (const PfxInt32 err = checkBodies(states, collidables, numRigidBodies); err != PFX_OK) {
    return err;
  }
  for (PfxUInt32 id = 0; id < numRigidBodies; ++id) {
    if (!isVisible(id)) continue;
    PfxVector3 center, half;
    collidables[id].getWorldAabb(states[id].getTransform(), center, half);
    drawAabb(center, half, bodyColor(states[id]));
  }
  return PFX_OK;
}

void PfxDebugRender::renderAabb(const PfxWorld& world) {
  hideRemovedBodies(world);
  renderAabb(world.getRigidStates(), collidablesOf(world), world.getNumRigidBodies());
}

PfxInt32 PfxDebugRender::renderLocalAxis(const PfxRigidState* states, PfxUInt32 numRigidBodies,
                                         PfxFloat scale) {
  if (numRigidBodies > 0 && !states) return PFX_ERR_NULL_POINTER;
  if (!(scale > 0) || !pfxIsFinite(scale)) return PFX_ERR_INVALID_VALUE;
  for (PfxUInt32 id = 0; id < numRigidBodies; ++id) {
    if (!isVisible(id)) continue;
    const PfxMatrix3 rotation = states[id].getOrientation().toRotationMatrix();
    const PfxVector3& origin = states[id].getPosition();
    drawLine(origin, origin + scale * rotation.col(0), kRed);
    drawLine(origin, origin + scale * rotation.col(1), kGreen);
    drawLine(origin, origin + scale * rotation.col(2), kBlue);
  }
  return PFX_OK;
}

PfxInt32 PfxDebugRender::renderLocalAxis(const PfxWorld& world, PfxFloat scale) {
  hideRemovedBodies(world);
  return renderLocalAxis(world.getRigidStates(), world.getNumRigidBodies(), scale);
}

PfxInt32 PfxDebugRender::renderIsland(const PfxIsland& island, const PfxRigidState* states,
                                      const PfxCollidable* collidables,
                                      PfxUInt32 numRigidBodies) {
  if (const PfxInt32 err = checkBodies(states, collidables, numRigidBodies); err != PFX_OK) {
    return err;
  }
  const PfxUInt32 numIslands = pfxGetNumIslands(island);
  for (PfxUInt32 islandId = 0; islandId < numIslands; ++islandId) {
    PfxUInt32 count = 0;
    const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(island, islandId, count);
    for (PfxUInt32 i = 0; i < count; ++i) {
      if (bodies[i] >= numRigidBodies) return PFX_ERR_OUT_OF_RANGE;
    }
  }
  for (PfxUInt32 islandId = 0; islandId < numIslands; ++islandId) {
    PfxUInt32 count = 0;
    const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(island, islandId, count);
    PfxVector3 lower = PfxVector3::Zero(), upper = PfxVector3::Zero();
    bool drawn = false;
    for (PfxUInt32 i = 0; i < count; ++i) {
      const PfxUInt32 id = bodies[i];
      if (!pfxMotionTypeIsDynamic(states[id].getMotionType()) || !isVisible(id)) continue;
      PfxVector3 center, half;
      collidables[id].getWorldAabb(states[id].getTransform(), center, half);
      lower = drawn ? PfxVector3(lower.cwiseMin(center - half)) : PfxVector3(center - half);
      upper = drawn ? PfxVector3(upper.cwiseMax(center + half)) : PfxVector3(center + half);
      drawn = true;
    }
    // Coloured by the island's lowest body, so that an island keeps its colour while other
    // islands come and go.
    if (drawn) drawAabb((lower + upper) / 2, (upper - lower) / 2, indexColor(bodies[0]));
  }
  return PFX_OK;
}

void PfxDebugRender::renderIsland(const PfxWorld& world) {
  hideRemovedBodies(world);
  renderIsland(world.getIsland(), world.getRigidStates(), collidablesOf(world),
               world.getNumRigidBodies());
}

void PfxDebugRender::drawContacts(const PfxContactManifold& manifold, const PfxRigidState* states,
                                  PfxFloat timeStep) const {
  const PfxUInt32 idA = manifold.getRigidBodyIdA(), idB = manifold.getRigidBodyIdB();
  if (manifold.getNumContacts() == 0 || !isVisible(idA) || !isVisible(idB)) return;
  const PfxTransform3 transformA = states[idA].getTransform();
  const PfxTransform3 transformB = states[idB].getTransform();
  for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
    const PfxContactPoint& cp = manifold.getContactPoint(c);
    const PfxVector3 pointA = transformA * cp.m_localPointA;
    const PfxVector3 pointB = transformB * cp.m_localPointB;
    if (m_point) {
      m_point(pointA, kRed);
      m_point(pointB, kBlue);
    }
    drawLine(pointA, pointA + m_drawLength * cp.getNormal(), kYellow);
    const PfxFloat force = cp.m_constraintRow[0].m_accumImpulse / timeStep;
    if (force > 0 && m_forceScale > 0) {
      drawLine(pointB, pointB + (force * m_forceScale) * cp.getNormal(), kOrange);
    }
  }
}

PfxInt32 PfxDebugRender::renderContact(const PfxConstraintPair* contactPairs,
                                       PfxUInt32 numContactPairs,
                                       const PfxContactManifold* offsetContactManifolds,
                                       const PfxRigidState* states, PfxUInt32 numRigidBodies,
                                       PfxFloat timeStep) {
  if (numContactPairs > 0 && (!contactPairs || !offsetContactManifolds || !states)) {
    return PFX_ERR_NULL_POINTER;
  }
  if (!(timeStep > 0) || !pfxIsFinite(timeStep)) return PFX_ERR_INVALID_VALUE;
  for (PfxUInt32 i = 0; i < numContactPairs; ++i) {
    const PfxContactManifold& manifold = offsetContactManifolds[pfxGetContactId(contactPairs[i])];
    if (manifold.getNumContacts() > 0 && (manifold.getRigidBodyIdA() >= numRigidBodies ||
                                          manifold.getRigidBodyIdB() >= numRigidBodies)) {
      return PFX_ERR_OUT_OF_RANGE;
    }
  }
  for (PfxUInt32 i = 0; i < numContactPairs; ++i) {
    drawContacts(offsetContactManifolds[pfxGetContactId(contactPairs[i])], states, timeStep);
  }
  return PFX_OK;
}

// The world keeps its awake and its sleeping pairs apart, so its pairs are drawn one by one.
void PfxDebugRender::renderContact(const PfxWorld& world) {
  const PfxFloat subTimeStep = world.getParam().timeStep / PfxFloat(world.getParam().subStep);
  for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
    drawContacts(world.getContactManifold(world.getContactPair(i)), world.getRigidStates(),
                 subTimeStep);
  }
}

PfxInt32 PfxDebugRender::renderJoint(const PfxJoint* joints, PfxUInt32 numJoints,
                                     const PfxRigidState* states, PfxUInt32 numRigidBodies) {
  if (numJoints > 0 && (!joints || !states)) return PFX_ERR_NULL_POINTER;
  for (PfxUInt32 j = 0; j < numJoints; ++j) {
    if (joints[j].m_rigidBodyIdA >= numRigidBodies || joints[j].m_rigidBodyIdB >= numRigidBodies) {
      return PFX_ERR_OUT_OF_RANGE;
    }
  }
  for (PfxUInt32 j = 0; j < numJoints; ++j) {
    const PfxJoint& joint = joints[j];
    if (!isVisible(joint.m_rigidBodyIdA) && !isVisible(joint.m_rigidBodyIdB)) continue;
    const PfxRigidState& stateA = states[joint.m_rigidBodyIdA];
    const PfxRigidState& stateB = states[joint.m_rigidBodyIdB];
    const PfxVector3 anchorA = stateA.getTransform() * joint.m_anchorA;
    const PfxVector3 anchorB = stateB.getTransform() * joint.m_anchorB;
    const PfxMatrix3 frame = stateA.getOrientation().toRotationMatrix() * joint.m_frameA;
    if (m_point) {
      m_point(anchorA, kMagenta);
      m_point(anchorB, kCyan);
    }
    drawLine(anchorA, anchorB, kRed);
    drawLine(anchorA, anchorA + m_drawLength * frame.col(0), kRed);
    drawLine(anchorA, anchorA + m_drawLength * frame.col(1), kGreen);
    drawLine(anchorA, anchorA + m_drawLength * frame.col(2), kBlue);
    for (int axis = 0; axis < 6; ++axis) {
      const PfxJointConstraint& c = joint.m_constraints[axis];
      if (c.m_lock != kPfxJointLockLimit) continue;
      const PfxFloat lower = c.m_movableLowerLimit, upper = c.m_movableUpperLimit;
      if (axis < 3) {
        drawLine(anchorA + lower * frame.col(axis), anchorA + upper * frame.col(axis), kCyan);
        continue;
      }
      if (joint.m_type == kPfxJointSwingTwist && axis == kPfxJointAxisSwing1) {
        // The cone: its half angle seen in the two planes through the twist axis.
        drawArc(anchorA, frame.col(1), frame.col(0), m_drawLength, -upper, upper, kYellow);
        drawArc(anchorA, frame.col(2), frame.col(0), m_drawLength, -upper, upper, kYellow);
        continue;
      }
      if (lower <= -PFX_PI && upper >= PFX_PI) continue;  // no limit in effect
      // Twist turns Y about X; each swing turns X about its own axis.
      const PfxVector3 turnAxis = frame.col(axis - 3);
      const PfxVector3 from = axis == kPfxJointAxisTwist ? frame.col(1) : frame.col(0);
      drawArc(anchorA, turnAxis, from, m_drawLength, lower, upper, kYellow);
    }
  }
  return PFX_OK;
}

void PfxDebugRender::renderJoint(const PfxWorld& world) {
  // One by one, as removed joints' slots (PfxWorld::removeJoint) are left out.
  for (PfxUInt32 id = 0; id < world.getNumJoints(); ++id) {
    if (!world.hasJoint(id)) continue;
    renderJoint(&world.getJoint(id), 1, world.getRigidStates(), world.getNumRigidBodies());
  }
}

void PfxDebugRender::drawLargeMeshIslands(const PfxRigidState* states,
                                          const PfxCollidable* collidables,
                                          PfxUInt32 numRigidBodies,
                                          const PfxVector4* planes) const {
  for (PfxUInt32 id = 0; id < numRigidBodies; ++id) {
    if (!isVisible(id)) continue;
    const PfxCollidable& collidable = collidables[id];
    const PfxTransform3 bodyTransform = states[id].getTransform();
    for (PfxUInt32 s = 0; s < collidable.getNumShapes(); ++s) {
      const PfxShape& shape = collidable.getShape(s);
      const PfxLargeTriMesh* mesh = shape.getLargeTriMesh();
      if (shape.getType() != kPfxShapeLargeTriMesh || !mesh) continue;
      const PfxTransform3 transform = bodyTransform * shape.getOffsetTransform();
      for (PfxUInt32 i = 0; i < mesh->m_numIslands; ++i) {
        const PfxLargeMeshIsland& island = mesh->m_islands[i];
        PfxVector3 lower, upper;
        islandBounds(*mesh, island, lower, upper);
        PfxTransform3 islandTransform = transform;
        islandTransform.translation() = transform * ((lower + upper) / 2);
        const PfxVector3 half = (upper - lower) / 2;
        if (planes && !boxMeetsFrustum(islandTransform, half, planes)) continue;
        drawBox(islandTransform, half, indexColor(i));
        for (PfxUInt32 t = 0; t < island.m_numTriangles; ++t) {
          PfxVector3 v[3];
          pfxGetLargeTriMeshTriangle(*mesh, island.m_firstTriangle + t, v[0], v[1], v[2]);
          for (int k = 0; k < 3; ++k) drawLine(transform * v[k], transform * v[(k + 1) % 3], kWhite);
        }
      }
    }
  }
}

PfxInt32 PfxDebugRender::renderLargeMesh(const PfxRigidState* states,
                                         const PfxCollidable* collidables,
                                         PfxUInt32 numRigidBodies) {
  if (const PfxInt32 err = checkBodies(states, collidables, numRigidBodies); err != PFX_OK) {
    return err;
  }
  drawLargeMeshIslands(states, collidables, numRigidBodies, nullptr);
  return PFX_OK;
}

void PfxDebugRender::renderLargeMesh(const PfxWorld& world) {
  hideRemovedBodies(world);
  renderLargeMesh(world.getRigidStates(), collidablesOf(world), world.getNumRigidBodies());
}

PfxInt32 PfxDebugRender::renderLargeMeshInFrustum(const PfxRigidState* states,
                                                  const PfxCollidable* collidables,
                                                  PfxUInt32 numRigidBodies,
                                                  const PfxVector4 planes[6]) {
  if (!planes) return PFX_ERR_NULL_POINTER;
  if (const PfxInt32 err = checkBodies(states, collidables, numRigidBodies); err != PFX_OK) {
    return err;
  }
  for (int p = 0; p < 6; ++p) {
    if (!planes[p].allFinite()) return PFX_ERR_INVALID_VALUE;
  }
  drawLargeMeshIslands(states, collidables, numRigidBodies, planes);
  return PFX_OK;
}

PfxInt32 PfxDebugRender::renderLargeMeshInFrustum(const PfxWorld& world,
                                                  const PfxVector4 planes[6]) {
  hideRemovedBodies(world);
  return renderLargeMeshInFrustum(world.getRigidStates(), collidablesOf(world),
                                  world.getNumRigidBodies(), planes);
}

PfxInt32 PfxDebugRender::setLargeMeshFlag(PfxUInt32 rigidBodyId, PfxUInt32 islandId,
                                          PfxUInt32 triangleId, PfxUInt32 flags) {
  if ((flags & ~PFX_DRENDER_MESH_FLG_ALL) != 0) return PFX_ERR_INVALID_FLAG;
  if (flags == 0) return PFX_ERR_INVALID_VALUE;
  for (LargeMeshFlag& mark : m_largeMeshFlags) {
    if (mark.rigidBodyId == rigidBodyId && mark.islandId == islandId &&
        mark.triangleId == triangleId) {
      mark.flags |= flags;
      return PFX_OK;
    }
  }
  m_largeMeshFlags.push_back({rigidBodyId, islandId, triangleId, flags});
  return PFX_OK;
}

void PfxDebugRender::clearLargeMeshFlags() { m_largeMeshFlags.clear(); }

PfxInt32 PfxDebugRender::renderLargeMeshByFlag(const PfxRigidState* states,
                                               const PfxCollidable* collidables,
                                               PfxUInt32 numRigidBodies) {
  if (const PfxInt32 err = checkBodies(states, collidables, numRigidBodies); err != PFX_OK) {
    return err;
  }
  for (const LargeMeshFlag& mark : m_largeMeshFlags) {
    if (mark.rigidBodyId >= numRigidBodies || !isVisible(mark.rigidBodyId)) continue;
    const PfxCollidable& collidable = collidables[mark.rigidBodyId];
    const PfxTransform3 bodyTransform = states[mark.rigidBodyId].getTransform();
    for (PfxUInt32 s = 0; s < collidable.getNumShapes(); ++s) {
      const PfxShape& shape = collidable.getShape(s);
      const PfxLargeTriMesh* mesh = shape.getLargeTriMesh();
      if (shape.getType() != kPfxShapeLargeTriMesh || !mesh || mark.islandId >= mesh->m_numIslands) {
        continue;
      }
      const PfxTransform3 transform = bodyTransform * shape.getOffsetTransform();
      const PfxLargeMeshIsland& island = mesh->m_islands[mark.islandId];
      if (mark.flags & PFX_DRENDER_MESH_FLG_ISLAND) {
        PfxVector3 lower, upper;
        islandBounds(*mesh, island, lower, upper);
        PfxTransform3 islandTransform = transform;
        islandTransform.translation() = transform * ((lower + upper) / 2);
        drawBox(islandTransform, (upper - lower) / 2, indexColor(mark.islandId));
        for (PfxUInt32 t = 0; t < island.m_numTriangles; ++t) {
          PfxVector3 v[3];
          pfxGetLargeTriMeshTriangle(*mesh, island.m_firstTriangle + t, v[0], v[1], v[2]);
          for (int k = 0; k < 3; ++k) drawLine(transform * v[k], transform * v[(k + 1) % 3], kWhite);
        }
      }
      if (mark.triangleId >= island.m_numTriangles) continue;
      PfxVector3 v[3];
      pfxGetLargeTriMeshTriangle(*mesh, island.m_firstTriangle + mark.triangleId, v[0], v[1], v[2]);
      for (PfxVector3& p : v) p = transform * p;
      const PfxVector3 normal = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
      if (mark.flags & PFX_DRENDER_MESH_FLG_EDGE) {
        for (int k = 0; k < 3; ++k) drawLine(v[k], v[(k + 1) % 3], kYellow);
      }
      if (mark.flags & PFX_DRENDER_MESH_FLG_FACET_AABB) {
        const PfxVector3 lower = v[0].cwiseMin(v[1]).cwiseMin(v[2]);
        const PfxVector3 upper = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
        drawAabb((lower + upper) / 2, (upper - lower) / 2, kCyan);
      }
      if (mark.flags & PFX_DRENDER_MESH_FLG_NORMAL) {
        const PfxVector3 centroid = (v[0] + v[1] + v[2]) / 3;
        drawLine(centroid, centroid + m_drawLength * normal, kMagenta);
      }
      if (mark.flags & PFX_DRENDER_MESH_FLG_THICKNESS) {
        const PfxVector3 depth = -mesh->m_thickness * normal;
        for (int k = 0; k < 3; ++k) {
          drawLine(v[k], v[k] + depth, kOrange);
          drawLine(v[k] + depth, v[(k + 1) % 3] + depth, kOrange);
        }
      }
    }
  }
  return PFX_OK;
}

void PfxDebugRender::renderLargeMeshByFlag(const PfxWorld& world) {
  hideRemovedBodies(world);
  renderLargeMeshByFlag(world.getRigidStates(), collidablesOf(world), world.getNumRigidBodies());
}

}  // namespace pfx

namespace pfx {

PfxInt32 PfxDebugRender::renderParticles(const PfxParticle* particles, PfxUInt32 numParticles,
                                         const PfxParticleDistanceConstraint* distanceConstraints,
                                         PfxUInt32 numDistanceConstraints,
                                         const PfxUInt32* triangleIndices, PfxUInt32 numTriangles,
                                         const PfxVector3& color) {
  if ((numParticles > 0 && !particles) || (numDistanceConstraints > 0 && !distanceConstraints) ||
      (numTriangles > 0 && !triangleIndices)) {
    return PFX_ERR_NULL_POINTER;
  }
  for (PfxUInt32 i = 0; i < numDistanceConstraints; ++i) {
    if (distanceConstraints[i].m_particleA >= numParticles ||
        distanceConstraints[i].m_particleB >= numParticles) {
      return PFX_ERR_OUT_OF_RANGE;
    }
  }
  for (PfxUInt32 i = 0; i < 3 * numTriangles; ++i) {
    if (triangleIndices[i] >= numParticles) return PFX_ERR_OUT_OF_RANGE;
  }
  if (m_point) {
    for (PfxUInt32 i = 0; i < numParticles; ++i) m_point(particles[i].m_position, color);
  }
  for (PfxUInt32 i = 0; i < numDistanceConstraints; ++i) {
    drawLine(particles[distanceConstraints[i].m_particleA].m_position,
             particles[distanceConstraints[i].m_particleB].m_position, color);
  }
  for (PfxUInt32 t = 0; t < numTriangles; ++t) {
    const PfxVector3& a = particles[triangleIndices[3 * t]].m_position;
    const PfxVector3& b = particles[triangleIndices[3 * t + 1]].m_position;
    const PfxVector3& c = particles[triangleIndices[3 * t + 2]].m_position;
    if (m_triangle) {
      m_triangle(a, b, c, color, PFX_PARTICLE_DRAW_ID);
    } else {
      drawLine(a, b, color);
      drawLine(b, c, color);
      drawLine(c, a, color);
    }
  }
  return PFX_OK;
}

void PfxDebugRender::renderParticles(const PfxWorld& world) {
  const PfxVector3 awake(PfxFloat(0.2), PfxFloat(0.4), 1);
  const PfxVector3 asleep(PfxFloat(0.5), PfxFloat(0.5), PfxFloat(0.5));
  const PfxVector3 pinColor(1, PfxFloat(0.6), 0);
  for (PfxUInt32 id = 0; id < world.getParticleGroupCapacity(); ++id) {
    const PfxParticleGroup* group = world.getParticleGroup(id);
    if (!group) continue;
    const PfxParticleGroupDesc d = group->desc();
    renderParticles(d.particles, d.numParticles, d.distanceConstraints, d.numDistanceConstraints,
                    d.triangleIndices, d.numTriangles, group->asleep ? asleep : awake);
    for (const PfxParticlePin& pin : group->pins) {
      PfxVector3 anchor = pin.m_anchor;
      if (pin.m_rigidBodyId != PFX_PARTICLE_PIN_WORLD) {
        if (!isVisible(pin.m_rigidBodyId)) continue;
        const PfxRigidState& s = world.getRigidState(pin.m_rigidBodyId);
        anchor = s.getPosition() + s.getOrientation() * pin.m_anchor;
      }
      drawLine(group->particles[pin.m_particle].m_position, anchor, pinColor);
    }
  }
}

}  // namespace pfx
