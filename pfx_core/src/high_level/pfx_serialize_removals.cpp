// The section GONE of the serialized format: the slots of PfxWorld's removed bodies, joints
// and couplings (README.md, "Serialization"), so that ids survive a save and a load.
#include "high_level/pfx_serialize_image.h"

namespace pfx {

namespace {

void encodeIds(PfxByteWriter& w, const std::vector<PfxUInt32>& ids) {
  w.u32(static_cast<PfxUInt32>(ids.size()));
  for (const PfxUInt32 id : ids) w.u32(id);
}

// Increasing ids below `count`, and a flag per slot.
bool decodeIds(PfxByteReader& r, const char* what, PfxUInt32 count, std::vector<PfxUInt32>& ids,
               std::vector<bool>& removed) {
  ids.resize(r.count(what, 4));
  removed.assign(count, false);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    ids[i] = r.u32(what);
    if (!r.ok()) return false;
    if (ids[i] >= count || (i > 0 && ids[i] <= ids[i - 1])) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, what,
                    "holds " + std::to_string(ids[i]) + ", which is not increasing or not below " +
                        std::to_string(count));
    }
    removed[ids[i]] = true;
  }
  return true;
}

std::vector<PfxUInt32> flaggedIds(const std::vector<PfxUInt8>& flags) {
  std::vector<PfxUInt32> ids;
  for (PfxUInt32 id = 0; id < flags.size(); ++id) {
    if (flags[id]) ids.push_back(id);
  }
  return ids;
}

}  // namespace

PfxSerializeRemovals PfxSerializeAccess::removals(const PfxWorld& world) {
  PfxSerializeRemovals removals;
  removals.bodies = flaggedIds(world.m_removedBodies);
  removals.joints = flaggedIds(world.m_removedJoints);
  removals.couplings = flaggedIds(world.m_removedCouplings);
  return removals;
}

void pfxEncodeRemovals(PfxByteWriter& w, const PfxSerializeRemovals& removals) {
  encodeIds(w, removals.bodies);
  encodeIds(w, removals.joints);
  encodeIds(w, removals.couplings);
}

bool pfxDecodeRemovals(PfxByteReader& r, PfxSerializeImage& image) {
  std::vector<bool> body, joint, coupling;
  PfxSerializeRemovals& removals = image.removals;
  if (!decodeIds(r, "bodies", image.numBodies(), removals.bodies, body) ||
      !decodeIds(r, "joints", static_cast<PfxUInt32>(image.joints.size()), removals.joints,
                 joint) ||
      !decodeIds(r, "couplings", static_cast<PfxUInt32>(image.jointCouplings.size()),
                 removals.couplings, coupling)) {
    return false;
  }
  for (const PfxUInt32 id : removals.bodies) {
    const PfxRigidState& state = image.states[id];
    if (state.getMotionType() != kPfxMotionTypeFixed || state.getContactFilterSelf() != 0 ||
        state.getContactFilterTarget() != 0) {
      return r.fail(PFX_ERR_INVALID_VALUE, "bodies",
                    "body " + std::to_string(id) +
                        " is removed but not inert (fixed, contact filters 0)");
    }
  }
  const auto names = [&](const char* what, PfxUInt32 index, const char* removedWhat,
                         PfxUInt32 removedId) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, what,
                  std::string(what) + " " + std::to_string(index) + " names removed " +
                      removedWhat + " " + std::to_string(removedId));
  };
  for (PfxUInt32 j = 0; j < image.joints.size(); ++j) {
    if (joint[j]) continue;
    for (const PfxUInt32 id : {image.joints[j].m_rigidBodyIdA, image.joints[j].m_rigidBodyIdB}) {
      if (body[id]) return names("joint", j, "body", id);
    }
  }
  for (PfxUInt32 c = 0; c < image.jointCouplings.size(); ++c) {
    if (coupling[c]) continue;
    const PfxJointCoupling& live = image.jointCouplings[c];
    for (const PfxUInt32 id : {live.m_leaderJointId, live.m_followerJointId}) {
      if (joint[id]) return names("coupling", c, "joint", id);
    }
  }
  for (const auto* pairs : {&image.pairs, &image.sleepingPairs}) {
    for (PfxUInt32 p = 0; p < pairs->size(); ++p) {
      for (const PfxUInt32 id : {pfxGetObjectIdA((*pairs)[p]), pfxGetObjectIdB((*pairs)[p])}) {
        if (body[id]) return names("pair", p, "body", id);
      }
    }
  }
  for (PfxUInt32 e = 0; e < image.excludedPairKeys.size(); ++e) {
    const PfxUInt64 key = image.excludedPairKeys[e];
    for (const PfxUInt32 id : {PfxUInt32(key >> 32), PfxUInt32(key)}) {
      if (body[id]) return names("exclusion", e, "body", id);
    }
  }
  return true;
}

bool pfxCheckRemovedPins(PfxByteReader& r, const PfxSerializeImage& image) {
  const std::vector<PfxUInt32>& removed = image.removals.bodies;
  const auto isRemoved = [&](PfxUInt32 id) {
    return std::binary_search(removed.begin(), removed.end(), id);
  };
  for (PfxUInt32 g = 0; g < image.particleGroups.size(); ++g) {
    if (!image.particleGroups[g]) continue;
    const PfxParticleGroup& group = *image.particleGroups[g];
    std::vector<PfxUInt32> bodies;
    for (const PfxParticlePin& pin : group.pins) bodies.push_back(pin.m_rigidBodyId);
    for (const PfxParticleTether& tether : group.tethers) bodies.push_back(tether.m_rigidBodyId);
    for (const PfxUInt32 id : bodies) {
      if (id != PFX_PARTICLE_PIN_WORLD && isRemoved(id)) {
        return r.fail(PFX_ERR_OUT_OF_RANGE, "pins",
                      "group " + std::to_string(g) + " is pinned to removed body " +
                          std::to_string(id));
      }
    }
  }
  return true;
}

}  // namespace pfx
