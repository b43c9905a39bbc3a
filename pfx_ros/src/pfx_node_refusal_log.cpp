#include "pfx_ros/pfx_node_refusal_log.h"

#include <ros/console.h>

namespace pfx {

void PfxNodeRefusalLog::refused(const std::string& service, const std::string& why) {
  Service& s = m_services[service];
  const Clock::time_point now = Clock::now();
  if (s.logged && now - s.lastLine < kPeriod) {
    ++s.unlogged;
    s.lastUnlogged = why;
    return;
  }
  if (s.unlogged > 0) {
    ROS_WARN_STREAM("pfx_node: " << service << " rejected: " << why << " (after " << s.unlogged
                                 << " more " << service << " requests refused, not logged)");
  } else {
    ROS_WARN_STREAM("pfx_node: " << service << " rejected: " << why);
  }
  s.lastLine = now;
  s.logged = true;
  s.unlogged = 0;
}

void PfxNodeRefusalLog::flush() {
  const Clock::time_point now = Clock::now();
  for (auto& [service, s] : m_services) {
    if (s.unlogged == 0 || now - s.lastLine < kPeriod) continue;
    ROS_WARN_STREAM("pfx_node: " << s.unlogged << " more " << service
                                 << " requests refused, not logged; the last: " << s.lastUnlogged);
    s.lastLine = now;
    s.unlogged = 0;
  }
}

}  // namespace pfx
