#include "bench_octomap.h"

#include <cmath>
#include <cstdio>
#include <random>

#include "bench_rays.h"
#include "bench_run.h"

#ifdef PFX_BENCH_HAVE_LOADERS
#include "pfx/loaders/pfx_octomap_loader.h"
#endif

namespace pfxbench {

#ifdef PFX_BENCH_HAVE_LOADERS

int runOctomapScene(std::vector<ResultRow>& rows) {
  using namespace pfx;
  const std::string path = std::string(PFX_SOURCE_DIR) + "/tests/loaders/data/room.bt";
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
  PfxWorld world;
  PfxOctomap map;
  std::string message;
  const double loadStart = processCpuSeconds();
  if (world.initialize(param) != PFX_OK ||
      pfxLoadOctomapFile(world, path, PfxOctomapLoadParam(), map, &message) != PFX_OK) {
    std::fprintf(stderr, "octomap: FAILED: %s\n", message.c_str());
    return 1;
  }
  const double loadSeconds = processCpuSeconds() - loadStart;

  // Start points over the map's bounds at 1.5 m, below the walls' tops, so every ray stays
  // in the room or its walls; each ray is 3 m long and ends below the floor.
  const PfxVector3 low = map.mesh.m_aabbMin, high = map.mesh.m_aabbMax;
  constexpr int kRays = 100000;
  std::mt19937 random(12345);
  auto uniform = [&](double a, double b) {
    return a + (b - a) * (static_cast<double>(random()) / 4294967296.0);
  };
  std::vector<PfxRayInput> in(kRays);
  std::vector<PfxRayOutput> out(kRays);
  for (PfxRayInput& ray : in) {
    const double tilt = uniform(0, 30 * M_PI / 180), heading = uniform(0, 2 * M_PI);
    const PfxVector3 down(static_cast<PfxFloat>(std::sin(tilt) * std::cos(heading)),
                          static_cast<PfxFloat>(std::sin(tilt) * std::sin(heading)),
                          static_cast<PfxFloat>(-std::cos(tilt)));
    ray.reset();
    ray.m_startPosition = PfxVector3(static_cast<PfxFloat>(uniform(low.x(), high.x())),
                                     static_cast<PfxFloat>(uniform(low.y(), high.y())),
                                     low.z() + PfxFloat(1.5));
    ray.m_direction = down * PfxFloat(3);
  }
  RayDistances unused(1);
  PfxInt32 err = PFX_OK;
  const double seconds = timeFastestPass(unused, [&](RayDistances&) {
    err = world.castRays(in.data(), out.data(), kRays);
  });
  if (err != PFX_OK) {
    std::fprintf(stderr, "octomap: FAILED: castRays: %s\n", pfxErrorString(err));
    return 1;
  }
  int hits = 0;
  for (const PfxRayOutput& o : out) hits += o.m_contactFlag ? 1 : 0;
  auto row = [&](const char* metric, double wall, double value) {
    rows.push_back(ResultRow{kOctomapSceneName, "pfx", "room.bt", 0, 1, 1, 1, wall, metric, value});
  };
  row("load_s", loadSeconds, loadSeconds);
  row("triangles", loadSeconds, map.mesh.m_numTriangles);
  row("rays_per_s", seconds, kRays / seconds);
  row("hits", seconds, static_cast<double>(hits) / kRays);
  std::fprintf(stderr, "octomap: %llu voxels -> %u triangles in %.4f s; %.3g rays/s, %d of %d hit\n",
               static_cast<unsigned long long>(map.numOccupiedVoxels), map.mesh.m_numTriangles,
               loadSeconds, kRays / seconds, hits, kRays);
  return 0;
}

#else

int runOctomapScene(std::vector<ResultRow>&) {
  std::fprintf(stderr, "octomap: skipped, built without the loaders (liboctomap-dev)\n");
  return 0;
}

#endif

}  // namespace pfxbench
