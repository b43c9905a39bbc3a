// Contacts against a large mesh: every convex shape and a compound against a brute-force
// reference over all triangles (array, BVH and quantized storage), internal edges (a box
// pushed across a flat mesh of small triangles stays level), a box resting on a
// million-triangle terrain, and contacts carried through a deformation.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"
#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_world.h"
#include "pfx_large_mesh_test_util.h"
#include "pfx_contact_test_util.h"

namespace {

using namespace pfx;
using namespace pfx_test;

PfxShape meshShape(const PfxLargeTriMesh* mesh) {
  PfxShape s;
  s.reset();
  s.setLargeTriMesh(mesh);
  return s;
}

PfxCollidable collidableOf(const PfxShape& shape) {
  PfxCollidable c;
  c.reset();
  EXPECT_EQ(c.addShape(shape), PFX_OK);
  EXPECT_EQ(c.finish(), PFX_OK);
  return c;
}

struct Deepest {
  bool found = false;
  PfxFloat distance = 0;
  PfxVector3 normal = PfxVector3::Zero();  // from the mesh to the shape
  PfxUInt32 sourceTriangle = 0;
  PfxFloat runnerUp = 1e30f;  // second deepest distance on another triangle
};

// Deepest candidate between a mesh collidable and a shape collidable, with the normal
// turned to point from the mesh to the shape whichever order was used.
void collect(const PfxContactCandidate* c, PfxUInt32 n, bool meshIsA, const PfxLargeTriMesh& mesh,
             Deepest& d) {
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxUInt32 source = pfxGetLargeTriMeshSourceTriangle(mesh, c[i].m_triangleIndex);
    const PfxVector3 normal = meshIsA ? c[i].m_normal : PfxVector3(-c[i].m_normal);
    if (!d.found || c[i].m_distance < d.distance) {
      if (d.found && source != d.sourceTriangle) d.runnerUp = std::min(d.runnerUp, d.distance);
      d.found = true;
      d.distance = c[i].m_distance;
      d.normal = normal;
      d.sourceTriangle = source;
    } else if (source != d.sourceTriangle) {
      d.runnerUp = std::min(d.runnerUp, c[i].m_distance);
    }
  }
}

// The reference searches nothing: each triangle of the mesh under test (as it stores it,
// so quantized meshes are compared on their own dequantized geometry, which
// BuildsInEveryStorageVariant holds within half a quantization step of the input) is a mesh
// of its own, met through its bounds alone.
class MeshContactReference : public ::testing::Test {
 protected:
  void SetUp() override {
    m_soup = makeRandomTriangles(1500, 12, PfxFloat(1.2), 21);
    m_hull = buildMesh(makeIcosahedronTriangles());
  }

  // The mesh's triangles as it stores them, nine coordinates each in the caller's order
  // (NaN where it dropped one: such a mesh compares unequal to every other, even itself, so
  // it never shares a reference, which costs time but never a wrong one).
  static std::vector<PfxFloat> storedTriangles(const PfxLargeTriMesh& mesh, PfxUInt32 numSource) {
    std::vector<PfxFloat> corners(9 * numSource, std::numeric_limits<PfxFloat>::quiet_NaN());
    for (PfxUInt32 t = 0; t < mesh.m_numTriangles; ++t) {
      PfxVector3 v[3];
      pfxGetLargeTriMeshTriangle(mesh, t, v[0], v[1], v[2]);
      PfxFloat* const out = &corners[9 * pfxGetLargeTriMeshSourceTriangle(mesh, t)];
      for (int k = 0; k < 3; ++k) std::copy_n(v[k].data(), 3, out + 3 * k);
    }
    return corners;
  }

  static std::vector<std::unique_ptr<MeshOwner>> splitTriangles(
      const std::vector<PfxFloat>& corners) {
    std::vector<std::unique_ptr<MeshOwner>> single(corners.size() / 9);
    for (std::size_t t = 0; t < single.size(); ++t) {
      if (std::isnan(corners[9 * t])) continue;
      MeshSource one;
      one.vertices.assign(corners.begin() + 9 * t, corners.begin() + 9 * t + 9);
      one.triangles = {0, 1, 2};
      single[t] = std::make_unique<MeshOwner>();
      EXPECT_EQ(pfxCreateLargeTriMesh(single[t]->mesh, one.param(0, kThickness)), PFX_OK);
    }
    return single;
  }

