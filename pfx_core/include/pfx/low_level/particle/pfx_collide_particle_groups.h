// Stage: contacts between the particles of two groups (a cloth falling on another cloth, a
// rope across a cloth), found once per step and solved in each iteration of a sub-step, after
// that iteration of each group's own constraints. Within a group, pfxDetectParticleContacts
// finds its pairs.
//
// Detection sorts group B's particles along x and, for each particle of A, looks at those of B
// within reach along x (sort and sweep); a pair is kept when the particles' contact filters
// match (pfxContactFiltersMatch) and they come within their radii, their travel over the step
// and the margin. The solve pushes each overlapping pair apart along the line between their
// centres, split by inverse mass, and undoes their sliding as far as friction allows.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"

namespace pfx {

struct PfxDetectParticleGroupContactsParam {
  // Scratch of pfxGetWorkBytesOfDetectParticleGroupContacts(numParticlesB) bytes, 16-byte
  // aligned.
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  const PfxParticle* particlesA = nullptr;
  PfxUInt32 numParticlesA = 0;
  const PfxParticle* particlesB = nullptr;
  PfxUInt32 numParticlesB = 0;
  PfxFloat contactMargin = PfxFloat(0.01);  // m
  PfxFloat timeStep = PfxFloat(1) / 60;     // of the whole step (s)
  // Written: m_particle indexes A, m_other B, m_kind kPfxParticleContactParticle.
  PfxParticleContact* contacts = nullptr;
  PfxUInt32 maxContacts = 0;
};

struct PfxDetectParticleGroupContactsResult {
  PfxUInt32 numContacts = 0;
  bool truncated = false;  // more were found than maxContacts (grow and detect again)
};

PfxUInt32 pfxGetWorkBytesOfDetectParticleGroupContacts(PfxUInt32 numParticlesB);

// Pairs in order of A's particle, then of B's along x. Rejects null arrays with a count
// (PFX_ERR_NULL_POINTER), a work buffer that is too small (PFX_ERR_OUT_OF_BUFFER) or
// misaligned (PFX_ERR_INVALID_ALIGNMENT), a negative or non-finite margin or time step and an
// invalid particle (PFX_ERR_INVALID_VALUE); the output is untouched then. Allocates nothing.
PfxInt32 pfxDetectParticleGroupContacts(const PfxDetectParticleGroupContactsParam& param,
                                        PfxDetectParticleGroupContactsResult& result);

struct PfxSolveParticleGroupContactsParam {
  PfxParticle* particlesA = nullptr;
  PfxUInt32 numParticlesA = 0;
  PfxParticle* particlesB = nullptr;
  PfxUInt32 numParticlesB = 0;
  PfxParticleContact* contacts = nullptr;  // from pfxDetectParticleGroupContacts
  PfxUInt32 numContacts = 0;
  // False: the contacts' multipliers start from zero, as at a sub-step's first iteration.
  // True: a later iteration of the same sub-step, going on from the multipliers (and so the
  // friction cone) that the earlier ones built up.
  bool continueSubStep = false;
};

// One iteration over the contacts. Rejects null arrays with a count (PFX_ERR_NULL_POINTER)
// and a contact naming a particle beyond the counts (PFX_ERR_OUT_OF_RANGE); nothing moves
// then. Serial, allocates nothing.
PfxInt32 pfxSolveParticleGroupContacts(const PfxSolveParticleGroupContactsParam& param);

// After both groups' pfxUpdateParticles: the velocity with which each pair that pushed this
// sub-step (a positive normal multiplier) separates along the line between its centres is
// taken out, split by inverse mass, as pfxUpdateParticles does for a group's own contacts;
// else the push that ended an overlap would leave as a rebound, and a light cloth on a taut
// cable would bounce off it. The same checks as pfxSolveParticleGroupContacts. Serial,
// allocates nothing.
PfxInt32 pfxUpdateParticleGroupContacts(const PfxSolveParticleGroupContactsParam& param);

}  // namespace pfx
