// The `meshfloor` scene: what a fixed concave mesh costs a robot standing on it. Bullet3's
// quadruped (urdf/zoo/quadruped.urdf, 18 bodies, read by pfxLoadUrdfFile) stands at dt 1/240
// on an 8 x 8 m terrain of 3,200 triangles with 5 cm bumps (a large triangle mesh on a fixed
// body, as the URDF loader makes of a fixed-base mesh link), and, as the reference, on the
// box that bounds that terrain. After a second to settle, two seconds are measured. Like the
// octomap scene it runs apart and for pfx only (the engine-neutral scenes have no meshes).
// TSV rows (engine pfx, variant mesh or box; dt 1/240, substeps 1, iterations 10):
//   step_ms           mean wall time of a step (wall_s_per_sim_s alike)
//   detect_ms         mean time of the collision detection stage per step
//   penetration_max   deepest overlap over the measured steps (m)
// Built only with the loaders (pfx_loaders); without them the scene is reported skipped.
#pragma once

#include <vector>

#include "bench_report.h"

namespace pfxbench {

constexpr const char* kMeshFloorSceneName = "meshfloor";

// Runs the scene and appends its rows; returns the number of failures.
int runMeshFloorScene(std::vector<ResultRow>& rows);

}  // namespace pfxbench
