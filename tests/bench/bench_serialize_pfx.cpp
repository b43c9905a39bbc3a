// The serialize scene on pfx: the bodies in a PfxWorld, saved with pfxSaveWorld and loaded
// into a fresh world with pfxLoadWorld.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "bench_rays.h"
#include "bench_serialize.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_serialize.h"

namespace pfxbench {

namespace {

bool sameState(const pfx::PfxRigidState& a, const pfx::PfxRigidState& b) {
  return a.getPosition() == b.getPosition() &&
         a.getOrientation().coeffs() == b.getOrientation().coeffs() &&
         a.getLinearVelocity() == b.getLinearVelocity() &&
         a.getAngularVelocity() == b.getAngularVelocity();
}

}  // namespace

bool runPfxSerialize(const std::vector<SerializeBody>& bodies, SerializeFigures& figures,
                     std::string& error) {
  using namespace pfx;
  PfxWorld original;
  double extent = 1;
  for (const SerializeBody& body : bodies) {
    extent = std::max({extent, std::abs(body.x) + 1, std::abs(body.z) + 1});
  }
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, PfxFloat(-kSerializeGroundHalfHeight), 0);
  const PfxFloat half = PfxFloat(kSerializeBodyHalfSize);
  PfxInt32 code =
      pfxAddBody(original,
                 pfxMakeShape(PfxBox(PfxFloat(extent), PfxFloat(kSerializeGroundHalfHeight),
                                     PfxFloat(extent))),
                 ground);
  for (const SerializeBody& body : bodies) {
    if (code != PFX_OK) break;
    PfxBodyInit init;
    init.position = PfxVector3(PfxFloat(body.x), PfxFloat(body.y), PfxFloat(body.z));
    code = body.sphere ? pfxAddBody(original, pfxMakeShape(PfxSphere(half)), init)
                       : pfxAddBody(original, pfxMakeShape(PfxBox(half, half, half)), init);
  }
  for (int i = 0; code == PFX_OK && i < kSerializeSteps; ++i) code = original.step();
  if (code != PFX_OK) {
    error = std::string("building the world: ") + pfxErrorString(code);
    return false;
  }

  const TemporaryFile file("pfx_bench_serialize_pfx");
  figures.writeSeconds = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < kSerializeTimedPasses; ++pass) {
    const double start = processCpuSeconds();
    std::FILE* out = std::fopen(file.path().c_str(), "wb");
    if (!out) {
      error = "cannot write " + file.path();
      return false;
    }
    code = pfxSaveWorld(original, out, &error);
    figures.fileBytes = double(std::ftell(out));
    const bool closed = std::fclose(out) == 0;
    figures.writeSeconds = std::min(figures.writeSeconds, processCpuSeconds() - start);
    if (code != PFX_OK || !closed) {
      if (code == PFX_OK) error = "cannot write " + file.path();
      return false;
    }
  }

  figures.readSeconds = std::numeric_limits<double>::infinity();
  figures.restored = true;
  for (int pass = 0; pass < kSerializeTimedPasses; ++pass) {
    PfxWorld copy;
    PfxSerializedMeshes meshes;
    const double start = processCpuSeconds();
    code = pfxLoadWorld(copy, file.path().c_str(), meshes, &error);
    figures.readSeconds = std::min(figures.readSeconds, processCpuSeconds() - start);
    if (code != PFX_OK) return false;
    if (copy.getNumRigidBodies() != original.getNumRigidBodies()) {
      figures.restored = false;
      continue;
    }
    for (PfxUInt32 i = 0; i < original.getNumRigidBodies(); ++i) {
      if (!sameState(original.getRigidState(i), copy.getRigidState(i))) figures.restored = false;
    }
  }
  return true;
}

}  // namespace pfxbench
