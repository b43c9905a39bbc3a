#include "pfx_ros/pfx_node_cables.h"

#include "pfx/high_level/pfx_world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace pfx {

const char* const kPfxNodeWorldLink = "world";

namespace {

// A hanging cable or cloth loses most of its swing within a few seconds; the shape it hangs
// in does not depend on it.
constexpr PfxFloat kLinearDamping = 1;  // 1/s
// How a cable is settled into its hanging shape before it joins the world: damped near
// critical for a cable sagging a metre or so, long enough for one sagging 5 m to come within
// a few per cent of rest, and at most kSettleIterations per sub-step, so that a long cable
// of many iterations takes about a second to settle.
constexpr PfxFloat kSettleDamping = 4;  // 1/s
constexpr PfxFloat kSettleTimeStep = PfxFloat(1) / 120;
constexpr PfxUInt32 kSettleSubSteps = 4;
constexpr PfxUInt32 kSettleIterations = 40;
constexpr PfxFloat kSettleTime = 6;  // s
// Cloth bends this softly (m/N over two cells): it drapes over an edge instead of bridging it.
constexpr PfxFloat kClothBendCompliance = PfxFloat(0.2);

std::string describe(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// "" when `value` is finite and in (0, max] (or [0, max] with zeroAllowed).
std::string checkNumber(const char* field, PfxFloat value, PfxFloat max, bool zeroAllowed,
                        const char* unit) {
  const bool aboveMin = zeroAllowed ? value >= 0 : value > 0;
  if (std::isfinite(double(value)) && aboveMin && value <= max) return "";
  return std::string(field) + ": " + describe(value) + " " + unit + ", must be " +
         (zeroAllowed ? "from 0" : "above 0") + " to " + describe(max);
}

std::string checkCount(const char* field, PfxUInt32 value, PfxUInt32 min, PfxUInt32 max) {
  if (value >= min && value <= max) return "";
  return std::string(field) + ": " + std::to_string(value) + ", must be a whole number from " +
         std::to_string(min) + " to " + std::to_string(max);
}

std::string checkPoint(const char* field, const PfxVector3& point, PfxFloat max) {
  if (pfxIsFinite(point) && point.norm() <= max) return "";
  return std::string(field) + ": must be 3 finite numbers within " + describe(max) + " m";
}

PfxVector3 inBody(const PfxNodeAnchorBody& body, const PfxVector3& world) {
  return body.pose.inverse() * world;
}

void pin(PfxParticleGroupBuilder& group, PfxUInt32 particle, const PfxNodeAnchorBody& body) {
  if (body.bodyId == PFX_PARTICLE_PIN_WORLD) {
    group.pinToWorld(particle);
  } else {
    group.pinToBody(particle, body.bodyId, inBody(body, group.particles[particle].m_position));
  }
}

}  // namespace

std::string pfxFirstReason(std::initializer_list<std::string> reasons) {
  for (const std::string& why : reasons) {
    if (!why.empty()) return why;
  }
  return "";
}

std::string pfxCheckCableSpec(const PfxNodeCableSpec& s) {
  // The world is 1000 m each way from the origin (PfxWorldParam).
  constexpr PfxFloat kWorldReach = 1000;
  return pfxFirstReason({
      checkPoint("start_point", s.startPoint, kWorldReach),
      checkPoint("end_point", s.endPoint, kWorldReach),
      checkNumber("length", s.length, kPfxNodeMaxCableLength, false, "m"),
      checkNumber("radius", s.radius, kPfxNodeMaxParticleRadius, false, "m"),
      checkNumber("mass_per_metre", s.massPerMetre, kPfxNodeMaxMassPerMetre, false, "kg/m"),
      checkNumber("stiffness", s.stiffness, std::numeric_limits<PfxFloat>::max(), true, "N"),
      checkCount("segments", s.segments, 1, kPfxNodeMaxCableSegments),
      checkCount("iterations", s.iterations, 1, PFX_MAX_ITERATIONS),
  });
}

std::string pfxCheckClothSpec(const PfxNodeClothSpec& s) {
  constexpr PfxFloat kWorldReach = 1000;
  std::string pins;
  static const char* const kPinNames[] = {"corner",   "corner_u",   "corner_v",  "corner_uv",
                                          "edge_u",   "edge_v",     "edge_u_far", "edge_v_far"};
  for (const std::string& name : s.pinned) {
    bool known = false;
    for (const char* k : kPinNames) known = known || name == k;
    if (!known) {
      pins = "pinned: '" + name +
             "' is none of corner, corner_u, corner_v, corner_uv, edge_u, edge_v, edge_u_far, "
             "edge_v_far";
      break;
    }
  }
  const PfxFloat sizeU = s.edgeU.norm(), sizeV = s.edgeV.norm();
  std::string shape;
  if (pfxIsFinite(s.edgeU) && pfxIsFinite(s.edgeV) &&
      !(s.edgeU.cross(s.edgeV).norm() > PfxFloat(1e-6) * sizeU * sizeV)) {
    shape = "edge_u, edge_v: must not be parallel (the cloth would have no area)";
  }
  return pfxFirstReason({
      checkPoint("corner", s.corner, kWorldReach),
      checkNumber("edge_u", sizeU, kPfxNodeMaxCableLength, false, "m long"),
      checkNumber("edge_v", sizeV, kPfxNodeMaxCableLength, false, "m long"),
      shape,
      checkCount("resolution[0]", s.resolutionU, 2, kPfxNodeMaxClothResolution),
      checkCount("resolution[1]", s.resolutionV, 2, kPfxNodeMaxClothResolution),
      checkNumber("mass_per_area", s.massPerArea, kPfxNodeMaxMassPerMetre, false, "kg/m^2"),
      checkNumber("radius", s.radius, kPfxNodeMaxParticleRadius, false, "m"),
      checkNumber("stiffness", s.stiffness, std::numeric_limits<PfxFloat>::max(), true, "N/m"),
      checkCount("iterations", s.iterations, 1, PFX_MAX_ITERATIONS),
      pins,
  });
}

PfxInt32 pfxBuildNodeCable(const PfxNodeCableSpec& spec, const PfxVector3& start,
                           const PfxNodeAnchorBody& startBody, const PfxVector3& end,
                           const PfxNodeAnchorBody* endBody, PfxParticleGroupBuilder& group,
                           std::string* message) {
  const PfxVector3 down(0, 0, -1);
  const PfxVector3 last = endBody ? end : PfxVector3(start + spec.length * down);
  const PfxFloat span = (last - start).norm();
  if (span > spec.length * PfxFloat(1.0001)) {
    if (message) {
      *message = "length: " + describe(spec.length) + " m, shorter than the " + describe(span) +
                 " m between its two ends";
    }
    return PFX_ERR_INVALID_VALUE;
  }
  const PfxUInt32 n = spec.segments + 1;
  PfxParticleGroupBuilder::Material material;
  material.particleMass = spec.massPerMetre * spec.length / PfxFloat(n);
  material.radius = spec.radius;
  const PfxFloat segment = spec.length / PfxFloat(spec.segments);
  material.stretchCompliance = spec.stiffness > 0 ? segment / spec.stiffness : 0;
  // Laid out straight to get rest lengths of length / segments, then folded into a V whose
  // two arms are half the length each, its tip straight below the middle of the ends.
  const PfxUInt32 first =
      group.addRope(start, start + spec.length * PfxVector3(1, 0, 0), n, material);
  const PfxFloat half = spec.length / 2;
  const PfxVector3 tip =
      (start + last) / 2 + std::sqrt(std::max(PfxFloat(0), half * half - span * span / 4)) * down;
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxFloat s = segment * PfxFloat(i);
    const PfxVector3 p = s <= half ? PfxVector3(start + (tip - start) * (s / half))
                                   : PfxVector3(tip + (last - tip) * ((s - half) / half));
    group.particles[first + i].m_position = p;
    group.particles[first + i].m_previousPosition = p;
  }
  pin(group, first, startBody);
  if (endBody) {
    pin(group, first + n - 1, *endBody);
  } else if (startBody.bodyId == PFX_PARTICLE_PIN_WORLD) {
    // Hanging free from the world: tethers keep a long cable from stretching under its
    // weight. Not from a body: a tether holds a particle to its anchor particle without
    // pulling on it, so the body would not carry the cable's weight.
    group.tetherRope(first, n, first);
  }
  group.linearDamping = kLinearDamping;
  group.iteration = spec.iterations;
  group.selfCollision = false;
  return PFX_OK;
}

