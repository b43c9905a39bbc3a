#include "pfx/low_level/particle/pfx_collide_particle_groups.h"

#include <algorithm>
#include <cmath>

#include "low_level/particle/pfx_particle_checks.h"
#include "low_level/particle/pfx_solve_particle_pair.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"

namespace pfx {

namespace {

const PfxParamNames kDetectAt{"pfxDetectParticleGroupContacts",
                              "PfxDetectParticleGroupContactsParam"};
const PfxParamNames kSolveAt{"pfxSolveParticleGroupContacts", "PfxSolveParticleGroupContactsParam"};
const PfxParamNames kUpdateAt{"pfxUpdateParticleGroupContacts",
                              "PfxSolveParticleGroupContactsParam"};

struct GroupCollisionWork {
  PfxUInt32* sortedB;  // B's particles in increasing x (ties by index)
  PfxFloat* sortedX;   // their x
};

std::size_t groupCollisionWorkBytes(PfxUInt32 numParticlesB, GroupCollisionWork* work, void* base) {
  const std::size_t indexBytes = pfxAlignBytes(sizeof(PfxUInt32) * numParticlesB);
  if (work) {
    work->sortedB = static_cast<PfxUInt32*>(base);
    work->sortedX = reinterpret_cast<PfxFloat*>(static_cast<char*>(base) + indexBytes);
  }
  return indexBytes + pfxAlignBytes(sizeof(PfxFloat) * numParticlesB);
}

PfxFloat reachOf(const PfxParticle& p, const PfxDetectParticleGroupContactsParam& param) {
  return p.m_radius + p.m_velocity.norm() * param.timeStep + param.contactMargin / 2;
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfDetectParticleGroupContacts(PfxUInt32 numParticlesB) {
  return static_cast<PfxUInt32>(groupCollisionWorkBytes(numParticlesB, nullptr, nullptr));
}

PfxInt32 pfxDetectParticleGroupContacts(const PfxDetectParticleGroupContactsParam& param,
                                        PfxDetectParticleGroupContactsResult& result) {
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckTimeStep(kDetectAt, param.timeStep)) != PFX_OK ||
      (err = pfxCheckValue(kDetectAt, "contactMargin", param.contactMargin,
                           param.contactMargin >= 0 && pfxIsFinite(param.contactMargin),
                           "zero or positive and finite")) != PFX_OK ||
      (err = pfxCheckParticles(kDetectAt, param.particlesA, param.numParticlesA)) != PFX_OK ||
      (err = pfxCheckParticles(kDetectAt, param.particlesB, param.numParticlesB)) != PFX_OK ||
      (err = pfxCheckRequired(kDetectAt, {{param.contacts, "contacts"}}, "maxContacts",
                              param.maxContacts)) != PFX_OK) {
    return err;
  }
  const PfxUInt32 needed = pfxGetWorkBytesOfDetectParticleGroupContacts(param.numParticlesB);
  if (param.numParticlesB > 0) {
    if (!param.workBuff || param.workBytes < needed) {
      return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                            "%s: %s::workBytes is %u, but %u particles of B need %u "
                            "(pfxGetWorkBytesOfDetectParticleGroupContacts)",
                            kDetectAt.stage, kDetectAt.param, param.workBuff ? param.workBytes : 0u,
                            param.numParticlesB, needed);
    }
    if (!pfxIsAligned(param.workBuff)) {
      return pfxRejectParam(PFX_ERR_INVALID_ALIGNMENT, "%s: %s::workBuff is not 16-byte aligned",
                            kDetectAt.stage, kDetectAt.param);
    }
  }
  result = PfxDetectParticleGroupContactsResult();
  if (param.numParticlesA == 0 || param.numParticlesB == 0) return PFX_OK;
  GroupCollisionWork work;
  groupCollisionWorkBytes(param.numParticlesB, &work, param.workBuff);
  const PfxParticle* b = param.particlesB;
  PfxFloat maxReachB = 0;
  for (PfxUInt32 j = 0; j < param.numParticlesB; ++j) {
    work.sortedB[j] = j;
    maxReachB = std::max(maxReachB, reachOf(b[j], param));
  }
  std::sort(work.sortedB, work.sortedB + param.numParticlesB, [&](PfxUInt32 i, PfxUInt32 j) {
    const PfxFloat xi = b[i].m_position.x(), xj = b[j].m_position.x();
    return xi < xj || (xi == xj && i < j);
  });
  for (PfxUInt32 k = 0; k < param.numParticlesB; ++k) {
    work.sortedX[k] = b[work.sortedB[k]].m_position.x();
  }
  for (PfxUInt32 i = 0; i < param.numParticlesA; ++i) {
    const PfxParticle& a = param.particlesA[i];
    const PfxFloat reachA = reachOf(a, param);
    const PfxFloat* first = std::lower_bound(work.sortedX, work.sortedX + param.numParticlesB,
                                             a.m_position.x() - reachA - maxReachB);
    const PfxFloat last = a.m_position.x() + reachA + maxReachB;
    for (PfxUInt32 k = static_cast<PfxUInt32>(first - work.sortedX);
         k < param.numParticlesB && work.sortedX[k] <= last; ++k) {
      const PfxParticle& other = b[work.sortedB[k]];
      if ((a.m_massInv == 0 && other.m_massInv == 0) ||
          !pfxContactFiltersMatch(a.m_contactFilterSelf, a.m_contactFilterTarget,
                                  other.m_contactFilterSelf, other.m_contactFilterTarget)) {
        continue;
      }
      const PfxFloat reach = reachA + reachOf(other, param);
      if ((a.m_position - other.m_position).squaredNorm() >= reach * reach) continue;
      if (result.numContacts == param.maxContacts) {
        result.truncated = true;
        continue;
      }
      PfxParticleContact& c = param.contacts[result.numContacts++];
      c = PfxParticleContact();
      c.m_kind = kPfxParticleContactParticle;
      c.m_particle = i;
      c.m_other = work.sortedB[k];
      c.m_friction = std::sqrt(a.m_friction * other.m_friction);
    }
  }
  return PFX_OK;
}

