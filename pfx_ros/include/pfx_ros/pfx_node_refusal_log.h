// The node's log of refused service requests and of dropped or changed topic messages. A
// client that sends bad requests in a loop
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
// A topic's messages are throttled by the text of the warning instead: a new problem shows at
// once, the same one again at most once a second with the count of its repeats.
// The node's one thread answers services and topics and runs the loop that flushes, so no
// lock.
#pragma once

#include <chrono>
#include <map>
#include <string>

namespace pfx {

class PfxNodeRefusalLog {
 public:
  void refused(const std::string& service, const std::string& why);
  // A warning about a topic's message ("joint_trajectory dropped: no points").
  void warn(const std::string& warning);
  // Logs the count of each service's refusals and each warning's repeats not logged, once
  // its second is over.
  void flush();

 private:
  using Clock = std::chrono::steady_clock;
  struct Service {
    Clock::time_point lastLine;
    bool logged = false;
    unsigned long unlogged = 0;
    std::string lastUnlogged;  // the reason of the last refusal counted
  };
  struct Repeats {
    Clock::time_point lastLine;
    unsigned long unlogged = 0;
  };
  static constexpr Clock::duration kPeriod = std::chrono::seconds(1);
  std::map<std::string, Service> m_services;
  // By text; a warning leaves once its second is over with no repeat to count, so a
  // publisher sending ever other values keeps at most a second's worth here.
  std::map<std::string, Repeats> m_warnings;
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
