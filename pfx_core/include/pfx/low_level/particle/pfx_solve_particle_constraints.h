// Stage: the constraint solve of a particle sub-step (XPBD, Macklin, Müller and Chentanez
// 2016). The predicted positions of pfxIntegrateParticles are projected onto the distance,
// angle, tether, pin and contact constraints, Gauss-Seidel, `iteration` times; with batches,
// a chain of distance constraints (a rope's links, a cloth's row) is one block of it, solved
// exactly to first order in one step (the source says how). Each
// constraint carries its multiplier through the iterations, so its compliance acts as a
// physical stiffness: the same error under the same load at any time step and iteration
// count. Following "Small Steps in Physics Simulation" (Macklin et al. 2019), many short
// sub-steps of one iteration each converge better than few long ones with many iterations.
//
// Rigid bodies are moved too: a contact or pin between a particle and an awake active body
// (or one-way) corrects both, split by their inverse masses at the point of contact, and the
// body's velocity takes up its position change over the sub-step (see the source for why
// that is stable with heavy bodies). Fixed, keyframe and sleeping bodies are not moved.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"
#include "pfx/low_level/particle/pfx_batch_particle_constraints.h"

namespace pfx {

struct PfxSolveParticleConstraintsParam {
  PfxParticle* particles = nullptr;
  PfxUInt32 numParticles = 0;
  PfxParticleDistanceConstraint* distanceConstraints = nullptr;
  PfxUInt32 numDistanceConstraints = 0;
  PfxParticleAngleConstraint* angleConstraints = nullptr;
  PfxUInt32 numAngleConstraints = 0;
  // Optional, both or neither: the chains and phases of pfxBatchParticleConstraints for
  // these constraints. Without them the constraints are solved one after another in the
  // order given; with them phase by phase, each phase's chains in parallel on the task
  // manager, the same bits whatever the thread count.
  const PfxParticleConstraintBatches* distanceBatches = nullptr;
  const PfxParticleConstraintBatches* angleBatches = nullptr;
  const PfxParticleTether* tethers = nullptr;
  PfxUInt32 numTethers = 0;
  PfxParticlePin* pins = nullptr;
  PfxUInt32 numPins = 0;
  PfxParticleContact* contacts = nullptr;
  PfxUInt32 numContacts = 0;
  // Indexed by rigid body id; required when a pin or contact names a body.
  PfxRigidState* offsetRigidStates = nullptr;
  const PfxRigidBody* offsetRigidBodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxFloat timeStep = PfxFloat(1) / 60;  // of the sub-step (s)
  PfxUInt32 iteration = 1;
  // False: the multipliers start from zero, as a sub-step's solve does. True: this call goes
  // on with a sub-step that earlier calls began, from the multipliers they left, so that a
  // caller can solve other constraints between iterations (PfxWorld solves the contacts
  // between two groups after each iteration of both); calls of one iteration each then give
  // the same bits as one call of as many iterations.
  bool continueSubStep = false;
  // With continueSubStep, the iterations of the sub-step that earlier calls solved: with
  // batches, odd iterations of a sub-step solve each chain of angle constraints the other
  // way round.
  PfxUInt32 iterationsDone = 0;
};

// Rejects null arrays with a count (PFX_ERR_NULL_POINTER); a constraint, tether, pin or
// contact naming a particle or body beyond the counts, or a particle twice
// (PFX_ERR_OUT_OF_RANGE / PFX_ERR_INVALID_VALUE); a negative or non-finite rest length,
// rest angle outside [0, pi], compliance or distance, a non-finite anchor, a time step that
// is not positive and finite, an iteration count of 0 and batches made for other
// constraints (PFX_ERR_INVALID_VALUE). The detail names the array, the index and the field.
// Nothing changes then. Tethers, pins and contacts are solved serially, after the phases;
// the result is the same bits run after run. Allocates nothing.
PfxInt32 pfxSolveParticleConstraints(const PfxSolveParticleConstraintsParam& param,
                                     PfxTaskManager* taskManager = nullptr);

// The same checks, without solving: what a caller storing constraints runs once up front.
PfxInt32 pfxCheckParticleConstraints(const PfxSolveParticleConstraintsParam& param);

}  // namespace pfx
