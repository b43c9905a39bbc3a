// Serialized worlds (pfxLoadWorld). The file's checksum is recomputed over the input's
// body first, as a file written by a buggy or hostile writer would carry a matching one,
// so that mutations reach the sections instead of stopping at the checksum. A refused file
// leaves the world as it was; a loaded one saves again, loads again to the same bytes, and
// steps with finite states.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "high_level/pfx_serialize_format.h"
#include "pfx_fuzz_util.h"

namespace {

std::vector<std::uint8_t> withMatchingChecksum(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  if (size >= pfx::kPfxSerializeHeaderBytes &&
      std::memcmp(data, pfx::kPfxSerializeMagic, sizeof(pfx::kPfxSerializeMagic)) == 0) {
    const std::size_t bodyBytes = size - pfx::kPfxSerializeHeaderBytes;
    pfx::pfxStoreLittle<pfx::PfxUInt64>(bytes.data() + 16, bodyBytes);
    pfx::pfxStoreLittle<pfx::PfxUInt64>(
        bytes.data() + 24,
        pfx::pfxSerializeChecksum(bytes.data() + pfx::kPfxSerializeHeaderBytes, bodyBytes));
  }
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pfx;
  const std::vector<std::uint8_t> bytes = withMatchingChecksum(data, size);
  PfxWorld world;
  PfxSerializedMeshes meshes;
  std::string error;
  if (pfx_fuzz::loadBytes(world, bytes.data(), bytes.size(), meshes, error) != PFX_OK) {
    if (size > 0 && error.empty()) pfx_fuzz::fail("world file refused without a message");
    pfx_fuzz::checkWorldEmpty(world, "refused world file");
    return 0;
  }
  pfx_fuzz::checkStatesFinite(world, "world file load");

  pfx_fuzz::checkSaveLoadRoundTrip(world);
  // Up to PFX_MAX_SUB_STEPS times PFX_MAX_ITERATIONS solver sweeps a step, which a file may
  // ask for: a world asking for more than a few hundred is loaded and saved again above but
  // not stepped, so that the run spends its time on many inputs rather than long steps.
  const PfxWorldParam& param = world.getParam();
  if (std::uint64_t(param.subStep) * param.iteration > 256) return 0;
  pfx_fuzz::stepAndCheck(world, 1, "world file step");
  return 0;
}