  static Deepest reference(const std::vector<std::unique_ptr<MeshOwner>>& single,
                           const PfxCollidable& shape, const PfxTransform3& pose) {
    Deepest d;
    for (PfxUInt32 t = 0; t < single.size(); ++t) {
      if (!single[t]) continue;
      const PfxCollidable mesh = collidableOf(meshShape(&single[t]->mesh));
      PfxContactCandidate c[PFX_MAX_CONTACT_CANDIDATES];
      const PfxUInt32 n = pfxContactCollidables(mesh, PfxTransform3::Identity(), shape, pose,
                                                kThreshold, c, PFX_MAX_CONTACT_CANDIDATES);
      Deepest one;
      collect(c, n, true, single[t]->mesh, one);
      if (!one.found) continue;
      if (!d.found || one.distance < d.distance) {
        const PfxFloat runnerUp = d.found ? std::min(d.runnerUp, d.distance) : 1e30f;
        d = one;
        d.sourceTriangle = t;
        d.runnerUp = runnerUp;
      } else {
        d.runnerUp = std::min(d.runnerUp, one.distance);
      }
    }
    return d;
  }

  void compareAll(const PfxCollidable& shape, const char* name) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<PfxFloat> u(-1, 1);
    std::vector<PfxTransform3> poses;
    for (int i = 0; i < 40; ++i) {
      const PfxFloat angle = u(rng) * PFX_PI;
      const PfxQuat q =
          PfxQuat(Eigen::AngleAxis<PfxFloat>(angle, PfxVector3{u(rng), u(rng), u(rng)}.normalized()));
      poses.push_back(pfxMakeTransform(q, PfxVector3{u(rng) * 10, u(rng) * 2, u(rng) * 10}));
    }
    struct Reference {
      std::vector<PfxFloat> corners;
      std::vector<Deepest> deepest;  // at each pose
    };
    std::vector<Reference> references;
    for (const PfxUInt32 flags :
         {0u, PFX_MESH_FLAG_USE_BVH, PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_HIGH_QUALITY,
          PFX_MESH_FLAG_USE_QUANTIZED, PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED}) {
      SCOPED_TRACE(std::string(name) + " flags " + std::to_string(flags));
      MeshOwner owner;
      ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, m_soup.param(flags, kThickness)), PFX_OK);
      // The reference depends on the triangles alone: the variants that store the same ones
      // share it (the three that do not quantize, and the two that do), where computing it
      // for each was most of this suite's time under AddressSanitizer.
      std::vector<PfxFloat> corners = storedTriangles(owner.mesh, m_soup.numTriangles());
      const auto known = std::find_if(references.begin(), references.end(),
                                      [&](const Reference& r) { return r.corners == corners; });
      const std::size_t at = known - references.begin();
      if (at == references.size()) {
        const auto single = splitTriangles(corners);
        Reference computed{std::move(corners), {}};
        for (const PfxTransform3& pose : poses) {
          computed.deepest.push_back(reference(single, shape, pose));
        }
        references.push_back(std::move(computed));
      }
      const std::vector<Deepest>& refs = references[at].deepest;
      const PfxCollidable mesh = collidableOf(meshShape(&owner.mesh));
      PfxUInt32 touching = 0;
      for (std::size_t i = 0; i < poses.size(); ++i) {
        const Deepest& ref = refs[i];
        for (const bool meshIsA : {true, false}) {
          PfxContactCandidate c[PFX_MAX_CONTACT_CANDIDATES];
          const PfxUInt32 n =
              meshIsA ? pfxContactCollidables(mesh, PfxTransform3::Identity(), shape, poses[i],
                                              kThreshold, c, PFX_MAX_CONTACT_CANDIDATES)
                      : pfxContactCollidables(shape, poses[i], mesh, PfxTransform3::Identity(),
                                              kThreshold, c, PFX_MAX_CONTACT_CANDIDATES);
          Deepest got;
          collect(c, n, meshIsA, owner.mesh, got);
          ASSERT_EQ(got.found, ref.found) << "pose " << i;
          if (!ref.found) continue;
          EXPECT_NEAR(got.distance, ref.distance, 2e-5) << "pose " << i;
          // Normals agree when one triangle is clearly the deepest.
          if (ref.runnerUp > ref.distance + PfxFloat(1e-4)) {
            EXPECT_EQ(got.sourceTriangle, ref.sourceTriangle) << "pose " << i;
            EXPECT_GT(got.normal.dot(ref.normal), 1 - 1e-4) << "pose " << i;
          }
          ++touching;
        }
      }
      EXPECT_GT(touching, 10u);  // the poses do reach the ground
    }
  }

  static constexpr PfxFloat kThreshold = PfxFloat(0.05);
  static constexpr PfxFloat kThickness = PfxFloat(0.3);
  MeshSource m_soup;
  PfxConvexMesh m_hull;
};

