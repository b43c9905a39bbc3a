#include "bench_rays.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace pfxbench {

namespace {

constexpr int kCellsPerSide = 512;
constexpr double kCellSize = 1.0;
constexpr std::size_t kRayCount = 100000;
constexpr unsigned kRaySeed = 6;
// Rays start this high, well above the highest point of the terrain (10 m).
constexpr double kRayStartHeight = 40;
constexpr double kRayLength = 100;
constexpr double kMaxTilt = 30 * 3.14159265358979323846 / 180;
// Starting points keep this far from the edge, beyond the 50 m a tilted ray travels
// sideways, so every ray meets the terrain.
constexpr double kRayMargin = 56;
constexpr double kDistanceTolerance = 1e-4;

double terrainHeight(double x, double z) {
  return 6.0 * std::sin(0.031 * x) * std::cos(0.027 * z) +
         2.5 * std::sin(0.11 * x + 0.7) * std::sin(0.093 * z + 1.3) +
         0.8 * std::sin(0.37 * x + 0.29 * z) + 0.3 * std::cos(0.9 * x - 0.7 * z);
}

// Uniform in [0, 1) from the generator's raw 32 bits, which the standard fixes, unlike
// the algorithms of its distributions.
double unit(std::mt19937& rng) { return double(rng() >> 8) * (1.0 / 16777216.0); }

struct Agreement {
  std::size_t mismatches = 0;
  double largestError = 0;
};

Agreement compareDistances(const RayDistances& reference, const RayDistances& distances) {
  Agreement agreement;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const bool referenceHit = reference[i] != kRayMiss;
    const bool hit = distances[i] != kRayMiss;
    if (referenceHit != hit) {
      ++agreement.mismatches;
      continue;
    }
    if (!hit) continue;
    const double error = std::abs(distances[i] - reference[i]);
    agreement.largestError = std::max(agreement.largestError, error);
    if (!(error <= kDistanceTolerance)) ++agreement.mismatches;
  }
  return agreement;
}

ResultRow makeRow(const std::string& engine, const std::string& variant, double wallSeconds,
                  const char* metric, double value) {
  ResultRow row;
  row.scene = kRaySceneName;
  row.engine = engine;
  row.variant = variant;
  row.dt = 0;
  row.substeps = 1;
  row.iterations = 1;
  row.threads = 1;
  row.wallSecondsPerSimSecond = wallSeconds;
  row.metric = metric;
  row.value = value;
  return row;
}

using RayAdapter = bool (*)(const RayTerrain&, const RaySet&, RayEngineFigures&, std::string&);

struct RayEngine {
  const char* name;
  RayAdapter run;  // null when the engine's library was not found
};

const std::vector<RayEngine>& rayEngines() {
  static const std::vector<RayEngine> engines = {
      {"pfx", runPfxRays},
#ifdef PFX_BENCH_HAVE_BULLET
      {"bullet", runBulletRays},
#else
      {"bullet", nullptr},
#endif
#ifdef PFX_BENCH_HAVE_EMBREE
      {"embree", runEmbreeRays},
#else
      {"embree", nullptr},
#endif
  };
  return engines;
}

}  // namespace

RayTerrain makeRayTerrain() {
  RayTerrain terrain;
  const int side = kCellsPerSide + 1;
  const double half = 0.5 * kCellsPerSide * kCellSize;
  terrain.vertices.reserve(3 * std::size_t(side) * side);
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const double x = -half + i * kCellSize, z = -half + j * kCellSize;
      terrain.vertices.insert(terrain.vertices.end(),
                              {float(x), float(terrainHeight(x, z)), float(z)});
    }
  }
  terrain.triangles.reserve(6 * std::size_t(kCellsPerSide) * kCellsPerSide);
  for (int j = 0; j < kCellsPerSide; ++j) {
    for (int i = 0; i < kCellsPerSide; ++i) {
      // Corners at (x, z), (x + 1, z), (x, z + 1), (x + 1, z + 1); seen from +Y, with X to
      // the right, +Z points down the page, so (a, c, b) runs counter-clockwise.
      const std::uint32_t a = std::uint32_t(j * side + i), b = a + 1, c = a + side, d = c + 1;
      terrain.triangles.insert(terrain.triangles.end(), {a, c, b, b, c, d});
    }
  }
  return terrain;
}

RaySet makeTerrainRays(std::size_t count) {
  RaySet rays;
  std::mt19937 rng(kRaySeed);
  const double reach = 0.5 * kCellsPerSide * kCellSize - kRayMargin;
  rays.starts.reserve(3 * count);
  rays.directions.reserve(3 * count);
  rays.lengths.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const double x = (2 * unit(rng) - 1) * reach;
    const double z = (2 * unit(rng) - 1) * reach;
    // Uniform over the cap of directions within kMaxTilt of straight down.
    const double cosTilt = 1 - unit(rng) * (1 - std::cos(kMaxTilt));
    const double sinTilt = std::sqrt(std::max(0.0, 1 - cosTilt * cosTilt));
    const double azimuth = 2 * 3.14159265358979323846 * unit(rng);
    const float dx = float(kRayLength * sinTilt * std::cos(azimuth));
    const float dy = float(-kRayLength * cosTilt);
    const float dz = float(kRayLength * sinTilt * std::sin(azimuth));
    rays.starts.insert(rays.starts.end(), {float(x), float(kRayStartHeight), float(z)});
    rays.directions.insert(rays.directions.end(), {dx, dy, dz});
    rays.lengths.push_back(std::sqrt(double(dx) * dx + double(dy) * dy + double(dz) * dz));
  }
  return rays;
}

