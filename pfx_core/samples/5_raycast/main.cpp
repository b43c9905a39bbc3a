// Sample 5_raycast: the seed's three raycast scenes, headless, and a measure of speed.
// (1) A range sensor in a scene of shapes that fell onto a floor: a 360 x 16 beam scan
//     whose every answer is checked against testing every body in turn. (2) One ray onto
//     each shape type, a compound and a large mesh included, checked against the hit point
//     and normal worked out by hand. (3) Contact filters: a ray that looks for one group
//     finds that group's body, and a ray that drops each group it has seen lists every
//     body along its path, nearest first. (4) Rays per second, one at a time and in a
//     batch, among 1,000 mixed bodies, through the world's hierarchy and through the seed's
//     six sorted proxy arrays.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/base_level/raycast/pfx_ray_shapes.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/low_level/broadphase/pfx_update_broadphase_proxies.h"
#include "pfx/low_level/raycast/pfx_cast_rays.h"

using namespace pfx;

namespace {

using Clock = std::chrono::steady_clock;

PfxRayInput makeRay(const PfxVector3& start, const PfxVector3& direction) {
  PfxRayInput ray;
  ray.reset();
  ray.m_startPosition = start;
  ray.m_direction = direction;
  return ray;
}

// Regular icosahedron, vertices (0, +-1, +-phi) and their cyclic permutations; its 20
// faces are the triples of vertices 2 apart from each other.
PfxConvexMesh makeIcosahedron() {
  const PfxFloat phi = (1 + std::sqrt(PfxFloat(5))) / 2;
  std::vector<PfxFloat> v;
  for (int perm = 0; perm < 3; ++perm) {
    for (int s1 = -1; s1 <= 1; s1 += 2) {
      for (int s2 = -1; s2 <= 1; s2 += 2) {
        const PfxFloat p[3] = {0, PfxFloat(s1), s2 * phi};
        v.insert(v.end(), {p[perm % 3], p[(1 + perm) % 3], p[(2 + perm) % 3]});
      }
    }
  }
  auto adjacent = [&](int a, int b) {
    PfxFloat d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (v[3 * a + k] - v[3 * b + k]) * (v[3 * a + k] - v[3 * b + k]);
    return std::abs(d2 - 4) < 1e-3f;
  };
  std::vector<PfxUInt16> indices;
  for (int a = 0; a < 12; ++a) {
    for (int b = a + 1; b < 12; ++b) {
      for (int c = b + 1; c < 12; ++c) {
        if (adjacent(a, b) && adjacent(b, c) && adjacent(a, c)) {
          indices.insert(indices.end(), {PfxUInt16(a), PfxUInt16(b), PfxUInt16(c)});
        }
      }
    }
  }
  PfxConvexMesh mesh;
  pfxCreateConvexMesh(mesh, v.data(), 12, indices.data(), PfxUInt32(indices.size()));
  return mesh;
}

// The closest hit found by testing every body of the world in id order: the reference
// for the world's walk over its proxy arrays.
PfxRayOutput castEveryBody(const PfxWorld& world, const PfxRayInput& ray) {
  PfxRayOutput closest;
  closest.setMiss(ray);
  for (PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    const PfxRigidState& state = world.getRigidState(id);
    if (!pfxContactFiltersMatch(ray.m_contactFilterSelf, ray.m_contactFilterTarget,
                                state.getContactFilterSelf(), state.getContactFilterTarget())) {
      continue;
    }
    PfxRayOutput hit;
    if (pfxRayCastCollidable(ray, world.getCollidable(id), state.getTransform(),
                             closest.m_variable, hit) &&
        (!closest.m_contactFlag || hit.m_variable < closest.m_variable)) {
      closest = hit;
      closest.m_objectId = id;
    }
  }
  return closest;
}

bool sameAnswer(const PfxRayOutput& a, const PfxRayOutput& b) {
  return a.m_contactFlag == b.m_contactFlag && a.m_objectId == b.m_objectId &&
         a.m_shapeId == b.m_shapeId && a.m_variable == b.m_variable &&
         a.m_contactPoint == b.m_contactPoint && a.m_contactNormal == b.m_contactNormal;
}

// (1) A range sensor 1.5 m above the floor in the middle of fallen shapes.
bool sensorScene(const PfxConvexMesh& icosahedron) {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  PfxBodyInit floor;
  floor.mass = 0;
  floor.position = PfxVector3(0, -0.5f, 0);
  pfxAddBody(world, pfxMakeShape(PfxBox(15, 0.5f, 15)), floor);
  const PfxShape shapes[5] = {pfxMakeShape(PfxSphere(0.4f)), pfxMakeShape(PfxBox(0.4f, 0.3f, 0.5f)),
                              pfxMakeShape(PfxCapsule(0.4f, 0.25f)), pfxMakeShape(PfxCylinder(0.3f, 0.4f)),
                              pfxMakeShape(&icosahedron)};
  std::mt19937 rng(1);
  std::uniform_real_distribution<PfxFloat> spread(-8, 8);
  for (int i = 0; i < 80; ++i) {
    PfxBodyInit init;
    init.position = PfxVector3(spread(rng), 1 + 0.5f * PfxFloat(i % 8), spread(rng));
    if (init.position.head<2>().norm() < 1.5f) init.position.x() += 3;
    PfxShape shape = shapes[i % 5];
    if (shape.getType() == kPfxShapeConvexMesh) {
      init.mass = 3;
    }
    pfxAddBody(world, shape, init);
  }
  for (int i = 0; i < 180; ++i) world.step();

  const PfxVector3 sensor(0, 1.5f, 0);
  const int numAzimuths = 360, numElevations = 16;
  const PfxFloat range = 30;
  std::vector<PfxRayInput> rays;
  for (int e = 0; e < numElevations; ++e) {
    const PfxFloat elevation = (-15 + 2 * PfxFloat(e)) * PFX_PI / 180;
    for (int a = 0; a < numAzimuths; ++a) {
      const PfxFloat azimuth = PfxFloat(a) * PFX_PI / 180;
      const PfxVector3 beam(std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                            std::cos(elevation) * std::sin(azimuth));
      rays.push_back(makeRay(sensor, beam * range));
    }
  }
  std::vector<PfxRayOutput> hits(rays.size());
  const Clock::time_point start = Clock::now();
  const PfxInt32 err = world.castRays(rays.data(), hits.data(), PfxUInt32(rays.size()));
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  int numHits = 0, onFloor = 0, agree = 0;
  PfxFloat nearest = range, farthest = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    agree += sameAnswer(hits[i], castEveryBody(world, rays[i])) ? 1 : 0;
    if (!hits[i].m_contactFlag) continue;
    ++numHits;
    onFloor += hits[i].m_objectId == 0 ? 1 : 0;
    const PfxFloat distance = hits[i].m_variable * range;
    nearest = std::min(nearest, distance);
    farthest = std::max(farthest, distance);
  }
  std::printf("sensor: %zu beams (360 x 16, range %.0f m) in %.2f ms, first cast of the step "
              "included: %d hit, %d of them the floor, nearest %.2f m, farthest %.2f m;\n"
              "        %d of %zu answers equal testing every one of the %u bodies\n",
              rays.size(), range, seconds * 1e3, numHits, onFloor, nearest, farthest, agree,
              rays.size(), world.getNumRigidBodies());
  return err == PFX_OK && agree == int(rays.size()) && numHits > 0 && onFloor > 0;
}

