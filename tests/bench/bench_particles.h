// The `rope` and `cloth` scenes: pfx's particles (PfxWorld particle groups, solved on
// positions with compliance) beside Bullet's soft bodies (btSoftBody in a
// btSoftRigidDynamicsWorld) on the same rope and the same cloth.
//
// rope: 2 m of rope, 41 particles of 10 g, hanging between two pins 1.6 m apart at the
// same height, released as a V of its own length (so that no link starts stretched) and
// left to settle; then the largest distance from a particle to the analytic catenary and
// the stretch (its length along the particles over its rest length, minus 1), for a sweep
// of solver settings (sub-steps of the step times iterations per sub-step: pfx's world
// sub-steps and the group's iterations; Bullet's world sub-steps, stepSimulation(dt, n,
// dt / n), and btSoftBody::Config::piterations), each with its CPU seconds per simulated
// second; pfx runs it again with tethers (variant 41_tethers). Variant `payload`: 1 m of rope, 21
// particles of 1 g, the first pinned, the last carrying 20 kg (1,000 times the rope's hanging mass)
// as a heavy end particle in both engines, released horizontal; the largest stretch over the run.
// pfx also runs it with tethers (long-range attachments, PfxParticleGroupBuilder::tetherRope),
// which Bullet's soft bodies do not have.
//
// cloth: a 2 m square cloth of 64 x 64 and of 128 x 128 particles, 1 kg in all, structural
// links along rows and columns and shear links across each square, no bending, dropped flat
// from 1.2 m onto a fixed sphere of radius 0.5 m resting on the ground. CPU milliseconds
// per step (mean and median, one thread), the deepest a particle's centre gets inside the
// sphere or below the ground over the run (the same geometric test on both engines'
// positions), the mean stretch of the structural links at the end, and whether every
// position stayed finite.
//
// What could not be matched:
//  - Stiffness: pfx's links are rigid (compliance 0 m/N), which its solver approaches at
//    any iteration count; Bullet's are at its stiffest linear stiffness, kLST = 1, a
//    fraction of the correction applied per iteration, so their stiffness depends on
//    iterations and sub-steps. Neither is a spring constant of the other's.
//  - Shear: pfx's cloth (addCloth) has both diagonals of each square; Bullet's
//    (btSoftBodyHelpers::CreatePatch) one, alternating.
//  - Thickness: pfx particles have a radius of 1 cm; Bullet's soft body has a collision
//    margin of 1 cm. pfx keeps particles out of shapes by their radius; Bullet collides
//    nodes against the rigid shapes' signed distance field (cluster collisions off).
//  - Friction 0.5 in both (pfx particle friction; Bullet's kDF and the rigid bodies'
//    friction). Damping: none in the cloth and the payload rope; the rope between pins
//    1/s in both (pfx's linear damping; Bullet's kDP set to give the same velocity
//    factor per sub-step of h, 1 / (1 + c h) with c = 1/s).
//  - Self-collision off in both, rope and cloth: Bullet's needs clusters; pfx's costs a
//    hashed grid.
//
// TSV rows (engine pfx or bullet; wall_s_per_sim_s is CPU seconds per simulated second):
//   rope, variant 41 (and 41_tethers): catenary_error (m), stretch (fraction), finite (1 or 0)
//   rope, variant payload:  stretch (largest over the run), finite
//   cloth, variant 64x64 and 128x128: step_ms_mean, step_ms_median, penetration_max (m),
//                           stretch (mean, end), finite
#pragma once

#include <string>
#include <vector>

#include "bench_cli.h"
#include "bench_report.h"

