// Debug rendering: every shape type comes out as a closed, outward-facing surface at the
// body's pose (or as its edges), the debug information lands where the world has it
// (contacts at the manifold's points, joints at their anchors with their limits, bounds of
// bodies and islands), invisible bodies are skipped and bad arguments are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_debug_render.h"
#include "pfx_large_mesh_test_util.h"
#include "pfx_test_meshes.h"

using namespace pfx;

namespace {

struct Triangle {
  PfxVector3 p[3];
  PfxUInt32 body;
  PfxVector3 normal() const { return (p[1] - p[0]).cross(p[2] - p[0]); }
  PfxFloat area() const { return normal().norm() / 2; }
};
struct Line {
  PfxVector3 a, b;
};
struct Arc {
  PfxVector3 position, axis, dir;
  PfxFloat radius, start, end;
};
struct Aabb {
  PfxVector3 center, half;
};

// Records every callback.
struct Recorder {
  std::vector<Triangle> triangles;
  std::vector<Line> lines;
  std::vector<PfxVector3> points;
  std::vector<Arc> arcs;
  std::vector<Aabb> aabbs;
  std::vector<Aabb> boxes;  // centre and half extents of box callbacks

  void attach(PfxDebugRender& render, bool withTriangles = true, bool withShapes = true) {
    if (withTriangles) {
      render.setDebugRenderTriangleFunc([this](const PfxVector3& a, const PfxVector3& b,
                                               const PfxVector3& c, const PfxVector3&,
                                               PfxUInt32 id) { triangles.push_back({{a, b, c}, id}); });
    }
    render.setDebugRenderLineFunc(
        [this](const PfxVector3& a, const PfxVector3& b, const PfxVector3&) { lines.push_back({a, b}); });
    render.setDebugRenderPointFunc([this](const PfxVector3& p, const PfxVector3&) { points.push_back(p); });
    if (!withShapes) return;
    render.setDebugRenderArcFunc([this](const PfxVector3& p, const PfxVector3& axis,
                                        const PfxVector3& dir, PfxFloat radius, PfxFloat start,
                                        PfxFloat end, const PfxVector3&) {
      arcs.push_back({p, axis, dir, radius, start, end});
    });
    render.setDebugRenderAabbFunc([this](const PfxVector3& center, const PfxVector3& half,
                                         const PfxVector3&) { aabbs.push_back({center, half}); });
    render.setDebugRenderBoxFunc([this](const PfxTransform3& t, const PfxVector3& half,
                                        const PfxVector3&) { boxes.push_back({t.translation(), half}); });
  }
  void clear() { *this = Recorder(); }
};

// Volume enclosed by the triangles (divergence theorem); positive when they face outward.
double enclosedVolume(const std::vector<Triangle>& triangles, const PfxVector3& inside) {
  double volume = 0;
  for (const Triangle& t : triangles) {
    const Eigen::Vector3d a = (t.p[0] - inside).cast<double>();
    const Eigen::Vector3d b = (t.p[1] - inside).cast<double>();
    const Eigen::Vector3d c = (t.p[2] - inside).cast<double>();
    volume += a.dot(b.cross(c)) / 6;
  }
  return volume;
}

PfxUInt32 addBody(PfxWorld& world, const PfxShape& shape, const PfxVector3& position,
                  const PfxQuat& orientation = PfxQuat::Identity(), PfxFloat mass = 1) {
  PfxBodyInit init;
  init.position = position;
  init.orientation = orientation;
  init.mass = mass;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, shape, init, &id), PFX_OK);
  return id;
}

const PfxQuat kTilt = PfxQuat(Eigen::AngleAxis<PfxFloat>(0.7f, PfxVector3(1, 2, 3).normalized()));

}  // namespace

TEST(DebugRender, BoxIsTwelveOutwardTrianglesOnItsCorners) {
  PfxWorld world;
  const PfxVector3 center(1, 2, 3), half(0.5f, 0.25f, 1);
  addBody(world, pfxMakeShape(PfxBox(half)), center, kTilt);
  PfxDebugRender render;
  Recorder r;
  r.attach(render);
  render.renderShapes(world);
  ASSERT_EQ(r.triangles.size(), 12u);
  const PfxTransform3 transform = world.getRigidState(0).getTransform();
  double area = 0;
  for (const Triangle& t : r.triangles) {
    EXPECT_EQ(t.body, 0u);
    for (const PfxVector3& p : t.p) {
      const PfxVector3 local = transform.inverse() * p;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(local[k]), half[k], 1e-5) << k;
    }
    EXPECT_GT(t.normal().dot((t.p[0] + t.p[1] + t.p[2]) / 3 - center), 0);
    area += t.area();
  }
  EXPECT_NEAR(area, 8 * (half.x() * half.y() + half.y() * half.z() + half.z() * half.x()), 1e-4);
  EXPECT_NEAR(enclosedVolume(r.triangles, center), 8 * half.prod(), 1e-4);
  EXPECT_TRUE(r.lines.empty());
}

