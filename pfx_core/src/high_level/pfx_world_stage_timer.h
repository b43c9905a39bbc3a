// Times one stage of PfxWorld's step into its statistics.
#pragma once

#include <chrono>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

class PfxStageTimer {
 public:
  using Clock = std::chrono::steady_clock;
  PfxStageTimer(PfxWorldStats& stats, PfxStage stage)
      : m_stats(stats), m_stage(stage), m_start(Clock::now()) {}
  ~PfxStageTimer() {
    m_stats.stageSeconds[m_stage] += std::chrono::duration<double>(Clock::now() - m_start).count();
  }
  PfxStageTimer(const PfxStageTimer&) = delete;
  PfxStageTimer& operator=(const PfxStageTimer&) = delete;

 private:
  PfxWorldStats& m_stats;
  PfxStage m_stage;
  Clock::time_point m_start;
};

}  // namespace pfx
