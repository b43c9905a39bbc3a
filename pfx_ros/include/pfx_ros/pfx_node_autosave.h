// ~autosave_period, ~autosave_file and ~resume: the world written to a file every so many
// seconds of simulated time (through PfxNodeSimulation::saveWorld, the ~save_world path),
// and read back when the node starts again after a crash. Each save goes to
// `<file>.tmp` in the same folder, is flushed to the disk and then renamed over the file,
// so a crash in the middle of a save leaves the previous save whole.
#pragma once

#include <ros/ros.h>

#include <string>

#include "pfx_ros/pfx_node_simulation.h"

namespace pfx {

class PfxNodeAutosave {
 public:
  // Reads the three parameters from `privateHandle`. False, with the reason in *message,
  // for a period that is NaN, infinite or negative, a period or ~resume without a file,
  // a file whose folder cannot be written, or ~resume beside ~cables or ~cloths (the file
  // holds them, and the node would add them again).
  bool configure(const ros::NodeHandle& privateHandle, std::string* message);
  // With ~resume, replaces the world just loaded with the one in the file. A missing file
  // is a fresh start (*notice says so); a file that does not read or was saved from
  // another robot or scene is refused (false, *message naming the file and the reason),
  // and stays as it is for whoever looks into it.
  bool resume(PfxNodeSimulation& simulation, std::string* message, std::string* notice);
  // After each step: saves when ~autosave_period has passed since the last save (or since
  // the start, or since the clock went back under ~load_world).
  void afterStep(const PfxNodeSimulation& simulation);

 private:
  // Writes the world to the temporary file, flushes it and renames it over the file.
  bool save(const PfxNodeSimulation& simulation, std::string* message) const;

  double m_period = 0;  // s of simulated time; 0: no autosave
  std::string m_file;
  std::string m_temporaryFile;
  bool m_resume = false;
  double m_lastSaveTime = 0;
};

}  // namespace pfx
