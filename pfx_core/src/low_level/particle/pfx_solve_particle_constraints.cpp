#include "pfx/low_level/particle/pfx_solve_particle_constraints.h"

#include <algorithm>
#include <cmath>

#include "low_level/particle/pfx_particle_checks.h"
#include "low_level/particle/pfx_particle_stages_checked.h"
#include "low_level/particle/pfx_solve_particle_pair.h"

namespace pfx {

namespace {

constexpr PfxFloat kPi = PfxFloat(3.14159265358979323846);
// Below this length (m) a direction is not defined and the constraint waits for the others.
constexpr PfxFloat kMinLength = PfxFloat(1e-9);
// Constraints of one phase per task: enough work to pay for handing it to a thread.
constexpr PfxUInt32 kConstraintsPerTask = 256;
// Chains of a phase solved side by side on one thread (solveChainsInSequence).
constexpr PfxUInt32 kChainsInStep = 4;
// Links of a distance chain solved as one system (solveDistanceChains): the scratch lives on
// the stack, so a longer chain is solved in pieces of this many, one after another.
constexpr PfxUInt32 kMaxDirectLinks = 256;

const PfxParamNames kSolveParticleConstraintsAt{"pfxSolveParticleConstraints",
                                                "PfxSolveParticleConstraintsParam"};

PfxInt32 rejectIndex(const char* array, PfxUInt32 i, const char* field, PfxUInt32 value,
                     const char* countField, PfxUInt32 count) {
  return pfxRejectParam(PFX_ERR_OUT_OF_RANGE, "%s: %s::%s[%u].%s is %u, but %s is %u",
                        kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param, array,
                        i, field, value, countField, count);
}

PfxInt32 rejectValue(const char* array, PfxUInt32 i, const char* field, double value,
                     const char* requirement) {
  return pfxRejectParam(PFX_ERR_INVALID_VALUE, "%s: %s::%s[%u].%s is %g; it must be %s",
                        kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param, array,
                        i, field, value, requirement);
}

bool nonNegative(PfxFloat x) { return x >= 0 && pfxIsFinite(x); }

// A rigid body as the particle solve sees it: whether corrections move it, and how.
//
// Why this coupling is stable with heavy bodies: a correction between a particle and a body
// is split by their generalized inverse masses at the contact point, w = 1/m + (r x n)^T
// I^-1 (r x n), exactly as the particle-particle corrections are split by 1/m; a heavy body
// has a small w and moves little, and no correction ever moves the pair further than the
// constraint error. The body's velocity then changes by its position change over the
// sub-step, which is the impulse lambda / h the constraint exerted (XPBD's velocity
// update, Müller et al. 2020): the rigid solver of the next sub-step sees the body moving
// as the rope or cloth left it, and energy is never added, only removed when a constraint
// absorbs motion. Applying an impulse on velocities alone would be the alternative, but it
// needs the particle's velocity at the same moment, which position based particles do not
// have until the end of the sub-step.
struct RigidAccess {
  PfxRigidState* states;
  const PfxRigidBody* bodies;
  PfxFloat timeStep;