TEST_F(MeshContactReference, Sphere) { compareAll(collidableOf(pfxMakeShape(PfxSphere(0.6f))), "sphere"); }

TEST_F(MeshContactReference, Box) {
  compareAll(collidableOf(pfxMakeShape(PfxBox(0.7f, 0.3f, 0.5f))), "box");
}

TEST_F(MeshContactReference, Capsule) {
  compareAll(collidableOf(pfxMakeShape(PfxCapsule(0.6f, 0.3f))), "capsule");
}

TEST_F(MeshContactReference, Cylinder) {
  compareAll(collidableOf(pfxMakeShape(PfxCylinder(0.5f, 0.4f))), "cylinder");
}

TEST_F(MeshContactReference, ConvexMesh) { compareAll(collidableOf(pfxMakeShape(&m_hull)), "hull"); }

TEST_F(MeshContactReference, Compound) {
  PfxShape shapes[2] = {pfxMakeShape(PfxBox(0.4f, 0.2f, 0.4f)), pfxMakeShape(PfxSphere(0.3f))};
  shapes[1].setOffsetPosition(PfxVector3(0.6f, -0.2f, 0));
  const PfxUInt16 ids[2] = {0, 1};
  PfxCollidable compound;
  ASSERT_EQ(compound.reset(shapes, ids, 2), PFX_OK);
  ASSERT_EQ(compound.addShape(shapes[0]), PFX_OK);
  ASSERT_EQ(compound.addShape(shapes[1]), PFX_OK);
  ASSERT_EQ(compound.finish(), PFX_OK);
  compareAll(compound, "compound");
}

TEST(MeshContacts, BoxOnAFlatGridRestsOnItsFaceWithTheTriangleAndWeights) {
  // Grid at y = 0 of 0.25 m cells; a box of half height 0.5 at y = 0.49 overlaps by 0.01.
  const MeshSource grid = makeFlatGrid(16, PfxFloat(0.25));
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
  const PfxCollidable mesh = collidableOf(meshShape(&owner.mesh));
  const PfxCollidable box = collidableOf(pfxMakeShape(PfxBox(0.6f, 0.5f, 0.6f)));
  const PfxTransform3 pose = pfxMakeTransform(PfxQuat::Identity(), PfxVector3(0.1f, 0.49f, 0.05f));
  PfxContactCandidate c[PFX_MAX_CONTACT_CANDIDATES];
  const PfxUInt32 n = pfxContactCollidables(box, pose, mesh, PfxTransform3::Identity(),
                                            PfxFloat(0.02), c, PFX_MAX_CONTACT_CANDIDATES);
  ASSERT_EQ(n, 4u);  // the corners of the box's bottom face
  for (PfxUInt32 i = 0; i < n; ++i) {
    // Box is A: the normal points from the box down into the mesh.
    EXPECT_NEAR(c[i].m_normal.y(), -1, 1e-5);
    EXPECT_NEAR(c[i].m_distance, -0.01, 1e-5);
    EXPECT_NEAR(std::abs(c[i].m_pointA.x() - 0.1f), 0.6, 1e-5);
    EXPECT_NEAR(c[i].m_pointB.y(), 0, 1e-6);
    ASSERT_LT(c[i].m_triangleIndex, owner.mesh.m_numTriangles);
    // The weights rebuild the mesh point on its triangle.
    PfxVector3 v0, v1, v2;
    pfxGetLargeTriMeshTriangle(owner.mesh, c[i].m_triangleIndex, v0, v1, v2);
    const PfxVector3 rebuilt =
        v0 * c[i].m_barycentric[0] + v1 * c[i].m_barycentric[1] + v2 * c[i].m_barycentric[2];
    EXPECT_LT((rebuilt - c[i].m_pointB).norm(), 1e-5);
  }
}

