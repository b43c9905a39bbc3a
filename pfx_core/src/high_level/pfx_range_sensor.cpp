#include "pfx/high_level/pfx_range_sensor.h"

#include <cmath>
#include <limits>

namespace pfx {

PfxInt32 pfxCheckRangeSensorParam(const PfxRangeSensorParam& p) {
  const PfxFloat values[] = {p.horizontalMinAngle, p.horizontalMaxAngle, p.verticalMinAngle,
                             p.verticalMaxAngle,   p.rangeMin,           p.rangeMax};
  for (PfxFloat v : values) {
    if (!std::isfinite(v)) return PFX_ERR_INVALID_VALUE;
  }
  if (p.horizontalSamples == 0 || p.verticalSamples == 0) return PFX_ERR_INVALID_VALUE;
  if (p.horizontalMinAngle > p.horizontalMaxAngle) return PFX_ERR_INVALID_VALUE;
  if (p.verticalMinAngle > p.verticalMaxAngle) return PFX_ERR_INVALID_VALUE;
  if (p.rangeMin < 0 || p.rangeMax <= p.rangeMin) return PFX_ERR_INVALID_VALUE;
  return PFX_OK;
}

PfxFloat pfxGetRangeSensorAngle(PfxFloat minAngle, PfxFloat maxAngle, PfxUInt32 samples,
                                PfxUInt32 index) {
  if (samples <= 1) return minAngle;
  return minAngle + (maxAngle - minAngle) * PfxFloat(index) / PfxFloat(samples - 1);
}

void pfxMakeRangeSensorRays(const PfxRangeSensorParam& p, const PfxTransform3& sensorPose,
                            PfxRayInput* rays) {
  const PfxMatrix3 rotation = sensorPose.linear();
  const PfxVector3 origin = sensorPose.translation();
  const PfxFloat span = p.rangeMax - p.rangeMin;
  for (PfxUInt32 v = 0; v < p.verticalSamples; ++v) {
    const PfxFloat pitch =
        pfxGetRangeSensorAngle(p.verticalMinAngle, p.verticalMaxAngle, p.verticalSamples, v);
    for (PfxUInt32 h = 0; h < p.horizontalSamples; ++h) {
      const PfxFloat yaw = pfxGetRangeSensorAngle(p.horizontalMinAngle, p.horizontalMaxAngle,
                                                  p.horizontalSamples, h);
      const PfxVector3 beam =
          rotation * PfxVector3(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                                std::sin(pitch));
      PfxRayInput& ray = rays[v * p.horizontalSamples + h];
      ray.reset();
      ray.m_startPosition = origin + beam * p.rangeMin;
      ray.m_direction = beam * span;
    }
  }
}

void pfxGetRangeSensorRanges(const PfxRangeSensorParam& p, const PfxRayOutput* hits,
                             PfxFloat* ranges) {
  const PfxUInt32 n = pfxGetRangeSensorNumRays(p);
  const PfxFloat span = p.rangeMax - p.rangeMin;
  for (PfxUInt32 i = 0; i < n; ++i) {
    ranges[i] = hits[i].m_contactFlag ? p.rangeMin + hits[i].m_variable * span
                                      : std::numeric_limits<PfxFloat>::infinity();
  }
}

}  // namespace pfx
