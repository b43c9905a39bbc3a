// What the fuzz targets share: a file for the loaders that read only paths, and the checks
// that a world is sound after a load or a call.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "pfx/pfx.h"

namespace pfx_fuzz {

// Ends the run with a report libFuzzer records as a crash, input saved.
[[noreturn]] inline void fail(const char* what, const std::string& detail = std::string()) {
  std::fprintf(stderr, "fuzz invariant broken: %s %s\n", what, detail.c_str());
  std::abort();
}

// A folder of this process's own, made once: the loaders that take a path read the input
// from a file in it (assimp and liboctomap pick a reader by the name and the first bytes).
// It goes when the process exits.
inline const std::string& scratchFolder() {
  static const std::string folder = [] {
    char pattern[] = "/tmp/pfx_fuzz_XXXXXX";
    if (!mkdtemp(pattern)) fail("mkdtemp");
    return std::string(pattern);
  }();
  static const int removeAtExit = std::atexit([] {
    std::error_code ignored;
    std::filesystem::remove_all(folder, ignored);
  });
  (void)removeAtExit;
  return folder;
}

inline std::string writeScratchFile(const std::string& name, const std::uint8_t* data,
                                    std::size_t size) {
  const std::string path = scratchFolder() + "/" + name;
  FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) fail("cannot write", path);
  if (size > 0 && std::fwrite(data, 1, size, file) != size) fail("short write", path);
  std::fclose(file);
  return path;
}

// Every body's state finite and its orientation of unit length: what any call that
// succeeded must leave, whatever the input was.
inline void checkStatesFinite(const pfx::PfxWorld& world, const char* after) {
  for (pfx::PfxUInt32 id = 0; id < world.getNumRigidBodies(); ++id) {
    const pfx::PfxRigidState& state = world.getRigidState(id);
    if (!state.isValid()) fail("state not finite or orientation not unit", after);
  }
}

// A load that failed must leave an empty world empty.
inline void checkWorldEmpty(const pfx::PfxWorld& world, const char* after) {
  if (world.getNumRigidBodies() != 0 || world.getNumJoints() != 0 ||
      world.getNumJointCouplings() != 0) {
    fail("a refused load left bodies or joints behind", after);
  }
}

// A few steps of a world that a loader built: its bodies must stay finite.
inline void stepAndCheck(pfx::PfxWorld& world, int steps, const char* after) {
  for (int i = 0; i < steps; ++i) {
    if (world.step() != pfx::PFX_OK) fail("step of a loaded world failed", after);
  }
  checkStatesFinite(world, after);
}

// The world as a saved file, in memory; saving a world that steps must not fail.
inline std::string savedBytes(const pfx::PfxWorld& world) {
  char* buffer = nullptr;
  std::size_t length = 0;
  FILE* file = open_memstream(&buffer, &length);
  if (!file) fail("open_memstream");
  std::string error;
  const pfx::PfxInt32 err = pfx::pfxSaveWorld(world, file, &error);
  std::fclose(file);
  std::string bytes(buffer, length);
  std::free(buffer);
  if (err != pfx::PFX_OK) fail("the world cannot be saved:", error);
  return bytes;
}

// pfxLoadWorld from bytes in memory, on numThreads whatever the file asks for (a file
// asking for 64 threads would only be slow).
inline pfx::PfxInt32 loadBytes(pfx::PfxWorld& world, const void* bytes, std::size_t size,
                               pfx::PfxSerializedMeshes& meshes, std::string& error,
                               pfx::PfxUInt32 numThreads = 1) {
  if (size == 0) return pfx::PFX_ERR_OUT_OF_BUFFER;  // fmemopen refuses an empty buffer
  FILE* file = fmemopen(const_cast<void*>(bytes), size, "rb");
  if (!file) fail("fmemopen");
  pfx::PfxLoadWorldOptions options;
  options.keepSavedNumThreads = false;
  options.numThreads = numThreads;
  const pfx::PfxInt32 err = pfx::pfxLoadWorld(world, file, meshes, &error, options);
  std::fclose(file);
  return err;
}

// A world saved, loaded into another and saved again gives the same bytes (the thread
// count, which a file also holds, included).
inline void checkSaveLoadRoundTrip(const pfx::PfxWorld& world) {
  const std::string first = savedBytes(world);
  pfx::PfxWorld loaded;
  pfx::PfxSerializedMeshes meshes;
  std::string error;
  if (loadBytes(loaded, first.data(), first.size(), meshes, error,
                world.getParam().numThreads) != pfx::PFX_OK) {
    fail("a saved world cannot be loaded:", error);
  }
  if (savedBytes(loaded) != first) fail("a loaded world saves other bytes");
}

}  // namespace pfx_fuzz
