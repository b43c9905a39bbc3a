// A depth camera as one batch of rays: a pinhole camera looking along its sensor frame's +X
// (image right along -Y, image down along -Z, as Gazebo's cameras), one ray per pixel
// through the pixel's centre, and the depth (distance along the optical axis) that the hits
// of a cast give. Pixel (u, v) has its centre at column u, row v; the principal point is the
// image's centre, ((width - 1) / 2, (height - 1) / 2), and the pixels are square, with the
// focal length (in pixels) that spreads the horizontal field of view over the image's width.
#pragma once

#include "pfx/base_level/raycast/pfx_ray.h"

namespace pfx {

struct PfxDepthCameraParam {
  PfxUInt32 width = 320;                     // pixels
  PfxUInt32 height = 240;                    // pixels
  PfxFloat horizontalFov = PfxFloat(1.047);  // rad, in (0, pi)
  PfxFloat nearClip = PfxFloat(0.05);        // m along the optical axis
  PfxFloat farClip = 10;
};

// PFX_OK, or PFX_ERR_INVALID_VALUE for a width or height of 0 or above 4096, a field of view
// outside (0, pi), a clip distance that is not finite, a negative nearClip or farClip <=
// nearClip.
PfxInt32 pfxCheckDepthCameraParam(const PfxDepthCameraParam& param);

inline PfxUInt32 pfxGetDepthCameraNumRays(const PfxDepthCameraParam& param) {
  return param.width * param.height;
}

// Focal length in pixels, fx = fy.
PfxFloat pfxGetDepthCameraFocalLength(const PfxDepthCameraParam& param);

// Writes width * height rays, row by row from the top-left pixel, for a camera at
// `cameraPose` (world). Each covers its pixel's line of sight from depth nearClip to depth
// farClip, so that what is nearer than the near plane is not seen. Filters admit every body.
// The param must pass pfxCheckDepthCameraParam.
void pfxMakeDepthCameraRays(const PfxDepthCameraParam& param, const PfxTransform3& cameraPose,
                            PfxRayInput* rays);

// The depth of each pixel from the hits of those rays, or +infinity where the line of sight
// met nothing before the far plane (REP 118).
void pfxGetDepthCameraDepths(const PfxDepthCameraParam& param, const PfxRayOutput* hits,
                             PfxFloat* depths);

}  // namespace pfx