  bool moves(PfxUInt32 id) const {
    const PfxRigidState& s = states[id];
    return pfxMotionTypeIsDynamic(s.getMotionType()) && s.isAwake();
  }
  PfxMatrix3 inertiaInvWorld(PfxUInt32 id) const {
    return pfxRotateInertia(states[id].getOrientation().toRotationMatrix(),
                            bodies[id].getInertiaInv());
  }
  // w of the body at the world point `point` along unit `direction`; 0 when it does not move.
  PfxFloat inverseMassAt(PfxUInt32 id, const PfxVector3& point, const PfxVector3& direction) const {
    if (!moves(id)) return 0;
    const PfxVector3 rn = (point - states[id].getPosition()).cross(direction);
    return bodies[id].getMassInv() + rn.dot(inertiaInvWorld(id) * rn);
  }
  // Moves the body by a positional impulse (kg m) at a world point, and its velocity with it.
  void applyPositionImpulse(PfxUInt32 id, const PfxVector3& point,
                            const PfxVector3& impulse) const {
    if (!moves(id)) return;
    PfxRigidState& s = states[id];
    const PfxVector3 dp = impulse * bodies[id].getMassInv();
    const PfxVector3 dtheta = inertiaInvWorld(id) * (point - s.getPosition()).cross(impulse);
    s.setPosition(s.getPosition() + dp);
    const PfxQuat& q = s.getOrientation();
    const PfxQuat spin(0, dtheta.x() / 2, dtheta.y() / 2, dtheta.z() / 2);
    const PfxQuat turn = spin * q;
    PfxQuat turned(q.w() + turn.w(), q.x() + turn.x(), q.y() + turn.y(), q.z() + turn.z());
    turned.normalize();
    s.setOrientation(turned);
    s.setLinearVelocity(s.getLinearVelocity() + dp / timeStep);
    s.setAngularVelocity(s.getAngularVelocity() + dtheta / timeStep);
  }
  PfxVector3 worldPoint(PfxUInt32 id, const PfxVector3& local) const {
    return states[id].getPosition() + states[id].getOrientation() * local;
  }
  PfxVector3 pointVelocity(PfxUInt32 id, const PfxVector3& point) const {
    const PfxRigidState& s = states[id];
    return s.getLinearVelocity() + s.getAngularVelocity().cross(point - s.getPosition());
  }
};

void solveDistance(PfxParticleDistanceConstraint& c, PfxParticle* particles, PfxFloat alphaScale) {
  PfxParticle& a = particles[c.m_particleA];
  PfxParticle& b = particles[c.m_particleB];
  const PfxFloat w = a.m_massInv + b.m_massInv;
  const PfxVector3 d = a.m_position - b.m_position;
  const PfxFloat length = d.norm();
  if (w == 0 || length < kMinLength) return;
  const PfxVector3 n = d / length;
  const PfxFloat alpha = c.m_compliance * alphaScale;
  const PfxFloat dLambda = (-(length - c.m_restLength) - alpha * c.m_lambda) / (w + alpha);
  c.m_lambda += dLambda;
  a.m_position += a.m_massInv * dLambda * n;
  b.m_position -= b.m_massInv * dLambda * n;
}

// A chain of distance constraints, link i from particle q_i to q_i+1, solved at once rather
// than link after link: one Newton step of XPBD on the whole chain, (J W J^T + alpha~)
// dLambda = -C - alpha~ lambda, whose matrix is tridiagonal because two links share a
// particle only when they are neighbours: diagonal w_i + w_i+1 + alpha~_i, beside it
// -w_i+1 n_i . n_i+1, n_i the unit direction of link i. The Thomas algorithm solves it in
// one sweep each way (the matrix is symmetric positive definite, so no pivoting). Link after
// link (Gauss-Seidel), a correction at one end of a 128-link row reached the other end only
// over many passes, and the part of a draped cloth hanging from a sphere stayed stretched;
// solved at once, each row, column and diagonal is inextensible to first order after every
// pass (the direct solve of "Direct position-based solver for stiff rods", Deul et al. 2018,
// on a chain of distance constraints). A link with no mass to move or no direction is left
// out, as solveDistance leaves it.
//
// Up to kChainsInStep chains (each at most kMaxDirectLinks links) are solved side by side: the
// forward sweep divides by each row's pivot, which waits for the row before, and taking the
// chains' rows in turn lets the processor overlap their divisions (one chain at a time, that
// sweep was two fifths of the solve of a 64 x 64 cloth). The chains share no particle, so the
// bits are those of one chain after another.
struct DistanceChain {
  const PfxUInt32* links;
  PfxUInt32 numLinks;
};

struct DistanceChainSystem {
  PfxVector3 direction[kMaxDirectLinks];
  // Row i of the matrix (its diagonal, the entry beside it toward link i + 1, and the
  // right-hand side), then after the forward sweep the eliminated row.
  PfxFloat diagonal[kMaxDirectLinks], beside[kMaxDirectLinks], rhs[kMaxDirectLinks];
};

void setUpDistanceChain(const DistanceChain& chain, const PfxParticleDistanceConstraint* constraints,
                        const PfxParticle* particles, PfxFloat alphaScale,
                        DistanceChainSystem& system) {
  for (PfxUInt32 i = 0; i < chain.numLinks; ++i) {
    const PfxParticleDistanceConstraint& c = constraints[chain.links[i]];
    const PfxParticle& a = particles[c.m_particleA];
    const PfxParticle& b = particles[c.m_particleB];
    const PfxVector3 d = a.m_position - b.m_position;
    const PfxFloat length = d.norm();
    const PfxFloat w = a.m_massInv + b.m_massInv;
    if (w == 0 || length < kMinLength) {
      system.direction[i] = PfxVector3::Zero();
      system.diagonal[i] = 1;
      system.rhs[i] = 0;
    } else {
      // One division for the three components (d / length divides each).
      system.direction[i] = d * (1 / length);
      const PfxFloat alpha = c.m_compliance * alphaScale;
      system.diagonal[i] = w + alpha;
      system.rhs[i] = -(length - c.m_restLength) - alpha * c.m_lambda;
    }
    // Link i - 1 ends at link i's particle A.
    if (i > 0) {
      system.beside[i - 1] = -a.m_massInv * system.direction[i - 1].dot(system.direction[i]);
    }
  }
  system.beside[chain.numLinks - 1] = 0;
}

// Back substitution, each link's multiplier applied as soon as it is known.
void applyDistanceChain(const DistanceChain& chain, const DistanceChainSystem& system,
                        PfxParticleDistanceConstraint* constraints, PfxParticle* particles) {
  PfxFloat dLambda = 0;
  for (PfxUInt32 i = chain.numLinks; i-- > 0;) {
    dLambda = system.rhs[i] - system.beside[i] * dLambda;
    PfxParticleDistanceConstraint& c = constraints[chain.links[i]];
    c.m_lambda += dLambda;
    PfxParticle& a = particles[c.m_particleA];
    PfxParticle& b = particles[c.m_particleB];
    a.m_position += a.m_massInv * dLambda * system.direction[i];
    b.m_position -= b.m_massInv * dLambda * system.direction[i];
  }
}

void solveDistanceChains(const DistanceChain* chains, PfxUInt32 numChains,
                         PfxParticleDistanceConstraint* constraints, PfxParticle* particles,
                         PfxFloat alphaScale) {
  DistanceChainSystem systems[kChainsInStep];
  PfxUInt32 longest = 0;
  for (PfxUInt32 c = 0; c < numChains; ++c) {
    setUpDistanceChain(chains[c], constraints, particles, alphaScale, systems[c]);
    longest = std::max(longest, chains[c].numLinks);
  }
  // Forward sweep: row i loses its entry left of the diagonal (that of row i - 1 beside it,
  // by symmetry); `beside` becomes the eliminated rows' entries over their pivots.
  PfxFloat left[kChainsInStep] = {};
  for (PfxUInt32 i = 0; i < longest; ++i) {
    for (PfxUInt32 c = 0; c < numChains; ++c) {
      if (i >= chains[c].numLinks) continue;
      DistanceChainSystem& s = systems[c];
      const PfxFloat inversePivot =
          1 / (i > 0 ? s.diagonal[i] - left[c] * s.beside[i - 1] : s.diagonal[i]);
      if (i > 0) s.rhs[i] -= left[c] * s.rhs[i - 1];
      s.rhs[i] *= inversePivot;
      left[c] = s.beside[i];
      s.beside[i] *= inversePivot;
    }
  }
  for (PfxUInt32 c = 0; c < numChains; ++c) {
    applyDistanceChain(chains[c], systems[c], constraints, particles);
  }
}

void solveAngle(PfxParticleAngleConstraint& c, PfxParticle* particles, PfxFloat alphaScale) {
  PfxParticle& a = particles[c.m_particleA];
  PfxParticle& b = particles[c.m_particleB];
  PfxParticle& cc = particles[c.m_particleC];
  const PfxVector3 e1 = a.m_position - b.m_position;
  const PfxVector3 e2 = cc.m_position - b.m_position;
  const PfxFloat l1 = e1.norm();
  const PfxFloat l2 = e2.norm();
  if (l1 < kMinLength || l2 < kMinLength) return;
  const PfxVector3 u1 = e1 / l1;
  const PfxVector3 u2 = e2 / l2;
  const PfxFloat cosAngle = std::clamp(u1.dot(u2), PfxFloat(-1), PfxFloat(1));
  // The parts of each segment's direction across the other: the angle opens when A moves
  // away from C's direction and C away from A's. Both vanish on a straight line, where the
  // angle has no gradient; a straight rest shape is then already met.
  const PfxVector3 across1 = u2 - cosAngle * u1;
  const PfxVector3 across2 = u1 - cosAngle * u2;
  const PfxFloat sinAngle = across1.norm();
  if (sinAngle < PfxFloat(1e-6)) return;
  const PfxVector3 gradA = -across1 / (sinAngle * l1);
  const PfxVector3 gradC = -across2 / (sinAngle * l2);
  const PfxVector3 gradB = -(gradA + gradC);
  const PfxFloat w = a.m_massInv * gradA.squaredNorm() + b.m_massInv * gradB.squaredNorm() +
                     cc.m_massInv * gradC.squaredNorm();
  if (w == 0) return;
  const PfxFloat angle = std::atan2(sinAngle, cosAngle);
  const PfxFloat alpha = c.m_compliance * alphaScale;
  const PfxFloat dLambda = (-(angle - c.m_restAngle) - alpha * c.m_lambda) / (w + alpha);
  c.m_lambda += dLambda;
  a.m_position += a.m_massInv * dLambda * gradA;
  b.m_position += b.m_massInv * dLambda * gradB;
  cc.m_position += cc.m_massInv * dLambda * gradC;
}

// The tether only moves the particle or body: its anchor is where the material hangs from.
void solveTether(const PfxParticleTether& t, PfxParticle* particles, const RigidAccess& rigid) {
  if (t.m_rigidBodyId != PFX_PARTICLE_PIN_WORLD) {
    const PfxVector3 point = rigid.worldPoint(t.m_rigidBodyId, t.m_localAnchor);
    const PfxVector3 d = point - particles[t.m_anchorParticle].m_position;
    const PfxFloat length = d.norm();
    if (length <= t.m_maxDistance) return;
    const PfxVector3 n = d / length;
    const PfxFloat w = rigid.inverseMassAt(t.m_rigidBodyId, point, n);
    if (w == 0) return;
    rigid.applyPositionImpulse(t.m_rigidBodyId, point, n * (-(length - t.m_maxDistance) / w));
    return;
  }
  PfxParticle& p = particles[t.m_particle];
  if (p.m_massInv == 0) return;
  const PfxVector3 d = p.m_position - particles[t.m_anchorParticle].m_position;
  const PfxFloat length = d.norm();
  if (length <= t.m_maxDistance) return;
  p.m_position -= d * ((length - t.m_maxDistance) / length);
}

void solvePin(PfxParticlePin& pin, PfxParticle* particles, const RigidAccess& rigid,
              PfxFloat alphaScale) {
  PfxParticle& p = particles[pin.m_particle];
  const bool onBody = pin.m_rigidBodyId != PFX_PARTICLE_PIN_WORLD;
  const PfxVector3 anchor = onBody ? rigid.worldPoint(pin.m_rigidBodyId, pin.m_anchor) : pin.m_anchor;
  const PfxVector3 d = p.m_position - anchor;
  const PfxFloat length = d.norm();
  if (length < kMinLength) return;
  const PfxVector3 n = d / length;
  const PfxFloat wBody = onBody ? rigid.inverseMassAt(pin.m_rigidBodyId, anchor, n) : 0;
  const PfxFloat alpha = pin.m_compliance * alphaScale;
  const PfxFloat w = p.m_massInv + wBody;
  if (w + alpha == 0) return;
  const PfxFloat dLambda = (-length - alpha * pin.m_lambda) / (w + alpha);
  pin.m_lambda += dLambda;
  p.m_position += p.m_massInv * dLambda * n;
  if (onBody) rigid.applyPositionImpulse(pin.m_rigidBodyId, anchor, -dLambda * n);
}

// Friction on positions (Macklin et al. 2014, "Unified particle physics"): the sliding of
// the particle against the other side over the sub-step is undone, as far as the friction
// cone of the normal multiplier accumulated so far allows.
PfxFloat frictionMultiplier(PfxParticleContact& c, const PfxVector3& slide, PfxFloat w,
                            PfxVector3& direction) {
  const PfxFloat slideLength = slide.norm();
  if (slideLength < kMinLength || w == 0) return 0;
  direction = slide / slideLength;
  const PfxFloat allowed = c.m_friction * c.m_lambdaNormal - c.m_lambdaTangent;
  const PfxFloat dLambda = std::min(slideLength / w, std::max(allowed, PfxFloat(0)));
  c.m_lambdaTangent += dLambda;
  return dLambda;
}

void solveRigidContact(PfxParticleContact& c, PfxParticle* particles, const RigidAccess& rigid) {
  PfxParticle& p = particles[c.m_particle];
  const PfxUInt32 body = c.m_other;
  if (c.m_localNormal.squaredNorm() == 0) return;  // out of reach this sub-step
  const PfxVector3 point = rigid.worldPoint(body, c.m_localPoint);
  const PfxVector3 n = rigid.states[body].getOrientation() * c.m_localNormal;
  const PfxFloat depth = (p.m_position - point).dot(n) - p.m_radius;
  if (depth >= 0) return;
  const PfxFloat w = p.m_massInv + rigid.inverseMassAt(body, point, n);
  if (w == 0) return;
  const PfxFloat dLambda = -depth / w;
  c.m_lambdaNormal += dLambda;
  p.m_position += p.m_massInv * dLambda * n;
  rigid.applyPositionImpulse(body, point, -dLambda * n);

  const PfxVector3 travel = (p.m_position - p.m_previousPosition) -
                            rigid.pointVelocity(body, point) * rigid.timeStep;
  const PfxVector3 slide = travel - travel.dot(n) * n;
  PfxVector3 t = PfxVector3::Zero();
  const PfxFloat wT = p.m_massInv + (slide.squaredNorm() > 0 ? rigid.inverseMassAt(body, point,
                                                                  slide.normalized())
                                                             : 0);
  const PfxFloat dLambdaT = frictionMultiplier(c, slide, wT, t);
  if (dLambdaT == 0) return;
  p.m_position -= p.m_massInv * dLambdaT * t;
  rigid.applyPositionImpulse(body, point, dLambdaT * t);
}

}  // namespace

void pfxSolveParticlePairContact(PfxParticleContact& c, PfxParticle& a, PfxParticle& b) {
  const PfxFloat w = a.m_massInv + b.m_massInv;
  const PfxVector3 d = a.m_position - b.m_position;
  const PfxFloat length = d.norm();
  const PfxFloat depth = length - (a.m_radius + b.m_radius);
  if (w == 0 || depth >= 0 || length < kMinLength) return;
  const PfxVector3 n = d / length;
  const PfxFloat dLambda = -depth / w;
  c.m_lambdaNormal += dLambda;
  a.m_position += a.m_massInv * dLambda * n;
  b.m_position -= b.m_massInv * dLambda * n;

  const PfxVector3 travel =
      (a.m_position - a.m_previousPosition) - (b.m_position - b.m_previousPosition);
  const PfxVector3 slide = travel - travel.dot(n) * n;
  PfxVector3 t = PfxVector3::Zero();
  const PfxFloat dLambdaT = frictionMultiplier(c, slide, w, t);
  a.m_position -= a.m_massInv * dLambdaT * t;
  b.m_position += b.m_massInv * dLambdaT * t;
}

namespace {

PfxInt32 checkParticleIndex(const char* array, PfxUInt32 i, const char* field, PfxUInt32 index,
                            PfxUInt32 numParticles) {
  if (index < numParticles) return PFX_OK;
  return rejectIndex(array, i, field, index, "numParticles", numParticles);
}

PfxInt32 checkBodyIndex(const char* array, PfxUInt32 i, PfxUInt32 id,
                        const PfxSolveParticleConstraintsParam& param) {
  if (id >= param.numRigidBodies) {
    return rejectIndex(array, i, "rigid body id", id, "numRigidBodies", param.numRigidBodies);
  }
  if (!param.offsetRigidStates || !param.offsetRigidBodies) {
    return pfxRejectParam(PFX_ERR_NULL_POINTER,
                          "%s: %s::offsetRigidStates or offsetRigidBodies is null, but %s[%u] "
                          "names rigid body %u",
                          kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param,
                          array, i, id);
  }
  return PFX_OK;
}

PfxInt32 checkDistinct(const char* array, PfxUInt32 i, PfxUInt32 a, PfxUInt32 b) {
  if (a != b) return PFX_OK;
  return pfxRejectParam(PFX_ERR_INVALID_VALUE, "%s: %s::%s[%u] names particle %u twice",
                        kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param, array,
                        i, a);
}

// Batches from pfxBatchParticleConstraints for as many constraints; that they name each
// constraint once and phases share no particle is the batching stage's promise, not
// checked each sub-step.
PfxInt32 checkBatches(const char* field, const PfxParticleConstraintBatches* batches,
                      PfxUInt32 numConstraints) {
  if (!batches) return PFX_OK;
  if (batches->numConstraints != numConstraints || batches->numPhases > PFX_MAX_PARTICLE_PHASES ||
      batches->numChains > numConstraints || (numConstraints > 0 && !batches->order) ||
      !batches->chainStart || batches->phaseStart[batches->numPhases] > batches->numChains ||
      batches->chainStart[batches->numChains] != numConstraints) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "%s: %s::%s were made for %u constraints in %u chains and %u phases, "
                          "but there are %u (pfxBatchParticleConstraints)",
                          kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param,
                          field, batches->numConstraints, batches->numChains, batches->numPhases,
                          numConstraints);
  }
  return PFX_OK;
}

