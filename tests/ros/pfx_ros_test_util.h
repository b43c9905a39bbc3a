// What the rostest programs share: calling a node's services, following /clock, reading
// TF, and the links and joints of a robot_description (parsed here with urdfdom, not with
// pfx's loader, so that the node is checked against the URDF itself). Every wait is
// bounded in wall time: a paused simulation must not hang a test.
#pragma once

#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <urdf_parser/urdf_parser.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "pfx/Raycast.h"

namespace pfx_test {

// What every rostest program holds once ros::init has run: a node handle, callbacks served
// on a thread of their own, and a TF listener.
struct RosClient {
  RosClient() { spinner.start(); }
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner{1};
  tf2_ros::Buffer tfBuffer;
  tf2_ros::TransformListener tfListener{tfBuffer};
};

// Calls a service and fails the test when the call itself fails (no such service, or the
// node died); the response's success flag is for the caller to check. The connection is
// asked to persist, so that the client closes it after the answer: a one-off call, which
// the node closes once it has answered, can see the connection closed before it reads the
// answer (ros/ros_comm#1976), and one in about 550 of node_load.test's calls came back
// failed so although the node had acted on it.
template <typename Service>
Service call(const std::string& name, Service srv) {
  ros::NodeHandle nh;
  ros::ServiceClient client = nh.serviceClient<Service>(name, true);
  EXPECT_TRUE(client.call(srv)) << "call of " << name << " failed";
  return srv;
}

inline pfx::Raycast rayRequest(double x, double y, double z, double dx, double dy, double dz) {
  pfx::Raycast srv;
  srv.request.origin.x = x;
  srv.request.origin.y = y;
  srv.request.origin.z = z;
  srv.request.direction.x = dx;
  srv.request.direction.y = dy;
  srv.request.direction.z = dz;
  return srv;
}

inline pfx::Raycast::Response raycast(const std::string& service, double x, double y, double z,
                                      double dx, double dy, double dz) {
  return call(service, rayRequest(x, y, z, dx, dy, dz)).response;
}

inline bool waitForServices(const std::vector<std::string>& names, double wallSeconds) {
  for (const std::string& name : names) {
    if (!ros::service::waitForService(name, ros::Duration(wallSeconds))) return false;
  }
  return true;
}

// The latest /clock, in seconds (negative before the first).
class ClockWatcher {
 public:
  explicit ClockWatcher(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("/clock", 100, &ClockWatcher::onClock, this)) {}
  double now() const { return m_seconds.load(); }
  bool connected() const { return m_sub.getNumPublishers() > 0; }
  // Waits until /clock reaches `seconds`; false if it does not within `wallSeconds`.
  bool waitUntil(double seconds, double wallSeconds) const {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (now() < seconds) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.01).sleep();
    }
    return true;
  }

 private:
  void onClock(const rosgraph_msgs::Clock& msg) { m_seconds.store(msg.clock.toSec()); }
  ros::Subscriber m_sub;
  std::atomic<double> m_seconds{-1.0};
};

// The latest message of a topic whose header carries a stamp.
template <typename Msg>
class Latest {
 public:
  Latest(ros::NodeHandle& nh, const std::string& topic)
      : m_sub(nh.subscribe(topic, 20, &Latest::onMessage, this)) {}
  bool connected() const { return m_sub.getNumPublishers() > 0; }
  // A message stamped `seconds` or later, within `wallSeconds`.
  bool waitFor(double seconds, Msg& out, double wallSeconds = 5) const {
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    for (;;) {
      {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (m_has && m_latest.header.stamp.toSec() >= seconds - 1e-9) {
          out = m_latest;
          return true;
        }
      }
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.01).sleep();
    }
  }

 private:
  void onMessage(const Msg& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_latest = msg;
    m_has = true;
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  Msg m_latest;
  bool m_has = false;
};

// The newest transform of `frame` in `fixedFrame`, waiting up to `wallSeconds` for one.
inline bool lookup(tf2_ros::Buffer& buffer, const std::string& fixedFrame, const std::string& frame,
                   geometry_msgs::TransformStamped& out, double wallSeconds = 10) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
  for (;;) {
    try {
      out = buffer.lookupTransform(fixedFrame, frame, ros::Time(0));
      return true;
    } catch (const tf2::TransformException&) {
      if (ros::WallTime::now() > deadline) return false;
      ros::WallDuration(0.02).sleep();
    }
  }
}

inline bool samePose(const geometry_msgs::TransformStamped& a,
                     const geometry_msgs::TransformStamped& b) {
  const auto& ta = a.transform;
  const auto& tb = b.transform;
  return ta.translation.x == tb.translation.x && ta.translation.y == tb.translation.y &&
         ta.translation.z == tb.translation.z && ta.rotation.x == tb.rotation.x &&
         ta.rotation.y == tb.rotation.y && ta.rotation.z == tb.rotation.z &&
         ta.rotation.w == tb.rotation.w;
}

// Links and joints of a URDF, as the file names them.
struct UrdfRobot {
  std::string root;
  int massiveLinks = 0;  // links with an inertial of positive mass
  std::vector<std::string> links;
  std::map<std::string, urdf::JointConstSharedPtr> joints;
};

inline bool hasLink(const UrdfRobot& robot, const std::string& name) {
  for (const std::string& link : robot.links) {
    if (link == name) return true;
  }
  return false;
}

inline bool readRobot(const std::string& param, UrdfRobot& robot) {
  std::string xml;
  if (!ros::param::get(param, xml)) return false;
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(xml);
  if (!model) return false;
  robot.root = model->getRoot()->name;
  for (const auto& link : model->links_) {
    robot.links.push_back(link.first);
    if (link.second->inertial && link.second->inertial->mass > 0) ++robot.massiveLinks;
  }
  for (const auto& joint : model->joints_) robot.joints[joint.first] = joint.second;
  return true;
}

// Runs a shell command to its end and returns what it wrote (stderr too, when the command
// says 2>&1), with its wait status in `status`: how the rostests start a second pfx_node
// with a configuration of their own.
inline std::string runCommand(const std::string& command, int& status) {
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[512];
  while (pipe && std::fgets(buffer, sizeof(buffer), pipe)) output += buffer;
  status = pipe ? pclose(pipe) : -1;
  return output;
}

inline std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace pfx_test
