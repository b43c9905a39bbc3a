// OctoMap files (.bt and .ot; pfxLoadOctomapFile tells them by their first line) into a
// fixed body: a refused file leaves the world empty, a loaded map is one body that rays
// and a sphere dropped on it meet with finite results.
#include <cstdint>
#include <string>

#include "pfx/loaders/pfx_octomap_loader.h"
#include "pfx_fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace pfx;
  const std::string path = pfx_fuzz::writeScratchFile("map.bt", data, size);
  PfxWorld world;
  PfxOctomap map;
  std::string message;
  if (pfxLoadOctomapFile(world, path, PfxOctomapLoadParam(), map, &message) != PFX_OK) {
    if (message.empty()) pfx_fuzz::fail("octomap refused without a message");
    pfx_fuzz::checkWorldEmpty(world, "refused octomap");
    return 0;
  }
  if (world.getNumRigidBodies() != 1 || map.bodyId != 0 || !map.meshCreated) {
    pfx_fuzz::fail("a loaded octomap is not one body");
  }
  PfxRayInput ray;
  ray.m_startPosition = PfxVector3(0, 0, 100);
  ray.m_direction = PfxVector3(PfxFloat(0.01), PfxFloat(0.02), -200);
  ray.m_contactFilterSelf = ray.m_contactFilterTarget = 0xffffffffu;
  PfxRayOutput hit;
  if (world.castRay(ray, hit) != PFX_OK) pfx_fuzz::fail("ray on an octomap refused");
  if (hit.m_contactFlag && (!(hit.m_variable >= 0) || !(hit.m_variable <= 1) ||
                            !pfxIsFinite(hit.m_contactPoint))) {
    pfx_fuzz::fail("ray hit outside the ray");
  }
  PfxBodyInit sphere;
  sphere.position = PfxVector3(0, 0, 1);
  if (pfxAddBody(world, pfxMakeShape(PfxSphere(PfxFloat(0.2))), sphere) != PFX_OK) {
    pfx_fuzz::fail("sphere refused");
  }
  pfx_fuzz::stepAndCheck(world, 2, "octomap steps");
  return 0;
}