PfxInt32 pfxSettleNodeCable(const PfxVector3& gravity, PfxParticleGroupBuilder& group) {
  // The cable alone, its pins held where they are, in a world of its own, heavily damped:
  // it swings into its hanging shape within a few seconds. Its particles then start there.
  PfxParticleGroupBuilder alone = group;
  for (PfxParticlePin& pin : alone.pins) {
    pin.m_rigidBodyId = PFX_PARTICLE_PIN_WORLD;
    pin.m_anchor = alone.particles[pin.m_particle].m_position;
  }
  alone.linearDamping = kSettleDamping;
  alone.iteration = std::min(alone.iteration, kSettleIterations);
  PfxWorldParam param;
  param.gravity = gravity;
  param.timeStep = kSettleTimeStep;
  param.subStep = kSettleSubSteps;
  param.enableSleep = false;
  PfxWorld world;
  PfxInt32 err = world.initialize(param);
  PfxUInt32 id = 0;
  if (err == PFX_OK) err = world.addParticleGroup(alone.desc(), &id);
  for (int i = 0; err == PFX_OK && i < int(kSettleTime / kSettleTimeStep); ++i) err = world.step();
  if (err != PFX_OK) return err;
  const std::vector<PfxParticle>& settled = world.getParticleGroup(id)->particles;
  for (std::size_t i = 0; i < settled.size(); ++i) {
    group.particles[i].m_position = settled[i].m_position;
    group.particles[i].m_previousPosition = settled[i].m_position;
  }
  return PFX_OK;
}

