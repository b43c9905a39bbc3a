#include "pfx_ros/pfx_node_autosave.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace pfx {

namespace {

std::string folderOf(const std::string& file) {
  const std::string folder = std::filesystem::path(file).parent_path().string();
  return folder.empty() ? "." : folder;
}

// Flushes a file or folder to the disk: a rename is only as safe as the bytes behind it.
bool flushToDisk(const std::string& path, int openFlags, std::string* message) {
  const int fd = ::open(path.c_str(), openFlags);
  const bool flushed = fd >= 0 && ::fsync(fd) == 0;
  if (!flushed && message) *message = path + ": cannot flush to disk: " + std::strerror(errno);
  if (fd >= 0) ::close(fd);
  return flushed;
}

}  // namespace

bool PfxNodeAutosave::configure(const ros::NodeHandle& nh, std::string* message) {
  nh.param("autosave_period", m_period, 0.0);
  nh.param<std::string>("autosave_file", m_file, "");
  nh.param("resume", m_resume, false);
  m_temporaryFile = m_file + ".tmp";
  const char* invalid = nullptr;
  if (!std::isfinite(m_period) || m_period < 0) {
    invalid = "~autosave_period must be a finite number of seconds >= 0 (0: no autosave)";
  } else if (m_period > 0 && m_file.empty()) {
    invalid = "~autosave_period is set but ~autosave_file is not";
  } else if (m_resume && m_file.empty()) {
    invalid = "~resume is set but ~autosave_file is not: there is nothing to resume from";
  } else if (m_resume && (nh.hasParam("cables") || nh.hasParam("cloths"))) {
    invalid =
        "~resume cannot be used with ~cables or ~cloths yet: the saved world holds them "
        "and they would be added a second time";
  }
  if (invalid) {
    *message = invalid;
    return false;
  }
  if (m_period == 0) return true;
  // A folder that cannot take the file is found now, not at the first save.
  const int fd = ::open(m_temporaryFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    *message = "~autosave_file: cannot write in the folder " + folderOf(m_file) + " (" +
               m_temporaryFile + ": " + std::strerror(errno) + ")";
    return false;
  }
  ::close(fd);
  std::remove(m_temporaryFile.c_str());
  return true;
}

bool PfxNodeAutosave::resume(PfxNodeSimulation& simulation, std::string* message,
                             std::string* notice) {
  if (m_resume) {
    std::error_code error;
    if (!std::filesystem::exists(m_file, error)) {
      *notice = "~resume: no " + m_file + " yet, starting afresh";
    } else {
      std::string why;
      if (simulation.loadWorld(m_file, &why) != PFX_OK) {
        *message = "~resume refused: " + why;
        return false;
      }
      std::ostringstream text;
      text << "~resume: continuing from " << m_file << " at t = " << simulation.getTime() << " s";
      *notice = text.str();
    }
  }
  m_lastSaveTime = simulation.getTime();
  return true;
}

void PfxNodeAutosave::afterStep(const PfxNodeSimulation& simulation) {
  if (m_period == 0) return;
  const double time = simulation.getTime();
  if (time < m_lastSaveTime) {  // a world loaded from earlier: the period counts from it
    m_lastSaveTime = time;
    return;
  }
  // Half a step of slack: the clock reaches a multiple of the period up to rounding.
  if (time - m_lastSaveTime < m_period - 0.5 * simulation.getTimeStep()) return;
  m_lastSaveTime = time;
  std::string why;
  if (!save(simulation, &why)) {
    ROS_ERROR_THROTTLE(10.0,
                       "pfx_node: autosave at t = %.3f s failed, %s keeps the save before: %s",
                       time, m_file.c_str(), why.c_str());
  }
}

bool PfxNodeAutosave::save(const PfxNodeSimulation& simulation, std::string* message) const {
  if (simulation.saveWorld(m_temporaryFile, message) != PFX_OK) return false;
  if (!flushToDisk(m_temporaryFile, O_RDONLY, message)) return false;
  if (std::rename(m_temporaryFile.c_str(), m_file.c_str()) != 0) {
    *message = "cannot rename " + m_temporaryFile + " to " + m_file + ": " + std::strerror(errno);
    return false;
  }
  return flushToDisk(folderOf(m_file), O_RDONLY | O_DIRECTORY, message);
}

}  // namespace pfx