// Chains begin .. end - 1 of the batches, each in sequence, every other chain from its end,
// so that neighbouring rows of a cloth carry their corrections opposite ways and no edge is
// where all of them pile up; `iteration` of the sub-step turns them all on odd iterations, so
// that a chain of many iterations does not creep toward one end. kChainsInStep chains at a
// time, a constraint of each in turn: a chain's constraints wait for each other, chains of a
// phase do not, so the processor overlaps their square roots and divisions. They share no
// particle, so the bits are those of one chain after another.
template <typename Solve>
void solveChainsInSequence(const PfxParticleConstraintBatches& batches, PfxUInt32 begin,
                           PfxUInt32 end, PfxUInt32 iteration, const Solve& solve) {
  for (PfxUInt32 chain = begin; chain < end; chain += kChainsInStep) {
    const PfxUInt32 numChains = std::min(kChainsInStep, end - chain);
    PfxUInt32 next[kChainsInStep], left[kChainsInStep];
    bool fromEnd[kChainsInStep];
    PfxUInt32 longest = 0;
    for (PfxUInt32 c = 0; c < numChains; ++c) {
      const PfxUInt32 first = batches.chainStart[chain + c];
      left[c] = batches.chainStart[chain + c + 1] - first;
      fromEnd[c] = ((chain + c + iteration) & 1) != 0;
      next[c] = fromEnd[c] ? first + left[c] - 1 : first;
      longest = std::max(longest, left[c]);
    }
    for (PfxUInt32 k = 0; k < longest; ++k) {
      for (PfxUInt32 c = 0; c < numChains; ++c) {
        if (k >= left[c]) continue;
        solve(batches.order[next[c]]);
        next[c] = fromEnd[c] ? next[c] - 1 : next[c] + 1;
      }
    }
  }
}

