// A particle group of PfxWorld (seed sample 9): a cloth, a rope, a head of hair. The world
// owns the group's particles and constraints (copied in from a PfxParticleGroupDesc) and
// steps them in the same step as the rigid bodies, through the stages of low_level/particle.
// PfxParticleGroupBuilder writes the usual shapes into a description.
#pragma once

#include <vector>

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/low_level/particle/pfx_batch_particle_constraints.h"

namespace pfx {

// What a group is made of; addParticleGroup copies the arrays. Indices are the group's own
// (particle 0 is the first of `particles`).
struct PfxParticleGroupDesc {
  const PfxParticle* particles = nullptr;
  PfxUInt32 numParticles = 0;
  const PfxParticleDistanceConstraint* distanceConstraints = nullptr;
  PfxUInt32 numDistanceConstraints = 0;
  const PfxParticleAngleConstraint* angleConstraints = nullptr;
  PfxUInt32 numAngleConstraints = 0;
  const PfxParticleTether* tethers = nullptr;
  PfxUInt32 numTethers = 0;
  const PfxParticlePin* pins = nullptr;
  PfxUInt32 numPins = 0;
  // Triples of particle indices, counter-clockwise seen from the front: the surface of a
  // cloth, for the debug render. Not a collision shape.
  const PfxUInt32* triangleIndices = nullptr;
  PfxUInt32 numTriangles = 0;
  PfxFloat linearDamping = 0;  // 1/s (pfx_integrate_particles.h)
  // Solver iterations per sub-step of the world (PfxWorldParam::subStep); compliance keeps
  // the stiffness the same at any count.
  PfxUInt32 iteration = 1;
  // Contacts between the group's own particles (cloth folding onto itself). Their contact
  // filters decide further. Particles of different groups collide when their filters let them.
  bool selfCollision = true;
};

// A group as the world keeps it.
struct PfxParticleGroup {
  std::vector<PfxParticle> particles;
  std::vector<PfxParticleDistanceConstraint> distanceConstraints;
  std::vector<PfxParticleAngleConstraint> angleConstraints;
  std::vector<PfxParticleTether> tethers;
  std::vector<PfxParticlePin> pins;
  std::vector<PfxUInt32> triangleIndices;
  PfxFloat linearDamping = 0;
  PfxUInt32 iteration = 1;
  bool selfCollision = true;
  // Contacts of the current step (numContacts of contacts), and the detection's scratch.
  std::vector<PfxParticleContact> contacts;
  PfxUInt32 numContacts = 0;
  std::vector<PfxVector4> detectWork;  // 16-byte elements, so that the buffer is aligned
  // The solve's chains and phases (pfxBatchParticleConstraints), made on the group's first
  // sub-step from the constraints alone, so that a loaded group solves in the same order.
  // Their order and chain start pointers are set to the four vectors before each use.
  std::vector<PfxUInt32> distanceOrder, angleOrder, distanceChainStart, angleChainStart;
  PfxParticleConstraintBatches distanceBatches, angleBatches;
  bool batched = false;
  // Sleep: steps the group has been still, and whether it sleeps (skipped by the step).
  PfxUInt32 sleepCount = 0;
  bool asleep = false;

