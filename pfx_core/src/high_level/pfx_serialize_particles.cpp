// The section PART of the serialized format: PfxWorld's particle groups (README.md,
// "Serialization").
#include "high_level/pfx_serialize_image.h"
#include "pfx/low_level/particle/pfx_solve_particle_constraints.h"
#include "pfx/low_level/pfx_error_detail.h"

namespace pfx {

namespace {

// The fewest bytes each record can take in a float file, so that a count the section's
// remaining bytes cannot hold is refused before anything is allocated for it.
constexpr std::size_t kParticleBytes = 12 * 4 + 2 * 4;
constexpr std::size_t kDistanceBytes = 2 * 4 + 3 * 4;
constexpr std::size_t kAngleBytes = 3 * 4 + 3 * 4;
constexpr std::size_t kTetherBytes = 2 * 4 + 4 + 4 + 3 * 4;
constexpr std::size_t kPinBytes = 2 * 4 + 3 * 4 + 2 * 4;
constexpr std::size_t kTriangleBytes = 3 * 4;

std::string particleAt(const char* what, PfxUInt32 i) {
  return std::string(what) + " " + std::to_string(i);
}

}  // namespace

void pfxEncodeParticleGroups(PfxByteWriter& w,
                             const std::vector<std::unique_ptr<PfxParticleGroup>>& groups) {
  w.u32(static_cast<PfxUInt32>(groups.size()));
  for (const auto& group : groups) {
    w.u8(group ? 1 : 0);
    if (!group) continue;
    const PfxParticleGroup& g = *group;
    w.real(g.linearDamping);
    w.u32(g.iteration);
    w.u8(g.selfCollision ? 1 : 0);
    w.u8(g.asleep ? 1 : 0);
    w.u32(g.sleepCount);
    w.u32(static_cast<PfxUInt32>(g.particles.size()));
    for (const PfxParticle& p : g.particles) {
      w.vec3(p.m_position);
      w.vec3(p.m_previousPosition);
      w.vec3(p.m_velocity);
      w.real(p.m_massInv);
      w.real(p.m_radius);
      w.real(p.m_friction);
      w.u32(p.m_contactFilterSelf);
      w.u32(p.m_contactFilterTarget);
    }
    w.u32(static_cast<PfxUInt32>(g.distanceConstraints.size()));
    for (const PfxParticleDistanceConstraint& c : g.distanceConstraints) {
      w.u32(c.m_particleA);
      w.u32(c.m_particleB);
      w.real(c.m_restLength);
      w.real(c.m_compliance);
      w.real(c.m_lambda);
    }
    w.u32(static_cast<PfxUInt32>(g.angleConstraints.size()));
    for (const PfxParticleAngleConstraint& c : g.angleConstraints) {
      w.u32(c.m_particleA);
      w.u32(c.m_particleB);
      w.u32(c.m_particleC);
      w.real(c.m_restAngle);
      w.real(c.m_compliance);
      w.real(c.m_lambda);
    }
    w.u32(static_cast<PfxUInt32>(g.tethers.size()));
    for (const PfxParticleTether& t : g.tethers) {
      w.u32(t.m_particle);
      w.u32(t.m_anchorParticle);
      w.real(t.m_maxDistance);
      w.u32(t.m_rigidBodyId);
      w.vec3(t.m_localAnchor);
    }
    w.u32(static_cast<PfxUInt32>(g.pins.size()));
    for (const PfxParticlePin& pin : g.pins) {
      w.u32(pin.m_particle);
      w.u32(pin.m_rigidBodyId);
      w.vec3(pin.m_anchor);
      w.real(pin.m_compliance);
      w.real(pin.m_lambda);
    }
    w.u32(static_cast<PfxUInt32>(g.triangleIndices.size() / 3));
    for (PfxUInt32 index : g.triangleIndices) w.u32(index);
  }
}

bool pfxDecodeParticleGroups(PfxByteReader& r, PfxSerializeImage& image) {
  const PfxUInt32 numGroups = r.count("count", 1);
  if (!r.ok()) return false;
  image.particleGroups.clear();
  image.particleGroups.resize(numGroups);
  for (PfxUInt32 id = 0; id < numGroups; ++id) {
    PfxTagScope tag(r, particleAt("group", id));
    const PfxUInt8 present = r.u8("present");
    if (!r.ok()) return false;
    if (present > 1) return r.fail(PFX_ERR_INVALID_VALUE, "present", "is neither 0 nor 1");
    if (!present) continue;
    auto group = std::make_unique<PfxParticleGroup>();
    PfxParticleGroup& g = *group;
    g.linearDamping = r.real("linearDamping");
    g.iteration = r.u32("iteration");
    g.selfCollision = r.u8("selfCollision") != 0;
    g.asleep = r.u8("asleep") != 0;
    g.sleepCount = r.u32("sleepCount");
    g.particles.resize(r.count("particles", kParticleBytes));
    for (PfxParticle& p : g.particles) {
      p.m_position = r.vec3("position");
      p.m_previousPosition = r.vec3("previousPosition");
      p.m_velocity = r.vec3("velocity");
      p.m_massInv = r.real("massInv");
      p.m_radius = r.real("radius");
      p.m_friction = r.real("friction");
      p.m_contactFilterSelf = r.u32("contactFilterSelf");
      p.m_contactFilterTarget = r.u32("contactFilterTarget");
    }
    g.distanceConstraints.resize(r.count("distance constraints", kDistanceBytes));
    for (PfxParticleDistanceConstraint& c : g.distanceConstraints) {
      c.m_particleA = r.u32("particleA");
      c.m_particleB = r.u32("particleB");
      c.m_restLength = r.real("restLength");
      c.m_compliance = r.real("compliance");
      c.m_lambda = r.real("lambda");
    }
    g.angleConstraints.resize(r.count("angle constraints", kAngleBytes));
    for (PfxParticleAngleConstraint& c : g.angleConstraints) {
      c.m_particleA = r.u32("particleA");
      c.m_particleB = r.u32("particleB");
      c.m_particleC = r.u32("particleC");
      c.m_restAngle = r.real("restAngle");
      c.m_compliance = r.real("compliance");
      c.m_lambda = r.real("lambda");
    }
    g.tethers.resize(r.count("tethers", kTetherBytes));
    for (PfxParticleTether& t : g.tethers) {
      t.m_particle = r.u32("particle");
      t.m_anchorParticle = r.u32("anchorParticle");
      t.m_maxDistance = r.real("maxDistance");
      t.m_rigidBodyId = r.u32("rigidBodyId");
      t.m_localAnchor = r.vec3("localAnchor");
    }
    g.pins.resize(r.count("pins", kPinBytes));
    for (PfxParticlePin& pin : g.pins) {
      pin.m_particle = r.u32("particle");
      pin.m_rigidBodyId = r.u32("rigidBodyId");
      pin.m_anchor = r.vec3("anchor");
      pin.m_compliance = r.real("compliance");
      pin.m_lambda = r.real("lambda");
    }
    g.triangleIndices.resize(3 * std::size_t(r.count("triangles", kTriangleBytes)));
    for (PfxUInt32& index : g.triangleIndices) index = r.u32("triangles");
    if (!r.ok()) return false;

    // What PfxWorld::addParticleGroup checks, against the bodies of this file.
    if (g.iteration == 0 || g.iteration > PFX_MAX_ITERATIONS) {
      return r.fail(PFX_ERR_INVALID_VALUE, "iteration",
                    "is " + std::to_string(g.iteration) + ", not 1 to " +
                        std::to_string(PFX_MAX_ITERATIONS));
    }
    if (!(g.linearDamping >= 0)) {
      return r.fail(PFX_ERR_INVALID_VALUE, "linearDamping", "is negative");
    }
    for (PfxUInt32 index : g.triangleIndices) {
      if (index >= g.particles.size()) {
        return r.fail(PFX_ERR_OUT_OF_RANGE, "triangles",
                      "name particle " + std::to_string(index) + " of " +
                          std::to_string(g.particles.size()));
      }
    }
    PfxSolveParticleConstraintsParam check;
    check.particles = g.particles.data();
    check.numParticles = static_cast<PfxUInt32>(g.particles.size());
    check.distanceConstraints = g.distanceConstraints.data();
    check.numDistanceConstraints = static_cast<PfxUInt32>(g.distanceConstraints.size());
    check.angleConstraints = g.angleConstraints.data();
    check.numAngleConstraints = static_cast<PfxUInt32>(g.angleConstraints.size());
    check.tethers = g.tethers.data();
    check.numTethers = static_cast<PfxUInt32>(g.tethers.size());
    check.pins = g.pins.data();
    check.numPins = static_cast<PfxUInt32>(g.pins.size());
    check.offsetRigidStates = image.states.data();
    check.offsetRigidBodies = image.bodies.data();
    check.numRigidBodies = image.numBodies();
    check.iteration = g.iteration;
    if (const PfxInt32 err = pfxCheckParticleConstraints(check); err != PFX_OK) {
      return r.fail(err, nullptr, pfxGetLastErrorDetail());
    }
    image.particleGroups[id] = std::move(group);
  }
  return true;
}

}  // namespace pfx