// Each phase's chains in parallel, then the left-over chains one by one:
// solveChains(begin, end) solves chains begin .. end - 1 of the batches.
template <typename SolveChains>
PfxInt32 solveInPhases(const PfxParticleConstraintBatches& batches, PfxTaskManager* taskManager,
                       const SolveChains& solveChains) {
  for (PfxUInt32 phase = 0; phase < batches.numPhases; ++phase) {
    const PfxUInt32 first = batches.phaseStart[phase];
    const PfxUInt32 count = batches.phaseStart[phase + 1] - first;
    const PfxUInt32 constraints = batches.chainStart[first + count] - batches.chainStart[first];
    // About kConstraintsPerTask constraints per task, whole chains.
    const PfxUInt32 chainsPerTask =
        std::max<PfxUInt32>(1, PfxUInt32(PfxUInt64(kConstraintsPerTask) * count /
                                         std::max<PfxUInt32>(constraints, 1)));
    const PfxInt32 err = pfxParallelFor(taskManager, count, chainsPerTask,
                                        [&](PfxUInt32 begin, PfxUInt32 end) {
                                          solveChains(first + begin, first + end);
                                        });
    if (err != PFX_OK) return err;
  }
  solveChains(batches.phaseStart[batches.numPhases], batches.numChains);
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxCheckParticleConstraints(const PfxSolveParticleConstraintsParam& param) {
  const PfxUInt32 n = param.numParticles;
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckTimeStep(kSolveParticleConstraintsAt, param.timeStep)) != PFX_OK ||
      (err = pfxCheckValue(kSolveParticleConstraintsAt, "iteration", param.iteration,
                           param.iteration > 0, "at least 1")) != PFX_OK ||
      (err = pfxCheckParticles(kSolveParticleConstraintsAt, param.particles, n)) != PFX_OK ||
      (err = pfxCheckRequired(kSolveParticleConstraintsAt,
                              {{param.distanceConstraints, "distanceConstraints"}},
                              "numDistanceConstraints", param.numDistanceConstraints)) != PFX_OK ||
      (err = pfxCheckRequired(kSolveParticleConstraintsAt,
                              {{param.angleConstraints, "angleConstraints"}}, "numAngleConstraints",
                              param.numAngleConstraints)) != PFX_OK ||
      (err = pfxCheckRequired(kSolveParticleConstraintsAt, {{param.tethers, "tethers"}},
                              "numTethers", param.numTethers)) != PFX_OK ||
      (err = pfxCheckRequired(kSolveParticleConstraintsAt, {{param.pins, "pins"}}, "numPins",
                              param.numPins)) != PFX_OK ||
      (err = pfxCheckRequired(kSolveParticleConstraintsAt, {{param.contacts, "contacts"}},
                              "numContacts", param.numContacts)) != PFX_OK) {
    return err;
  }
  if ((err = checkBatches("distanceBatches", param.distanceBatches,
                          param.numDistanceConstraints)) != PFX_OK ||
      (err = checkBatches("angleBatches", param.angleBatches, param.numAngleConstraints)) !=
          PFX_OK) {
    return err;
  }
  if (!param.distanceBatches != !param.angleBatches) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "%s: %s::distanceBatches and angleBatches must be given both or neither",
                          kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param);
  }
  for (PfxUInt32 i = 0; i < param.numDistanceConstraints; ++i) {
    const PfxParticleDistanceConstraint& c = param.distanceConstraints[i];
    const char* array = "distanceConstraints";
    if ((err = checkParticleIndex(array, i, "particleA", c.m_particleA, n)) != PFX_OK ||
        (err = checkParticleIndex(array, i, "particleB", c.m_particleB, n)) != PFX_OK ||
        (err = checkDistinct(array, i, c.m_particleA, c.m_particleB)) != PFX_OK) {
      return err;
    }
    if (!nonNegative(c.m_restLength)) {
      return rejectValue(array, i, "restLength", c.m_restLength, "zero or positive and finite");
    }
    if (!nonNegative(c.m_compliance)) {
      return rejectValue(array, i, "compliance", c.m_compliance, "zero or positive and finite");
    }
  }
  for (PfxUInt32 i = 0; i < param.numAngleConstraints; ++i) {
    const PfxParticleAngleConstraint& c = param.angleConstraints[i];
    const char* array = "angleConstraints";
    if ((err = checkParticleIndex(array, i, "particleA", c.m_particleA, n)) != PFX_OK ||
        (err = checkParticleIndex(array, i, "particleB", c.m_particleB, n)) != PFX_OK ||
        (err = checkParticleIndex(array, i, "particleC", c.m_particleC, n)) != PFX_OK ||
        (err = checkDistinct(array, i, c.m_particleA, c.m_particleB)) != PFX_OK ||
        (err = checkDistinct(array, i, c.m_particleB, c.m_particleC)) != PFX_OK ||
        (err = checkDistinct(array, i, c.m_particleA, c.m_particleC)) != PFX_OK) {
      return err;
    }
    if (!(c.m_restAngle >= 0 && c.m_restAngle <= kPi)) {
      return rejectValue(array, i, "restAngle", c.m_restAngle, "in [0, pi]");
    }
    if (!nonNegative(c.m_compliance)) {
      return rejectValue(array, i, "compliance", c.m_compliance, "zero or positive and finite");
    }
  }
  for (PfxUInt32 i = 0; i < param.numTethers; ++i) {
    const PfxParticleTether& t = param.tethers[i];
    const char* array = "tethers";
    if ((err = checkParticleIndex(array, i, "anchorParticle", t.m_anchorParticle, n)) != PFX_OK) {
      return err;
    }
    if (t.m_rigidBodyId != PFX_PARTICLE_PIN_WORLD) {
      if ((err = checkBodyIndex(array, i, t.m_rigidBodyId, param)) != PFX_OK) return err;
      if (!pfxIsFinite(t.m_localAnchor)) {
        return pfxRejectParam(
            PFX_ERR_INVALID_VALUE, "%s: %s::tethers[%u].localAnchor is not finite",
            kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param, i);
      }
    } else if ((err = checkParticleIndex(array, i, "particle", t.m_particle, n)) != PFX_OK ||
               (err = checkDistinct(array, i, t.m_particle, t.m_anchorParticle)) != PFX_OK) {
      return err;
    }
    if (!nonNegative(t.m_maxDistance)) {
      return rejectValue(array, i, "maxDistance", t.m_maxDistance, "zero or positive and finite");
    }
  }
  for (PfxUInt32 i = 0; i < param.numPins; ++i) {
    const PfxParticlePin& pin = param.pins[i];
    const char* array = "pins";
    if ((err = checkParticleIndex(array, i, "particle", pin.m_particle, n)) != PFX_OK) return err;
    if (pin.m_rigidBodyId != PFX_PARTICLE_PIN_WORLD &&
        (err = checkBodyIndex(array, i, pin.m_rigidBodyId, param)) != PFX_OK) {
      return err;
    }
    if (!pfxIsFinite(pin.m_anchor)) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE, "%s: %s::pins[%u].anchor is not finite",
                            kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param,
                            i);
    }
    if (!nonNegative(pin.m_compliance)) {
      return rejectValue(array, i, "compliance", pin.m_compliance, "zero or positive and finite");
    }
  }
  for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
    const PfxParticleContact& c = param.contacts[i];
    const char* array = "contacts";
    if ((err = checkParticleIndex(array, i, "particle", c.m_particle, n)) != PFX_OK) return err;
    if (c.m_kind == kPfxParticleContactParticle) {
      if ((err = checkParticleIndex(array, i, "other", c.m_other, n)) != PFX_OK ||
          (err = checkDistinct(array, i, c.m_particle, c.m_other)) != PFX_OK) {
        return err;
      }
    } else if (c.m_kind == kPfxParticleContactRigidBody) {
      if ((err = checkBodyIndex(array, i, c.m_other, param)) != PFX_OK) return err;
      if (!pfxIsFinite(c.m_localPoint) || !pfxIsFinite(c.m_localNormal)) {
        return pfxRejectParam(
            PFX_ERR_INVALID_VALUE, "%s: %s::contacts[%u]: point or normal is not finite",
            kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param, i);
      }
    } else {
      return pfxRejectParam(PFX_ERR_INVALID_FLAG, "%s: %s::contacts[%u].kind is %u",
                            kSolveParticleConstraintsAt.stage, kSolveParticleConstraintsAt.param, i,
                            unsigned(c.m_kind));
    }
    if (!nonNegative(c.m_friction)) {
      return rejectValue(array, i, "friction", c.m_friction, "zero or positive and finite");
    }
  }
  return PFX_OK;
}