  PfxParticleGroupDesc desc() const;
};

// A point where a particle touches a body (PfxWorld::getParticleBodyContacts).
struct PfxParticleBodyContact {
  PfxUInt32 m_particleGroupId = 0;
  PfxUInt32 m_particle = 0;
  PfxUInt32 m_rigidBodyId = 0;
  PfxUInt8 m_shapeId = 0;  // the body's shape touched (its index in the body's collidable)
  PfxVector3 m_point = PfxVector3::Zero();   // world, midway between the two surfaces
  PfxVector3 m_normal = PfxVector3::Zero();  // world, unit, out of the body to the particle
  PfxFloat m_depth = 0;    // overlap (m), > 0 when the particle is inside the body
  PfxFloat m_impulse = 0;  // normal impulse of the last sub-step (N s), >= 0
};

// A point where particles of two groups touch (PfxWorld::getParticleGroupContacts).
struct PfxParticleGroupContact {
  PfxUInt32 m_particleGroupIdA = 0;  // the lower id
  PfxUInt32 m_particleA = 0;
  PfxUInt32 m_particleGroupIdB = 0;
  PfxUInt32 m_particleB = 0;
  PfxVector3 m_point = PfxVector3::Zero();   // world, midway between the two surfaces
  PfxVector3 m_normal = PfxVector3::Zero();  // world, unit, from B's particle to A's
  PfxFloat m_depth = 0;    // overlap (m), > 0 when the two spheres overlap
  PfxFloat m_impulse = 0;  // normal impulse of the last sub-step (N s), >= 0
};

// Fills vectors that a PfxParticleGroupDesc then points at: ropes (or hair strands) and
// rectangular cloths, with the distance, angle and tether constraints that make them
// behave, and pins.
class PfxParticleGroupBuilder {
 public:
  struct Material {
    PfxFloat particleMass = PfxFloat(0.01);  // kg
    PfxFloat radius = PfxFloat(0.01);         // m
    PfxFloat friction = PfxFloat(0.5);
    PfxFloat stretchCompliance = 0;           // m/N
    // Softness in bending; a negative value adds no bending constraints. A rope's bending is
    // angle constraints, in rad/(N m); a cloth's is distance constraints across two
    // particles, in m/N. Bending much stiffer than the stretch constraints can follow in
    // one iteration (below about 0.1 m/N for cloth of 2 g particles) fights the contacts of
    // a cloth folding over an edge and gains speed from them: give stiff cloth more
    // iterations per sub-step (PfxParticleGroupDesc::iteration).
    PfxFloat bendCompliance = -1;
    PfxUInt32 contactFilterSelf = 1;
    PfxUInt32 contactFilterTarget = 0xffffffffu;
  };

  // A rope of numParticles (>= 2) particles from `start` to `end` in a straight line; its
  // length is the distance between them. Returns the index of its first particle.
  PfxUInt32 addRope(const PfxVector3& start, const PfxVector3& end, PfxUInt32 numParticles,
                    const Material& material);
  // A cloth of numU x numV particles (each >= 2) at corner + i * edgeU / (numU - 1) +
  // j * edgeV / (numV - 1), particle i + j * numU, with stretch constraints along its rows,
  // columns and diagonals, bending as distance constraints across two particles, and its
  // triangles. Returns the index of its first particle.
  PfxUInt32 addCloth(const PfxVector3& corner, const PfxVector3& edgeU, const PfxVector3& edgeV,
                     PfxUInt32 numU, PfxUInt32 numV, const Material& material);
  // Pins a particle where it is to the world, or to a body (anchor in the body's frame).
  void pinToWorld(PfxUInt32 particle);
  void pinToBody(PfxUInt32 particle, PfxUInt32 rigidBodyId, const PfxVector3& localAnchor);
  // Sets a particle's mass (kg; 0 holds it where it is).
  void setMass(PfxUInt32 particle, PfxFloat mass);
  // Adds a tether from every particle of the range [first, first + count) of a rope to
  // `anchor`, one of its particles, as long as the rope's rest length between them: the
  // long-range attachments that keep a hanging rope or cloth from stretching. Only for
  // material that hangs freely from the anchor: a tether pulls in a straight line, so on a
  // rope wrapped over an edge it presses the rope into the edge and friction locks it.
  void tetherRope(PfxUInt32 first, PfxUInt32 count, PfxUInt32 anchor);
  // Tethers the point localAnchor of a body (the weight at the end of a rope) to `anchor`,
  // no further than maxDistance: the long-range attachment that keeps a heavy body from
  // stretching the rope it hangs on.
  void tetherBody(PfxUInt32 rigidBodyId, const PfxVector3& localAnchor, PfxUInt32 anchor,
                  PfxFloat maxDistance);
  // The same for a cloth from addCloth: each particle to `anchor` with the shortest rest
  // distance along the cloth's grid, as the crow flies on its flat rest shape.
  void tetherCloth(PfxUInt32 first, PfxUInt32 numU, PfxUInt32 numV, PfxUInt32 anchor);

  PfxParticleGroupDesc desc() const;

  std::vector<PfxParticle> particles;
  std::vector<PfxParticleDistanceConstraint> distanceConstraints;
  std::vector<PfxParticleAngleConstraint> angleConstraints;
  std::vector<PfxParticleTether> tethers;
  std::vector<PfxParticlePin> pins;
  std::vector<PfxUInt32> triangleIndices;
  PfxFloat linearDamping = 0;
  PfxUInt32 iteration = 1;
  bool selfCollision = true;

 private:
  void addDistance(PfxUInt32 a, PfxUInt32 b, PfxFloat compliance);
};

}  // namespace pfx
