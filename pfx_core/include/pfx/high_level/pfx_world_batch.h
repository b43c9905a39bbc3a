// Many independent worlds in one process, stepped together: each world steps on one thread
// of the batch's task manager, the worlds spread over the threads, and their states are
// gathered into one array. The tool for randomized trials and learning, where thousands of
// small worlds (a robot arm, a ragdoll) each need little more than one core's cache.
//
// A world steps in a batch exactly as alone: a batch's step gives, world for world, the bits
// of stepping the same worlds one by one, whatever the batch's thread count.
#pragma once

#include <memory>
#include <vector>

#include "pfx/base_level/task/pfx_tbb_task_manager.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx/high_level/pfx_world.h"

namespace pfx {

// Floats per body in PfxWorldBatch::gatherStates: position (3), orientation as x, y, z, w
// (4), linear velocity (3), angular velocity (3).
constexpr PfxUInt32 PFX_BATCH_STATE_FLOATS = 13;

// FNV-1a (64 bits) over every body's state as gatherStates lays it out, the bytes of each
// PfxFloat in little-endian order: equal hashes say two runs ended in the same bits (a job
// run on another machine, in a batch or alone). Float and double builds hash differently.
PfxUInt64 pfxHashRigidStates(const PfxWorld& world);

class PfxWorldBatch {
 public:
  PfxWorldBatch();  // one thread
  ~PfxWorldBatch();
  PfxWorldBatch(const PfxWorldBatch&) = delete;
  PfxWorldBatch& operator=(const PfxWorldBatch&) = delete;

  // Threads that step the worlds (0: every core the process may use). The worlds keep
  // their own PfxWorldParam::numThreads for their inner stages; give them 1, so that the
  // threads go to whole worlds. PFX_ERR_OUT_OF_RANGE above PFX_MAX_THREADS.
  PfxInt32 setNumThreads(PfxUInt32 numThreads);
  PfxUInt32 getNumThreads() const { return m_taskManager.getNumThreads(); }

  // Adds a world the caller owns and keeps alive, unmoved, while it is in the batch.
  // PFX_ERR_INVALID_VALUE when it is in the batch already.
  PfxInt32 addWorld(PfxWorld& world, PfxUInt32* outIndex = nullptr);
  // Adds `count` copies of `source` (through pfxSaveWorldToBytes, so each continues exactly
  // as the source would, contacts and simulated time included) that the batch owns, each
  // stepping on one thread. `error` (optional) gets the serializer's reason on failure;
  // then nothing was added.
  PfxInt32 addCopies(const PfxWorld& source, PfxUInt32 count, std::string* error = nullptr);
  // Removes every world (the caller's are left as they are).
  void clear();

  PfxUInt32 getNumWorlds() const { return static_cast<PfxUInt32>(m_worlds.size()); }
  // The world at `index` (in the order added), to set its states, forces or joint drives
  // between steps. Out of range is a programming error (asserted).
  PfxWorld& getWorld(PfxUInt32 index);
  const PfxWorld& getWorld(PfxUInt32 index) const;

  // Steps every world `count` times. A world whose step fails stops there and the others go
  // on; the error returned is that of the lowest-numbered failed world, which
  // pfxGetLastErrorDetail() names.
  PfxInt32 step(PfxUInt32 count = 1);

  // Bodies over all worlds, and the first of world `index` in gatherStates' rows
  // (index == getNumWorlds() gives the total).
  PfxUInt32 getNumRigidBodies() const;
  PfxUInt32 getFirstBody(PfxUInt32 index) const;
  // Every world's body states, world after world, PFX_BATCH_STATE_FLOATS floats per body,
  // into `out`, which holds `capacity` floats. PFX_ERR_OUT_OF_BUFFER when that is fewer
  // than getNumRigidBodies() * PFX_BATCH_STATE_FLOATS (nothing written), PFX_ERR_NULL_POINTER
  // for a null `out` with bodies to write. Runs on the batch's threads.
  PfxInt32 gatherStates(PfxFloat* out, PfxUInt64 capacity);

 private:
  // A copy the batch made, with the meshes its shapes point to.
  struct OwnedWorld {
    PfxWorld world;
    PfxSerializedMeshes meshes;
  };

  PfxTbbTaskManager m_taskManager;
  std::vector<PfxWorld*> m_worlds;
  std::vector<std::unique_ptr<OwnedWorld>> m_owned;
  std::vector<PfxInt32> m_stepErrors;  // per world, written by its own task
};

}  // namespace pfx
