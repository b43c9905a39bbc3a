// Stage: the contacts of particles with rigid bodies and with each other, found once per
// step and solved in each of its sub-steps (pfx_solve_particle_constraints.h).
//
// Against rigid bodies a particle is a sphere of its radius queried through the bodies'
// hierarchy (pfxQueryContacts), so every shape a body may hold is met, compounds and large
// meshes included, by the same narrow phase the bodies use among themselves. Between
// particles the stage hashes them into a grid of cells as large as the largest particle's
// reach, and compares each with those of its own and the 26 neighbouring cells.
//
// Bodies and particles are found when they come within contactMargin of each other (plus
// the particle's travel over the step); the contact is kept as a plane fixed to the body, so
// a body that moves during the step carries it along.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"
#include "pfx/low_level/collision/pfx_query_contacts.h"

namespace pfx {

// The most contacts kept for one particle against rigid bodies (the deepest first).
constexpr PfxUInt32 PFX_MAX_PARTICLE_RIGID_CONTACTS = 4;

struct PfxDetectParticleContactsParam {
  // Scratch of pfxGetWorkBytesOfDetectParticleContacts(numParticles) bytes, 16-byte aligned.
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  const PfxParticle* particles = nullptr;
  PfxUInt32 numParticles = 0;
  // The bodies, as pfxQueryContacts takes them; no proxies means no bodies.
  PfxQueryContactsParam rigidBodies;
  // Indexed by rigid body id, for the friction of a contact; required with proxies.
  const PfxRigidBody* offsetRigidBodies = nullptr;
  bool detectRigidBodyContacts = true;
  bool detectParticleContacts = true;
  PfxFloat contactMargin = PfxFloat(0.01);  // m
  PfxFloat timeStep = PfxFloat(1) / 60;     // of the whole step (s)
  PfxParticleContact* contacts = nullptr;
  PfxUInt32 maxContacts = 0;
};

struct PfxDetectParticleContactsResult {
  PfxUInt32 numContacts = 0;
  // More contacts were found than maxContacts; those beyond were dropped (grow and detect again).
  bool truncated = false;
};

PfxUInt32 pfxGetWorkBytesOfDetectParticleContacts(PfxUInt32 numParticles);

// Writes the rigid-body contacts particle by particle, then the particle pairs in order of
// their first particle. Rejects null arrays with a count (PFX_ERR_NULL_POINTER), a work
// buffer that is too small (PFX_ERR_OUT_OF_BUFFER) or misaligned (PFX_ERR_INVALID_ALIGNMENT),
// a negative or non-finite margin or time step and an invalid particle
// (PFX_ERR_INVALID_VALUE); the output is untouched then. Allocates nothing.
PfxInt32 pfxDetectParticleContacts(const PfxDetectParticleContactsParam& param,
                                   PfxDetectParticleContactsResult& result,
                                   PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
