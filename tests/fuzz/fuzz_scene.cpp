// Scene files: pfx scene XML (pfxLoadSceneXmlString) and SDFormat (pfxLoadSdfString), told
// apart by the root element as pfxLoadSceneFile tells them. A refused scene leaves the world
// empty with its parameters as they were; a loaded one steps with finite states.
#include <cstdint>
#include <cstring>
#include <string>

#include "pfx/loaders/pfx_scene_loader.h"
#include "pfx_fuzz_util.h"

namespace {

bool sameParam(const pfx::PfxWorldParam& a, const pfx::PfxWorldParam& b) {
  return a.gravity == b.gravity && a.timeStep == b.timeStep && a.subStep == b.subStep &&
         a.iteration == b.iteration && a.worldCenter == b.worldCenter &&
         a.worldExtent == b.worldExtent && a.pipeline == b.pipeline &&
         a.enableSleep == b.enableSleep;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pfx;
  const std::string text(reinterpret_cast<const char*>(data), size);
  PfxWorld world;
  const PfxWorldParam before = world.getParam();
  PfxSceneLoadParam param;
  param.modelPaths.push_back(pfx_fuzz::scratchFolder());  // model:// finds nothing there
  PfxSceneModel model;
  std::string message;
  const bool sdf = text.find("<sdf") != std::string::npos;
  const PfxInt32 err =
      sdf ? pfxLoadSdfString(world, text, param, model, &message)
          : pfxLoadSceneXmlString(world, text, pfx_fuzz::scratchFolder(), param, model, &message);
  if (err != PFX_OK) {
    if (message.empty()) pfx_fuzz::fail("scene refused without a message");
    pfx_fuzz::checkWorldEmpty(world, "refused scene");
    if (!sameParam(world.getParam(), before)) pfx_fuzz::fail("refused scene changed the physics");
    return 0;
  }
  pfx_fuzz::checkStatesFinite(world, "scene load");
  // A file asking for a tiny step and many sub-steps and iterations may take long per step;
  // one step shows the bodies it built are sound.
  pfx_fuzz::stepAndCheck(world, 1, "scene step");
  return 0;
}