TEST(DebugRender, SphereTrianglesLieOnItsSurface) {
  PfxWorld world;
  const PfxVector3 center(-1, 0.5f, 2);
  const PfxFloat radius = 0.3f;
  addBody(world, pfxMakeShape(PfxSphere(radius)), center, kTilt);
  PfxDebugRender render;
  Recorder r;
  r.attach(render);
  render.renderShapes(world);
  ASSERT_GT(r.triangles.size(), 50u);
  for (const Triangle& t : r.triangles) {
    for (const PfxVector3& p : t.p) EXPECT_NEAR((p - center).norm(), radius, 1e-5);
    EXPECT_GT(t.normal().dot((t.p[0] + t.p[1] + t.p[2]) / 3 - center), 0);
  }
  // A closed polyhedron inscribed in the sphere: a little less than its volume, and closer
  // with finer segments.
  const double exact = 4.0 / 3.0 * PFX_PI * radius * radius * radius;
  const double coarse = enclosedVolume(r.triangles, center);
  EXPECT_LT(coarse, exact);
  EXPECT_GT(coarse, 0.85 * exact);
  ASSERT_EQ(render.setCircleSegments(64), PFX_OK);
  r.clear();
  render.renderShapes(world);
  const double fine = enclosedVolume(r.triangles, center);
  EXPECT_LT(fine, exact);
  EXPECT_GT(fine, coarse);
  EXPECT_GT(fine, 0.99 * exact);
  EXPECT_EQ(render.setCircleSegments(2), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.setCircleSegments(1000), PFX_ERR_INVALID_VALUE);
}

// Capsules and cylinders lie along their local X axis; both come out closed and facing out.
TEST(DebugRender, CapsuleAndCylinderAlongX) {
  PfxWorld world;
  const PfxFloat halfLength = 0.4f, radius = 0.1f;
  addBody(world, pfxMakeShape(PfxCapsule(halfLength, radius)), PfxVector3(0, 1, 0), kTilt);
  addBody(world, pfxMakeShape(PfxCylinder(halfLength, radius)), PfxVector3(2, 1, 0), kTilt);
  PfxDebugRender render;
  ASSERT_EQ(render.setCircleSegments(48), PFX_OK);
  Recorder r;
  r.attach(render);
  render.renderShapes(world);
  std::vector<Triangle> shapes[2];
  for (const Triangle& t : r.triangles) shapes[t.body].push_back(t);
  ASSERT_FALSE(shapes[0].empty());
  ASSERT_FALSE(shapes[1].empty());
  for (PfxUInt32 id = 0; id < 2; ++id) {
    const PfxTransform3 inverse = world.getRigidState(id).getTransform().inverse();
    for (const Triangle& t : shapes[id]) {
      for (const PfxVector3& p : t.p) {
        const PfxVector3 local = inverse * p;
        const PfxFloat radial = std::hypot(local.y(), local.z());
        if (id == 0) {  // distance to the segment equals the radius
          const PfxFloat along = std::clamp(local.x(), -halfLength, halfLength);
          EXPECT_NEAR((local - PfxVector3(along, 0, 0)).norm(), radius, 1e-5);
        } else {  // on a cap or on the side
          EXPECT_LE(std::abs(local.x()), halfLength + 1e-5f);
          EXPECT_LE(radial, radius + 1e-5f);
          EXPECT_TRUE(std::abs(std::abs(local.x()) - halfLength) < 1e-5f ||
                      std::abs(radial - radius) < 1e-5f);
        }
      }
    }
  }
  const double capsule = 2 * halfLength * PFX_PI * radius * radius +
                         4.0 / 3.0 * PFX_PI * radius * radius * radius;
  const double cylinder = 2 * halfLength * PFX_PI * radius * radius;
  EXPECT_NEAR(enclosedVolume(shapes[0], world.getRigidState(0).getPosition()), capsule,
              0.02 * capsule);
  EXPECT_NEAR(enclosedVolume(shapes[1], world.getRigidState(1).getPosition()), cylinder,
              0.02 * cylinder);
}

