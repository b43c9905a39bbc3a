#include "bench_mesh_floor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#ifdef PFX_BENCH_HAVE_LOADERS
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/loaders/pfx_urdf_loader.h"
#endif

namespace pfxbench {

#ifdef PFX_BENCH_HAVE_LOADERS

namespace {

using namespace pfx;

constexpr int kCells = 40;               // per side
constexpr PfxFloat kCell = PfxFloat(0.2);  // m
constexpr PfxFloat kBump = PfxFloat(0.05);  // m
constexpr int kStepsPerSecond = 240;

PfxFloat terrainHeight(PfxFloat x, PfxFloat y) {
  return kBump * std::sin(PfxFloat(1.3) * x) * std::cos(PfxFloat(1.1) * y);
}

struct Terrain {
  std::vector<PfxFloat> vertices;
  std::vector<PfxUInt32> triangles;
  PfxLargeTriMesh mesh{};
  ~Terrain() { pfxReleaseLargeTriMesh(mesh); }

  PfxInt32 build() {
    const PfxFloat origin = -kCells * kCell / 2;
    for (int j = 0; j <= kCells; ++j) {
      for (int i = 0; i <= kCells; ++i) {
        const PfxFloat x = origin + PfxFloat(i) * kCell, y = origin + PfxFloat(j) * kCell;
        vertices.insert(vertices.end(), {x, y, terrainHeight(x, y)});
      }
    }
    for (int j = 0; j < kCells; ++j) {
      for (int i = 0; i < kCells; ++i) {
        const PfxUInt32 a = j * (kCells + 1) + i, b = a + 1, c = a + kCells + 2, d = a + kCells + 1;
        triangles.insert(triangles.end(), {a, b, c, a, c, d});  // facing +Z
      }
    }
    PfxCreateLargeTriMeshParam param;
    param.m_vertices = vertices.data();
    param.m_numVertices = static_cast<PfxUInt32>(vertices.size() / 3);
    param.m_triangles = triangles.data();
    param.m_numTriangles = static_cast<PfxUInt32>(triangles.size() / 3);
    param.m_flags = PFX_MESH_FLAG_USE_BVH;
    return pfxCreateLargeTriMesh(mesh, param);
  }
};

// Returns false (and says why) when the scene cannot be built or stepped.
bool runVariant(bool onMesh, const Terrain& terrain, std::vector<ResultRow>& rows) {
  const char* variant = onMesh ? "mesh" : "box";
  PfxWorldParam param;
  param.gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
  param.timeStep = PfxFloat(1) / kStepsPerSecond;
  param.iteration = 10;
  param.enableSleep = false;
  param.measureStages = true;  // the collision detection's share of the step
  PfxWorld world;
  if (world.initialize(param) != PFX_OK) return false;
  PfxBodyInit ground;
  ground.mass = 0;
  PfxShape shape;
  if (onMesh) {
    shape.reset();
    shape.setLargeTriMesh(&terrain.mesh);
  } else {
    const PfxFloat half = kCells * kCell / 2;
    shape = pfxMakeShape(PfxBox(half, half, kBump));
  }
  if (pfxAddBody(world, shape, ground) != PFX_OK) return false;
  const std::string urdf = std::string(PFX_SOURCE_DIR) + "/urdf/zoo/quadruped.urdf";
  PfxUrdfModel model;
  std::string message;
  if (pfxLoadUrdfFile(world, urdf, PfxUrdfLoadParam(), model, &message) != PFX_OK) {
    std::fprintf(stderr, "meshfloor: FAILED: %s\n", message.c_str());
    return false;
  }
  // Feet 2 cm above the bumps' tops.
  PfxFloat lowest = std::numeric_limits<PfxFloat>::max();
  for (PfxUInt32 id = model.firstBodyId; id < world.getNumRigidBodies(); ++id) {
    PfxVector3 centre, half;
    world.getCollidable(id).getWorldAabb(world.getRigidState(id).getTransform(), centre, half);
    lowest = std::min(lowest, centre.z() - half.z());
  }
  for (PfxUInt32 id = model.firstBodyId; id < world.getNumRigidBodies(); ++id) {
    PfxRigidState state = world.getRigidState(id);
    state.setPosition(state.getPosition() + PfxVector3(0, 0, kBump + PfxFloat(0.02) - lowest));
    if (world.setRigidState(id, state) != PFX_OK) return false;
  }
  double stepSeconds = 0, detectSeconds = 0;
  PfxFloat deepest = 0;
  constexpr int kSettle = kStepsPerSecond, kMeasured = 2 * kStepsPerSecond;
  for (int step = 0; step < kSettle + kMeasured; ++step) {
    if (world.step() != PFX_OK) {
      std::fprintf(stderr, "meshfloor: FAILED: step %d on the %s\n", step, variant);
      return false;
    }
    if (step < kSettle) continue;
    const PfxWorldStats& stats = world.getStats();
    stepSeconds += stats.stepSeconds;
    detectSeconds += stats.stageSeconds[kPfxStageDetectCollision];
    deepest = std::max(deepest, stats.maxPenetration);
  }
  const double wall = stepSeconds / (kMeasured / double(kStepsPerSecond));
  auto row = [&](const char* metric, double value) {
    rows.push_back(ResultRow{kMeshFloorSceneName, "pfx", variant, param.timeStep, 1,
                             static_cast<int>(param.iteration), 1, wall, metric, value});
  };
  row("step_ms", 1e3 * stepSeconds / kMeasured);
  row("detect_ms", 1e3 * detectSeconds / kMeasured);
  row("penetration_max", deepest);
  std::fprintf(stderr, "meshfloor: quadruped on the %s: %.3f ms a step, %.3f ms detecting\n",
               onMesh ? "3,200-triangle terrain" : "terrain's bounding box",
               1e3 * stepSeconds / kMeasured, 1e3 * detectSeconds / kMeasured);
  return true;
}

}  // namespace

int runMeshFloorScene(std::vector<ResultRow>& rows) {
  Terrain terrain;
  if (terrain.build() != PFX_OK) {
    std::fprintf(stderr, "meshfloor: FAILED: the terrain mesh\n");
    return 1;
  }
  int failures = 0;
  for (const bool onMesh : {true, false}) failures += runVariant(onMesh, terrain, rows) ? 0 : 1;
  return failures;
}

#else

int runMeshFloorScene(std::vector<ResultRow>&) {
  std::fprintf(stderr, "meshfloor: skipped, built without the loaders\n");
  return 0;
}

#endif

}  // namespace pfxbench