// A sphere against a mesh (as collidables, within `threshold`): every contact must point
// up (+y) with the given distance.
void expectSphereContactsUp(const PfxLargeTriMesh& meshData, PfxFloat radius,
                            const PfxVector3& center, PfxFloat threshold, PfxFloat distance) {
  const PfxCollidable mesh = collidableOf(meshShape(&meshData));
  const PfxCollidable ball = collidableOf(pfxMakeShape(PfxSphere(radius)));
  PfxContactCandidate c[PFX_MAX_CONTACT_CANDIDATES];
  const PfxUInt32 n = pfxContactCollidables(mesh, PfxTransform3::Identity(), ball,
                                            pfxMakeTransform(PfxQuat::Identity(), center),
                                            threshold, c, PFX_MAX_CONTACT_CANDIDATES);
  ASSERT_GE(n, 1u);
  for (PfxUInt32 i = 0; i < n; ++i) {
    EXPECT_NEAR(c[i].m_normal.y(), 1, 1e-5);
    EXPECT_NEAR(c[i].m_distance, distance, 1e-5);
  }
}

TEST(MeshContacts, DeepOverlapIsPushedUpNotThrough) {
  // A sphere of radius 0.5 whose centre is 0.05 above the faces of a mesh 0.2 thick: it
  // reaches 0.45 below the face, deeper than the prism. The contact still points up, with
  // depth 0.45.
  const MeshSource grid = makeFlatGrid(8, 1);
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(0, PfxFloat(0.2))), PFX_OK);
  expectSphereContactsUp(owner.mesh, 0.5f, PfxVector3(0.3f, 0.05f, 0.2f), 0.02f, -0.45f);
}

TEST(MeshContacts, ShapeBeyondAPrismGetsNoContactFromItsFace) {
  // A closed slab 0.05 thick: a grid facing up at y = 0 and one facing down at y = -0.05,
  // prisms 0.01 deep. A sphere resting on the top lies 0.04 beyond the bottom faces'
  // prisms, within the contact threshold: the bottom faces must not pull it down into the
  // slab (their face contact would be 0.25 deep), only the top holds it.
  const MeshSource top = makeFlatGrid(4, 1);
  MeshSource slab = top;
  for (PfxUInt32 v = 0; v < top.numVertices(); ++v) {
    slab.vertices.insert(slab.vertices.end(),
                         {top.vertices[3 * v], PfxFloat(-0.05), top.vertices[3 * v + 2]});
  }
  for (PfxUInt32 t = 0; t < top.numTriangles(); ++t) {
    const PfxUInt32* tri = &top.triangles[3 * t];
    const PfxUInt32 n = top.numVertices();
    slab.triangles.insert(slab.triangles.end(), {tri[0] + n, tri[2] + n, tri[1] + n});
  }
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, slab.param(0, PfxFloat(0.01))), PFX_OK);
  expectSphereContactsUp(owner.mesh, 0.1f, PfxVector3(0.3f, 0.1f, 0.2f), 0.06f, 0);
}

TEST(MeshContacts, BoxEdgeOnASeamGetsTheFaceNormal) {
  // A box tilted 30 degrees about z touches the flat grid with one bottom edge lying along
  // the seam x = 0 between two cells. Without internal-edge handling the prism's side
  // face there would give a slanted or sideways normal; with it, every normal is +Y.
  const MeshSource grid = makeFlatGrid(4, 1);
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(0)), PFX_OK);
  const PfxCollidable mesh = collidableOf(meshShape(&owner.mesh));
  const PfxCollidable box = collidableOf(pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)));
  // Turned 30 degrees about z, the box's lowest edge is (x, y) = (-0.5, -0.5): rotated, it
  // lies at (-0.183, -0.683), below the other corners (0.683, -0.183) and (-0.683, 0.183).
  // It lands on the origin, 0.005 deep, when the centre sits at -R (-0.5, -0.5, 0) - 0.005 y.
  const PfxQuat q(Eigen::AngleAxis<PfxFloat>(PFX_PI / 6, PfxVector3::UnitZ()));
  const PfxVector3 centre = -(q * PfxVector3(-0.5f, -0.5f, 0)) - PfxVector3(0, 0.005f, 0);
  PfxContactCandidate c[PFX_MAX_CONTACT_CANDIDATES];
  const PfxUInt32 n = pfxContactCollidables(mesh, PfxTransform3::Identity(), box,
                                            pfxMakeTransform(q, centre), PfxFloat(0.02), c,
                                            PFX_MAX_CONTACT_CANDIDATES);
  ASSERT_GE(n, 1u);
  for (PfxUInt32 i = 0; i < n; ++i) {
    EXPECT_GT(c[i].m_normal.y(), 1 - 1e-5);
    EXPECT_NEAR(c[i].m_distance, -0.005, 1e-4);
  }
}

