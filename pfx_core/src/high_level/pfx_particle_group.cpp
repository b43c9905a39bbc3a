#include "pfx/high_level/pfx_particle_group.h"

namespace pfx {

namespace {

template <typename T>
const T* dataOrNull(const std::vector<T>& v) {
  return v.empty() ? nullptr : v.data();
}

template <typename Group>
PfxParticleGroupDesc describe(const Group& g) {
  PfxParticleGroupDesc d;
  d.particles = dataOrNull(g.particles);
  d.numParticles = static_cast<PfxUInt32>(g.particles.size());
  d.distanceConstraints = dataOrNull(g.distanceConstraints);
  d.numDistanceConstraints = static_cast<PfxUInt32>(g.distanceConstraints.size());
  d.angleConstraints = dataOrNull(g.angleConstraints);
  d.numAngleConstraints = static_cast<PfxUInt32>(g.angleConstraints.size());
  d.tethers = dataOrNull(g.tethers);
  d.numTethers = static_cast<PfxUInt32>(g.tethers.size());
  d.pins = dataOrNull(g.pins);
  d.numPins = static_cast<PfxUInt32>(g.pins.size());
  d.triangleIndices = dataOrNull(g.triangleIndices);
  d.numTriangles = static_cast<PfxUInt32>(g.triangleIndices.size() / 3);
  d.linearDamping = g.linearDamping;
  d.iteration = g.iteration;
  d.selfCollision = g.selfCollision;
  return d;
}

PfxParticle makeParticle(const PfxVector3& position, const PfxParticleGroupBuilder::Material& m) {
  PfxParticle p;
  p.m_position = position;
  p.m_previousPosition = position;
  p.m_massInv = m.particleMass > 0 ? 1 / m.particleMass : 0;
  p.m_radius = m.radius;
  p.m_friction = m.friction;
  p.m_contactFilterSelf = m.contactFilterSelf;
  p.m_contactFilterTarget = m.contactFilterTarget;
  return p;
}

}  // namespace

PfxParticleGroupDesc PfxParticleGroup::desc() const { return describe(*this); }
PfxParticleGroupDesc PfxParticleGroupBuilder::desc() const { return describe(*this); }

void PfxParticleGroupBuilder::addDistance(PfxUInt32 a, PfxUInt32 b, PfxFloat compliance) {
  PfxParticleDistanceConstraint c;
  c.m_particleA = a;
  c.m_particleB = b;
  c.m_restLength = (particles[a].m_position - particles[b].m_position).norm();
  c.m_compliance = compliance;
  distanceConstraints.push_back(c);
}

PfxUInt32 PfxParticleGroupBuilder::addRope(const PfxVector3& start, const PfxVector3& end,
                                           PfxUInt32 numParticles, const Material& material) {
  const PfxUInt32 first = static_cast<PfxUInt32>(particles.size());
  const PfxUInt32 n = numParticles < 2 ? 2 : numParticles;
  for (PfxUInt32 i = 0; i < n; ++i) {
    particles.push_back(makeParticle(start + (end - start) * (PfxFloat(i) / PfxFloat(n - 1)), material));
  }
  for (PfxUInt32 i = 0; i + 1 < n; ++i) addDistance(first + i, first + i + 1, material.stretchCompliance);
  if (material.bendCompliance >= 0) {
    for (PfxUInt32 i = 0; i + 2 < n; ++i) {
      PfxParticleAngleConstraint c;
      c.m_particleA = first + i;
      c.m_particleB = first + i + 1;
      c.m_particleC = first + i + 2;
      c.m_compliance = material.bendCompliance;
      angleConstraints.push_back(c);
    }
  }
  return first;
}

PfxUInt32 PfxParticleGroupBuilder::addCloth(const PfxVector3& corner, const PfxVector3& edgeU,
                                            const PfxVector3& edgeV, PfxUInt32 numU,
                                            PfxUInt32 numV, const Material& material) {
  const PfxUInt32 first = static_cast<PfxUInt32>(particles.size());
  const PfxUInt32 nu = numU < 2 ? 2 : numU;
  const PfxUInt32 nv = numV < 2 ? 2 : numV;
  auto at = [&](PfxUInt32 i, PfxUInt32 j) { return first + i + j * nu; };
  for (PfxUInt32 j = 0; j < nv; ++j) {
    for (PfxUInt32 i = 0; i < nu; ++i) {
      particles.push_back(makeParticle(corner + edgeU * (PfxFloat(i) / PfxFloat(nu - 1)) +
                                           edgeV * (PfxFloat(j) / PfxFloat(nv - 1)),
                                       material));
    }
  }
  // Each line of links listed end to end, every link starting where the one before ended:
  // the solve takes such a run as a chain and carries a correction along the whole line in
  // one pass (pfx_batch_particle_constraints.h).
  const PfxFloat stretch = material.stretchCompliance;
  for (PfxUInt32 j = 0; j < nv; ++j) {
    for (PfxUInt32 i = 0; i + 1 < nu; ++i) addDistance(at(i, j), at(i + 1, j), stretch);
  }
  for (PfxUInt32 i = 0; i < nu; ++i) {
    for (PfxUInt32 j = 0; j + 1 < nv; ++j) addDistance(at(i, j), at(i, j + 1), stretch);
  }
  // Shear along both diagonals, so the cloth keeps no preferred direction: the lines of
  // (i, j) - (i + 1, j + 1) from the bottom row and the left column, then those of
  // (i + 1, j) - (i, j + 1) from the bottom row and the right column.
  const auto diagonal = [&](PfxUInt32 i, PfxUInt32 j) {
    for (; i + 1 < nu && j + 1 < nv; ++i, ++j) addDistance(at(i, j), at(i + 1, j + 1), stretch);
  };
  for (PfxUInt32 j = nv - 1; j > 0; --j) diagonal(0, j - 1);
  for (PfxUInt32 i = 1; i + 1 < nu; ++i) diagonal(i, 0);
  const auto antiDiagonal = [&](PfxUInt32 i, PfxUInt32 j) {
    for (; i > 0 && j + 1 < nv; --i, ++j) addDistance(at(i, j), at(i - 1, j + 1), stretch);
  };
  for (PfxUInt32 i = 1; i < nu; ++i) antiDiagonal(i, 0);
  for (PfxUInt32 j = 1; j + 1 < nv; ++j) antiDiagonal(nu - 1, j);
  for (PfxUInt32 j = 0; j + 1 < nv; ++j) {
    for (PfxUInt32 i = 0; i + 1 < nu; ++i) {
      triangleIndices.insert(triangleIndices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      triangleIndices.insert(triangleIndices.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  if (material.bendCompliance >= 0) {
    // Bending as distance constraints that skip a particle: cheap, and soft through their
    // compliance; angle constraints across a grid would fight each other at the corners.
    // Two chains along each row and column, of the even and of the odd particles.
    for (PfxUInt32 j = 0; j < nv; ++j) {
      for (PfxUInt32 start = 0; start < 2; ++start) {
        for (PfxUInt32 i = start; i + 2 < nu; i += 2) {
          addDistance(at(i, j), at(i + 2, j), material.bendCompliance);
        }
      }
    }
    for (PfxUInt32 i = 0; i < nu; ++i) {
      for (PfxUInt32 start = 0; start < 2; ++start) {
        for (PfxUInt32 j = start; j + 2 < nv; j += 2) {
          addDistance(at(i, j), at(i, j + 2), material.bendCompliance);
        }
      }
    }
  }
  return first;
}

void PfxParticleGroupBuilder::pinToWorld(PfxUInt32 particle) {
  PfxParticlePin pin;
  pin.m_particle = particle;
  pin.m_anchor = particles[particle].m_position;
  pins.push_back(pin);
}

void PfxParticleGroupBuilder::pinToBody(PfxUInt32 particle, PfxUInt32 rigidBodyId,
                                        const PfxVector3& localAnchor) {
  PfxParticlePin pin;
  pin.m_particle = particle;
  pin.m_rigidBodyId = rigidBodyId;
  pin.m_anchor = localAnchor;
  pins.push_back(pin);
}

void PfxParticleGroupBuilder::setMass(PfxUInt32 particle, PfxFloat mass) {
  particles[particle].m_massInv = mass > 0 ? 1 / mass : 0;
}

void PfxParticleGroupBuilder::tetherRope(PfxUInt32 first, PfxUInt32 count, PfxUInt32 anchor) {
  for (PfxUInt32 i = first; i < first + count; ++i) {
    if (i == anchor) continue;
    PfxFloat length = 0;
    const PfxUInt32 lo = i < anchor ? i : anchor;
    const PfxUInt32 hi = i < anchor ? anchor : i;
    for (PfxUInt32 k = lo; k < hi; ++k) {
      length += (particles[k + 1].m_position - particles[k].m_position).norm();
    }
    PfxParticleTether t;
    t.m_particle = i;
    t.m_anchorParticle = anchor;
    t.m_maxDistance = length;
    tethers.push_back(t);
  }
}

void PfxParticleGroupBuilder::tetherBody(PfxUInt32 rigidBodyId, const PfxVector3& localAnchor,
                                         PfxUInt32 anchor, PfxFloat maxDistance) {
  PfxParticleTether t;
  t.m_anchorParticle = anchor;
  t.m_maxDistance = maxDistance;
  t.m_rigidBodyId = rigidBodyId;
  t.m_localAnchor = localAnchor;
  tethers.push_back(t);
}

void PfxParticleGroupBuilder::tetherCloth(PfxUInt32 first, PfxUInt32 numU, PfxUInt32 numV,
                                          PfxUInt32 anchor) {
  for (PfxUInt32 i = first; i < first + numU * numV; ++i) {
    if (i == anchor) continue;
    PfxParticleTether t;
    t.m_particle = i;
    t.m_anchorParticle = anchor;
    t.m_maxDistance = (particles[i].m_position - particles[anchor].m_position).norm();
    tethers.push_back(t);
  }
}

}  // namespace pfx
