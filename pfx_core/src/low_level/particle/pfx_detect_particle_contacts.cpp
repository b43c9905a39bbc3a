#include "pfx/low_level/particle/pfx_detect_particle_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base_level/collision/pfx_contact_checked.h"
#include "low_level/particle/pfx_particle_checks.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kDetectedParticlesPerTask = 64;

// The scratch, carved out of workBuff: a fixed set of rigid-contact slots per particle (so
// that particles are queried in parallel and gathered in index order), then the grid.
struct ParticleDetectionWork {
  PfxParticleContact* rigidSlots;
  PfxUInt32* rigidCounts;
  PfxUInt32* cellStart;  // tableSize + 1 entries
  PfxUInt32* cellParticles;
  PfxUInt32* particleCell;
  PfxUInt32 tableSize;
};

PfxUInt32 tableSizeFor(PfxUInt32 numParticles) {
  PfxUInt32 size = 1;
  while (size < 2 * numParticles && size < (1u << 30)) size <<= 1;
  return size;
}

std::size_t particleDetectionWorkBytes(PfxUInt32 numParticles, ParticleDetectionWork* work, void* base) {
  const PfxUInt32 tableSize = tableSizeFor(numParticles);
  std::size_t offset = 0;
  // Offsets first, pointers only into a buffer: the sizing call passes none, and an offset
  // added to a null pointer is undefined.
  auto take = [&](std::size_t bytes) {
    const std::size_t at = offset;
    offset += pfxAlignBytes(bytes);
    return at;
  };
  const std::size_t slots =
      take(sizeof(PfxParticleContact) * numParticles * PFX_MAX_PARTICLE_RIGID_CONTACTS);
  const std::size_t counts = take(sizeof(PfxUInt32) * numParticles);
  const std::size_t cellStart = take(sizeof(PfxUInt32) * (tableSize + 1));
  const std::size_t cellParticles = take(sizeof(PfxUInt32) * numParticles);
  const std::size_t particleCell = take(sizeof(PfxUInt32) * numParticles);
  if (work) {
    char* const bytes = static_cast<char*>(base);
    work->rigidSlots = reinterpret_cast<PfxParticleContact*>(bytes + slots);
    work->rigidCounts = reinterpret_cast<PfxUInt32*>(bytes + counts);
    work->cellStart = reinterpret_cast<PfxUInt32*>(bytes + cellStart);
    work->cellParticles = reinterpret_cast<PfxUInt32*>(bytes + cellParticles);
    work->particleCell = reinterpret_cast<PfxUInt32*>(bytes + particleCell);
    work->tableSize = tableSize;
  }
  return offset;
}

PfxFloat reachOf(const PfxParticle& p, const PfxDetectParticleContactsParam& param) {
  return p.m_radius + p.m_velocity.norm() * param.timeStep + param.contactMargin / 2;
}

// The bodies near the group, found once per call: each particle then meets only these, by
// their bounds and then the narrow phase, instead of descending the bodies' hierarchy and
// having its query checked on its own. A group near more bodies than this asks the
// hierarchy particle by particle.
constexpr PfxUInt32 kMaxNearBodies = 32;

struct NearBody {
  PfxUInt32 id;
  PfxUInt32 filterSelf, filterTarget;
  PfxTransform3 transform;
  PfxVector3 lo, hi;  // world bounds
  // Its pose and shapes passed the narrow phase's checks, which then need not run for
  // each particle.
  bool checked;
};

struct NearBodies {
  NearBody bodies[kMaxNearBodies];
  PfxUInt32 count = 0;
  bool all = true;  // false: too many, query the hierarchy instead
};

void findNearBodies(const PfxDetectParticleContactsParam& param, NearBodies& near) {
  PfxVector3 lo = PfxVector3::Constant(std::numeric_limits<PfxFloat>::max());
  PfxVector3 hi = -lo;
  for (PfxUInt32 i = 0; i < param.numParticles; ++i) {
    const PfxParticle& p = param.particles[i];
    const PfxVector3 reach = PfxVector3::Constant(p.m_radius + p.m_velocity.norm() * param.timeStep +
                                                  param.contactMargin);
    lo = lo.cwiseMin(p.m_position - reach);
    hi = hi.cwiseMax(p.m_position + reach);
  }
  const PfxQueryContactsParam& bodies = param.rigidBodies;
  for (PfxUInt32 k = 0; k < bodies.numProxies; ++k) {
    const PfxBroadphaseProxy& proxy = bodies.bvhProxies[k];
    const PfxUInt32 id = pfxGetObjectId(proxy);
    const PfxTransform3 transform = bodies.offsetRigidStates[id].getTransform();
    PfxVector3 center, half;
    bodies.offsetCollidables[id].getWorldAabb(transform, center, half);
    if (((center + half).array() < lo.array()).any() ||
        ((center - half).array() > hi.array()).any()) {
      continue;
    }
    if (near.count == kMaxNearBodies) {
      near.all = false;
      return;
    }
    const PfxCollidable& collidable = bodies.offsetCollidables[id];
    bool checked = pfxIsRigidTransform(transform);
    for (PfxUInt32 j = 0; j < collidable.getNumShapes(); ++j) {
      checked = checked && pfxIsContactShape(collidable.getShape(j));
    }
    near.bodies[near.count++] = {id,           pfxGetSelf(proxy), pfxGetTarget(proxy), transform,
                                 center - half, center + half,    checked};
  }
}

