// The reader against damaged files: cut at every byte, every byte of a small file changed
// (with the checksum left stale, and set again so that the checks behind it are reached),
// a sample of a large file's bytes changed, a wrong version, counts of 2^31, a mesh whose
// triangles name vertices it does not have, NaN. Each load ends in an error naming the
// place, or in a world that steps; none crashes, none allocates more than the file can
// justify, and a failed load leaves the world and the meshes it was given as they were.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>

#include "pfx_serialize_test_world.h"

// The largest single heap request while a load runs, to show that a count in a file
// cannot make the reader allocate for elements the file does not hold.
namespace {
std::atomic<bool> g_trackAllocations{false};
std::atomic<std::size_t> g_largestAllocation{0};
void noteAllocation(std::size_t size) {
  if (!g_trackAllocations) return;
  std::size_t seen = g_largestAllocation.load();
  while (size > seen && !g_largestAllocation.compare_exchange_weak(seen, size)) {
  }
}
}  // namespace

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) {
  noteAllocation(size);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t align) {
  noteAllocation(size);
  const std::size_t a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

using namespace pfx;
using namespace pfx_test;

namespace {

// A load into a world that already holds something, which must come through a failure
// untouched, and a check of what the failure said.
class Target {
 public:
  Target() {
    addBody(m_world, pfxMakeShape(PfxSphere(1)), PfxVector3(0, 3, 0), 1);
    EXPECT_EQ(m_world.step(), PFX_OK);
    m_bytes = saveWorld(m_world);
  }

  // Loads `bytes`; returns the error code. On failure the error must name a place (unless
  // the file is too short to have one) and nothing may have changed; on success the world
  // must step.
  PfxInt32 load(const Bytes& bytes, bool checkWorld) {
    std::string error;
    g_largestAllocation = 0;
    g_trackAllocations = true;
    PfxWorld fresh;
    const PfxInt32 err = loadWorld(checkWorld ? m_world : fresh, m_meshes, bytes, &error);
    g_trackAllocations = false;
    // The file's bytes, the mesh arrays it may fill and per-element bookkeeping; never a
    // count taken on trust.
    EXPECT_LT(g_largestAllocation.load(), 4 * bytes.size() + 4096) << error;
    if (err == PFX_OK) {
      EXPECT_TRUE(error.empty());
      PfxWorld& loaded = checkWorld ? m_world : fresh;
      // What loads steps without crashing. A changed value may be one the world accepts and
      // still cannot simulate (a gravity of 1e30 turns the states infinite, which the next
      // step reports), and a file may ask for a billion iterations, a parameter too: only
      // worlds of a sane amount of work are stepped.
      const PfxWorldParam& param = loaded.getParam();
      if (PfxUInt64(param.subStep) * param.iteration <= 1000) {
        const PfxInt32 stepped = loaded.step();
        EXPECT_TRUE(stepped == PFX_OK || stepped == PFX_ERR_INVALID_VALUE)
            << pfxGetLastErrorDetail();
      }
      if (checkWorld) {
        PfxSerializedMeshes none;
        EXPECT_EQ(loadWorld(m_world, none, m_bytes), PFX_OK);
      }
      m_meshes.clear();
      return err;
    }
    EXPECT_FALSE(error.empty());
    EXPECT_NE(error.find(':'), std::string::npos) << "no place named: " << error;
    EXPECT_TRUE(m_meshes.largeMeshes().empty() && m_meshes.convexMeshes().empty());
    if (checkWorld) {
      EXPECT_EQ(saveWorld(m_world), m_bytes) << "a failed load changed the world";
    }
    return err;
  }

 private:
  PfxWorld m_world;
  PfxSerializedMeshes m_meshes;
  Bytes m_bytes;
};

const Bytes& smallFile() {
  static const Bytes bytes = [] {
    SmallWorld small;
    return saveWorld(small.world);
  }();
  return bytes;
}

// The error of loading `bytes` into a fresh world, with its tags as a string.
PfxInt32 loadError(const Bytes& bytes, std::string& error) {
  PfxWorld world;
  PfxSerializedMeshes meshes;
  return loadWorld(world, meshes, bytes, &error);
}

void putReal(Bytes& bytes, std::size_t at, double value) {
  if (bytes[12] == 4) {
    const float f = static_cast<float>(value);
    PfxUInt32 bits;
    std::memcpy(&bits, &f, 4);
    putU32(bytes, at, bits);
  } else {
    PfxUInt64 bits;
    std::memcpy(&bits, &value, 8);
    for (int i = 0; i < 8; ++i) bytes[at + i] = PfxUInt8(bits >> (8 * i));
  }
}

TEST(SerializeReader, TheSmallFileLoadsAndIsSmall) {
  const Bytes& bytes = smallFile();
  EXPECT_LT(bytes.size(), 20000u);
  Target target;
  EXPECT_EQ(target.load(bytes, true), PFX_OK);
}

TEST(SerializeReader, FileCutAtEveryByteIsRejected) {
  const Bytes& bytes = smallFile();
  Target target;
  for (std::size_t size = 0; size < bytes.size(); ++size) {
    const Bytes cut(bytes.begin(), bytes.begin() + size);
    ASSERT_EQ(target.load(cut, size % 16 == 0), PFX_ERR_OUT_OF_BUFFER) << "cut at " << size;
  }
  std::string error;
  EXPECT_EQ(loadError(Bytes(bytes.begin(), bytes.begin() + 40), error), PFX_ERR_OUT_OF_BUFFER);
  EXPECT_EQ(error.rfind("body: the file ends after 8 of the", 0), 0u) << error;
  EXPECT_EQ(loadError(Bytes(bytes.begin(), bytes.begin() + 20), error), PFX_ERR_OUT_OF_BUFFER);
  EXPECT_EQ(error.rfind("header: ", 0), 0u) << error;
}

TEST(SerializeReader, EveryChangedByteIsCaught) {
  const Bytes& bytes = smallFile();
  Target target;
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    Bytes changed = bytes;
    changed[at] ^= 0x5a;
    ASSERT_NE(target.load(changed, at % 16 == 0), PFX_OK) << "byte " << at;
  }
}

TEST(SerializeReader, EveryChangedByteBehindAResealedChecksumLoadsSafelyOrIsRejected) {
  const Bytes& bytes = smallFile();
  Target target;
  int rejected = 0;
  for (std::size_t at = 32; at < bytes.size(); ++at) {
    // Every bit flipped on even bytes, the lowest one on odd ones (a count off by one).
    const PfxUInt8 pattern = at % 2 == 0 ? 0xff : 0x01;
    Bytes changed = bytes;
    changed[at] ^= pattern;
    resealChecksum(changed);
    rejected += target.load(changed, at % 16 == 0) != PFX_OK;
    if (::testing::Test::HasFailure()) FAIL() << "byte " << at << " ^ " << int(pattern);
  }
  // Most bytes are values that may take any other finite value; counts, ids, enums and
  // exponents may not.
  EXPECT_GT(rejected, int(bytes.size() / 40));
}

TEST(SerializeReader, ASampleOfALargeFilesBytesLoadsSafelyOrIsRejected) {
  MixedWorld mixed;
  buildMixedWorld(mixed, 1);
  for (int step = 0; step < 120; ++step) {
    driveMixedWorld(mixed.world, mixed, mixed.deform.mesh, step);
    ASSERT_EQ(mixed.world.step(), PFX_OK);
  }
  const Bytes bytes = saveWorld(mixed.world);
  Target target;
  std::mt19937 rng(7);
  for (int i = 0; i < 150; ++i) {
    Bytes changed = bytes;
    const std::size_t at = 32 + rng() % (bytes.size() - 32);
    changed[at] ^= PfxUInt8(1 + rng() % 255);
    resealChecksum(changed);
    target.load(changed, false);
    if (::testing::Test::HasFailure()) FAIL() << "byte " << at;
  }
}

TEST(SerializeReader, WrongMagicVersionOrPrecisionIsRejected) {
  std::string error;
  Bytes changed = smallFile();
  putU32(changed, 8, PFX_SERIALIZE_VERSION + 1);
  EXPECT_EQ(loadError(changed, error), PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(error.rfind("header/version: is " + std::to_string(PFX_SERIALIZE_VERSION + 1) +
                            "; this build reads versions 1 to " +
                            std::to_string(PFX_SERIALIZE_VERSION),
                        0),
            0u)
      << error;
  putU32(changed, 8, 0);
  EXPECT_EQ(loadError(changed, error), PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(error.rfind("header/version: is 0;", 0), 0u) << error;
  changed = smallFile();
  changed[0] = 'X';
  EXPECT_EQ(loadError(changed, error), PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(error.rfind("header/magic:", 0), 0u) << error;
  changed = smallFile();
  changed[12] = 2;
  EXPECT_EQ(loadError(changed, error), PFX_ERR_INVALID_FLAG);
  EXPECT_EQ(error.rfind("header/precision:", 0), 0u) << error;
}

TEST(SerializeReader, HugeCountsAreRejectedWithoutAllocatingForThem) {
  const Bytes& bytes = smallFile();
  const std::size_t realBytes = bytes[12];
  const struct {
    const char* section;
    std::size_t offset;
    const char* place;
  } counts[] = {
      {"BODY", 0, "bodies/count"},
      {"JOIN", 0, "joints/count"},
      {"CPLG", 0, "joint couplings/count"},
      {"EXCL", 0, "exclusions/count"},
      {"CMSH", 0, "convex meshes/count"},
      {"LMSH", 0, "large meshes/count"},
      {"CONT", 0, "contacts/numManifolds"},
      {"CONT", 4, "contacts/numFree"},
      // The first large mesh's vertices, then its triangles.
      {"LMSH", 4 + 4 + 1, "large meshes/large mesh 0/counts"},
      {"LMSH", 4 + 4 + 1 + 4, "large meshes/large mesh 0/counts"},
  };
  Target target;
  for (const auto& count : counts) {
    for (PfxUInt32 value : {0x80000000u, 0xffffffffu}) {
      Bytes changed = bytes;
      putU32(changed, sectionPayload(changed, count.section) + count.offset, value);
      resealChecksum(changed);
      std::string error;
      EXPECT_NE(loadError(changed, error), PFX_OK) << count.place;
      EXPECT_EQ(error.rfind(count.place, 0), 0u) << error;
      EXPECT_NE(target.load(changed, true), PFX_OK);
    }
  }
  (void)realBytes;
}

// Offset of the first triangle corner of large mesh `index`, and whether corners are 16-bit.
std::size_t firstCorner(const Bytes& bytes, PfxUInt32 index, bool& offsets) {
  const std::size_t realBytes = bytes[12];
  std::size_t at = sectionPayload(bytes, "LMSH") + 4;
  for (PfxUInt32 m = 0;; ++m) {
    const PfxUInt8 storage = bytes[at + 4];
    const PfxUInt32 numVertices = getU32(bytes, at + 5);
    const PfxUInt32 numTriangles = getU32(bytes, at + 9);
    const PfxUInt32 numIslands = getU32(bytes, at + 17);
    const PfxUInt32 numNodes = getU32(bytes, at + 21);
    const std::size_t vertices = at + 25 + 7 * realBytes;
    const std::size_t corners = vertices + 3 * numVertices * ((storage & 1) ? 2 : realBytes);
    offsets = (storage & 2) != 0;
    if (m == index) return corners;
    at = corners + 3 * numTriangles * (offsets ? 2 : 4) + numTriangles * ((storage & 4) ? 2 : 4) +
         numTriangles + 16 * (numIslands + numNodes);
  }
}

TEST(SerializeReader, TrianglesNamingMissingVerticesAreRejected) {
  for (PfxUInt32 mesh : {0u, 1u}) {
    Bytes changed = smallFile();
    bool offsets = false;
    const std::size_t at = firstCorner(changed, mesh, offsets);
    EXPECT_EQ(offsets, mesh == 0) << "the quantized mesh keeps 16-bit corners, the other not";
    if (offsets) {
      changed[at] = changed[at + 1] = 0xff;
    } else {
      putU32(changed, at, 1000);
    }
    resealChecksum(changed);
    std::string error;
    EXPECT_EQ(loadError(changed, error), PFX_ERR_OUT_OF_RANGE);
    EXPECT_EQ(
        error.rfind("large meshes/large mesh " + std::to_string(mesh) + "/triangles: triangle ", 0),
        0u)
        << error;
    Target target;
    EXPECT_EQ(target.load(changed, true), PFX_ERR_OUT_OF_RANGE);
  }
}

TEST(SerializeReader, NaNAndInfinityAreRejectedWhereTheyStand) {
  Bytes changed = smallFile();
  putReal(changed, sectionPayload(changed, "BODY") + 4, std::numeric_limits<double>::quiet_NaN());
  resealChecksum(changed);
  std::string error;
  EXPECT_EQ(loadError(changed, error), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(error.rfind("bodies/body 0/state/position: is nan", 0), 0u) << error;
  Target target;
  EXPECT_EQ(target.load(changed, true), PFX_ERR_INVALID_VALUE);

  changed = smallFile();
  putReal(changed, sectionPayload(changed, "PARM") + 9 * changed[12],
          std::numeric_limits<double>::infinity());
  resealChecksum(changed);
  EXPECT_EQ(loadError(changed, error), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(error.rfind("parameters/timeStep: is inf", 0), 0u) << error;
}

TEST(SerializeReader, SubStepsOrIterationsAboveTheirMaximumsAreRejected) {
  const Bytes& bytes = smallFile();
  // After worldCenter, worldExtent, gravity and timeStep: subStep, then iteration.
  const std::size_t subStep = sectionPayload(bytes, "PARM") + 10 * bytes[12];
  const struct {
    std::size_t at;
    PfxUInt32 value;
    const char* message;
  } cases[] = {
      {subStep, PFX_MAX_SUB_STEPS + 1, "parameters/subStep: 101 above 100"},
      {subStep, 0xffffffffu, "parameters/subStep: 4294967295 above 100"},
      {subStep + 4, PFX_MAX_ITERATIONS + 1, "parameters/iteration: 1001 above 1000"},
      {subStep + 4, 3000000000u, "parameters/iteration: 3000000000 above 1000"},
  };
  Target target;
  for (const auto& c : cases) {
    Bytes changed = bytes;
    putU32(changed, c.at, c.value);
    resealChecksum(changed);
    std::string error;
    EXPECT_EQ(loadError(changed, error), PFX_ERR_OUT_OF_RANGE);
    EXPECT_EQ(error.rfind(c.message, 0), 0u) << error;
    EXPECT_EQ(target.load(changed, true), PFX_ERR_OUT_OF_RANGE);
  }
  Bytes most = bytes;
  putU32(most, subStep, PFX_MAX_SUB_STEPS);
  putU32(most, subStep + 4, PFX_MAX_ITERATIONS);
  resealChecksum(most);
  PfxWorld world;
  PfxSerializedMeshes meshes;
  ASSERT_EQ(loadWorld(world, meshes, most), PFX_OK);
  EXPECT_EQ(world.getParam().subStep, PFX_MAX_SUB_STEPS);
  EXPECT_EQ(world.getParam().iteration, PFX_MAX_ITERATIONS);
}

TEST(SerializeReader, TheSeedsReadReportsTagsAndLeavesTheBuffersAlone) {
  Bytes changed = smallFile();
  putReal(changed, sectionPayload(changed, "BODY") + 4, std::numeric_limits<double>::quiet_NaN());
  resealChecksum(changed);
  struct App {
    PfxWorldParam param;
    double time = -1;
    PfxRigidState states[32];
    std::vector<std::string> tags;
    PfxInt32 code = PFX_OK;
    int resizes = 0;
  } app;
  std::memset(static_cast<void*>(app.states), 0x33, sizeof(app.states));
  const App before = app;
  PfxSerializeCallbacks callbacks;
  callbacks.userData = &app;
  callbacks.init = [](PfxSerializeCapacity& c, PfxSerializeBuffer& b, void* self) {
    App& a = *static_cast<App*>(self);
    b.worldParam = &a.param;
    b.simulatedTime = &a.time;
    b.rigidStates = a.states;
    c.numRigidBodies = 32;
    return true;
  };
  callbacks.resize = [](PfxSerializeCapacity&, PfxSerializeBuffer&, const PfxSerializeCapacity&,
                        void* self) {
    ++static_cast<App*>(self)->resizes;
    return false;
  };
  callbacks.error = [](PfxInt32 code, const char* const* tags, PfxUInt32 numTags, void* self) {
    static_cast<App*>(self)->code = code;
    static_cast<App*>(self)->tags.assign(tags, tags + numTags);
  };
  FilePtr file = fileWith(changed);
  EXPECT_EQ(pfxSerializeRead(file.get(), callbacks), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(app.code, PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(app.tags, (std::vector<std::string>{"bodies", "body 0", "state", "position"}));
  EXPECT_EQ(app.resizes, 0) << "nothing is sized for a file that fails";
  EXPECT_EQ(app.time, before.time);
  EXPECT_EQ(std::memcmp(app.states, before.states, sizeof(app.states)), 0);
  EXPECT_EQ(std::string(pfxGetLastErrorDetail())
                .rfind("pfxSerializeRead: bodies/body 0/state/position", 0),
            0u)
      << pfxGetLastErrorDetail();
}

}  // namespace