TEST(DebugRender, ConvexMeshCompoundAndLargeMesh) {
  PfxWorld world;
  const pfx_test::TriangleList tetra = pfx_test::makeTetrahedronTriangles();
  PfxConvexMesh mesh;
  ASSERT_EQ(pfxCreateConvexMesh(mesh, tetra.vertices.data(), tetra.numVertices(),
                                tetra.indices.data(), tetra.numIndices()),
            PFX_OK);
  const PfxUInt32 convex = addBody(world, pfxMakeShape(&mesh), PfxVector3(0, 3, 0), kTilt);

  // A compound of two boxes at offsets: 24 triangles, each box around its own offset.
  PfxShape parts[2] = {pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), pfxMakeShape(PfxBox(0.2f, 0.1f, 0.1f))};
  parts[0].setOffsetPosition(PfxVector3(-0.5f, 0, 0));
  parts[1].setOffsetPosition(PfxVector3(0.5f, 0, 0));
  parts[1].setOffsetOrientation(PfxQuat(Eigen::AngleAxis<PfxFloat>(0.5f, PfxVector3::UnitY())));
  PfxBodyInit init;
  init.position = PfxVector3(5, 1, 0);
  PfxUInt32 compound = 0;
  ASSERT_EQ(pfxAddBody(world, parts, 2, init, &compound), PFX_OK);

  pfx_test::MeshSource grid = pfx_test::makeFlatGrid(8, 0.5f);
  pfx_test::MeshOwner ground;
  ASSERT_EQ(pfxCreateLargeTriMesh(ground.mesh, grid.param(0)), PFX_OK);
  const PfxUInt32 terrain = addBody(world, pfxMakeShape(PfxSphere(1)), PfxVector3(0, -1, 0));
  PfxShape groundShape;
  groundShape.reset();
  groundShape.setLargeTriMesh(&ground.mesh);
  PfxBodyInit fixed;
  fixed.mass = 0;
  fixed.position = PfxVector3(0, -2, 0);
  PfxUInt32 meshBody = 0;
  ASSERT_EQ(pfxAddBody(world, &groundShape, 1, fixed, &meshBody), PFX_OK);

  PfxDebugRender render;
  render.setVisible(terrain, false);
  Recorder r;
  r.attach(render);
  render.renderShapes(world);
  std::vector<Triangle> byBody[4];
  for (const Triangle& t : r.triangles) byBody[t.body].push_back(t);
  EXPECT_EQ(byBody[convex].size(), mesh.m_numFacets);
  EXPECT_NEAR(enclosedVolume(byBody[convex], world.getRigidState(convex).getPosition()), 8.0 / 3.0,
              1e-4);
  ASSERT_EQ(byBody[compound].size(), 24u);
  const PfxTransform3 body = world.getRigidState(compound).getTransform();
  for (int part = 0; part < 2; ++part) {
    const PfxTransform3 inverse = (body * parts[part].getOffsetTransform()).inverse();
    const PfxVector3 half = parts[part].getBox().m_half;
    for (int t = 12 * part; t < 12 * part + 12; ++t) {
      for (const PfxVector3& p : byBody[compound][t].p) {
        const PfxVector3 local = inverse * p;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(local[k]), half[k], 1e-5);
      }
    }
  }
  EXPECT_TRUE(byBody[terrain].empty());  // invisible
  ASSERT_EQ(byBody[meshBody].size(), ground.mesh.m_numTriangles);
  double meshArea = 0;
  for (const Triangle& t : byBody[meshBody]) {
    meshArea += t.area();
    EXPECT_GT(t.normal().y(), 0);  // the grid faces up
    for (const PfxVector3& p : t.p) EXPECT_NEAR(p.y(), -2, 1e-6);
  }
  EXPECT_NEAR(meshArea, 16, 1e-4);

  // Without a triangle callback the same shapes come as edges: a box's twelve, a convex
  // mesh's own edges, every triangle's three on a large mesh.
  PfxDebugRender wire;
  Recorder w;
  w.attach(wire, false);
  wire.setVisible(terrain, false);
  wire.renderShapes(world);
  EXPECT_TRUE(w.triangles.empty());
  EXPECT_EQ(w.lines.size(),
            mesh.m_numEdges + 2 * 12 + 3 * std::size_t(ground.mesh.m_numTriangles));
}