// The particle's contact points with the near bodies, as pfxQueryContacts reports them. The
// particle's sphere passes the narrow phase's checks: its particle was checked.
PfxUInt32 contactNearBodies(const NearBodies& near, const PfxDetectParticleContactsParam& param,
                            const PfxContactQueryInput& query, PfxFloat radius,
                            PfxContactCandidate* candidates, PfxQueryContact* found,
                            PfxUInt32 maxFound) {
  const PfxVector3 center = query.transform.translation();
  const PfxVector3 reach = PfxVector3::Constant(radius + query.contactThreshold);
  PfxUInt32 numFound = 0;
  for (PfxUInt32 k = 0; k < near.count && numFound < maxFound; ++k) {
    const NearBody& body = near.bodies[k];
    if (((center + reach).array() < body.lo.array()).any() ||
        ((center - reach).array() > body.hi.array()).any() ||
        !pfxContactFiltersMatch(query.contactFilterSelf, query.contactFilterTarget,
                                body.filterSelf, body.filterTarget)) {
      continue;
    }
    const auto contact = body.checked ? pfxContactCheckedCollidables : pfxContactCollidables;
    const PfxUInt32 count = contact(*query.collidable, query.transform,
                                    param.rigidBodies.offsetCollidables[body.id], body.transform,
                                    query.contactThreshold, candidates, PFX_MAX_CONTACT_CANDIDATES);
    for (PfxUInt32 c = 0; c < count && numFound < maxFound; ++c) {
      found[numFound].m_contact = candidates[c];
      found[numFound].m_rigidBodyId = body.id;
      ++numFound;
    }
  }
  return numFound;
}

// What detectRigid reuses from one particle to the next: made for each particle, the arrays
// of contact points (whose members start initialised) and the particle's sphere collidable
// (its shape checked, its bounds found) were a third of a 64 x 64 cloth's contact detection.
// The sphere is made again only when the radius changes; a cloth's particles share one.
class RigidDetectionScratch {
 public:
  // Room for two bodies' worth of points; a particle touching more keeps what fits.
  static constexpr PfxUInt32 kMaxFound = 2 * PFX_MAX_CONTACT_CANDIDATES;
  PfxQueryContact found[kMaxFound];
  PfxContactCandidate candidates[PFX_MAX_CONTACT_CANDIDATES];

  const PfxCollidable& sphereOf(PfxFloat radius) {
    if (radius != m_radius) {
      PfxShape sphere;
      sphere.reset();
      sphere.setSphere(PfxSphere(radius));
      m_sphere.reset();
      m_sphere.addShape(sphere);
      m_sphere.finish();
      m_radius = radius;
    }
    return m_sphere;
  }

 private:
  PfxCollidable m_sphere;
  PfxFloat m_radius = -1;
};

