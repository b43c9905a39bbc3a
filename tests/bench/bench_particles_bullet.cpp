// The rope and cloth scenes on Bullet's soft bodies: btSoftBody in a
// btSoftRigidDynamicsWorld with the default soft body solver, one thread. The solver
// setting is the world's sub-steps (stepSimulation(dt, n, dt / n)) and the soft body's
// position iterations (Config::piterations); links at the stiffest Bullet offers, kLST = 1.
#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "bench_particles.h"
#include "bench_run.h"

namespace pfxbench {

namespace {

// The world and everything it points at, destroyed in the right order.
struct SoftWorld {
  btSoftBodyRigidBodyCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDefaultSoftBodySolver softSolver;
  btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration, &softSolver};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::vector<std::unique_ptr<btSoftBody>> softBodies;

  SoftWorld() {
    // pfx's gravity (PfxWorldParam's default), here and in the soft bodies' own copy.
    const btVector3 gravity(0, btScalar(-9.80665), 0);
    world.setGravity(gravity);
    btSoftBodyWorldInfo& info = world.getWorldInfo();
    info.m_gravity = gravity;
    info.air_density = 0;  // no aerodynamics: pfx has none
    info.m_sparsesdf.Initialize();
  }
  ~SoftWorld() {
    for (auto& body : softBodies) world.removeSoftBody(body.get());
    for (auto& body : bodies) world.removeRigidBody(body.get());
  }

  // kDP: Bullet scales the nodes' velocities by 1 - kDP at each of its steps.
  btSoftBody* addSoftBody(btSoftBody* body, int iterations, btScalar kDP = 0) {
    softBodies.emplace_back(body);
    body->m_materials[0]->m_kLST = 1;
    body->m_cfg.piterations = iterations;
    body->m_cfg.kDP = kDP;
    world.addSoftBody(body);
    return body;
  }

  void addFixed(btCollisionShape* shape, const btVector3& position, btScalar friction) {
    shapes.emplace_back(shape);
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape);
    info.m_startWorldTransform.setOrigin(position);
    info.m_friction = friction;
    bodies.emplace_back(new btRigidBody(info));
    world.addRigidBody(bodies.back().get());
  }

  void step(double dt, const SolverSetting& setting) {
    world.stepSimulation(btScalar(dt), setting.substeps, btScalar(dt / setting.substeps));
  }
};

std::vector<ParticlePoint> positionsOf(const btSoftBody& body) {
  std::vector<ParticlePoint> points;
  points.reserve(body.m_nodes.size());
  for (int i = 0; i < body.m_nodes.size(); ++i) {
    const btVector3& x = body.m_nodes[i].m_x;
    points.push_back({double(x.x()), double(x.y()), double(x.z())});
  }
  return points;
}

// A chain of links through `points`, each node of `mass` (0 holds it).
btSoftBody* makeRope(SoftWorld& soft, const std::vector<ParticlePoint>& points,
                     const std::vector<btScalar>& masses) {
  std::vector<btVector3> x;
  for (const ParticlePoint& p : points) x.emplace_back(btScalar(p.x), btScalar(p.y), btScalar(p.z));
  auto* body = new btSoftBody(&soft.world.getWorldInfo(), int(x.size()), x.data(), masses.data());
  for (int i = 1; i < int(x.size()); ++i) body->appendLink(i - 1, i);
  return body;
}

}  // namespace

bool runBulletRope(double dt, double seconds, const SolverSetting& setting, RopeFigures& figures,
                   std::string&) {
  SoftWorld soft;
  std::vector<btScalar> masses(kRopeParticles, btScalar(kRopeParticleMass));
  masses.front() = masses.back() = 0;
  // pfx's damping divides the velocity by 1 + c h at each sub-step of h; the same here.
  const double h = dt / setting.substeps;
  const btScalar kDP = btScalar(kRopeDamping * h / (1 + kRopeDamping * h));
  btSoftBody* rope =
      soft.addSoftBody(makeRope(soft, makeRopeStart(), masses), setting.iterations, kDP);
  const int steps = int(std::lround(seconds / dt));
  const double cpuStart = processCpuSeconds();
  for (int step = 0; step < steps; ++step) soft.step(dt, setting);
  figures.cpuPerSimSecond = (processCpuSeconds() - cpuStart) / (steps * dt);
  const std::vector<ParticlePoint> end = positionsOf(*rope);
  figures.finite = allFinite(end);
  figures.catenaryError = catenaryError(end);
  figures.stretch = ropeStretch(end, kRopeLength);
  return true;
}