TEST(DebugRender, ContactPointsAreTheManifoldsPoints) {
  PfxWorld world;
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -0.5f, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(5, 0.5f, 5)), ground), PFX_OK);
  const PfxUInt32 box = addBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), PfxVector3(0, 0.35f, 0));
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  ASSERT_EQ(world.getStats().numContactPoints, 4u);
  // Asleep by now: the contact is drawn from the pair set aside, with its last impulses.
  ASSERT_TRUE(world.getRigidState(box).isAsleep());

  PfxDebugRender render;
  Recorder r;
  r.attach(render);
  render.renderContact(world);
  ASSERT_EQ(r.points.size(), 8u);  // on A's surface and on B's, per point
  const PfxContactManifold& manifold = world.getContactManifold(world.getContactPair(0));
  const PfxTransform3 a = world.getRigidState(manifold.getRigidBodyIdA()).getTransform();
  const PfxTransform3 b = world.getRigidState(manifold.getRigidBodyIdB()).getTransform();
  PfxFloat totalForce = 0;
  for (PfxUInt32 c = 0; c < 4; ++c) {
    const PfxContactPoint& cp = manifold.getContactPoint(c);
    EXPECT_LT((r.points[2 * c] - a * cp.m_localPointA).norm(), 1e-6);
    EXPECT_LT((r.points[2 * c + 1] - b * cp.m_localPointB).norm(), 1e-6);
    const Line& normal = r.lines[2 * c];
    EXPECT_LT((normal.a - r.points[2 * c]).norm(), 1e-6);
    EXPECT_NEAR((normal.b - normal.a).norm(), 0.1, 1e-5);
    EXPECT_NEAR(std::abs((normal.b - normal.a).normalized().y()), 1, 1e-4);
    const Line& force = r.lines[2 * c + 1];
    totalForce += (force.b - force.a).norm() / 0.01f;
  }
  // The four force lines add up to the box's weight (1 kg).
  EXPECT_NEAR(totalForce, 9.80665, 0.3);

  ASSERT_EQ(render.setForceScale(0), PFX_OK);  // normals only
  r.clear();
  render.renderContact(world);
  EXPECT_EQ(r.lines.size(), 4u);

  render.setVisible(box, false);
  r.clear();
  render.renderContact(world);
  EXPECT_TRUE(r.points.empty());
  EXPECT_TRUE(r.lines.empty());
}

TEST(DebugRender, JointAnchorsAxesAndLimitArcs) {
  PfxWorld world;
  PfxBodyInit fixed;
  fixed.mass = 0;
  PfxUInt32 base = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.05f)), fixed, &base), PFX_OK);
  const PfxUInt32 arm = addBody(world, pfxMakeShape(PfxBox(0.25f, 0.05f, 0.05f)), PfxVector3(0.3f, 0, 0));
  PfxHingeJointInitParam hinge;
  hinge.anchorPoint = PfxVector3(0.05f, 0, 0);
  hinge.axis = PfxVector3::UnitZ();
  hinge.lowerAngle = -0.4f;
  hinge.upperAngle = 0.9f;
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(base), world.getRigidState(arm), hinge),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);

  PfxDebugRender render;
  Recorder r;
  r.attach(render);
  render.renderJoint(world);
  ASSERT_EQ(r.points.size(), 2u);
  EXPECT_LT((r.points[0] - hinge.anchorPoint).norm(), 1e-6);
  EXPECT_LT((r.points[1] - hinge.anchorPoint).norm(), 1e-6);
  ASSERT_EQ(r.arcs.size(), 1u);
  const Arc& arc = r.arcs[0];
  EXPECT_FLOAT_EQ(arc.start, -0.4f);
  EXPECT_FLOAT_EQ(arc.end, 0.9f);
  EXPECT_LT((arc.axis - PfxVector3::UnitZ()).norm(), 1e-6);
  EXPECT_NEAR(arc.dir.dot(arc.axis), 0, 1e-6);
  EXPECT_LT((arc.position - hinge.anchorPoint).norm(), 1e-6);
  EXPECT_EQ(r.lines.size(), 4u);  // the gap and three frame axes

  // Without an arc callback the arc comes as chords on the same circle.
  PfxDebugRender lines;
  Recorder l;
  l.attach(lines, true, false);
  lines.renderJoint(world);
  ASSERT_GT(l.lines.size(), 4u);
  for (std::size_t i = 4; i < l.lines.size(); ++i) {
    EXPECT_NEAR((l.lines[i].a - hinge.anchorPoint).norm(), 0.1, 1e-5);
    EXPECT_NEAR((l.lines[i].b - hinge.anchorPoint).norm(), 0.1, 1e-5);
  }
  // The chords run from the lower limit's angle to the upper's, turning about +Z from the
  // frame's Y axis.
  const PfxVector3 first = l.lines[4].a - hinge.anchorPoint;
  const PfxVector3 last = l.lines.back().b - hinge.anchorPoint;
  EXPECT_NEAR(std::atan2(first.dot(arc.axis.cross(arc.dir)), first.dot(arc.dir)), -0.4, 1e-4);
  EXPECT_NEAR(std::atan2(last.dot(arc.axis.cross(arc.dir)), last.dot(arc.dir)), 0.9, 1e-4);
}