// Adds a fixed body holding the mesh.
PfxUInt32 addGround(PfxWorld& world, const PfxLargeTriMesh& mesh) {
  PfxBodyInit init;
  init.mass = 0;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, meshShape(&mesh), init, &id), PFX_OK);
  return id;
}

TEST(MeshContacts, BoxPushedAcrossManySmallTrianglesKeepsItsHeight) {
  // 12 m square of 0.2 m cells: 7,200 triangles, a seam every 0.2 m along the way.
  const MeshSource grid = makeFlatGrid(60, PfxFloat(0.2));
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
  PfxWorld world;
  PfxWorldParam param;
  param.worldExtent = PfxVector3::Constant(50);
  ASSERT_EQ(world.initialize(param), PFX_OK);
  addGround(world, owner.mesh);
  PfxBodyInit init;
  init.mass = 2;
  init.friction = 0;
  init.position = PfxVector3(-4, 0.25f, -3);
  PfxUInt32 box = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.3f, 0.25f, 0.2f)), init, &box), PFX_OK);
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);  // settle
  // Pushed diagonally at 3 m/s (crossing cell edges and diagonals alike) for 2 s.
  PfxRigidState state = world.getRigidState(box);
  state.setLinearVelocity(PfxVector3(3, 0, 2));
  ASSERT_EQ(world.setRigidState(box, state), PFX_OK);
  PfxFloat lowest = 1e9f, highest = -1e9f, maxTilt = 0;
  for (int i = 0; i < 120; ++i) {
    ASSERT_EQ(world.step(), PFX_OK);
    const PfxRigidState& s = world.getRigidState(box);
    lowest = std::min(lowest, s.getPosition().y());
    highest = std::max(highest, s.getPosition().y());
    maxTilt = std::max(maxTilt, (s.getOrientation() * PfxVector3::UnitY()).cross(PfxVector3::UnitY()).norm());
  }
  const PfxRigidState& end = world.getRigidState(box);
  EXPECT_GT(end.getPosition().x(), 1);  // it did travel, over 25 cells
  EXPECT_LT(highest - lowest, 1e-3);
  // Rests at its half height 0.25, less at most the world's tolerated overlap (0.005).
  EXPECT_NEAR(lowest, 0.25, 6e-3);
  EXPECT_LT(maxTilt, 2e-3);
}

TEST(MeshContacts, BoxRestsOnAMillionTriangleTerrain) {
  // 1000 x 500 cells of 1 m, two triangles each: 1,000,000 triangles of rolling ground,
  // y = 2 sin(x / 40) cos(z / 30).
  const auto height = [](PfxFloat x, PfxFloat z) {
    return 2 * std::sin(x / 40) * std::cos(z / 30);
  };
  const MeshSource terrain = makeHeightField(1000, 500, 1, height);
  ASSERT_EQ(terrain.numTriangles(), 1000000u);
  MeshOwner owner;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, terrain.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("1,000,000 triangles: built in %.2f s, %u islands, %.1f bytes per triangle\n",
              seconds, owner.mesh.m_numIslands, double(owner.mesh.m_bytes) / 1e6);
  EXPECT_GT(owner.mesh.m_numIslands, PFX_LARGE_MESH_SEED_MAX_ISLANDS);

  PfxWorld world;
  PfxWorldParam param;
  param.worldExtent = PfxVector3(600, 100, 600);
  ASSERT_EQ(world.initialize(param), PFX_OK);
  addGround(world, owner.mesh);
  PfxBodyInit init;
  init.mass = 1;
  const PfxFloat x = 123.4f, z = -56.7f;
  init.position = PfxVector3(x, height(x, z) + 1, z);
  PfxUInt32 box = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.4f, 0.4f, 0.4f)), init, &box), PFX_OK);
  for (int i = 0; i < 180; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxRigidState& s = world.getRigidState(box);
  // At rest, on the ground: the slope here is below 3 degrees, so the box's centre sits
  // about half its height (0.4) above the surface under it.
  EXPECT_LT(s.getLinearVelocity().norm(), 0.05);
  const PfxVector3 p = s.getPosition();
  EXPECT_NEAR(p.y() - height(p.x(), p.z()), 0.4, 0.03);
}