struct Expected {
  const char* name;
  PfxRayInput ray;
  PfxVector3 point;
  PfxVector3 normal;
  PfxUInt32 shapeId;
  PfxUInt32 triangle;
};

// (2) One ray onto each kind of shape, each answer worked out by hand.
bool everyShapeScene(const PfxConvexMesh& icosahedron) {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  std::vector<Expected> expected;
  const PfxVector3 down(0, -10, 0);
  auto addFixed = [&](const PfxShape* shapes, PfxUInt32 n, const PfxVector3& position,
                      const PfxQuat& orientation) {
    PfxBodyInit init;
    init.mass = 0;
    init.position = position;
    init.orientation = orientation;
    PfxUInt32 id;
    pfxAddBody(world, shapes, n, init, &id);
    return id;
  };
  const PfxQuat turnY(Eigen::AngleAxis<PfxFloat>(0.7f, PfxVector3::UnitY()));
  // Sphere r 0.5 at (-9, 1, 0): straight down onto its top, y = 1.5.
  PfxShape s = pfxMakeShape(PfxSphere(0.5f));
  addFixed(&s, 1, PfxVector3(-9, 1, 0), PfxQuat::Identity());
  expected.push_back({"sphere", makeRay(PfxVector3(-9, 5, 0), down), PfxVector3(-9, 1.5f, 0),
                      PfxVector3(0, 1, 0), 0, PFX_RAY_NO_TRIANGLE});
  // Box (0.5, 0.25, 0.5) turned about Y: its top stays at y = 1.25.
  s = pfxMakeShape(PfxBox(0.5f, 0.25f, 0.5f));
  addFixed(&s, 1, PfxVector3(-6, 1, 0), turnY);
  expected.push_back({"box", makeRay(PfxVector3(-6, 5, 0.1f), down), PfxVector3(-6, 1.25f, 0.1f),
                      PfxVector3(0, 1, 0), 0, PFX_RAY_NO_TRIANGLE});
  // Capsule (half length 0.6, r 0.3) along X turned about Y: a ray down 0.4 m along its
  // axis from the centre meets the side's top line, y = 1.3.
  s = pfxMakeShape(PfxCapsule(0.6f, 0.3f));
  addFixed(&s, 1, PfxVector3(-3, 1, 0), turnY);
  const PfxVector3 alongCapsule = turnY * PfxVector3(0.4f, 0, 0);
  expected.push_back({"capsule", makeRay(PfxVector3(-3, 5, 0) + alongCapsule, down),
                      PfxVector3(-3, 1.3f, 0) + alongCapsule, PfxVector3(0, 1, 0), 0,
                      PFX_RAY_NO_TRIANGLE});
  // Cylinder (half length 0.4, r 0.5) stood up (X turned onto Y): the cap at y = 1.4.
  s = pfxMakeShape(PfxCylinder(0.4f, 0.5f));
  addFixed(&s, 1, PfxVector3(0, 1, 0),
           PfxQuat(Eigen::AngleAxis<PfxFloat>(PFX_PI / 2, PfxVector3::UnitZ())));
  expected.push_back({"cylinder", makeRay(PfxVector3(0.2f, 5, 0.1f), down),
                      PfxVector3(0.2f, 1.4f, 0.1f), PfxVector3(0, 1, 0), 0, PFX_RAY_NO_TRIANGLE});
  // Icosahedron at (3, 1, 0): its top edge joins (+-1, phi, 0); the face through it and
  // (0, 1, phi) has the normal (0, phi, 1/phi) / |.| and the plane phi y + z / phi = phi^2,
  // so the ray down at z = 0.3 meets it at y = phi - 0.3 / phi^2.
  s = pfxMakeShape(&icosahedron);
  addFixed(&s, 1, PfxVector3(3, 1, 0), PfxQuat::Identity());
  const PfxFloat phi = (1 + std::sqrt(PfxFloat(5))) / 2;
  expected.push_back({"convex mesh", makeRay(PfxVector3(3, 5, 0.3f), down),
                      PfxVector3(3, 1 + phi - 0.3f / (phi * phi), 0.3f),
                      PfxVector3(0, phi, 1 / phi).normalized(), 0, PFX_RAY_NO_TRIANGLE});
  // Compound of a sphere (r 0.3, 0.5 m to -X) and a box (half 0.3, 0.5 m to +X) at
  // (6, 1, 0): the ray onto the box's side reports shape 1, top at y = 1.3.
  PfxShape compound[2] = {pfxMakeShape(PfxSphere(0.3f)), pfxMakeShape(PfxBox(0.3f, 0.3f, 0.3f))};
  compound[0].setOffsetPosition(PfxVector3(-0.5f, 0, 0));
  compound[1].setOffsetPosition(PfxVector3(0.5f, 0, 0));
  addFixed(compound, 2, PfxVector3(6, 1, 0), PfxQuat::Identity());
  expected.push_back({"compound", makeRay(PfxVector3(6.5f, 5, 0), down), PfxVector3(6.5f, 1.3f, 0),
                      PfxVector3(0, 1, 0), 1, PFX_RAY_NO_TRIANGLE});
  // Large mesh: a 4 x 4 grid of 1 m cells on the slope y = 0.2 x + 0.1 z (exact on every
  // triangle, as the slope is a plane), moved to (9, 0, 0). Cell (i, j) holds triangles
  // 2 (4 j + i) (corners a, d, c: where z - z0 >= x - x0) and 2 (4 j + i) + 1 (corners a,
  // c, b: the rest), a at the cell's low corner (x0, z0). Local (0.7, 0.2) lies in cell
  // i = 2, j = 2 (x0 = z0 = 0), below the diagonal: triangle 2 (4 * 2 + 2) + 1 = 21.
  // Normal (-0.2, 1, -0.1) / |.|.
  std::vector<PfxFloat> vertices;
  std::vector<PfxUInt32> triangles;
  for (int j = 0; j <= 4; ++j) {
    for (int i = 0; i <= 4; ++i) {
      const PfxFloat x = PfxFloat(i) - 2, z = PfxFloat(j) - 2;
      vertices.insert(vertices.end(), {x, 0.2f * x + 0.1f * z, z});
    }
  }
  for (PfxUInt32 j = 0; j < 4; ++j) {
    for (PfxUInt32 i = 0; i < 4; ++i) {
      const PfxUInt32 a = 5 * j + i, b = a + 1, d = a + 5, c = d + 1;
      triangles.insert(triangles.end(), {a, d, c, a, c, b});
    }
  }
  PfxCreateLargeTriMeshParam meshParam;
  meshParam.m_vertices = vertices.data();
  meshParam.m_numVertices = PfxUInt32(vertices.size() / 3);
  meshParam.m_triangles = triangles.data();
  meshParam.m_numTriangles = PfxUInt32(triangles.size() / 3);
  meshParam.m_flags = PFX_MESH_FLAG_USE_BVH;
  PfxLargeTriMesh mesh{};
  if (pfxCreateLargeTriMesh(mesh, meshParam) != PFX_OK) return false;
  PfxShape ground;
  ground.reset();
  ground.setLargeTriMesh(&mesh);
  addFixed(&ground, 1, PfxVector3(9, 0, 0), PfxQuat::Identity());
  expected.push_back({"large mesh", makeRay(PfxVector3(9.7f, 5, 0.2f), down),
                      PfxVector3(9.7f, 0.2f * 0.7f + 0.1f * 0.2f, 0.2f),
                      PfxVector3(-0.2f, 1, -0.1f).normalized(), 0, 21});

  bool ok = true;
  double worst = 0;
  for (PfxUInt32 id = 0; id < expected.size(); ++id) {
    const Expected& e = expected[id];
    PfxRayOutput out;
    if (world.castRay(e.ray, out) != PFX_OK || !out.m_contactFlag) {
      std::printf("every shape: %-11s MISSED\n", e.name);
      ok = false;
      continue;
    }
    const double pointError = (out.m_contactPoint - e.point).norm() / std::max(PfxFloat(1), e.point.norm());
    const double normalError = (out.m_contactNormal - e.normal).norm();
    worst = std::max({worst, pointError, normalError});
    const bool right = out.m_objectId == id && out.m_shapeId == e.shapeId &&
                       out.m_triangleIndex == e.triangle && pointError <= 1e-5 &&
                       normalError <= 1e-5;
    ok = ok && right;
    char triangle[24] = "";
    if (out.m_triangleIndex != PFX_RAY_NO_TRIANGLE) {
      std::snprintf(triangle, sizeof(triangle), " triangle %u", out.m_triangleIndex);
    }
    std::printf("every shape: %-11s body %u shape %u%-12s at (%7.4f, %7.4f, %7.4f) normal "
                "(%6.3f, %6.3f, %6.3f): %s\n",
                e.name, out.m_objectId, out.m_shapeId, triangle,
                out.m_contactPoint.x(), out.m_contactPoint.y(), out.m_contactPoint.z(),
                out.m_contactNormal.x(), out.m_contactNormal.y(), out.m_contactNormal.z(),
                right ? "as worked out" : "WRONG");
  }
  std::printf("every shape: largest error against the hand-worked answers %.1e (relative)\n", worst);
  pfxReleaseLargeTriMesh(mesh);
  return ok;
}