TEST(DebugRender, BoundsAxesAndIslands) {
  PfxWorld world;
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -0.5f, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(10, 0.5f, 10)), ground), PFX_OK);
  // Two stacks of two boxes far apart, and a pair of balls held by a joint in the air.
  for (const PfxFloat x : {-4.0f, 4.0f}) {
    addBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), PfxVector3(x, 0.3f, 0));
    addBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), PfxVector3(x, 0.9f, 0));
  }
  const PfxUInt32 ballA = addBody(world, pfxMakeShape(PfxSphere(0.1f)), PfxVector3(0, 5, 0));
  const PfxUInt32 ballB = addBody(world, pfxMakeShape(PfxSphere(0.1f)), PfxVector3(0.5f, 5, 0));
  PfxBallJointInitParam ball;
  ball.anchorPoint = PfxVector3(0.25f, 5, 0);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeBallJoint(joint, world.getRigidState(ballA), world.getRigidState(ballB), ball),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  ASSERT_EQ(world.step(), PFX_OK);

  PfxDebugRender render;
  Recorder r;
  r.attach(render);
  render.renderAabb(world);
  ASSERT_EQ(r.aabbs.size(), world.getNumRigidBodies());
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    PfxVector3 center, half;
    world.getCollidable(id).getWorldAabb(world.getRigidState(id).getTransform(), center, half);
    EXPECT_LT((r.aabbs[id].center - center).norm(), 1e-6);
    EXPECT_LT((r.aabbs[id].half - half).norm(), 1e-6);
  }

  // Islands: each stack (the ground joins none), and the jointed balls.
  r.clear();
  render.renderIsland(world);
  ASSERT_EQ(r.aabbs.size(), 3u);
  for (const Aabb& island : r.aabbs) {
    const bool stack = std::abs(std::abs(island.center.x()) - 4) < 0.05f;
    const bool balls = std::abs(island.center.y() - 5) < 0.05f;
    EXPECT_TRUE(stack || balls);
    if (stack) {
      EXPECT_NEAR(island.half.y(), 0.6, 0.02);  // both boxes of the stack
    } else if (balls) {
      EXPECT_NEAR(island.half.x(), 0.35, 0.02);
    }
  }
  render.setVisible(ballA, false);
  render.setVisible(ballB, false);
  r.clear();
  render.renderIsland(world);
  EXPECT_EQ(r.aabbs.size(), 2u);

  r.clear();
  EXPECT_EQ(render.renderLocalAxis(world, 0.2f), PFX_OK);
  ASSERT_EQ(r.lines.size(), 3 * std::size_t(world.getNumRigidBodies() - 2));
  EXPECT_NEAR((r.lines[0].b - r.lines[0].a).norm(), 0.2, 1e-6);
  const std::size_t before = r.lines.size();
  EXPECT_EQ(render.renderLocalAxis(world, -1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.renderLocalAxis(world, std::numeric_limits<PfxFloat>::quiet_NaN()),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(r.lines.size(), before);

  r.clear();
  render.renderWorld(world);
  ASSERT_EQ(r.aabbs.size(), 1u);
  EXPECT_EQ(r.aabbs[0].half, world.getParam().worldExtent);

  // Without AABB and box callbacks, bounds come as the twelve edges of the box.
  PfxDebugRender lines;
  Recorder l;
  l.attach(lines, true, false);
  lines.renderWorld(world);
  EXPECT_EQ(l.lines.size(), 12u);
}

TEST(DebugRender, LargeMeshIslandsFrustumAndFlags) {
  PfxWorld world;
  pfx_test::MeshSource grid = pfx_test::makeFlatGrid(16, 1);  // 512 triangles, 8 islands
  pfx_test::MeshOwner ground;
  ASSERT_EQ(pfxCreateLargeTriMesh(ground.mesh, grid.param(0)), PFX_OK);
  ASSERT_GT(ground.mesh.m_numIslands, 2u);
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(&ground.mesh);
  PfxBodyInit fixed;
  fixed.mass = 0;
  PfxUInt32 id = 0;
  ASSERT_EQ(pfxAddBody(world, &shape, 1, fixed, &id), PFX_OK);

  PfxDebugRender render;
  Recorder r;
  r.attach(render);
  render.renderLargeMesh(world);
  EXPECT_EQ(r.boxes.size(), ground.mesh.m_numIslands);
  EXPECT_EQ(r.lines.size(), 3 * std::size_t(ground.mesh.m_numTriangles));
  for (const Aabb& box : r.boxes) {
    EXPECT_LE(box.half.x(), 8 + 1e-5f);
    EXPECT_NEAR(box.half.y(), 0, 1e-6);
  }

  // A frustum that keeps x >= 0 only (the other five planes far away).
  PfxVector4 planes[6] = {PfxVector4(1, 0, 0, 0),      PfxVector4(-1, 0, 0, 100),
                          PfxVector4(0, 1, 0, 100),    PfxVector4(0, -1, 0, 100),
                          PfxVector4(0, 0, 1, 100),    PfxVector4(0, 0, -1, 100)};
  r.clear();
  ASSERT_EQ(render.renderLargeMeshInFrustum(world, planes), PFX_OK);
  ASSERT_GT(r.boxes.size(), 0u);
  EXPECT_LT(r.boxes.size(), ground.mesh.m_numIslands);
  for (const Aabb& box : r.boxes) EXPECT_GE(box.center.x() + box.half.x(), -1e-5f);
  planes[2][1] = std::numeric_limits<PfxFloat>::quiet_NaN();
  r.clear();
  EXPECT_EQ(render.renderLargeMeshInFrustum(world, planes), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.renderLargeMeshInFrustum(world, nullptr), PFX_ERR_NULL_POINTER);
  EXPECT_TRUE(r.boxes.empty());
  EXPECT_TRUE(r.lines.empty());

  // One triangle flagged for its edges and normal.
  EXPECT_EQ(render.setLargeMeshFlag(id, 1, 2, 1u << 7), PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(render.setLargeMeshFlag(id, 1, 2, 0), PFX_ERR_INVALID_VALUE);
  ASSERT_EQ(render.setLargeMeshFlag(id, 1, 2, PFX_DRENDER_MESH_FLG_EDGE), PFX_OK);
  ASSERT_EQ(render.setLargeMeshFlag(id, 1, 2, PFX_DRENDER_MESH_FLG_NORMAL), PFX_OK);
  ASSERT_EQ(render.setLargeMeshFlag(id, 9999, 0, PFX_DRENDER_MESH_FLG_ALL), PFX_OK);  // no island
  r.clear();
  render.renderLargeMeshByFlag(world);
  ASSERT_EQ(r.lines.size(), 4u);
  PfxVector3 v[3];
  pfxGetLargeTriMeshTriangle(ground.mesh, ground.mesh.m_islands[1].m_firstTriangle + 2, v[0], v[1], v[2]);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT((r.lines[k].a - v[k]).norm(), 1e-6);
    EXPECT_LT((r.lines[k].b - v[(k + 1) % 3]).norm(), 1e-6);
  }
  EXPECT_LT((r.lines[3].a - (v[0] + v[1] + v[2]) / 3).norm(), 1e-6);
  EXPECT_NEAR(r.lines[3].b.y() - r.lines[3].a.y(), 0.1, 1e-6);  // the face looks up
  render.clearLargeMeshFlags();
  r.clear();
  render.renderLargeMeshByFlag(world);
  EXPECT_TRUE(r.lines.empty());
}

TEST(DebugRender, SettersRejectBadValues) {
  PfxDebugRender render;
  EXPECT_EQ(render.setDrawLength(0), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.setDrawLength(std::numeric_limits<PfxFloat>::infinity()), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.setForceScale(-1), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.setForceScale(std::numeric_limits<PfxFloat>::quiet_NaN()), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.setDrawLength(0.5f), PFX_OK);
  EXPECT_TRUE(render.isVisible(12345));  // bodies start visible
  render.setVisible(3, false);
  EXPECT_FALSE(render.isVisible(3));
  EXPECT_TRUE(render.isVisible(2));
  render.resetVisible(10);
  EXPECT_TRUE(render.isVisible(3));
}

namespace {

template <typename T, typename Same>
bool sameSequence(const std::vector<T>& a, const std::vector<T>& b, Same same) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!same(a[i], b[i])) return false;
  }
  return true;
}