TEST(MeshContacts, DeformationCarriesContactsAndLiftsTheBody) {
  const MeshSource grid = makeFlatGrid(20, PfxFloat(0.5));
  MeshOwner owner;
  ASSERT_EQ(pfxCreateLargeTriMesh(owner.mesh, grid.param(PFX_MESH_FLAG_USE_BVH, PfxFloat(0.3))),
            PFX_OK);
  PfxWorld world;
  PfxWorldParam param;
  param.worldExtent = PfxVector3::Constant(50);
  ASSERT_EQ(world.initialize(param), PFX_OK);
  const PfxUInt32 ground = addGround(world, owner.mesh);
  PfxBodyInit init;
  init.mass = 1;
  init.position = PfxVector3(0.3f, 0.2f, 0.1f);
  PfxUInt32 box = 0;
  ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(0.3f, 0.2f, 0.3f)), init, &box), PFX_OK);
  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  const PfxFloat restY = world.getRigidState(box).getPosition().y();
  ASSERT_NEAR(restY, 0.2, 6e-3);

  // Find the manifold and a point on the mesh.
  const auto manifoldOf = [&]() -> const PfxContactManifold* {
    for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
      const PfxContactManifold& m = world.getContactManifold(world.getContactPair(i));
      if (m.getNumContacts() > 0) return &m;
    }
    return nullptr;
  };
  const PfxContactManifold* manifold = manifoldOf();
  ASSERT_NE(manifold, nullptr);
  ASSERT_NE(manifold->getContactPoint(0).m_triangleIndex, PFX_CONTACT_NO_TRIANGLE);
  const bool groundIsA = manifold->getRigidBodyIdA() == ground;
  const PfxVector3 anchorBefore = groundIsA ? manifold->getContactPoint(0).m_localPointA
                                            : manifold->getContactPoint(0).m_localPointB;

  // Lift every vertex by 0.1 m: the box now overlaps by 0.1 more, and is put back on top.
  std::vector<PfxFloat> lifted = grid.vertices;
  for (std::size_t v = 1; v < lifted.size(); v += 3) lifted[v] += PfxFloat(0.1);
  const PfxFloat before = world.getRigidState(box).getPosition().y();
  ASSERT_EQ(world.updateLargeTriMesh(ground, owner.mesh, lifted.data(), grid.numVertices()), PFX_OK);
  const PfxVector3 anchorAfter = groundIsA ? manifold->getContactPoint(0).m_localPointA
                                           : manifold->getContactPoint(0).m_localPointB;
  EXPECT_NEAR(anchorAfter.y() - anchorBefore.y(), 0.1, 1e-5);
  EXPECT_NEAR(anchorAfter.x(), anchorBefore.x(), 1e-5);
  EXPECT_NEAR(world.getRigidState(box).getPosition().y() - before, 0.1, 1e-4);
  // The bounds of the ground followed.
  EXPECT_NEAR(world.getCollidable(ground).getCenter().y(), 0.1, 1e-5);

  // Bad calls change nothing: a wrong body, a wrong count.
  EXPECT_EQ(world.updateLargeTriMesh(box, owner.mesh, lifted.data(), grid.numVertices()),
            PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(world.updateLargeTriMesh(99, owner.mesh, lifted.data(), grid.numVertices()),
            PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(world.updateLargeTriMesh(ground, owner.mesh, lifted.data(), 3), PFX_ERR_OUT_OF_RANGE);

  for (int i = 0; i < 60; ++i) ASSERT_EQ(world.step(), PFX_OK);
  EXPECT_NEAR(world.getRigidState(box).getPosition().y(), restY + 0.1, 6e-3);
}

}  // namespace