// (3) Five boxes in a row along +X, each in its own contact-filter group (self bit k).
bool filterScene() {
  PfxWorld world;
  world.initialize(PfxWorldParam());
  for (int k = 0; k < 5; ++k) {
    PfxBodyInit init;
    init.mass = 0;
    init.position = PfxVector3(2.0f * PfxFloat(k), 0, 0);
    PfxRigidState state;
    PfxUInt32 id;
    pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), init, &id);
    state = world.getRigidState(id);
    state.setContactFilterSelf(1u << k);
    world.setRigidState(id, state);
  }
  bool ok = true;
  // A ray looking for one group finds that group's box, behind the others.
  std::printf("filters: ray looking for group");
  for (int k = 0; k < 5; ++k) {
    PfxRayInput ray = makeRay(PfxVector3(-3, 0.1f, 0), PfxVector3(15, 0, 0));
    ray.m_contactFilterTarget = 1u << k;
    PfxRayOutput out;
    world.castRay(ray, out);
    std::printf(" %d -> body %u%s", k, out.m_objectId, k < 4 ? "," : "\n");
    ok = ok && out.m_contactFlag && out.m_objectId == PfxUInt32(k);
  }
  // A ray that drops each group it has seen lists the bodies along its path, nearest first.
  PfxRayInput ray = makeRay(PfxVector3(12, 0.1f, 0), PfxVector3(-20, 0, 0));
  std::printf("filters: peeling a ray from x = 12 towards -X finds bodies");
  int found = 0;
  PfxRayOutput out;
  while (world.castRay(ray, out) == PFX_OK && out.m_contactFlag) {
    std::printf(" %u (x = %.1f)", out.m_objectId, out.m_contactPoint.x());
    ok = ok && out.m_objectId == PfxUInt32(4 - found);
    ++found;
    ray.m_contactFilterTarget &= ~world.getRigidState(out.m_objectId).getContactFilterSelf();
  }
  std::printf("\n");
  return ok && found == 5;
}

