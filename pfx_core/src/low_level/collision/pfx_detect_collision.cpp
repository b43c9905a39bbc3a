#include "pfx/low_level/collision/pfx_detect_collision.h"

#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

namespace {

// Radius of a sphere about the body's origin that holds all its shapes.
PfxFloat boundingRadius(const PfxCollidable& collidable) {
  return collidable.getCenter().norm() + collidable.getHalf().norm();
}

// How close two bodies may come, at their current velocities, within one step.
PfxFloat closingDistance(const PfxRigidState& a, const PfxCollidable& ca, const PfxRigidState& b,
                         const PfxCollidable& cb, PfxFloat timeStep) {
  const PfxFloat linear = (b.getLinearVelocity() - a.getLinearVelocity()).norm();
  const PfxFloat angular = a.getAngularVelocity().norm() * boundingRadius(ca) +
                           b.getAngularVelocity().norm() * boundingRadius(cb);
  return (linear + angular) * timeStep;
}

constexpr PfxUInt32 kDetectedPairsPerTask = 32;

void detectPair(const PfxDetectCollisionParam& param, PfxConstraintPair& pair,
                PfxContactCandidate* candidates, PfxContactManifold& unshared) {
  const PfxUInt32 idA = pfxGetObjectIdA(pair);
  const PfxUInt32 idB = pfxGetObjectIdB(pair);
  const PfxRigidState& stateA = param.offsetRigidStates[idA];
  const PfxRigidState& stateB = param.offsetRigidStates[idB];
  const PfxCollidable& collA = param.offsetCollidables[idA];
  const PfxCollidable& collB = param.offsetCollidables[idB];
  const PfxTransform3 transformA = stateA.getTransform();
  const PfxTransform3 transformB = stateB.getTransform();
  const PfxFloat threshold =
      param.contactMargin + closingDistance(stateA, collA, stateB, collB, param.timeStep);
  const PfxUInt32 numCandidates =
      pfxContactCollidables(collA, transformA, collB, transformB, threshold, candidates,
                            PFX_MAX_CONTACT_CANDIDATES);
  const PfxUInt32 contactId = pfxGetContactId(pair);
  const bool shared = contactId == param.sharedEmptyContactId;
  PfxContactManifold& manifold = shared ? unshared : param.offsetContactManifolds[contactId];
  if (shared) unshared.reset(idA, idB);
  pfxSetNumConstraints(pair, manifold.update(candidates, numCandidates, transformA, transformB,
                                             param.matchDistanceSq));
}

}  // namespace

PfxInt32 pfxDetectCollision(const PfxDetectCollisionParam& param, PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxDetectCollision", "PfxDetectCollisionParam"};
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.contactPairs, "contactPairs"},
                               {param.offsetContactManifolds, "offsetContactManifolds"},
                               {param.offsetRigidStates, "offsetRigidStates"},
                               {param.offsetCollidables, "offsetCollidables"}},
                              "numContactPairs", param.numContactPairs)) != PFX_OK ||
      (err = pfxCheckValue(at, "contactMargin", param.contactMargin,
                           param.contactMargin >= 0 && pfxIsFinite(param.contactMargin),
                           "finite and not negative")) != PFX_OK ||
      (err = pfxCheckValue(at, "timeStep", param.timeStep,
                           param.timeStep >= 0 && pfxIsFinite(param.timeStep),
                           "finite and not negative")) != PFX_OK ||
      (err = pfxCheckValue(at, "matchDistanceSq", param.matchDistanceSq,
                           param.matchDistanceSq >= 0, "not negative")) != PFX_OK ||
      (err = pfxCheckPairsInRange(at, "contactPairs", param.contactPairs, param.numContactPairs,
                                  param.numRigidBodies, "numContactManifolds",
                                  param.numContactManifolds)) != PFX_OK) {
    return err;
  }

  // Each pair writes only its own manifold (or the task's, for a pair naming the shared
  // empty one) and its own pair.
  pfxParallelFor(taskManager, param.numContactPairs, kDetectedPairsPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   PfxContactCandidate candidates[PFX_MAX_CONTACT_CANDIDATES];
                   PfxContactPoint unsharedPoints[PFX_NUM_CONTACTS_PER_MANIFOLD];
                   PfxContactManifold unshared(unsharedPoints, PFX_NUM_CONTACTS_PER_MANIFOLD);
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     detectPair(param, param.contactPairs[i], candidates, unshared);
                   }
                 });
  return PFX_OK;
}

}  // namespace pfx
