// The seed's math types as names over Eigen's fixed-size types, and the few helpers
// that Eigen does not name the way a physics reader expects.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

using PfxVector3 = Eigen::Matrix<PfxFloat, 3, 1>;
using PfxPoint3 = PfxVector3;
using PfxVector4 = Eigen::Matrix<PfxFloat, 4, 1>;
// Unaligned, so that the plain-data structs holding orientations have no hidden padding:
// they copy, compare and serialize byte for byte.
using PfxQuat = Eigen::Quaternion<PfxFloat, Eigen::DontAlign>;
using PfxMatrix3 = Eigen::Matrix<PfxFloat, 3, 3>;
using PfxMatrix4 = Eigen::Matrix<PfxFloat, 4, 4>;
using PfxTransform3 = Eigen::Transform<PfxFloat, 3, Eigen::Isometry>;

constexpr PfxFloat PFX_PI = PfxFloat(3.14159265358979323846);
// Below this a length is treated as zero: vectors are not normalised, axes not built.
constexpr PfxFloat PFX_EPSILON = PfxFloat(1e-6);

inline bool pfxIsFinite(PfxFloat x) { return std::isfinite(x); }
inline bool pfxIsFinite(const PfxVector3& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}
inline bool pfxIsFinite(const PfxQuat& q) {
  return std::isfinite(q.x()) && std::isfinite(q.y()) && std::isfinite(q.z()) &&
         std::isfinite(q.w());
}
inline bool pfxIsFinite(const PfxMatrix3& m) { return m.allFinite(); }

// A unit quaternion within float round-off; callers reject anything further off.
inline bool pfxIsUnitQuat(const PfxQuat& q) {
  return pfxIsFinite(q) && std::abs(q.squaredNorm() - PfxFloat(1)) < PfxFloat(1e-3);
}

inline PfxTransform3 pfxMakeTransform(const PfxQuat& rotation, const PfxVector3& translation) {
  PfxTransform3 t;
  t.linear() = rotation.toRotationMatrix();
  t.translation() = translation;
  return t;
}

// Skew-symmetric matrix such that pfxCrossMatrix(a) * b == a.cross(b).
inline PfxMatrix3 pfxCrossMatrix(const PfxVector3& a) {
  PfxMatrix3 m;
  m << 0, -a[2], a[1], a[2], 0, -a[0], -a[1], a[0], 0;
  return m;
}

// Two unit vectors completing n to a right-handed orthonormal basis (n must be unit).
// Branch-free construction (Duff et al. 2017) so that nearby normals give nearby tangents,
// which keeps warm-started friction impulses meaningful from frame to frame.
inline void pfxGetPlaneSpace(const PfxVector3& n, PfxVector3& t1, PfxVector3& t2) {
  const PfxFloat sign = std::copysign(PfxFloat(1), n[2]);
  const PfxFloat a = PfxFloat(-1) / (sign + n[2]);
  const PfxFloat b = n[0] * n[1] * a;
  t1 = PfxVector3(PfxFloat(1) + sign * n[0] * n[0] * a, sign * b, -sign * n[0]);
  t2 = PfxVector3(b, sign + n[1] * n[1] * a, -n[1]);
}

// The inverse of a symmetric positive definite matrix (an inertia or an inverse inertia)
// whose entries may lie anywhere in float's range. The plain 3x3 inverse divides by the
// determinant, a product of three entries, which leaves that range long before they do: a
// moment of 8e13 kg m^2 (moments up to 1e18 are accepted) has an inverse whose determinant,
// 2e-42, is denormal, and its reciprocal infinite. Scaled by a power of two to a largest
// diagonal entry near one, the determinant stays within the range the moment ratio allows,
// and the result has the plain inverse's bits wherever that one stayed in range.
inline PfxMatrix3 pfxInverseDefinite(const PfxMatrix3& m) {
  const PfxFloat scale = std::ldexp(PfxFloat(1), -std::ilogb(m.diagonal().maxCoeff()));
  return (m * scale).inverse() * scale;
}

// Inertia tensor expressed in another frame: R I R^T.
inline PfxMatrix3 pfxRotateInertia(const PfxMatrix3& rotation, const PfxMatrix3& inertia) {
  return rotation * inertia * rotation.transpose();
}

}  // namespace pfx
