#include "pfx/low_level/collision/pfx_detect_collision.h"

#include <cmath>

#include "base_level/collision/pfx_contact_checked.h"
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

// The slack of boundsApart and sphereApart, relative to the coordinates compared: it covers
// the rounding of the two bounds' computations, so that a pair is only called apart when
// its routine would surely find nothing.
constexpr PfxFloat kApartRelativeSlack = PfxFloat(1e-5);

// Whether two bodies' bounds (their collidables' boxes, which hold every shape's box) lie
// further apart along a world axis than `threshold`: then no pair of their shapes passes
// the bounds test in pfxContactCollidables either (a shape's world box lies inside its
// body's), and the pair has no contact. Most broad-phase pairs of a falling crowd are such
// neighbours, and this test costs a fraction of the shapes' validation and poses. NaN poses
// compare false and go on to pfxContactCollidables, which rejects them.
bool boundsApart(const PfxCollidable& collA, const PfxTransform3& transformA,
                 const PfxCollidable& collB, const PfxTransform3& transformB,
                 PfxFloat threshold) {
  PfxVector3 centerA, halfA, centerB, halfB;
  collA.getWorldAabb(transformA, centerA, halfA);
  collB.getWorldAabb(transformB, centerB, halfB);
  for (int axis = 0; axis < 3; ++axis) {
    const PfxFloat reach = halfA[axis] + halfB[axis] + threshold;
    const PfxFloat slack =
        kApartRelativeSlack * (std::abs(centerA[axis]) + std::abs(centerB[axis]) + reach);
    if (std::abs(centerB[axis] - centerA[axis]) > reach + slack) return true;
  }
  return false;
}

// A ball in the world that holds a body made of one sphere or one box.
struct ShapeBall {
  PfxVector3 centre;
  PfxFloat radius = 0;
  bool sphere = false;
};

bool ballOfOnlyShape(const PfxCollidable& collidable, const PfxTransform3& transform,
                     ShapeBall& ball) {
  if (collidable.getNumShapes() != 1) return false;
  const PfxShape& shape = collidable.getShape(0);
  ball.sphere = shape.getType() == kPfxShapeSphere;
  if (ball.sphere) {
    ball.radius = shape.getSphere().m_radius;
  } else if (shape.getType() == kPfxShapeBox) {
    ball.radius = shape.getBox().m_half.norm();
  } else {
    return false;
  }
  ball.centre = transform * shape.getOffsetPosition();
  return true;
}

// Whether a sphere lies further than `threshold` from the ball of the other body's sphere
// or box. The routines for a sphere against a sphere or a box measure the distance from the
// sphere's centre itself and add nothing beyond the threshold, so they would find no
// contact; this test spares the shapes' checks and poses for the many such neighbours in a
// pile. (A box against a box is left to its routine: what it measures along a face normal
// can be less than the distance between the boxes.) Slack and NaN as in boundsApart.
bool sphereApart(const PfxCollidable& collA, const PfxTransform3& transformA,
                 const PfxCollidable& collB, const PfxTransform3& transformB,
                 PfxFloat threshold) {
  ShapeBall a, b;
  if (!ballOfOnlyShape(collA, transformA, a) || !ballOfOnlyShape(collB, transformB, b) ||
      !(a.sphere || b.sphere)) {
    return false;
  }
  const PfxFloat reach = a.radius + b.radius + threshold;
  const PfxFloat slack =
      kApartRelativeSlack * (a.centre.cwiseAbs().maxCoeff() + b.centre.cwiseAbs().maxCoeff() + reach);
  return (b.centre - a.centre).squaredNorm() > (reach + slack) * (reach + slack);
}

constexpr PfxUInt32 kDetectedPairsPerTask = 32;
constexpr PfxUInt32 kCheckedBodiesPerTask = 1024;

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
  const bool checked = param.checkedBodies && param.checkedBodies[idA] &&
                       param.checkedBodies[idB] && threshold >= 0 && pfxIsFinite(threshold);
  const auto contact = checked ? pfxContactCheckedCollidables : pfxContactCollidables;
  const PfxUInt32 numCandidates =
      boundsApart(collA, transformA, collB, transformB, threshold) ||
              sphereApart(collA, transformA, collB, transformB, threshold)
          ? 0
          : contact(collA, transformA, collB, transformB, threshold, candidates,
                    PFX_MAX_CONTACT_CANDIDATES);
  const PfxUInt32 contactId = pfxGetContactId(pair);
  const bool shared = contactId == param.sharedEmptyContactId;
  if (shared && numCandidates == 0) {
    // The shared manifold stays empty; a fresh one given no candidates would too.
    pfxSetNumConstraints(pair, 0);
    return;
  }
  PfxContactManifold& manifold = shared ? unshared : param.offsetContactManifolds[contactId];
  if (shared) unshared.reset(idA, idB);
  pfxSetNumConstraints(pair, manifold.update(candidates, numCandidates, transformA, transformB,
                                             param.matchDistanceSq));
}

}  // namespace

void pfxCheckContactBodies(const PfxRigidState* states, const PfxCollidable* collidables,
                           PfxUInt32 numRigidBodies, PfxUInt8* checked,
                           PfxTaskManager* taskManager) {
  pfxParallelFor(taskManager, numRigidBodies, kCheckedBodiesPerTask,
                 [&](PfxUInt32 begin, PfxUInt32 end) {
                   for (PfxUInt32 i = begin; i < end; ++i) {
                     bool ok = pfxIsRigidTransform(states[i].getTransform());
                     const PfxCollidable& collidable = collidables[i];
                     for (PfxUInt32 j = 0; ok && j < collidable.getNumShapes(); ++j) {
                       ok = pfxIsContactShape(collidable.getShape(j));
                     }
                     checked[i] = ok ? 1 : 0;
                   }
                 });
}

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
