// PfxWorldBatch: whole worlds as the items of one parallel-for. A world never meets another
// world's data, so the split of worlds over threads cannot change any world's bits.
#include "pfx/high_level/pfx_world_batch.h"

#include <algorithm>
#include <cassert>
#include <string>

#include "high_level/pfx_serialize_format.h"
#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

// One body's row of gatherStates.
void copyStateRow(const PfxRigidState& state, PfxFloat* row) {
  std::copy_n(state.getPosition().data(), 3, row);
  std::copy_n(state.getOrientation().coeffs().data(), 4, row + 3);
  std::copy_n(state.getLinearVelocity().data(), 3, row + 7);
  std::copy_n(state.getAngularVelocity().data(), 3, row + 10);
}

}  // namespace

PfxUInt64 pfxHashRigidStates(const PfxWorld& world) {
  PfxUInt64 hash = 0xcbf29ce484222325ull;
  PfxFloat row[PFX_BATCH_STATE_FLOATS];
  for (PfxUInt32 b = 0; b < world.getNumRigidBodies(); ++b) {
    copyStateRow(world.getRigidState(b), row);
    for (const PfxFloat value : row) {
      // Little-endian whatever the machine's, so that hashes compare across machines.
      PfxUInt8 bytes[sizeof(PfxFloat)];
      pfxStoreLittle(bytes, value);
      for (const PfxUInt8 byte : bytes) hash = (hash ^ byte) * 0x100000001b3ull;
    }
  }
  return hash;
}

PfxWorldBatch::PfxWorldBatch() = default;
PfxWorldBatch::~PfxWorldBatch() = default;

PfxInt32 PfxWorldBatch::setNumThreads(PfxUInt32 numThreads) {
  if (numThreads > PFX_MAX_THREADS) {
    return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                          "PfxWorldBatch::setNumThreads: %u threads, more than PFX_MAX_THREADS (%u)",
                          numThreads, PFX_MAX_THREADS);
  }
  return m_taskManager.initialize(numThreads);
}

PfxInt32 PfxWorldBatch::addWorld(PfxWorld& world, PfxUInt32* outIndex) {
  if (std::find(m_worlds.begin(), m_worlds.end(), &world) != m_worlds.end()) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "PfxWorldBatch::addWorld: the world is in the batch already");
  }
  if (outIndex) *outIndex = getNumWorlds();
  m_worlds.push_back(&world);
  m_stepErrors.push_back(PFX_OK);
  return PFX_OK;
}

PfxInt32 PfxWorldBatch::addCopies(const PfxWorld& source, PfxUInt32 count, std::string* error) {
  std::vector<PfxUInt8> bytes;
  PfxInt32 err = pfxSaveWorldToBytes(source, bytes, error);
  if (err != PFX_OK) return err;
  // The batch's threads go to whole worlds; the thread count changes no result.
  PfxLoadWorldOptions options;
  options.keepSavedNumThreads = false;
  options.numThreads = 1;
  std::vector<std::unique_ptr<OwnedWorld>> copies(count);
  for (auto& copy : copies) {
    copy = std::make_unique<OwnedWorld>();
    err = pfxLoadWorldFromBytes(copy->world, bytes.data(), bytes.size(), copy->meshes, error,
                                options);
    if (err != PFX_OK) return err;
  }
  for (auto& copy : copies) {
    m_worlds.push_back(&copy->world);
    m_stepErrors.push_back(PFX_OK);
    m_owned.push_back(std::move(copy));
  }
  return PFX_OK;
}

void PfxWorldBatch::clear() {
  m_worlds.clear();
  m_owned.clear();
  m_stepErrors.clear();
}

PfxWorld& PfxWorldBatch::getWorld(PfxUInt32 index) {
  assert(index < getNumWorlds());
  return *m_worlds[index];
}

const PfxWorld& PfxWorldBatch::getWorld(PfxUInt32 index) const {
  assert(index < getNumWorlds());
  return *m_worlds[index];
}

PfxInt32 PfxWorldBatch::step(PfxUInt32 count) {
  const PfxInt32 err =
      pfxParallelFor(&m_taskManager, getNumWorlds(), 1, [this, count](PfxUInt32 begin, PfxUInt32 end) {
        for (PfxUInt32 i = begin; i < end; ++i) {
          PfxInt32 worldErr = PFX_OK;
          for (PfxUInt32 s = 0; s < count && worldErr == PFX_OK; ++s) worldErr = m_worlds[i]->step();
          m_stepErrors[i] = worldErr;
        }
      });
  if (err != PFX_OK) return err;
  for (PfxUInt32 i = 0; i < getNumWorlds(); ++i) {
    if (m_stepErrors[i] != PFX_OK) {
      return pfxRejectParam(m_stepErrors[i], "PfxWorldBatch::step: world %u of %u failed its step",
                            i, getNumWorlds());
    }
  }
  return PFX_OK;
}

PfxUInt32 PfxWorldBatch::getNumRigidBodies() const { return getFirstBody(getNumWorlds()); }

PfxUInt32 PfxWorldBatch::getFirstBody(PfxUInt32 index) const {
  PfxUInt32 first = 0;
  for (PfxUInt32 i = 0; i < index && i < getNumWorlds(); ++i) first += m_worlds[i]->getNumRigidBodies();
  return first;
}

PfxInt32 PfxWorldBatch::gatherStates(PfxFloat* out, PfxUInt64 capacity) {
  const PfxUInt64 needed = PfxUInt64(getNumRigidBodies()) * PFX_BATCH_STATE_FLOATS;
  if (needed > 0 && !out) {
    return pfxRejectParam(PFX_ERR_NULL_POINTER, "PfxWorldBatch::gatherStates: out is null");
  }
  if (capacity < needed) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                          "PfxWorldBatch::gatherStates: room for %llu floats, %llu needed",
                          static_cast<unsigned long long>(capacity),
                          static_cast<unsigned long long>(needed));
  }
  std::vector<PfxUInt32> firstBodies(getNumWorlds());
  for (PfxUInt32 i = 0, first = 0; i < getNumWorlds(); ++i) {
    firstBodies[i] = first;
    first += m_worlds[i]->getNumRigidBodies();
  }
  return pfxParallelFor(&m_taskManager, getNumWorlds(), 16, [&](PfxUInt32 begin, PfxUInt32 end) {
    for (PfxUInt32 i = begin; i < end; ++i) {
      const PfxWorld& world = *m_worlds[i];
      PfxFloat* row = out + PfxUInt64(firstBodies[i]) * PFX_BATCH_STATE_FLOATS;
      for (PfxUInt32 b = 0; b < world.getNumRigidBodies(); ++b, row += PFX_BATCH_STATE_FLOATS) {
        copyStateRow(world.getRigidState(b), row);
      }
    }
  });
}

}  // namespace pfx