// Cylinders of many sizes dropped, rolling and tipping onto the ground (a 100 m slab, a
// mesh of two 100 m triangles, a grid of 0.5 m cells): in no step does the world report an
// overlap beyond the one the cylinder had when the step measured its contacts. (A thin
// cylinder rolling on the slab was reported 50 m deep for one step, and missed 2 cm; on
// the two triangles cylinders were reported up to 10 cm deeper than they were.)
TEST(MeshContacts, CylindersOnTheGroundReportNoFalseOverlap) {
  MeshSource twoTriangles;
  twoTriangles.vertices = {-50, 0, -50, 50, 0, -50, 50, 0, 50, -50, 0, 50};
  twoTriangles.triangles = {0, 3, 2, 0, 2, 1};
  const MeshSource grid = makeFlatGrid(40, PfxFloat(0.5));
  MeshOwner large, fine;
  ASSERT_EQ(pfxCreateLargeTriMesh(large.mesh, twoTriangles.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
  ASSERT_EQ(pfxCreateLargeTriMesh(fine.mesh, grid.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
  std::mt19937 random(7);
  std::uniform_real_distribution<PfxFloat> uniform(-1, 1);
  for (const int ground : {0, 1, 2}) {
    PfxFloat worstExcess = 0;
    for (int trial = 0; trial < 40; ++trial) {
      PfxWorldParam param;
      param.enableSleep = false;
      param.worldExtent = PfxVector3::Constant(60);
      param.timeStep = trial % 2 ? PfxFloat(1) / 240 : PfxFloat(1) / 60;
      PfxWorld world;
      ASSERT_EQ(world.initialize(param), PFX_OK);
      if (ground == 0) {
        PfxBodyInit slab;
        slab.mass = 0;
        slab.position = PfxVector3(0, -0.5f, 0);
        ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxBox(50, 0.5f, 50)), slab), PFX_OK);
      } else {
        addGround(world, ground == 1 ? large.mesh : fine.mesh);
      }
      const PfxFloat halfLength = 0.02f + 0.2f * (uniform(random) + 1);
      const PfxFloat radius = 0.02f + 0.1f * (uniform(random) + 1);
      // How far the cylinder reaches below its centre with its axis (X) turned to `axis`.
      const auto reachBelowCentre = [&](const PfxVector3& axis) {
        return std::abs(axis.y()) * halfLength +
               radius * std::sqrt(std::max(PfxFloat(0), 1 - axis.y() * axis.y()));
      };
      PfxBodyInit init;
      init.mass = 1;
      const PfxVector3 turn{uniform(random), uniform(random), uniform(random)};
      init.orientation = PfxQuat(Eigen::AngleAxis<PfxFloat>(3 * uniform(random), turn.normalized()));
      init.position = PfxVector3{0.3f * uniform(random),
                                 reachBelowCentre(init.orientation * PfxVector3::UnitX()) +
                                     0.01f * (uniform(random) + 1),
                                 0.3f * uniform(random)};
      init.angularVelocity = 2 * PfxVector3{uniform(random), uniform(random), uniform(random)};
      init.linearVelocity = PfxVector3{uniform(random), 0, uniform(random)};
      PfxUInt32 id = 0;
      ASSERT_EQ(pfxAddBody(world, pfxMakeShape(PfxCylinder(halfLength, radius)), init, &id),
                PFX_OK);
      for (int step = 0; step < 240; ++step) {
        // The step measures its contacts before it moves the bodies.
        const PfxRigidState before = world.getRigidState(id);
        ASSERT_EQ(world.step(), PFX_OK);
        const PfxFloat trueOverlap =
            std::max(PfxFloat(0), reachBelowCentre(before.getOrientation() * PfxVector3::UnitX()) -
                                      before.getPosition().y());
        const PfxFloat excess = world.getStats().maxPenetration - trueOverlap;
        EXPECT_LT(excess, 1e-3f) << "trial " << trial << ", step " << step;
        worstExcess = std::max(worstExcess, excess);
      }
    }
    std::printf("cylinders on %s: reported overlap beyond the true one at most %.2e m\n",
                ground == 0 ? "a 100 m slab" : ground == 1 ? "two 100 m triangles" : "a grid",
                worstExcess);
  }
}