namespace pfxbench {

constexpr const char* kRopeSceneName = "rope";
constexpr const char* kClothSceneName = "cloth";

struct ParticlePoint {
  double x = 0, y = 0, z = 0;
};

// Rope between pins: 2 m, pins at (-0.8, 0, 0) and (0.8, 0, 0), kRopeParticles particles.
constexpr double kRopeLength = 2.0;
constexpr double kRopeHalfSpan = 0.8;
constexpr int kRopeParticles = 41;
constexpr double kRopeParticleMass = 0.01;  // kg; the two pinned ends have none
// Linear damping (1/s) so that the rope comes to rest within the run: without it, a rope
// solved with many small sub-steps keeps swinging for minutes and the error measures its
// swing, not its shape.
constexpr double kRopeDamping = 1.0;
// The starting V: two straight legs meeting below the middle, each half the rope's length.
std::vector<ParticlePoint> makeRopeStart();

// The payload rope: from (0, 0, 0) to (1, 0, 0), the first particle pinned.
constexpr double kPayloadRopeLength = 1.0;
constexpr int kPayloadRopeParticles = 21;
constexpr double kPayloadParticleMass = 0.001;  // kg
constexpr double kPayloadMass = 20;             // kg, on the last particle

// Cloth: kClothSize square at height kClothHeight, centred over the sphere.
constexpr double kClothSize = 2.0;
constexpr double kClothHeight = 1.2;
constexpr double kClothMass = 1.0;        // kg, in all
constexpr double kClothThickness = 0.01;  // m: pfx particle radius, Bullet margin
constexpr double kClothFriction = 0.5;
constexpr double kClothSphereRadius = 0.5;  // centre (0, 0.5, 0), on the ground y = 0
constexpr double kGroundHalfExtent = 5;     // the ground is a box 10 x 1 x 10 m, top at y = 0

struct SolverSetting {
  int substeps = 1;
  int iterations = 1;
};

struct RopeFigures {
  double catenaryError = 0;  // m
  double stretch = 0;        // fraction
  double cpuPerSimSecond = 0;
  bool finite = true;
};

struct ClothFigures {
  double stepMsMean = 0, stepMsMedian = 0;
  double penetration = 0;  // m
  double stretch = 0;      // mean of the structural links, fraction
  double cpuPerSimSecond = 0;
  bool finite = true;
};

// What a run measures on its engine's final particle positions.
double catenaryError(const std::vector<ParticlePoint>& positions);
double ropeStretch(const std::vector<ParticlePoint>& positions, double restLength);
// Deepest a position is inside the cloth scene's sphere or below its ground (m, >= 0).
double clothPenetration(const std::vector<ParticlePoint>& positions);
// Mean relative stretch of the links between neighbours in rows and columns of a side x
// side grid of positions (particle i + j * side).
double clothStretch(const std::vector<ParticlePoint>& positions, int side);
bool allFinite(const std::vector<ParticlePoint>& positions);

// Each engine's side; false with `error` when the engine refused the scene. `tethers` is
// pfx's only (the payload rope).
bool runPfxRope(double dt, double seconds, const SolverSetting& setting, bool tethers,
                RopeFigures& figures, std::string& error);
bool runPfxPayload(double dt, double seconds, const SolverSetting& setting, bool tethers,
                   RopeFigures& figures, std::string& error);
bool runPfxCloth(int side, double dt, double seconds, const SolverSetting& setting,
                 ClothFigures& figures, std::string& error);
bool runBulletRope(double dt, double seconds, const SolverSetting& setting, RopeFigures& figures,
                   std::string& error);
bool runBulletPayload(double dt, double seconds, const SolverSetting& setting, RopeFigures& figures,
                      std::string& error);
bool runBulletCloth(int side, double dt, double seconds, const SolverSetting& setting,
                    ClothFigures& figures, std::string& error);

// The scenes, under the command line's --engine, --dt (each time step its own rows;
// 1/60 s if not given) and --seconds (rope 20 s, cloth 3 s if not given). They append
// their rows and return their failures: an engine that refused the scene, and for pfx,
// as a check that can fail, a position that is not finite, a rope at 20 sub-steps of 5
// iterations further than 1 cm from the catenary, or a cloth particle's centre deeper
// than its radius inside the sphere or the ground.
int runRopeScene(const Options& options, std::vector<ResultRow>& rows);
int runClothScene(const Options& options, std::vector<ResultRow>& rows);

}  // namespace pfxbench