PfxInt32 pfxSolveParticleConstraints(const PfxSolveParticleConstraintsParam& param,
                                     PfxTaskManager* taskManager) {
  if (const PfxInt32 err = pfxCheckParticleConstraints(param); err != PFX_OK) return err;
  return pfxSolveCheckedParticleConstraints(param, taskManager);
}

PfxInt32 pfxSolveCheckedParticleConstraints(const PfxSolveParticleConstraintsParam& param,
                                            PfxTaskManager* taskManager) {
  PfxParticle* particles = param.particles;
  const RigidAccess rigid{param.offsetRigidStates, param.offsetRigidBodies, param.timeStep};
  // XPBD's time-step-scaled compliance, alpha / h^2.
  const PfxFloat alphaScale = 1 / (param.timeStep * param.timeStep);
  if (!param.continueSubStep) {
    for (PfxUInt32 i = 0; i < param.numDistanceConstraints; ++i) param.distanceConstraints[i].m_lambda = 0;
    for (PfxUInt32 i = 0; i < param.numAngleConstraints; ++i) param.angleConstraints[i].m_lambda = 0;
    for (PfxUInt32 i = 0; i < param.numPins; ++i) param.pins[i].m_lambda = 0;
    for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
      param.contacts[i].m_lambdaNormal = 0;
      param.contacts[i].m_lambdaTangent = 0;
    }
  }
  for (PfxUInt32 iteration = 0; iteration < param.iteration; ++iteration) {
    const PfxUInt32 subStepIteration = param.iterationsDone + iteration;
    const auto distance = [&](PfxUInt32 i) {
      solveDistance(param.distanceConstraints[i], particles, alphaScale);
    };
    const auto angle = [&](PfxUInt32 i) {
      solveAngle(param.angleConstraints[i], particles, alphaScale);
    };
    if (param.distanceBatches) {
      const PfxParticleConstraintBatches& distanceBatches = *param.distanceBatches;
      const PfxParticleConstraintBatches& angleBatches = *param.angleBatches;
      // A chain of one link, a lone rope's, is solveDistance; one longer than a system holds
      // is solved in pieces, one after another. The chains left over after the phases may
      // share particles and are solved one at a time.
      const auto distanceChains = [&](PfxUInt32 begin, PfxUInt32 end) {
        const PfxUInt32 atOnce =
            begin >= distanceBatches.phaseStart[distanceBatches.numPhases] ? 1 : kChainsInStep;
        DistanceChain sideBySide[kChainsInStep];
        PfxUInt32 numSideBySide = 0;
        for (PfxUInt32 chain = begin; chain < end; ++chain) {
          const PfxUInt32* links = distanceBatches.order + distanceBatches.chainStart[chain];
          const PfxUInt32 numLinks =
              distanceBatches.chainStart[chain + 1] - distanceBatches.chainStart[chain];
          if (numLinks == 1) {
            distance(links[0]);
          } else if (numLinks > kMaxDirectLinks) {
            for (PfxUInt32 done = 0; done < numLinks; done += kMaxDirectLinks) {
              const DistanceChain piece{links + done, std::min(kMaxDirectLinks, numLinks - done)};
              solveDistanceChains(&piece, 1, param.distanceConstraints, particles, alphaScale);
            }
          } else {
            sideBySide[numSideBySide++] = {links, numLinks};
          }
          if (numSideBySide == atOnce || (chain + 1 == end && numSideBySide > 0)) {
            solveDistanceChains(sideBySide, numSideBySide, param.distanceConstraints, particles,
                                alphaScale);
            numSideBySide = 0;
          }
        }
      };
      const auto angleChains = [&](PfxUInt32 begin, PfxUInt32 end) {
        solveChainsInSequence(angleBatches, begin, end, subStepIteration, angle);
      };
      PfxInt32 err = PFX_OK;
      if ((err = solveInPhases(distanceBatches, taskManager, distanceChains)) != PFX_OK ||
          (err = solveInPhases(angleBatches, taskManager, angleChains)) != PFX_OK) {
        return err;
      }
    } else {
      for (PfxUInt32 i = 0; i < param.numDistanceConstraints; ++i) distance(i);
      for (PfxUInt32 i = 0; i < param.numAngleConstraints; ++i) angle(i);
    }
    // Tethers after the chain: they take out what the chain's unconverged solve stretched.
    for (PfxUInt32 i = 0; i < param.numTethers; ++i) {
      solveTether(param.tethers[i], particles, rigid);
    }
    for (PfxUInt32 i = 0; i < param.numPins; ++i) solvePin(param.pins[i], particles, rigid, alphaScale);
    // Contacts last, and those with bodies after those among particles, so that what is
    // left of the sub-step's error is never a particle inside a body.
    for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
      PfxParticleContact& c = param.contacts[i];
      if (c.m_kind == kPfxParticleContactParticle) {
        pfxSolveParticlePairContact(c, particles[c.m_particle], particles[c.m_other]);
      }
    }
    for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
      PfxParticleContact& c = param.contacts[i];
      if (c.m_kind == kPfxParticleContactRigidBody) solveRigidContact(c, particles, rigid);
    }
  }
  return PFX_OK;
}

}  // namespace pfx
