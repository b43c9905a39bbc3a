// The `rays` scene: rays per second against a large static triangle mesh, side by side
// for pfx's large mesh in every storage variant, Bullet's btBvhTriangleMeshShape and
// Embree 3. It measures speed, not simulation error, so it does not go through the
// stepping Engine interface: each engine's adapter (bench_rays_<name>.cpp) builds the mesh,
// casts the same rays in each of its ways and hands back build time, memory and the hit
// distances, which are checked against pfx's.
//
// Terrain: 512 x 512 cells of 1 m, two triangles each (524,288 triangles, 513 x 513
// vertices), centred on the origin, height a sum of sines within +-10 m. Rays: 100,000
// from random points 40 m up over the inner 400 x 400 m, pointing down within 30 degrees
// of vertical, 100 m long, so that every ray hits. Both come from fixed seeds and use
// the generator's raw output only, so every machine casts the very same rays.
//
// Time is the process's CPU time (CLOCK_PROCESS_CPUTIME_ID), builds and casts alike: the
// machines this runs on are shared, and wall time there swings by a factor of two with
// other processes' load, while CPU time leaves out the time the process waits for a core.
// With one thread working, as here, it equals the wall time on an idle machine. It still
// moves by some 20% with the load, which shares caches and cores, so compare the figures
// of one run with each other rather than with another run's.
//
// Settings that could not be matched between engines:
// - Threads. Every ray is cast on the calling thread, one at a time or in the engine's
//   batch call, so rays/s are single-threaded throughout. Embree's device is created with
//   "threads=1", which limits its build to one thread too; the log line of its build shows
//   its CPU and wall seconds (more CPU than wall time would mean more threads).
// - Instruction set. pfx and the Debian Bullet are compiled for baseline x86-64 (SSE2);
//   Embree picks its widest kernels (AVX2 or AVX-512) at run time.
// - Precision. All three are single precision. pfx's quantized variants store positions
//   to half a step of (extent / 65535) per axis (about 4 mm here across the 512 m
//   terrain), so their distances are expected to differ from the exact ones by that much.
// - Watertightness. pfx's triangle test is watertight; Bullet widens every triangle by a
//   small tolerance; Embree's default (non-robust) mode is watertight only in practice.
// - Memory. pfx: the mesh's own block (PfxLargeTriMesh::m_bytes), which holds a copy of
//   the vertices and everything its rays need. Bullet: heap bytes in use after building
//   minus before (glibc mallinfo2), plus the caller's vertex and index arrays, which
//   btTriangleIndexVertexArray reads in place instead of copying. Embree: bytes its
//   device reports allocating (rtcSetDeviceMemoryMonitorFunction), with the vertices and
//   indices copied into buffers it owns.
//
// TSV rows (scene `rays`; dt, substeps and iterations do not apply and read 0, 1, 1):
//   engine pfx / bullet / embree, metric build_s and bytes_per_triangle, wall_s_per_sim_s =
//   build CPU seconds; engine naming the way rays are cast, metric rays_per_s,
//   wall_s_per_sim_s = CPU seconds per batch of all rays (the fastest of several passes),
//   and metric mismatches (rays whose hit
//   distance differs from pfx's reference by more than 1e-4 m, a miss on one side
//   included) and distance_error_max (m, over rays both hit). The ways:
//   pfx        pfxRayCastLargeTriMesh, one ray at a time
//   pfx_world  PfxWorld::castRay with the mesh as a fixed body, one at a time
//   pfx_batch  PfxWorld::castRays, all rays in one call (cast in the Morton order of their
//              start points, outputs in the callers' order)
//   bullet     btCollisionWorld::rayTest with ClosestRayResultCallback
//   bullet_shape  btBvhTriangleMeshShape::performRaycast with a closest-hit callback
//   embree     rtcIntersect1
//   embree16   rtcIntersect16, 16 rays a packet
//   embree_stream  rtcIntersect1M over all rays
// variant is the storage variant: for pfx array or bvh, with _quantized and _hq
// (PFX_MESH_FLAG_HIGH_QUALITY); Bullet's is quantized_bvh, Embree's high_quality.
// pfx's reference is the array variant cast through pfxRayCastLargeTriMesh. The rows go to
// the TSV (stdout and --out) but into no plot: they are a table, not error against time.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "bench_report.h"
#include "bench_run.h"

