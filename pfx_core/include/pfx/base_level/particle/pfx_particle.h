// Particles and the constraints between them (seed sample 9, "Particle Physics"): cloth,
// rope and hair are particles held together by distance and angle constraints and solved on
// positions (position based dynamics). The stages that move them are in low_level/particle.
//
// Stiffness is given as compliance, the inverse of stiffness, in physical units (XPBD,
// Macklin et al. 2016): a constraint of compliance alpha under a force f settles at the
// error C = alpha * f, whatever the time step, sub-step or iteration count. Compliance 0 is
// a rigid constraint.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

// One particle: a small sphere with a mass.
struct PfxParticle {
  PfxVector3 m_position = PfxVector3::Zero();
  // Where the particle was at the start of the current sub-step: the velocity at its end is
  // the distance travelled over the sub-step (pfxUpdateParticles).
  PfxVector3 m_previousPosition = PfxVector3::Zero();
  PfxVector3 m_velocity = PfxVector3::Zero();
  // 0 holds the particle where the application puts it (a pin to the world).
  PfxFloat m_massInv = 1;
  PfxFloat m_radius = PfxFloat(0.01);
  PfxFloat m_friction = PfxFloat(0.5);
  // As for rigid bodies (pfxContactFiltersMatch): two particles, or a particle and a body,
  // touch only when the filters of both let them.
  PfxUInt32 m_contactFilterSelf = 1;
  PfxUInt32 m_contactFilterTarget = 0xffffffffu;
};

// Keeps two particles at restLength (m). Compliance in m/N.
struct PfxParticleDistanceConstraint {
  PfxUInt32 m_particleA = 0;
  PfxUInt32 m_particleB = 0;
  PfxFloat m_restLength = 0;
  PfxFloat m_compliance = 0;
  PfxFloat m_lambda = 0;  // the sub-step's accumulated multiplier (N s^2), solver scratch
};

// Bends three particles toward the angle restAngle (rad, in [0, pi]) at the middle one, B,
// between the segments BA and BC: pi keeps a rope or hair straight. Compliance in
// rad / (N m).
struct PfxParticleAngleConstraint {
  PfxUInt32 m_particleA = 0;
  PfxUInt32 m_particleB = 0;
  PfxUInt32 m_particleC = 0;
  PfxFloat m_restAngle = PfxFloat(3.14159265358979323846);
  PfxFloat m_compliance = 0;
  PfxFloat m_lambda = 0;
};

// A long-range attachment (Kim, Chentanez and Müller 2012): a particle may be no further
// than maxDistance (m) from an anchor particle, usually one the rope or cloth hangs from,
// with maxDistance the length of the path along the material between them. It only pulls;
// it costs one projection per particle and stops the stretch that a long chain of distance
// constraints shows under its own weight when the solver has not converged.
//
// The tethered end may be a point of a rigid body instead (a weight hanging on a rope): the
// body is then moved back within reach, by its own inverse mass at the point, and a heavy
// body no longer stretches the rope by the many iterations a chain of light particles needs
// to carry it.
struct PfxParticleTether {
  PfxUInt32 m_particle = 0;  // ignored when m_rigidBodyId names a body
  PfxUInt32 m_anchorParticle = 0;
  PfxFloat m_maxDistance = 0;
  PfxUInt32 m_rigidBodyId = 0xffffffffu;  // PFX_PARTICLE_PIN_WORLD: the particle is tethered
  PfxVector3 m_localAnchor = PfxVector3::Zero();  // the tethered point, in the body's frame
};

// PfxParticlePin::m_rigidBodyId of a pin to a fixed point of the world, and
// PfxParticleTether::m_rigidBodyId of a tether that holds a particle.
constexpr PfxUInt32 PFX_PARTICLE_PIN_WORLD = 0xffffffffu;

// Ties a particle to a point of a rigid body (in the body's frame: a cable tied to a robot
// link moves with it, and pulls on it) or of the world. Compliance in m/N.
struct PfxParticlePin {
  PfxUInt32 m_particle = 0;
  PfxUInt32 m_rigidBodyId = PFX_PARTICLE_PIN_WORLD;
  PfxVector3 m_anchor = PfxVector3::Zero();  // body frame, or world for a world pin
  PfxFloat m_compliance = 0;
  PfxFloat m_lambda = 0;
};

enum PfxParticleContactKind : PfxUInt8 {
  kPfxParticleContactRigidBody = 0,
  kPfxParticleContactParticle,
};

// A contact found once per step (pfxDetectParticleContacts) and solved in every sub-step.
// Against a rigid body it is a plane fixed to the body: the point on the body's surface and
// the normal out of the body, both in the body's frame, so that the plane moves with the
// body through the sub-steps; pfxRefreshParticleContacts turns it to follow a curved shape
// at each sub-step. Between two particles it is just the pair.
struct PfxParticleContact {
  PfxVector3 m_localPoint = PfxVector3::Zero();
  PfxVector3 m_localNormal = PfxVector3::Zero();
  PfxUInt32 m_particle = 0;
  PfxUInt32 m_other = 0;  // rigid body id or particle index
  PfxFloat m_friction = 0;  // of the pair (geometric mean)
  PfxUInt8 m_kind = kPfxParticleContactRigidBody;
  PfxUInt8 m_shapeId = 0;  // the body's shape touched (its index in the body's collidable)
  // Solver scratch: the sub-step's accumulated normal and friction multipliers (kg m).
  PfxFloat m_lambdaNormal = 0;
  PfxFloat m_lambdaTangent = 0;
};

// A particle whose every value is finite, whose inverse mass, radius and friction are not
// negative and whose radius is positive.
bool pfxIsValidParticle(const PfxParticle& particle);

}  // namespace pfx