void detectRigid(const PfxDetectParticleContactsParam& param, const NearBodies& near,
                 PfxUInt32 i, const ParticleDetectionWork& work, RigidDetectionScratch& scratch) {
  const PfxParticle& p = param.particles[i];
  PfxUInt32& count = work.rigidCounts[i];
  count = 0;
  if (p.m_massInv == 0) return;
  PfxContactQueryInput query;
  query.collidable = &scratch.sphereOf(p.m_radius);
  query.transform = pfxMakeTransform(PfxQuat::Identity(), p.m_position);
  query.contactThreshold = p.m_velocity.norm() * param.timeStep + param.contactMargin;
  query.contactFilterSelf = p.m_contactFilterSelf;
  query.contactFilterTarget = p.m_contactFilterTarget;
  constexpr PfxUInt32 kMaxFound = RigidDetectionScratch::kMaxFound;
  PfxQueryContact* found = scratch.found;
  PfxUInt32 numFound = 0;
  if (near.all) {
    numFound = contactNearBodies(near, param, query, p.m_radius, scratch.candidates, found,
                                 kMaxFound);
  } else {
    PfxQueryContactsResult result;
    if (pfxQueryContacts(query, param.rigidBodies, found, kMaxFound, result) != PFX_OK) return;
    numFound = result.numContacts;
  }
  // The deepest first, so that a particle among many triangles keeps those that hold it.
  std::sort(found, found + numFound, [](const PfxQueryContact& a, const PfxQueryContact& b) {
    return a.m_contact.m_distance < b.m_contact.m_distance ||
           (a.m_contact.m_distance == b.m_contact.m_distance && a.m_rigidBodyId < b.m_rigidBodyId);
  });
  for (PfxUInt32 k = 0; k < numFound && count < PFX_MAX_PARTICLE_RIGID_CONTACTS; ++k) {
    const PfxQueryContact& q = found[k];
    const PfxRigidState& state = param.rigidBodies.offsetRigidStates[q.m_rigidBodyId];
    if (state.getMotionType() == kPfxMotionTypeTrigger) continue;
    const PfxQuat toBody = state.getOrientation().conjugate();
    PfxParticleContact& c = work.rigidSlots[i * PFX_MAX_PARTICLE_RIGID_CONTACTS + count++];
    c = PfxParticleContact();
    c.m_kind = kPfxParticleContactRigidBody;
    c.m_particle = i;
    c.m_other = q.m_rigidBodyId;
    c.m_shapeId = q.m_contact.m_shapeIdB;
    c.m_localPoint = toBody * (q.m_contact.m_pointB - state.getPosition());
    c.m_localNormal = toBody * (-q.m_contact.m_normal);
    c.m_friction = std::sqrt(p.m_friction *
                             param.offsetRigidBodies[q.m_rigidBodyId].getFriction());
  }
}

struct CellCoord {
  PfxInt64 x, y, z;
};

CellCoord cellOf(const PfxVector3& position, PfxFloat inverseCellSize) {
  return {static_cast<PfxInt64>(std::floor(position.x() * inverseCellSize)),
          static_cast<PfxInt64>(std::floor(position.y() * inverseCellSize)),
          static_cast<PfxInt64>(std::floor(position.z() * inverseCellSize))};
}

PfxUInt32 bucketOf(const CellCoord& c, PfxUInt32 tableSize) {
  const PfxUInt64 h = static_cast<PfxUInt64>(c.x) * 73856093u ^
                      static_cast<PfxUInt64>(c.y) * 19349663u ^
                      static_cast<PfxUInt64>(c.z) * 83492791u;
  return static_cast<PfxUInt32>(h & (tableSize - 1));
}

// Counting sort of the particles by bucket, stable, so that each bucket lists its particles
// in index order.
void fillGrid(const PfxDetectParticleContactsParam& param, PfxFloat inverseCellSize,
              const ParticleDetectionWork& work) {
  std::fill(work.cellStart, work.cellStart + work.tableSize + 1, 0u);
  for (PfxUInt32 i = 0; i < param.numParticles; ++i) {
    const PfxUInt32 bucket = bucketOf(cellOf(param.particles[i].m_position, inverseCellSize),
                                      work.tableSize);
    work.particleCell[i] = bucket;
    ++work.cellStart[bucket + 1];
  }
  for (PfxUInt32 b = 0; b < work.tableSize; ++b) work.cellStart[b + 1] += work.cellStart[b];
  // cellStart[b] is used as the insertion cursor of bucket b, then restored.
  for (PfxUInt32 i = 0; i < param.numParticles; ++i) {
    work.cellParticles[work.cellStart[work.particleCell[i]]++] = i;
  }
  for (PfxUInt32 b = work.tableSize; b > 0; --b) work.cellStart[b] = work.cellStart[b - 1];
  work.cellStart[0] = 0;
}

bool particlesMeet(const PfxParticle& a, const PfxParticle& b) {
  return (a.m_massInv > 0 || b.m_massInv > 0) &&
         pfxContactFiltersMatch(a.m_contactFilterSelf, a.m_contactFilterTarget,
                                b.m_contactFilterSelf, b.m_contactFilterTarget);
}

}  // namespace

PfxUInt32 pfxGetWorkBytesOfDetectParticleContacts(PfxUInt32 numParticles) {
  return static_cast<PfxUInt32>(particleDetectionWorkBytes(numParticles, nullptr, nullptr));
}

