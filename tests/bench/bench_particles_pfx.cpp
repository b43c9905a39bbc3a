// The rope and cloth scenes on pfx: particle groups of a PfxWorld (sleep off, one thread),
// the world's sub-steps and the group's iterations per sub-step as the solver setting.
#include <algorithm>
#include <cmath>

#include "bench_particles.h"
#include "bench_rays.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_world.h"
#include "pfx/low_level/pfx_error_detail.h"

namespace pfxbench {

namespace {

using namespace pfx;


PfxVector3 toPfx(const ParticlePoint& p) {
  return PfxVector3(PfxFloat(p.x), PfxFloat(p.y), PfxFloat(p.z));
}

std::vector<ParticlePoint> positionsOf(const PfxParticleGroup& group) {
  std::vector<ParticlePoint> points;
  points.reserve(group.particles.size());
  for (const PfxParticle& p : group.particles) {
    points.push_back(
        {double(p.m_position.x()), double(p.m_position.y()), double(p.m_position.z())});
  }
  return points;
}

bool startWorld(PfxWorld& world, double dt, const SolverSetting& setting, std::string& error) {
  PfxWorldParam param;
  param.timeStep = PfxFloat(dt);
  param.subStep = PfxUInt32(setting.substeps);
  param.enableSleep = false;
  param.numThreads = 1;
  const PfxInt32 code = world.initialize(param);
  if (code != PFX_OK) error = std::string("building the world: ") + pfxErrorString(code);
  return code == PFX_OK;
}

// The cloth's fixed ground, a box whose top is at height 0.
bool addGround(PfxWorld& world, std::string& error) {
  PfxBodyInit ground;
  ground.mass = 0;
  ground.friction = PfxFloat(kClothFriction);
  ground.position = PfxVector3(0, PfxFloat(-0.5), 0);
  const PfxFloat extent = PfxFloat(kGroundHalfExtent);
  const PfxInt32 code =
      pfxAddBody(world, pfxMakeShape(PfxBox(extent, PfxFloat(0.5), extent)), ground);
  if (code != PFX_OK) error = std::string("adding the ground: ") + pfxErrorString(code);
  return code == PFX_OK;
}

bool addGroup(PfxWorld& world, PfxParticleGroupBuilder& builder, const SolverSetting& setting,
              PfxUInt32& id, std::string& error) {
  builder.iteration = PfxUInt32(setting.iterations);
  // Bullet's soft bodies here do not collide with themselves (that needs clusters).
  builder.selfCollision = false;
  const PfxInt32 code = world.addParticleGroup(builder.desc(), &id);
  if (code != PFX_OK) error = std::string("addParticleGroup: ") + pfxGetLastErrorDetail();
  return code == PFX_OK;
}

bool stepOnce(PfxWorld& world, std::string& error) {
  const PfxInt32 code = world.step();
  if (code != PFX_OK) error = std::string("step: ") + pfxGetLastErrorDetail();
  return code == PFX_OK;
}

}  // namespace

bool runPfxRope(double dt, double seconds, const SolverSetting& setting, bool tethers,
                RopeFigures& figures, std::string& error) {
  PfxWorld world;
  if (!startWorld(world, dt, setting, error)) return false;
  PfxParticleGroupBuilder builder;
  PfxParticleGroupBuilder::Material material;
  material.particleMass = PfxFloat(kRopeParticleMass);
  // The V in two legs from the same points as Bullet's; the second leg's first particle is
  // the tip, already the first leg's last, so it is dropped and its links renumbered.
  const std::vector<ParticlePoint> start = makeRopeStart();
  const PfxUInt32 half = (kRopeParticles - 1) / 2;
  builder.addRope(toPfx(start[0]), toPfx(start[half]), half + 1, material);
  PfxParticleGroupBuilder leg;
  leg.addRope(toPfx(start[half]), toPfx(start[kRopeParticles - 1]), half + 1, material);
  builder.particles.insert(builder.particles.end(), leg.particles.begin() + 1, leg.particles.end());
  for (PfxParticleDistanceConstraint link : leg.distanceConstraints) {
    link.m_particleA += half;
    link.m_particleB += half;
    builder.distanceConstraints.push_back(link);
  }
  builder.setMass(0, 0);
  builder.setMass(kRopeParticles - 1, 0);
  builder.linearDamping = PfxFloat(kRopeDamping);
  // Tethers from both pins, each as long as the rope between: they pull where the links
  // have not yet converged, and are slack on the catenary, which they leave unchanged.
  if (tethers) {
    builder.tetherRope(0, kRopeParticles, 0);
    builder.tetherRope(0, kRopeParticles, kRopeParticles - 1);
  }
  PfxUInt32 id = 0;
  if (!addGroup(world, builder, setting, id, error)) return false;
  const int steps = int(std::lround(seconds / dt));
  const double cpuStart = processCpuSeconds();
  for (int step = 0; step < steps; ++step) {
    if (!stepOnce(world, error)) return false;
  }
  figures.cpuPerSimSecond = (processCpuSeconds() - cpuStart) / (steps * dt);
  const std::vector<ParticlePoint> end = positionsOf(*world.getParticleGroup(id));
  figures.finite = allFinite(end);
  figures.catenaryError = catenaryError(end);
  figures.stretch = ropeStretch(end, kRopeLength);
  return true;
}

bool runPfxPayload(double dt, double seconds, const SolverSetting& setting, bool tethers,
                   RopeFigures& figures, std::string& error) {
  PfxWorld world;
  if (!startWorld(world, dt, setting, error)) return false;
  PfxParticleGroupBuilder builder;
  PfxParticleGroupBuilder::Material material;
  material.particleMass = PfxFloat(kPayloadParticleMass);
  const PfxUInt32 last = kPayloadRopeParticles - 1;
  builder.addRope(PfxVector3::Zero(), PfxVector3(PfxFloat(kPayloadRopeLength), 0, 0),
                  kPayloadRopeParticles, material);
  builder.setMass(0, 0);
  builder.setMass(last, PfxFloat(kPayloadMass));
  // Tethered from both ends: the payload outweighs a particle 20,000 times, so it anchors
  // the rope's lower end as the pin anchors the upper one.
  if (tethers) {
    builder.tetherRope(0, kPayloadRopeParticles, 0);
    builder.tetherRope(0, kPayloadRopeParticles, last);
  }
  PfxUInt32 id = 0;
  if (!addGroup(world, builder, setting, id, error)) return false;
  const int steps = int(std::lround(seconds / dt));
  double cpu = 0;
  for (int step = 0; step < steps; ++step) {
    const double cpuStart = processCpuSeconds();
    if (!stepOnce(world, error)) return false;
    cpu += processCpuSeconds() - cpuStart;
    const std::vector<ParticlePoint> now = positionsOf(*world.getParticleGroup(id));
    figures.finite = figures.finite && allFinite(now);
    figures.stretch = std::max(figures.stretch, ropeStretch(now, kPayloadRopeLength));
  }
  figures.cpuPerSimSecond = cpu / (steps * dt);
  return true;
}

bool runPfxCloth(int side, double dt, double seconds, const SolverSetting& setting,
                 ClothFigures& figures, std::string& error) {
  PfxWorld world;
  if (!startWorld(world, dt, setting, error) || !addGround(world, error)) return false;
  PfxBodyInit fixed;
  fixed.mass = 0;
  fixed.friction = PfxFloat(kClothFriction);
  fixed.position = PfxVector3(0, PfxFloat(kClothSphereRadius), 0);
  const PfxInt32 code =
      pfxAddBody(world, pfxMakeShape(PfxSphere(PfxFloat(kClothSphereRadius))), fixed);
  if (code != PFX_OK) {
    error = std::string("pfxAddBody: ") + pfxErrorString(code);
    return false;
  }
  PfxParticleGroupBuilder builder;
  PfxParticleGroupBuilder::Material material;
  material.particleMass = PfxFloat(kClothMass / (side * side));
  material.radius = PfxFloat(kClothThickness);
  material.friction = PfxFloat(kClothFriction);
  const PfxFloat half = PfxFloat(kClothSize / 2), size = PfxFloat(kClothSize);
  builder.addCloth(PfxVector3(-half, PfxFloat(kClothHeight), -half), PfxVector3(size, 0, 0),
                   PfxVector3(0, 0, size), PfxUInt32(side), PfxUInt32(side), material);
  PfxUInt32 id = 0;
  if (!addGroup(world, builder, setting, id, error)) return false;
  const int steps = int(std::lround(seconds / dt));
  std::vector<double> stepSeconds;
  stepSeconds.reserve(steps);
  for (int step = 0; step < steps; ++step) {
    const double cpuStart = processCpuSeconds();
    if (!stepOnce(world, error)) return false;
    stepSeconds.push_back(processCpuSeconds() - cpuStart);
    const std::vector<ParticlePoint> now = positionsOf(*world.getParticleGroup(id));
    figures.finite = figures.finite && allFinite(now);
    figures.penetration = std::max(figures.penetration, clothPenetration(now));
  }
  double total = 0;
  for (const double s : stepSeconds) total += s;
  figures.stepMsMean = 1e3 * total / steps;
  std::nth_element(stepSeconds.begin(), stepSeconds.begin() + steps / 2, stepSeconds.end());
  figures.stepMsMedian = 1e3 * stepSeconds[steps / 2];
  figures.cpuPerSimSecond = total / (steps * dt);
  figures.stretch = clothStretch(positionsOf(*world.getParticleGroup(id)), side);
  return true;
}

}  // namespace pfxbench
