// Drops a box onto a fixed box through the installed umbrella header and library; exits 0
// when it comes to rest on top and a low-level stage given no time step names the field.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "pfx/pfx.h"

int main() {
  using namespace pfx;
  PfxWorld world;
  PfxBodyInit ground;
  ground.mass = 0;
  pfxAddBody(world, pfxMakeShape(PfxBox(2, 0.5f, 2)), ground);
  PfxBodyInit box;
  box.position = PfxVector3(0, 2, 0);
  PfxUInt32 id = 0;
  if (pfxAddBody(world, pfxMakeShape(PfxBox(0.5f, 0.5f, 0.5f)), box, &id) != PFX_OK) return 1;
  for (int i = 0; i < 120; ++i) world.step();
  const PfxFloat y = world.getRigidState(id).getPosition().y();
  std::printf("box rests at y = %.4f\n", y);
  PfxUpdateRigidStatesParam update;
  const bool named = pfxUpdateRigidStates(update) == SCE_PFX_ERR_INVALID_VALUE &&
                     std::strstr(pfxGetLastErrorDetail(), "timeStep") != nullptr;
  std::printf("a stage without its time step: %s\n", pfxGetLastErrorDetail());
  return std::abs(y - 1.0f) < 0.01f && named ? 0 : 1;
}
