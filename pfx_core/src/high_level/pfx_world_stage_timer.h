// Times one stage of PfxWorld's step into its statistics, when the world measures its
// stages (PfxWorldParam::measureStages).
#pragma once

#include <chrono>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

class PfxStageTimer {
 public:
  using Clock = std::chrono::steady_clock;
  PfxStageTimer(PfxWorldStats& stats, PfxStage stage, bool measures)
      : m_stats(stats), m_stage(stage), m_measures(measures) {
    if (m_measures) m_start = Clock::now();
  }
  ~PfxStageTimer() {
    if (!m_measures) return;
    m_stats.stageSeconds[m_stage] += std::chrono::duration<double>(Clock::now() - m_start).count();
  }
  PfxStageTimer(const PfxStageTimer&) = delete;
  PfxStageTimer& operator=(const PfxStageTimer&) = delete;

 private:
  PfxWorldStats& m_stats;
  PfxStage m_stage;
  bool m_measures;
  Clock::time_point m_start;
};

}  // namespace pfx
