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

void PfxNodeRefusalLog::warn(const std::string& warning) {
  const Clock::time_point now = Clock::now();
  const auto [it, added] = m_warnings.try_emplace(warning);
  Repeats& r = it->second;
  if (!added && now - r.lastLine < kPeriod) {
    ++r.unlogged;
    return;
  }
  ROS_WARN_STREAM("pfx_node: " << warning);
  r.lastLine = now;
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
  for (auto it = m_warnings.begin(); it != m_warnings.end();) {
    Repeats& r = it->second;
    if (now - r.lastLine < kPeriod) {
      ++it;
    } else if (r.unlogged == 0) {
      it = m_warnings.erase(it);
    } else {
      ROS_WARN_STREAM("pfx_node: " << it->first << " (" << r.unlogged
                                   << (r.unlogged == 1 ? " more time" : " more times")
                                   << ", not logged one by one)");
      r.lastLine = now;
      r.unlogged = 0;
      ++it;
    }
  }
}

}  // namespace pfx
