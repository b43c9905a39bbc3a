// URDF text into a world (pfxLoadUrdfString): a refused robot leaves the world empty, a
// loaded one steps with finite states. Mesh files named by the input are looked for in an
// empty folder and allowed to be missing, so that each input runs in milliseconds.
#include <cstdint>
#include <string>
#include <vector>

#include "pfx/loaders/pfx_urdf_loader.h"
#include "pfx_fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pfx;
  const std::string xml(reinterpret_cast<const char*>(data), size);
  PfxWorldParam worldParam;
  worldParam.gravity = PfxVector3(0, 0, PfxFloat(-9.81));
  PfxWorld world;
  if (world.initialize(worldParam) != PFX_OK) pfx_fuzz::fail("initialize");

  PfxUrdfLoadParam param;
  param.allowMissingMeshes = true;
  param.placeAboveGround = true;
  PfxUrdfModel model;
  std::string message;
  const PfxInt32 err = pfxLoadUrdfString(world, xml, pfx_fuzz::scratchFolder(), param, model,
                                         &message);
  if (err != PFX_OK) {
    if (message.empty()) pfx_fuzz::fail("urdf refused without a message");
    pfx_fuzz::checkWorldEmpty(world, "refused urdf");
    return 0;
  }
  pfx_fuzz::checkStatesFinite(world, "urdf load");
  std::vector<double> positions, velocities;
  pfxGetUrdfJointStates(world, model, positions, velocities);
  pfx_fuzz::stepAndCheck(world, 2, "urdf steps");
  return 0;
}
