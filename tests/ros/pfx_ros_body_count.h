// The number of bodies in the world as the node's /diagnostics reports it (removed slots
// not counted), for the rostests that check that a refused request added no body and that a
// deletion removed the bodies it should.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>

#include <mutex>
#include <string>

namespace pfx_test {

// The number of bodies in the world, from the node's /diagnostics.
class BodyCount {
 public:
  explicit BodyCount(ros::NodeHandle& nh)
      : m_sub(nh.subscribe("/diagnostics", 10, &BodyCount::onReport, this)) {}
  // The count of a report that arrives after this call, or -1 after `wallSeconds`.
  double next(double wallSeconds = 5) const {
    int seen;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      seen = m_reports;
    }
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(wallSeconds);
    while (ros::WallTime::now() < deadline) {
      {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (m_reports > seen) return m_bodies;
      }
      ros::WallDuration(0.02).sleep();
    }
    return -1;
  }

 private:
  void onReport(const diagnostic_msgs::DiagnosticArray& msg) {
    std::lock_guard<std::mutex> lock(m_mutex);
    for (const diagnostic_msgs::DiagnosticStatus& status : msg.status) {
      if (status.name != "pfx_node: simulation") continue;
      for (const diagnostic_msgs::KeyValue& kv : status.values) {
        if (kv.key == "bodies") m_bodies = std::stod(kv.value);
      }
      ++m_reports;
    }
  }
  ros::Subscriber m_sub;
  mutable std::mutex m_mutex;
  double m_bodies = -1;
  int m_reports = 0;
};

}  // namespace pfx_test
