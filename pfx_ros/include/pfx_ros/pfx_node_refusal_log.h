// The node's log of refused service requests. A client that sends bad requests in a loop
// would otherwise put one WARN per call on /rosout, hundreds a second, which roscpp queues
// without bound when the rosout node falls behind. Per service, a refusal is logged with its
// reason at most once per second of wall time; the refusals not logged meanwhile are counted,
// and the count goes out with the service's next logged refusal or, once that second is over,
// from flush() with the last reason counted. So every refusal shows in the log, by its reason or in
// a count, and a service logs at most one line a second. Every refused request still gets its
// reason in its response: the log is for whoever watches the node.
//
// Wall time, not ROS time: under use_sim_time a paused node's clock stands still, and a
// ROS_WARN_THROTTLE would then stay silent for good (and in the first simulated second).
// The node's one thread answers services and runs the loop that flushes, so no lock.
#pragma once

#include <chrono>
#include <map>
#include <string>

namespace pfx {

class PfxNodeRefusalLog {
 public:
  void refused(const std::string& service, const std::string& why);
  // Logs the count of each service's refusals not logged, once its second is over.
  void flush();

 private:
  using Clock = std::chrono::steady_clock;
  struct Service {
    Clock::time_point lastLine;
    bool logged = false;
    unsigned long unlogged = 0;
    std::string lastUnlogged;  // the reason of the last refusal counted
  };
  static constexpr Clock::duration kPeriod = std::chrono::seconds(1);
  std::map<std::string, Service> m_services;
};

// Fills `res` as a refusal of `service`'s request for the reason `why`, and logs it; true:
// the call itself worked, success says the request did not.
template <typename Response>
bool pfxRejectRequest(PfxNodeRefusalLog& log, Response& res, const char* service,
                      const std::string& why) {
  res.success = false;
  res.message = why;
  log.refused(service, why);
  return true;
}

}  // namespace pfx
