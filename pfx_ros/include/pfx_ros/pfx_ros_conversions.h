// Between geometry_msgs (double) and pfx's math types (PfxFloat). A value that is finite as
// a double may not be as a float (1e300), so validity is checked after conversion.
#pragma once

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/Vector3.h>

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

inline PfxVector3 pfxFromMsg(const geometry_msgs::Point& p) {
  return PfxVector3(PfxFloat(p.x), PfxFloat(p.y), PfxFloat(p.z));
}
inline PfxVector3 pfxFromMsg(const geometry_msgs::Vector3& v) {
  return PfxVector3(PfxFloat(v.x), PfxFloat(v.y), PfxFloat(v.z));
}
// Not normalised: the caller decides what to do with a quaternion that is not unit.
inline PfxQuat pfxFromMsg(const geometry_msgs::Quaternion& q) {
  return PfxQuat(PfxFloat(q.w), PfxFloat(q.x), PfxFloat(q.y), PfxFloat(q.z));
}

inline geometry_msgs::Point pfxToPointMsg(const PfxVector3& v) {
  geometry_msgs::Point p;
  p.x = v[0];
  p.y = v[1];
  p.z = v[2];
  return p;
}
inline geometry_msgs::Vector3 pfxToVector3Msg(const PfxVector3& v) {
  geometry_msgs::Vector3 m;
  m.x = v[0];
  m.y = v[1];
  m.z = v[2];
  return m;
}
inline geometry_msgs::Quaternion pfxToQuaternionMsg(const PfxQuat& q) {
  geometry_msgs::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}
inline geometry_msgs::Transform pfxToTransformMsg(const PfxTransform3& t) {
  geometry_msgs::Transform m;
  m.translation = pfxToVector3Msg(t.translation());
  m.rotation = pfxToQuaternionMsg(PfxQuat(t.linear()).normalized());
  return m;
}

}  // namespace pfx
