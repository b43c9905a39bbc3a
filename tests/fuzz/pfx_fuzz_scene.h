// What the two scene targets check, pfx scene XML (fuzz_scene) and SDFormat (fuzz_sdf): a
// refused scene leaves the world empty with its parameters as they were; a loaded one steps
// with finite states. They are two targets because libsdformat builds its whole description
// of the format anew for every document (a quarter of a second each under ASan), which held
// the pfx XML reader to the same few inputs per second.
#pragma once

#include <string>

#include "pfx/loaders/pfx_scene_loader.h"
#include "pfx_fuzz_util.h"

namespace pfx_fuzz {

inline bool sameParam(const pfx::PfxWorldParam& a, const pfx::PfxWorldParam& b) {
  return a.gravity == b.gravity && a.timeStep == b.timeStep && a.subStep == b.subStep &&
         a.iteration == b.iteration && a.worldCenter == b.worldCenter &&
         a.worldExtent == b.worldExtent && a.pipeline == b.pipeline &&
         a.enableSleep == b.enableSleep;
}

// `load(world, param, model, message)` reads the input into the world and returns the error.
template <class Load>
void checkSceneLoad(Load load) {
  using namespace pfx;
  PfxWorld world;
  const PfxWorldParam before = world.getParam();
  PfxSceneLoadParam param;
  param.modelPaths.push_back(scratchFolder());  // model:// finds nothing there
  PfxSceneModel model;
  std::string message;
  if (load(world, param, model, message) != PFX_OK) {
    if (message.empty()) fail("scene refused without a message");
    checkWorldEmpty(world, "refused scene");
    if (!sameParam(world.getParam(), before)) fail("refused scene changed the physics");
    return;
  }
  checkStatesFinite(world, "scene load");
  // A file asking for a tiny step and many sub-steps and iterations may take long per step;
  // one step shows the bodies it built are sound.
  stepAndCheck(world, 1, "scene step");
}

}  // namespace pfx_fuzz