bool runBulletPayload(double dt, double seconds, const SolverSetting& setting, RopeFigures& figures,
                      std::string&) {
  SoftWorld soft;
  std::vector<ParticlePoint> points(kPayloadRopeParticles);
  for (int i = 0; i < kPayloadRopeParticles; ++i) {
    points[i].x = kPayloadRopeLength * i / (kPayloadRopeParticles - 1);
  }
  std::vector<btScalar> masses(kPayloadRopeParticles, btScalar(kPayloadParticleMass));
  masses.front() = 0;
  masses.back() = btScalar(kPayloadMass);
  btSoftBody* rope = soft.addSoftBody(makeRope(soft, points, masses), setting.iterations);
  const int steps = int(std::lround(seconds / dt));
  double cpu = 0;
  for (int step = 0; step < steps; ++step) {
    const double cpuStart = processCpuSeconds();
    soft.step(dt, setting);
    cpu += processCpuSeconds() - cpuStart;
    const std::vector<ParticlePoint> now = positionsOf(*rope);
    figures.finite = figures.finite && allFinite(now);
    figures.stretch = std::max(figures.stretch, ropeStretch(now, kPayloadRopeLength));
  }
  figures.cpuPerSimSecond = cpu / (steps * dt);
  return true;
}

bool runBulletCloth(int side, double dt, double seconds, const SolverSetting& setting,
                    ClothFigures& figures, std::string&) {
  SoftWorld soft;
  const btScalar ground = btScalar(kGroundHalfExtent), friction = btScalar(kClothFriction);
  soft.addFixed(new btBoxShape(btVector3(ground, btScalar(0.5), ground)),
                btVector3(0, btScalar(-0.5), 0), friction);
  soft.addFixed(new btSphereShape(btScalar(kClothSphereRadius)),
                btVector3(0, btScalar(kClothSphereRadius), 0), friction);
  const btScalar h = btScalar(kClothHeight), half = btScalar(kClothSize / 2);
  // Node i + j * side at (-1 + 2 i / (side - 1), h, -1 + 2 j / (side - 1)), as pfx's.
  btSoftBody* cloth = btSoftBodyHelpers::CreatePatch(
      soft.world.getWorldInfo(), btVector3(-half, h, -half), btVector3(half, h, -half),
      btVector3(-half, h, half), btVector3(half, h, half), side, side, 0, true);
  for (int i = 0; i < cloth->m_nodes.size(); ++i) {
    cloth->setMass(i, btScalar(kClothMass / (side * side)));
  }
  cloth->getCollisionShape()->setMargin(btScalar(kClothThickness));
  cloth->m_cfg.kDF = friction;
  soft.addSoftBody(cloth, setting.iterations);
  const int steps = int(std::lround(seconds / dt));
  std::vector<double> stepSeconds;
  stepSeconds.reserve(steps);
  for (int step = 0; step < steps; ++step) {
    const double cpuStart = processCpuSeconds();
    soft.step(dt, setting);
    stepSeconds.push_back(processCpuSeconds() - cpuStart);
    const std::vector<ParticlePoint> now = positionsOf(*cloth);
    figures.finite = figures.finite && allFinite(now);
    figures.penetration = std::max(figures.penetration, clothPenetration(now));
  }
  double total = 0;
  for (const double s : stepSeconds) total += s;
  figures.stepMsMean = 1e3 * total / steps;
  std::nth_element(stepSeconds.begin(), stepSeconds.begin() + steps / 2, stepSeconds.end());
  figures.stepMsMedian = 1e3 * stepSeconds[steps / 2];
  figures.cpuPerSimSecond = total / (steps * dt);
  figures.stretch = clothStretch(positionsOf(*cloth), side);
  return true;
}

}  // namespace pfxbench
