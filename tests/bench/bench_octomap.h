// The `octomap` scene: an OctoMap of a room (tests/loaders/data/room.bt: 8 x 6 m at 5 cm,
// 97,784 occupied voxels) loaded as static geometry by pfxLoadOctomapFile, then 100,000
// rays cast into it from random points under the ceiling's height, pointing down within 30
// degrees of vertical. Like the rays scene it measures speed, not stepping, and runs apart.
// TSV rows (engine pfx, variant room.bt; dt, substeps and iterations read 0, 1, 1):
//   load_s       CPU seconds to read the file and build its body (wall_s_per_sim_s too)
//   triangles    triangles of the exposed-face mesh the voxels became
//   rays_per_s   PfxWorld::castRays over all rays, the fastest of several passes
//   hits         share of the rays that hit (all but those starting inside a wall)
// Built only with the loaders (pfx_loaders); without them the scene is reported skipped.
#pragma once

#include <string>
#include <vector>

#include "bench_report.h"

namespace pfxbench {

constexpr const char* kOctomapSceneName = "octomap";

// Runs the scene and appends its rows; returns the number of failures (0 or 1).
int runOctomapScene(std::vector<ResultRow>& rows);

}  // namespace pfxbench
