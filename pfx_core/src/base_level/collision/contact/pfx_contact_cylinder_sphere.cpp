#include <algorithm>
#include <cmath>

#include "base_level/collision/contact/pfx_contact_pairs.h"

namespace pfx {

void pfxContactCylinderSphere(PfxFloat halfLen, PfxFloat radius,
                              const PfxTransform3& cylinderTransform, const PfxVector3& centre,
                              PfxFloat sphereRadius, PfxContactSink& sink) {
  const PfxMatrix3 rotation = cylinderTransform.linear();
  const PfxVector3 local = rotation.transpose() * (centre - cylinderTransform.translation());
  const PfxVector3 radial(0, local.y(), local.z());
  const PfxFloat radialLen = radial.norm();
  const PfxFloat axialSign = local.x() < 0 ? PfxFloat(-1) : PfxFloat(1);
  PfxVector3 onCylinder;  // local
  PfxVector3 normal;      // local, from the cylinder to the sphere
  PfxFloat distance;      // of the centre from the cylinder's surface, negative inside
  if (std::abs(local.x()) > halfLen || radialLen > radius) {
    const PfxFloat radialScale = radialLen > radius ? radius / radialLen : PfxFloat(1);
    onCylinder = PfxVector3(std::clamp(local.x(), -halfLen, halfLen), local.y() * radialScale,
                            local.z() * radialScale);
    const PfxVector3 away = local - onCylinder;
    distance = away.norm();
    normal = away / distance;
  } else if (halfLen - std::abs(local.x()) <= radius - radialLen || radialLen <= PFX_EPSILON) {
    // Inside, nearer a cap (or on the axis, where the side has no one direction: the way
    // out through a cap is then taken, whichever is nearer).
    normal = PfxVector3(axialSign, 0, 0);
    distance = std::abs(local.x()) - halfLen;
    onCylinder = PfxVector3(axialSign * halfLen, local.y(), local.z());
  } else {
    normal = radial / radialLen;
    distance = radialLen - radius;
    onCylinder = normal * radius + PfxVector3(local.x(), 0, 0);
  }
  if (distance - sphereRadius >= sink.getThreshold()) return;
  const PfxVector3 worldNormal = rotation * normal;
  sink.add(worldNormal, cylinderTransform * onCylinder, centre - worldNormal * sphereRadius,
           distance - sphereRadius);
}

}  // namespace pfx
