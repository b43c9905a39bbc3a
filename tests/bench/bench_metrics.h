// The error figures of a run, computed from the body states an engine reports at the
// sample times. The same code judges every engine.
#pragma once

#include <vector>

#include "bench_engine.h"
#include "bench_scene.h"

namespace pfxbench {

// A figure the run could not give (it blew up, or its reference did).
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Follows one run. observe() is called with the initial states and then at every sample
// time, the last one at the end of the run; observeJoints() with the joints' anchors at the
// start and after every step.
class MetricRecorder {
 public:
  explicit MetricRecorder(const Scene& scene);
  void observe(const std::vector<BodyState>& states);
  void observeJoints(const std::vector<JointAnchors>& anchors);
  // A figure of the scene's metrics other than position_error; NaN where the run produced
  // non-finite states or nothing was observed.
  double value(Metric metric) const;

 private:
  const Scene& m_scene;
  std::vector<BodyState> m_first;
  std::vector<BodyState> m_last;
  double m_stackDrift = 0;
  double m_penetration = 0;
  double m_jointGap = 0;
};

// The points whose paths position_error compares: the eight corners of the bounding box,
// in its own frame, of each tracked body (every dynamic body unless the scene names some),
// so that an error of orientation shows as one of position. Appended to `points`.
void appendTrackedPoints(const Scene& scene, const std::vector<BodyState>& states,
                         std::vector<Vec3>& points);

// Largest distance between matching tracked points of a run and its reference; NaN if
// the two did not record the same samples or any point is not finite.
double largestDeviation(const std::vector<Vec3>& run, const std::vector<Vec3>& reference);

}  // namespace pfxbench