// Whether two recordings hold the same calls with the same arguments, in the same order.
bool sameDrawing(const Recorder& a, const Recorder& b) {
  const auto sameTriangle = [](const Triangle& x, const Triangle& y) {
    return x.p[0] == y.p[0] && x.p[1] == y.p[1] && x.p[2] == y.p[2] && x.body == y.body;
  };
  const auto sameLine = [](const Line& x, const Line& y) { return x.a == y.a && x.b == y.b; };
  const auto samePoint = [](const PfxVector3& x, const PfxVector3& y) { return x == y; };
  const auto sameArc = [](const Arc& x, const Arc& y) {
    return x.position == y.position && x.axis == y.axis && x.dir == y.dir &&
           x.radius == y.radius && x.start == y.start && x.end == y.end;
  };
  const auto sameAabb = [](const Aabb& x, const Aabb& y) {
    return x.center == y.center && x.half == y.half;
  };
  return sameSequence(a.triangles, b.triangles, sameTriangle) &&
         sameSequence(a.lines, b.lines, sameLine) && sameSequence(a.points, b.points, samePoint) &&
         sameSequence(a.arcs, b.arcs, sameArc) && sameSequence(a.aabbs, b.aabbs, sameAabb) &&
         sameSequence(a.boxes, b.boxes, sameAabb);
}