namespace {

PfxInt32 checkGroupContacts(const PfxSolveParticleGroupContactsParam& param,
                            const PfxParamNames& at) {
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at,
                              {{param.contacts, "contacts"},
                               {param.particlesA, "particlesA"},
                               {param.particlesB, "particlesB"}},
                              "numContacts", param.numContacts)) != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
    const PfxParticleContact& c = param.contacts[i];
    if (c.m_particle >= param.numParticlesA || c.m_other >= param.numParticlesB) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "%s: %s::contacts[%u] names particles %u of A and %u of B, but "
                            "numParticlesA is %u and numParticlesB %u",
                            at.stage, at.param, i, c.m_particle, c.m_other,
                            param.numParticlesA, param.numParticlesB);
    }
  }
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxSolveParticleGroupContacts(const PfxSolveParticleGroupContactsParam& param) {
  if (const PfxInt32 err = checkGroupContacts(param, kSolveAt); err != PFX_OK) return err;
  for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
    PfxParticleContact& c = param.contacts[i];
    if (!param.continueSubStep) {
      c.m_lambdaNormal = 0;
      c.m_lambdaTangent = 0;
    }
    pfxSolveParticlePairContact(c, param.particlesA[c.m_particle], param.particlesB[c.m_other]);
  }
  return PFX_OK;
}

PfxInt32 pfxUpdateParticleGroupContacts(const PfxSolveParticleGroupContactsParam& param) {
  if (const PfxInt32 err = checkGroupContacts(param, kUpdateAt); err != PFX_OK) return err;
  for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
    const PfxParticleContact& c = param.contacts[i];
    if (c.m_lambdaNormal <= 0) continue;
    pfxRemoveParticlePairSeparation(param.particlesA[c.m_particle], param.particlesB[c.m_other]);
  }
  return PFX_OK;
}

}  // namespace pfx
