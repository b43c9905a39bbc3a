#include "pfx/high_level/pfx_depth_camera.h"

#include <cmath>
#include <limits>

namespace pfx {

PfxInt32 pfxCheckDepthCameraParam(const PfxDepthCameraParam& p) {
  if (p.width == 0 || p.height == 0 || p.width > 4096 || p.height > 4096) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (!std::isfinite(p.horizontalFov) || p.horizontalFov <= 0 ||
      p.horizontalFov >= PfxFloat(3.14159265358979)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (!std::isfinite(p.nearClip) || !std::isfinite(p.farClip)) return PFX_ERR_INVALID_VALUE;
  if (p.nearClip < 0 || p.farClip <= p.nearClip) return PFX_ERR_INVALID_VALUE;
  return PFX_OK;
}

PfxFloat pfxGetDepthCameraFocalLength(const PfxDepthCameraParam& p) {
  return PfxFloat(p.width) / (2 * std::tan(p.horizontalFov / 2));
}

void pfxMakeDepthCameraRays(const PfxDepthCameraParam& p, const PfxTransform3& cameraPose,
                            PfxRayInput* rays) {
  const PfxFloat focal = pfxGetDepthCameraFocalLength(p);
  const PfxFloat cx = PfxFloat(p.width - 1) / 2;
  const PfxFloat cy = PfxFloat(p.height - 1) / 2;
  const PfxMatrix3 rotation = cameraPose.linear();
  const PfxVector3 origin = cameraPose.translation();
  const PfxFloat span = p.farClip - p.nearClip;
  for (PfxUInt32 v = 0; v < p.height; ++v) {
    for (PfxUInt32 u = 0; u < p.width; ++u) {
      // A step of depth 1 along this pixel's line of sight.
      const PfxVector3 sight =
          rotation * PfxVector3(1, -(PfxFloat(u) - cx) / focal, -(PfxFloat(v) - cy) / focal);
      PfxRayInput& ray = rays[v * p.width + u];
      ray.reset();
      ray.m_startPosition = origin + sight * p.nearClip;
      ray.m_direction = sight * span;
    }
  }
}

void pfxGetDepthCameraDepths(const PfxDepthCameraParam& p, const PfxRayOutput* hits,
                             PfxFloat* depths) {
  const PfxUInt32 n = pfxGetDepthCameraNumRays(p);
  const PfxFloat span = p.farClip - p.nearClip;
  for (PfxUInt32 i = 0; i < n; ++i) {
    depths[i] = hits[i].m_contactFlag ? p.nearClip + hits[i].m_variable * span
                                      : std::numeric_limits<PfxFloat>::infinity();
  }
}

}  // namespace pfx
