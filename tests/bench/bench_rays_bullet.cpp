// The rays scene on Bullet: the terrain as a btBvhTriangleMeshShape (quantized AABB
// compression on) over a btTriangleIndexVertexArray that reads the terrain's arrays in
// place, cast through a btCollisionWorld (rayTest, ClosestRayResultCallback) and straight
// into the shape (performRaycast).
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletCollisionCommon.h>
#include <malloc.h>

#include <memory>
#include <string>
#include <vector>

#include "bench_rays.h"

namespace pfxbench {

namespace {

// Heap bytes in use, both from the arenas and mapped directly.
double heapBytesInUse() {
  const struct mallinfo2 info = mallinfo2();
  return double(info.uordblks) + double(info.hblkhd);
}

// The closest triangle a ray meets; every hit shortens the ray to it.
class ClosestTriangleCallback : public btTriangleRaycastCallback {
 public:
  ClosestTriangleCallback(const btVector3& from, const btVector3& to)
      : btTriangleRaycastCallback(from, to) {}
  btScalar reportHit(const btVector3&, btScalar hitFraction, int, int) override {
    hit = true;
    return hitFraction;
  }
  bool hit = false;
};

}  // namespace

bool runBulletRays(const RayTerrain& terrain, const RaySet& rays, RayEngineFigures& figures,
                   std::string&) {
  // Bullet reads the terrain's own arrays: indices as int, vertices as btScalar.
  static_assert(sizeof(int) == sizeof(std::uint32_t), "indices are shared with Bullet as int");
  static_assert(sizeof(btScalar) == sizeof(float), "vertices are shared with Bullet as float");
  const double heapBefore = heapBytesInUse();
  const double start = processCpuSeconds();
  auto vertexArray = std::make_unique<btTriangleIndexVertexArray>(
      int(terrain.numTriangles()),
      const_cast<int*>(reinterpret_cast<const int*>(terrain.triangles.data())), int(3 * sizeof(int)),
      int(terrain.numVertices()), const_cast<btScalar*>(terrain.vertices.data()),
      int(3 * sizeof(btScalar)));
  auto shape = std::make_unique<btBvhTriangleMeshShape>(vertexArray.get(), true, true);
  RayBuildFigures build{"bullet", "quantized_bvh", 0, 0};
  build.buildSeconds = processCpuSeconds() - start;
  const double sharedArrayBytes = double(terrain.vertices.size() * sizeof(float) +
                                         terrain.triangles.size() * sizeof(std::uint32_t));
  build.bytesPerTriangle =
      (heapBytesInUse() - heapBefore + sharedArrayBytes) / double(terrain.numTriangles());
  figures.builds.push_back(build);

  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &configuration);
  btCollisionObject ground;
  ground.setCollisionShape(shape.get());
  world.addCollisionObject(&ground);

  std::vector<btVector3> from(rays.size()), to(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    from[i] = btVector3(rays.starts[3 * i], rays.starts[3 * i + 1], rays.starts[3 * i + 2]);
    to[i] = from[i] + btVector3(rays.directions[3 * i], rays.directions[3 * i + 1],
                                rays.directions[3 * i + 2]);
  }

  RayCastFigures throughWorld{"bullet", "quantized_bvh", 0, RayDistances(rays.size())};
  throughWorld.secondsPerBatch = timeFastestPass(throughWorld.distances, [&](RayDistances& out) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
      btCollisionWorld::ClosestRayResultCallback result(from[i], to[i]);
      world.rayTest(from[i], to[i], result);
      out[i] = result.hasHit() ? result.m_closestHitFraction * rays.lengths[i] : kRayMiss;
    }
  });
  figures.casts.push_back(std::move(throughWorld));

  RayCastFigures intoShape{"bullet_shape", "quantized_bvh", 0, RayDistances(rays.size())};
  intoShape.secondsPerBatch = timeFastestPass(intoShape.distances, [&](RayDistances& out) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ClosestTriangleCallback result(from[i], to[i]);
      shape->performRaycast(&result, from[i], to[i]);
      out[i] = result.hit ? result.m_hitFraction * rays.lengths[i] : kRayMiss;
    }
  });
  figures.casts.push_back(std::move(intoShape));

  world.removeCollisionObject(&ground);
  return true;
}

}  // namespace pfxbench
