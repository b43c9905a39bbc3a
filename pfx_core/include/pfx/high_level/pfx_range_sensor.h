// A scanning range sensor (2D laser or multi-beam lidar) as one batch of rays: the rays of
// one scan in the sensor's frame, and the ranges that the hits of a cast give. The sensor
// looks along its +X axis; a horizontal angle turns about +Z (counter-clockwise seen from
// above), a vertical angle tilts up towards +Z, as Gazebo's ray sensor and REP 103 have it.
// Ray i of a scan is horizontal sample i % horizontalSamples of vertical sample
// i / horizontalSamples, so that the rays of one vertical sample are one LaserScan.
#pragma once

#include "pfx/base_level/raycast/pfx_ray.h"

namespace pfx {

struct PfxRangeSensorParam {
  PfxUInt32 horizontalSamples = 1;
  PfxFloat horizontalMinAngle = 0;  // rad; with one sample, the only angle
  PfxFloat horizontalMaxAngle = 0;
  PfxUInt32 verticalSamples = 1;
  PfxFloat verticalMinAngle = 0;
  PfxFloat verticalMaxAngle = 0;
  PfxFloat rangeMin = 0;  // m, measured from the sensor's origin
  PfxFloat rangeMax = 1;
};

// PFX_OK, or PFX_ERR_INVALID_VALUE for a sample count of 0, an angle or range that is not
// finite, a minimum angle above its maximum, a negative rangeMin or rangeMax <= rangeMin.
PfxInt32 pfxCheckRangeSensorParam(const PfxRangeSensorParam& param);

inline PfxUInt32 pfxGetRangeSensorNumRays(const PfxRangeSensorParam& param) {
  return param.horizontalSamples * param.verticalSamples;
}

// Angle of sample `index` of `samples` spread evenly over [minAngle, maxAngle], ends included.
PfxFloat pfxGetRangeSensorAngle(PfxFloat minAngle, PfxFloat maxAngle, PfxUInt32 samples,
                                PfxUInt32 index);

// Writes the scan's pfxGetRangeSensorNumRays rays for a sensor at `sensorPose` (world). Each
// ray covers [rangeMin, rangeMax] of its beam: it starts rangeMin from the origin, so that
// what lies closer (the robot's own shell, usually) is not seen, as a real sensor's blind zone.
// Filters admit every body. The param must pass pfxCheckRangeSensorParam.
void pfxMakeRangeSensorRays(const PfxRangeSensorParam& param, const PfxTransform3& sensorPose,
                            PfxRayInput* rays);

// The range of each beam from the hits of those rays: the distance from the sensor's origin
// to the hit, or +infinity where the beam hit nothing within rangeMax (REP 117).
void pfxGetRangeSensorRanges(const PfxRangeSensorParam& param, const PfxRayOutput* hits,
                             PfxFloat* ranges);

}  // namespace pfx
