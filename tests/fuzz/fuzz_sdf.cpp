// SDFormat worlds and models (pfxLoadSdfString); pfx scene XML has its own target,
// fuzz_scene. Checks as pfx_fuzz_scene.h says.
#include <cstdint>
#include <string>

#include "pfx_fuzz_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  pfx_fuzz::checkSceneLoad([&](pfx::PfxWorld& world, const pfx::PfxSceneLoadParam& param,
                               pfx::PfxSceneModel& model, std::string& message) {
    return pfx::pfxLoadSdfString(world, text, param, model, &message);
  });
  return 0;
}