std::size_t numCalls(const Recorder& r) {
  return r.triangles.size() + r.lines.size() + r.points.size() + r.arcs.size() + r.aabbs.size() +
         r.boxes.size();
}

}  // namespace

// The seed's render functions take the low-level arrays; a world's forms draw the world's
// arrays through them, so both give the very same calls.
TEST(DebugRender, ArrayFormsDrawWhatTheWorldFormsDraw) {
  PfxWorldParam param;
  param.enableSleep = false;
  PfxWorld world;
  world.initialize(param);
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, -0.5f, 0);
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(10, 0.5f, 10)), ground), PFX_OK);
  addBody(world, pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f)), PfxVector3(-2, 0.3f, 0), kTilt);
  addBody(world, pfxMakeShape(PfxCapsule(0.3f, 0.2f)), PfxVector3(2, 0.3f, 0));
  const PfxUInt32 ballA = addBody(world, pfxMakeShape(PfxSphere(0.1f)), PfxVector3(0, 5, 0));
  const PfxUInt32 ballB = addBody(world, pfxMakeShape(PfxSphere(0.1f)), PfxVector3(0.5f, 5, 0));
  PfxSwingTwistJointInitParam swingTwist;
  swingTwist.anchorPoint = PfxVector3(0.25f, 5, 0);
  PfxJoint joint;
  ASSERT_EQ(pfxInitializeSwingTwistJoint(joint, world.getRigidState(ballA),
                                         world.getRigidState(ballB), swingTwist),
            PFX_OK);
  ASSERT_EQ(world.addJoint(joint), PFX_OK);
  for (int i = 0; i < 30; ++i) ASSERT_EQ(world.step(), PFX_OK);
  ASSERT_GT(world.getStats().numContactPoints, 0u);

  const PfxUInt32 n = world.getNumRigidBodies();
  const PfxRigidState* states = world.getRigidStates();
  const PfxCollidable* collidables = &world.getCollidable(0);
  // The world's pairs and manifolds laid out as a pipeline of one's own would hold them.
  std::vector<PfxConstraintPair> pairs;
  std::vector<PfxContactManifold> manifolds;
  for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
    pairs.push_back(world.getContactPair(i));
    pfxSetContactId(pairs.back(), i);
    manifolds.push_back(world.getContactManifold(world.getContactPair(i)));
  }

  PfxDebugRender render;
  render.setVisible(ballB, false);  // visibility applies to both forms
  Recorder fromWorld, fromArrays;
  const auto compare = [&](const char* what, auto drawWorld, auto drawArrays) {
    fromWorld.clear();
    fromWorld.attach(render);
    drawWorld();
    fromArrays.clear();
    fromArrays.attach(render);
    EXPECT_EQ(drawArrays(), PFX_OK) << what;
    EXPECT_GT(numCalls(fromWorld), 0u) << what;
    EXPECT_TRUE(sameDrawing(fromWorld, fromArrays)) << what;
  };
  compare("shapes", [&] { render.renderShapes(world); },
          [&] { return render.renderShapes(states, collidables, n); });
  compare("world", [&] { render.renderWorld(world); },
          [&] { return render.renderWorld(param.worldCenter, param.worldExtent); });
  compare("aabb", [&] { render.renderAabb(world); },
          [&] { return render.renderAabb(states, collidables, n); });
  compare("local axis", [&] { render.renderLocalAxis(world, 0.3f); },
          [&] { return render.renderLocalAxis(states, n, 0.3f); });
  compare("island", [&] { render.renderIsland(world); },
          [&] { return render.renderIsland(world.getIsland(), states, collidables, n); });
  compare("contact", [&] { render.renderContact(world); },
          [&] {
            return render.renderContact(pairs.data(), static_cast<PfxUInt32>(pairs.size()),
                                        manifolds.data(), states, n, param.timeStep);
          });
  compare("joint", [&] { render.renderJoint(world); },
          [&] { return render.renderJoint(&world.getJoint(0), 1, states, n); });
}