void pfxBuildNodeCloth(const PfxNodeClothSpec& spec, const PfxNodeAnchorBody& pinBody,
                       PfxParticleGroupBuilder& group) {
  const PfxUInt32 nu = spec.resolutionU, nv = spec.resolutionV;
  PfxParticleGroupBuilder::Material material;
  const PfxFloat area = spec.edgeU.cross(spec.edgeV).norm();
  material.particleMass = spec.massPerArea * area / PfxFloat(nu * nv);
  material.radius = spec.radius;
  material.stretchCompliance = spec.stiffness > 0 ? 1 / spec.stiffness : 0;
  material.bendCompliance = kClothBendCompliance;
  const PfxUInt32 first = group.addCloth(spec.corner, spec.edgeU, spec.edgeV, nu, nv, material);
  auto at = [&](PfxUInt32 i, PfxUInt32 j) { return first + i + j * nu; };
  for (const std::string& name : spec.pinned) {
    if (name == "corner") pin(group, at(0, 0), pinBody);
    if (name == "corner_u") pin(group, at(nu - 1, 0), pinBody);
    if (name == "corner_v") pin(group, at(0, nv - 1), pinBody);
    if (name == "corner_uv") pin(group, at(nu - 1, nv - 1), pinBody);
    for (PfxUInt32 i = 0; i < nu; ++i) {
      if (name == "edge_u") pin(group, at(i, 0), pinBody);
      if (name == "edge_u_far") pin(group, at(i, nv - 1), pinBody);
    }
    for (PfxUInt32 j = 0; j < nv; ++j) {
      if (name == "edge_v") pin(group, at(0, j), pinBody);
      if (name == "edge_v_far") pin(group, at(nu - 1, j), pinBody);
    }
  }
  group.linearDamping = kLinearDamping;
  group.iteration = spec.iterations;
}

}  // namespace pfx