PfxInt32 pfxDetectParticleContacts(const PfxDetectParticleContactsParam& param,
                                   PfxDetectParticleContactsResult& result,
                                   PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxDetectParticleContacts", "PfxDetectParticleContactsParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckValue(at, "contactMargin", param.contactMargin,
                           param.contactMargin >= 0 && pfxIsFinite(param.contactMargin),
                           "zero or positive and finite")) != PFX_OK ||
      (err = pfxCheckParticles(at, param.particles, param.numParticles)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.contacts, "contacts"}}, "maxContacts",
                              param.maxContacts)) != PFX_OK) {
    return err;
  }
  const bool withBodies = param.detectRigidBodyContacts && param.rigidBodies.numProxies > 0;
  if (withBodies && !param.offsetRigidBodies) {
    return pfxRejectNull(at, "offsetRigidBodies", "rigidBodies.numProxies",
                         param.rigidBodies.numProxies);
  }
  const PfxUInt32 needed = pfxGetWorkBytesOfDetectParticleContacts(param.numParticles);
  if (param.numParticles > 0) {
    if (!param.workBuff || param.workBytes < needed) {
      return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                            "pfxDetectParticleContacts: PfxDetectParticleContactsParam::workBytes "
                            "is %u, but %u particles need %u (pfxGetWorkBytesOfDetectParticleContacts)",
                            param.workBuff ? param.workBytes : 0u, param.numParticles, needed);
    }
    if (!pfxIsAligned(param.workBuff)) {
      return pfxRejectParam(PFX_ERR_INVALID_ALIGNMENT,
                            "pfxDetectParticleContacts: PfxDetectParticleContactsParam::workBuff "
                            "is not 16-byte aligned");
    }
  }
  result = PfxDetectParticleContactsResult();
  if (param.numParticles == 0) return PFX_OK;
  ParticleDetectionWork work;
  particleDetectionWorkBytes(param.numParticles, &work, param.workBuff);

  PfxUInt32 numContacts = 0;
  auto emit = [&](const PfxParticleContact& c) {
    if (numContacts < param.maxContacts) {
      param.contacts[numContacts++] = c;
    } else {
      result.truncated = true;
    }
  };
  if (withBodies) {
    NearBodies near;
    findNearBodies(param, near);
    err = pfxParallelFor(taskManager, param.numParticles, kDetectedParticlesPerTask,
                         [&](PfxUInt32 begin, PfxUInt32 end) {
                           RigidDetectionScratch scratch;
                           for (PfxUInt32 i = begin; i < end; ++i) {
                             detectRigid(param, near, i, work, scratch);
                           }
                         });
    if (err != PFX_OK) return err;
    for (PfxUInt32 i = 0; i < param.numParticles; ++i) {
      for (PfxUInt32 k = 0; k < work.rigidCounts[i]; ++k) {
        emit(work.rigidSlots[i * PFX_MAX_PARTICLE_RIGID_CONTACTS + k]);
      }
    }
  }
  if (param.detectParticleContacts && param.numParticles > 1) {
    PfxFloat maxReach = 0;
    for (PfxUInt32 i = 0; i < param.numParticles; ++i) {
      maxReach = std::max(maxReach, reachOf(param.particles[i], param));
    }
    const PfxFloat inverseCellSize = 1 / (2 * maxReach);
    fillGrid(param, inverseCellSize, work);
    for (PfxUInt32 i = 0; i < param.numParticles; ++i) {
      const PfxParticle& a = param.particles[i];
      const CellCoord home = cellOf(a.m_position, inverseCellSize);
      const PfxFloat reachA = reachOf(a, param);
      // Neighbouring cells may share a bucket: each bucket is searched once.
      PfxUInt32 visited[27];
      PfxUInt32 numVisited = 0;
      for (int dz = -1; dz <= 1; ++dz) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const PfxUInt32 bucket =
                bucketOf({home.x + dx, home.y + dy, home.z + dz}, work.tableSize);
            if (std::find(visited, visited + numVisited, bucket) != visited + numVisited) continue;
            visited[numVisited++] = bucket;
            for (PfxUInt32 k = work.cellStart[bucket]; k < work.cellStart[bucket + 1]; ++k) {
              const PfxUInt32 j = work.cellParticles[k];
              if (j <= i) continue;
              const PfxParticle& b = param.particles[j];
              if (!particlesMeet(a, b)) continue;
              const PfxFloat reach = reachA + reachOf(b, param);
              if ((a.m_position - b.m_position).squaredNorm() >= reach * reach) continue;
              PfxParticleContact c;
              c.m_kind = kPfxParticleContactParticle;
              c.m_particle = i;
              c.m_other = j;
              c.m_friction = std::sqrt(a.m_friction * b.m_friction);
              emit(c);
            }
          }
        }
      }
    }
  }
  result.numContacts = numContacts;
  return PFX_OK;
}

}  // namespace pfx