const std::vector<std::string>& rayEngineNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> list;
    for (const RayEngine& engine : rayEngines()) list.push_back(engine.name);
    return list;
  }();
  return names;
}

bool takeRaySceneRequest(std::vector<std::string>& scenes, std::vector<std::string>& engines,
                         RaySceneRequest& request, std::string& error) {
  request = RaySceneRequest();
  if (scenes.empty()) {
    request.wanted = true;
  } else {
    const auto rays = std::remove(scenes.begin(), scenes.end(), std::string(kRaySceneName));
    request.wanted = rays != scenes.end();
    scenes.erase(rays, scenes.end());
    request.otherScenes = !scenes.empty();
  }
  request.engines = engines;
  const auto embree = std::remove(engines.begin(), engines.end(), std::string("embree"));
  const bool askedForEmbree = embree != engines.end();
  engines.erase(embree, engines.end());
  if (askedForEmbree && engines.empty() && request.otherScenes) {
    error = "embree runs only the rays scene: add --scene rays or another engine";
    return false;
  }
  return true;
}

int runRayScene(const RaySceneRequest& request, std::vector<ResultRow>& rows) {
  std::vector<const RayEngine*> selected;
  const std::vector<std::string>& names =
      request.engines.empty() ? rayEngineNames() : request.engines;
  for (const std::string& name : names) {
    const auto found = std::find_if(rayEngines().begin(), rayEngines().end(),
                                    [&](const RayEngine& e) { return name == e.name; });
    if (found == rayEngines().end()) {
      std::fprintf(stderr, "rays: %s skipped, it has no raycast adapter\n", name.c_str());
    } else if (!found->run) {
      std::fprintf(stderr, "rays: %s skipped, its library was not found when pfx_bench was configured\n",
                   name.c_str());
    } else {
      selected.push_back(&*found);
    }
  }
  if (selected.empty()) return 0;

  const RayTerrain terrain = makeRayTerrain();
  const RaySet rays = makeTerrainRays(kRayCount);
  std::fprintf(stderr, "rays: %zu triangles, %zu vertices, %zu rays\n", terrain.numTriangles(),
               terrain.numVertices(), rays.size());

  // pfx's answers are the reference every engine is checked against, so they are cast
  // even when pfx itself is not asked for.
  RayDistances reference;
  std::string error;
  if (!castPfxReferenceRays(terrain, rays, reference, error)) {
    std::fprintf(stderr, "rays: pfx reference FAILED: %s\n", error.c_str());
    return 1;
  }

  int failures = 0;
  for (const RayEngine* engine : selected) {
    RayEngineFigures figures;
    if (!engine->run(terrain, rays, figures, error)) {
      std::fprintf(stderr, "rays: %s FAILED: %s\n", engine->name, error.c_str());
      ++failures;
      continue;
    }
    for (const RayBuildFigures& build : figures.builds) {
      std::fprintf(stderr, "rays: %-6s %-22s build %8.3f s, %7.2f bytes per triangle\n",
                   build.engine.c_str(), build.variant.c_str(), build.buildSeconds,
                   build.bytesPerTriangle);
      rows.push_back(makeRow(build.engine, build.variant, build.buildSeconds, "build_s",
                             build.buildSeconds));
      rows.push_back(makeRow(build.engine, build.variant, build.buildSeconds,
                             "bytes_per_triangle", build.bytesPerTriangle));
    }
    for (const RayCastFigures& cast : figures.casts) {
      const Agreement agreement = compareDistances(reference, cast.distances);
      const double raysPerSecond = double(rays.size()) / cast.secondsPerBatch;
      std::fprintf(stderr,
                   "rays: %-13s %-22s %11.0f rays/s, %zu mismatches, largest error %.3g m\n",
                   cast.engine.c_str(), cast.variant.c_str(), raysPerSecond,
                   agreement.mismatches, agreement.largestError);
      rows.push_back(makeRow(cast.engine, cast.variant, cast.secondsPerBatch, "rays_per_s",
                             raysPerSecond));
      rows.push_back(makeRow(cast.engine, cast.variant, cast.secondsPerBatch, "mismatches",
                             double(agreement.mismatches)));
      rows.push_back(makeRow(cast.engine, cast.variant, cast.secondsPerBatch,
                             "distance_error_max", agreement.largestError));
    }
  }
  return failures;
}

}  // namespace pfxbench