// Arrays of one's own, without a world: drawn where they are; arrays that do not fit their
// counts, and sizes that are not finite and positive, draw nothing.
TEST(DebugRender, ArrayFormsTakeThePipelinesArraysAndRefuseBadOnes) {
  PfxRigidState states[2];
  PfxCollidable collidables[2];
  for (PfxUInt32 id = 0; id < 2; ++id) {
    states[id].reset();
    states[id].setPosition(PfxVector3(PfxFloat(id), 1, 2));
    states[id].setOrientation(kTilt);
    states[id].setMotionType(kPfxMotionTypeActive);
    states[id].setRigidBodyId(id);
    PfxShape shape = pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f));
    collidables[id].reset();
    collidables[id].addShape(shape);
    collidables[id].finish();
  }
  PfxDebugRender render;
  Recorder r;
  r.attach(render);
  ASSERT_EQ(render.renderLocalAxis(states, 2, 0.5f), PFX_OK);
  ASSERT_EQ(r.lines.size(), 6u);
  const PfxMatrix3 rotation = kTilt.toRotationMatrix();
  for (PfxUInt32 id = 0; id < 2; ++id) {
    for (int axis = 0; axis < 3; ++axis) {
      const Line& line = r.lines[3 * id + axis];
      EXPECT_LT((line.a - states[id].getPosition()).norm(), 1e-6);
      EXPECT_LT((line.b - line.a - 0.5f * rotation.col(axis)).norm(), 1e-5);
    }
  }

  // Joint and contact of body 1 with a body 2 that these arrays do not hold.
  PfxJoint joint;
  PfxBallJointInitParam ball;
  ball.anchorPoint = PfxVector3(0.5f, 1, 2);
  ASSERT_EQ(pfxInitializeBallJoint(joint, states[0], states[1], ball), PFX_OK);
  joint.m_rigidBodyIdB = 2;
  PfxContactManifold manifold;
  manifold.reset(1, 2);
  PfxContactCandidate candidate{};
  candidate.m_normal = PfxVector3::UnitX();
  candidate.m_pointA = candidate.m_pointB = PfxVector3(0.5f, 1, 2);
  candidate.m_distance = 0;
  manifold.update(&candidate, 1, states[0].getTransform(), states[1].getTransform(), 0);
  ASSERT_EQ(manifold.getNumContacts(), 1u);
  PfxConstraintPair pair;
  pfxInitializePair(pair, 1, kPfxMotionTypeActive, 2, kPfxMotionTypeActive);
  pfxSetContactId(pair, 0);
  // Eigen leaves a vector's coefficients as it finds them: "= {}" would pass the stack's
  // old bytes, NaN now and then, so every plane is filled.
  PfxVector4 planes[6];
  PfxVector4 nanPlanes[6];
  for (int p = 0; p < 6; ++p) {
    planes[p] = PfxVector4::Zero();  // every point inside
    nanPlanes[p] = PfxVector4::Zero();
  }
  nanPlanes[2][3] = std::numeric_limits<PfxFloat>::quiet_NaN();

  r.clear();
  EXPECT_EQ(render.renderLocalAxis(nullptr, 2), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(render.renderLocalAxis(states, 2, 0), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.renderShapes(states, nullptr, 2), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(render.renderAabb(nullptr, collidables, 2), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(render.renderLargeMesh(states, nullptr, 2), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(render.renderLargeMeshByFlag(nullptr, collidables, 2), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(render.renderLargeMeshInFrustum(states, collidables, 2, nullptr),
            PFX_ERR_NULL_POINTER);
  EXPECT_EQ(render.renderLargeMeshInFrustum(states, collidables, 2, nanPlanes),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.renderWorld(PfxVector3::Zero(), PfxVector3(1, 0, 1)), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.renderJoint(&joint, 1, states, 2), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(render.renderJoint(nullptr, 1, states, 2), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(render.renderContact(&pair, 1, &manifold, states, 2, 1.0f / 60), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(render.renderContact(&pair, 1, &manifold, states, 3, 0), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(render.renderContact(&pair, 1, nullptr, states, 3, 1.0f / 60), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(numCalls(r), 0u);
  EXPECT_EQ(render.renderLargeMeshInFrustum(states, collidables, 2, planes), PFX_OK);
}