namespace pfxbench {

struct RayTerrain {
  std::vector<float> vertices;        // xyz, Y up
  std::vector<std::uint32_t> triangles;  // three vertex indices each, counter-clockwise seen from +Y
  std::size_t numVertices() const { return vertices.size() / 3; }
  std::size_t numTriangles() const { return triangles.size() / 3; }
};

// A ray covers start + t * direction for t in [0, 1].
struct RaySet {
  std::vector<float> starts;      // xyz
  std::vector<float> directions;  // xyz, as long as the ray
  std::vector<double> lengths;    // of each direction, to turn fractions into metres
  std::size_t size() const { return lengths.size(); }
};

RayTerrain makeRayTerrain();
RaySet makeTerrainRays(std::size_t count);

// Hit distance (m) of each ray; a miss is +infinity.
using RayDistances = std::vector<double>;
constexpr double kRayMiss = std::numeric_limits<double>::infinity();

struct RayBuildFigures {
  std::string engine;
  std::string variant;
  double buildSeconds = 0;
  double bytesPerTriangle = 0;
};

struct RayCastFigures {
  std::string engine;  // the way rays were cast, e.g. pfx_world
  std::string variant;
  double secondsPerBatch = 0;
  RayDistances distances;
};

struct RayEngineFigures {
  std::vector<RayBuildFigures> builds;
  std::vector<RayCastFigures> casts;
};

// Casts every ray once untimed (which fills `distances`), then times kRayTimedPasses
// more passes and returns the fastest, so that a pass whose caches another process on
// the machine cooled does not count.
constexpr int kRayTimedPasses = 5;
template <class CastAll>
double timeFastestPass(RayDistances& distances, CastAll&& castAll) {
  castAll(distances);
  double fastest = std::numeric_limits<double>::infinity();
  RayDistances scratch(distances.size());
  for (int pass = 0; pass < kRayTimedPasses; ++pass) {
    const double start = processCpuSeconds();
    castAll(scratch);
    const double seconds = processCpuSeconds() - start;
    if (seconds < fastest) fastest = seconds;
  }
  return fastest;
}

// Each adapter appends its figures; false with `error` when the engine failed.
bool runPfxRays(const RayTerrain& terrain, const RaySet& rays, RayEngineFigures& figures,
                std::string& error);
bool runBulletRays(const RayTerrain& terrain, const RaySet& rays, RayEngineFigures& figures,
                   std::string& error);
bool runEmbreeRays(const RayTerrain& terrain, const RaySet& rays, RayEngineFigures& figures,
                   std::string& error);

// The reference every engine is checked against: pfx's array variant, cast through
// pfxRayCastLargeTriMesh.
bool castPfxReferenceRays(const RayTerrain& terrain, const RaySet& rays, RayDistances& distances,
                          std::string& error);

// The engines the rays scene knows, in order; peers not found when pfx_bench was
// configured are skipped with a message.
const std::vector<std::string>& rayEngineNames();

constexpr const char* kRaySceneName = "rays";

struct RaySceneRequest {
  bool wanted = false;           // the rays scene is to run
  bool otherScenes = true;       // other scenes remain to run as well
  std::vector<std::string> engines;  // empty: every engine of the rays scene
};

// Takes the rays scene and the rays-only engine (embree) out of the scene and engine lists,
// which the stepped scenes then use as before. False with `error` when embree is the only
// engine asked for scenes other than rays.
bool takeRaySceneRequest(std::vector<std::string>& scenes, std::vector<std::string>& engines,
                         RaySceneRequest& request, std::string& error);

// Runs the rays scene for the request's engines and appends its TSV rows to `rows`,
// logging progress on stderr. Returns the number of engines that failed.
int runRayScene(const RaySceneRequest& request, std::vector<ResultRow>& rows);

}  // namespace pfxbench