// (4) Rays per second among 1,000 mixed bodies spread through a 100 m cube: the world's
// hierarchy, the seed's sorted arrays on the same bodies, and testing every body.
bool speedScene(const PfxConvexMesh& icosahedron) {
  PfxWorldParam param;
  param.worldExtent = PfxVector3::Constant(60);
  PfxWorld world;
  world.initialize(param);
  std::mt19937 rng(7);
  std::uniform_real_distribution<PfxFloat> unit(-1, 1);
  std::uniform_real_distribution<PfxFloat> size(0.3f, 1.5f);
  for (int i = 0; i < 1000; ++i) {
    PfxShape shapes[2];
    PfxUInt32 n = 1;
    switch (i % 6) {
      case 0: shapes[0] = pfxMakeShape(PfxSphere(size(rng))); break;
      case 1: shapes[0] = pfxMakeShape(PfxBox(size(rng), size(rng), size(rng))); break;
      case 2: shapes[0] = pfxMakeShape(PfxCapsule(size(rng), size(rng) * 0.5f)); break;
      case 3: shapes[0] = pfxMakeShape(PfxCylinder(size(rng), size(rng))); break;
      case 4: shapes[0] = pfxMakeShape(&icosahedron); break;
      default:
        shapes[0] = pfxMakeShape(PfxSphere(size(rng)));
        shapes[1] = pfxMakeShape(PfxBox(size(rng), size(rng), size(rng)));
        shapes[1].setOffsetPosition(PfxVector3(1.5f, 0, 0));
        n = 2;
        break;
    }
    PfxBodyInit init;
    init.mass = 0;
    init.position = PfxVector3(unit(rng), unit(rng), unit(rng)) * 50;
    init.orientation = PfxQuat(1 + unit(rng), unit(rng), unit(rng), unit(rng)).normalized();
    pfxAddBody(world, shapes, n, init);
  }
  // Rays of 30 m from random points in random directions, as range sensors scattered
  // through the scene would cast them.
  const int numRays = 200000;
  std::vector<PfxRayInput> rays;
  for (int i = 0; i < numRays; ++i) {
    PfxVector3 d(unit(rng), unit(rng), unit(rng));
    while (d.norm() < 0.1f) d = PfxVector3(unit(rng), unit(rng), unit(rng));
    rays.push_back(makeRay(PfxVector3(unit(rng), unit(rng), unit(rng)) * 50, d.normalized() * 30));
  }
  std::vector<PfxRayOutput> single(numRays), batch(numRays), walked(numRays), walkedBatch(numRays);
  Clock::time_point t0 = Clock::now();
  PfxRayOutput first;
  world.castRay(rays[0], first);  // updates the proxies and the hierarchy
  const double buildSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  for (int i = 0; i < numRays; ++i) world.castRay(rays[i], single[i]);
  const double singleSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  world.castRays(rays.data(), batch.data(), numRays);
  const double batchSeconds = std::chrono::duration<double>(Clock::now() - t0).count();

  // The seed's way on the same bodies: six sorted proxy arrays, walked.
  const PfxUInt32 n = world.getNumRigidBodies();
  std::vector<PfxRigidState> states(world.getRigidStates(), world.getRigidStates() + n);
  std::vector<PfxBroadphaseProxy> arrays(7 * std::size_t(n));
  PfxUpdateBroadphaseProxiesParam update;
  update.workBuff = &arrays[6 * std::size_t(n)];
  update.workBytes = pfxGetWorkBytesOfUpdateBroadphaseProxies(n);
  update.offsetRigidStates = states.data();
  update.offsetCollidables = &world.getCollidable(0);
  update.numRigidBodies = n;
  PfxBroadphaseProxy** targets[6] = {&update.proxiesX,  &update.proxiesY,  &update.proxiesZ,
                                     &update.proxiesXb, &update.proxiesYb, &update.proxiesZb};
  for (int k = 0; k < 6; ++k) *targets[k] = &arrays[k * std::size_t(n)];
  update.worldCenter = param.worldCenter;
  update.worldExtent = param.worldExtent;
  PfxUpdateBroadphaseProxiesResult updated;
  t0 = Clock::now();
  pfxUpdateBroadphaseProxies(update, updated);
  const double sortSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  PfxRayCastParam walk;
  walk.offsetRigidStates = states.data();
  walk.offsetCollidables = update.offsetCollidables;
  walk.proxiesX = update.proxiesX;
  walk.proxiesY = update.proxiesY;
  walk.proxiesZ = update.proxiesZ;
  walk.proxiesXb = update.proxiesXb;
  walk.proxiesYb = update.proxiesYb;
  walk.proxiesZb = update.proxiesZb;
  walk.numProxies = updated.numProxies;
  walk.rangeCenter = param.worldCenter;
  walk.rangeExtent = param.worldExtent;
  t0 = Clock::now();
  for (int i = 0; i < numRays; ++i) pfxCastSingleRay(rays[i], walked[i], walk);
  const double walkSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  pfxCastRays(rays.data(), walkedBatch.data(), numRays, walk);
  const double walkBatchSeconds = std::chrono::duration<double>(Clock::now() - t0).count();

  const int numBrute = 5000;
  t0 = Clock::now();
  int agree = 0, hits = 0;
  for (int i = 0; i < numBrute; ++i) agree += sameAnswer(castEveryBody(world, rays[i]), single[i]) ? 1 : 0;
  const double bruteSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  bool same = true;
  for (int i = 0; i < numRays; ++i) {
    same = same && sameAnswer(single[i], batch[i]) && sameAnswer(single[i], walked[i]) &&
           sameAnswer(single[i], walkedBatch[i]);
    hits += single[i].m_contactFlag ? 1 : 0;
  }
  std::printf("speed: 1,000 mixed bodies in a 100 m cube, %d rays of 30 m from random points, "
              "%d hit; one thread:\n"
              "       hierarchy (PfxWorld)   single %8.0f rays/s, batch %8.0f rays/s; proxies and "
              "hierarchy updated in %.3f ms\n"
              "       six sorted arrays      single %8.0f rays/s, batch %8.0f rays/s; arrays sorted "
              "in %.3f ms\n"
              "       testing every body     single %8.0f rays/s\n"
              "       all answers equal: %s; %d of %d equal testing every body\n",
              numRays, hits, numRays / singleSeconds, numRays / batchSeconds, buildSeconds * 1e3,
              numRays / walkSeconds, numRays / walkBatchSeconds, sortSeconds * 1e3,
              numBrute / bruteSeconds, same ? "yes" : "NO", agree, numBrute);
  return same && agree == numBrute;
}

}  // namespace

int main() {
  const PfxConvexMesh icosahedron = makeIcosahedron();
  const bool a = sensorScene(icosahedron);
  const bool b = everyShapeScene(icosahedron);
  const bool c = filterScene();
  const bool d = speedScene(icosahedron);
  std::printf("%s\n", a && b && c && d ? "every ray answered as expected" : "A RAY WAS ANSWERED WRONGLY");
  return a && b && c && d ? 0 : 1;
}
