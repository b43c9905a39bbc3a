#include "bench_cli.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <sstream>

namespace pfxbench {

namespace {

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

bool parseNumber(const std::string& text, double& value) {
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(value);
}

// "1/60" or "0.0166".
bool parseTimeStep(const std::string& text, double& dt) {
  const std::size_t slash = text.find('/');
  double numerator = 0, denominator = 1;
  if (slash == std::string::npos) {
    if (!parseNumber(text, numerator)) return false;
  } else if (!parseNumber(text.substr(0, slash), numerator) ||
             !parseNumber(text.substr(slash + 1), denominator) || denominator == 0) {
    return false;
  }
  dt = numerator / denominator;
  return dt > 0 && std::isfinite(dt);
}

bool parsePositiveInts(const std::string& name, const std::string& text, std::vector<int>& out,
                       std::string& error) {
  out.clear();
  for (const std::string& item : splitList(text)) {
    char* end = nullptr;
    const long value = std::strtol(item.c_str(), &end, 10);
    if (end == item.c_str() || *end != '\0' || value < 1 || value > 1000000) {
      error = name + ": not a positive integer: '" + item + "'";
      return false;
    }
    out.push_back(static_cast<int>(value));
  }
  if (out.empty()) error = name + ": no value given";
  return !out.empty();
}

}  // namespace

const char* usage() {
  return "usage: pfx_bench [--scene NAME[,NAME...]] [--engine NAME[,NAME...]] [--dt DT[,DT...]]\n"
         "                 [--iterations N[,N...]] [--substeps N[,N...]] [--threads N[,N...]]\n"
         "                 [--seconds S] [--out DIR] [--same-bits] [--characters N[,N...]]\n"
         "                 [--limit METRIC=BOUND[,METRIC=BOUND...]]\n"
         "  Steps each scene with each engine for each combination of the settings and\n"
         "  prints one TSV row per error metric on stdout. DT is 1/60 or 0.0166.\n"
         "  Defaults: every scene, every engine built, dt 1/30,1/60,1/120,1/240,1/480,1/960,\n"
         "  10 iterations, 1 sub-step, 1 thread, each scene's own duration.\n"
         "  --out DIR also writes DIR/results.tsv and one plot per scene, DIR/<scene>.png.\n"
         "  --same-bits compares every run with the first run of the same scene, engine\n"
         "  and settings but another thread count (--threads 1,2,4): each gets a row\n"
         "  same_bits (1 when the final positions, orientations and velocities of all\n"
         "  bodies are bit-identical, else 0), and any 0 makes pfx_bench exit with 1.\n"
         "  --limit joint_gap_max=0.001 makes pfx_bench exit with 1 when a run's figure of\n"
         "  that metric is above the bound or not a number (the run blew up).\n"
         "  The scene rays measures rays per second against a 524,288-triangle terrain\n"
         "  (pfx, bullet and also embree; no time step, no plot), see bench_rays.h; the\n"
         "  scene octomap loads a 97,784-voxel OctoMap and casts rays into it (pfx only),\n"
         "  see bench_octomap.h. The scene urdf (built with the loaders) drives the joint\n"
         "  motors of urdf/arm.urdf along a reference, see bench_scenes_urdf.cpp; the scene\n"
         "  robots drops ragdolls on 1 to 64 such arms in one world and adds rows of the\n"
         "  cost per step and per robot, see bench_scenes_robots.cpp. The\n"
         "  scene meshfloor (pfx only, with the loaders) stands a quadruped on a\n"
         "  3,200-triangle terrain and on its bounding box, see bench_mesh_floor.h. The\n"
         "  scene serialize writes worlds of 4,000 and 100,000 bodies to a file and reads\n"
         "  them back (pfx, and bullet's serializer), see bench_serialize.h. The scene\n"
         "  characters walks 100 and 1,000 characters (--characters) over a course with\n"
         "  pfx's character controller and Bullet's btKinematicCharacterController, for\n"
         "  --seconds (30 by default) at each --dt (1/60 by default), and prints a table\n"
         "  on stderr; it fails when a pfx character does not arrive, falls through the\n"
         "  floor or climbs the steep ramp. See bench_characters.h. The scenes\n"
         "  rope (a rope between two pins against its catenary, and one carrying 1,000\n"
         "  times its mass) and cloth (64 x 64 and 128 x 128 onto a sphere) step pfx's\n"
         "  particles and bullet's soft bodies over their own solver settings, at dt 1/60\n"
         "  unless --dt is given, see bench_particles.h. The scene batch steps 1 to 1,024\n"
         "  copies of the arm and of a ragdoll together (PfxWorldBatch) on each --threads\n"
         "  count and reports world-steps per second, see bench_batch.h.\n";
}

bool parseOptions(int argc, const char* const* argv, Options& options, std::string& error) {
  for (int i = 1; i < argc; ++i) {
    const std::string option = argv[i];
    if (option == "--help" || option == "-h") {
      options.help = true;
      continue;
    }
    if (option == "--same-bits") {
      options.sameBits = true;
      continue;
    }
    static const char* const kOptionsWithValue[] = {"--scene",    "--engine",  "--dt",
                                                    "--iterations", "--substeps", "--threads",
                                                    "--seconds",  "--out",
                                                    "--characters", "--limit"};
    if (std::find(std::begin(kOptionsWithValue), std::end(kOptionsWithValue), option) ==
        std::end(kOptionsWithValue)) {
      error = "unknown option: " + option;
      return false;
    }
    if (i + 1 >= argc) {
      error = option + ": missing value";
      return false;
    }
    const std::string value = argv[++i];
    if (option == "--scene") {
      options.scenes = splitList(value);
    } else if (option == "--engine") {
      options.engines = splitList(value);
    } else if (option == "--dt") {
      options.timeSteps.clear();
      options.timeStepsGiven = true;
      for (const std::string& item : splitList(value)) {
        double dt = 0;
        if (!parseTimeStep(item, dt)) {
          error = "--dt: not a time step: '" + item + "'";
          return false;
        }
        options.timeSteps.push_back(dt);
      }
      if (options.timeSteps.empty()) {
        error = "--dt: no value given";
        return false;
      }
    } else if (option == "--iterations") {
      if (!parsePositiveInts(option, value, options.iterations, error)) return false;
    } else if (option == "--substeps") {
      if (!parsePositiveInts(option, value, options.substeps, error)) return false;
    } else if (option == "--threads") {
      if (!parsePositiveInts(option, value, options.threads, error)) return false;
    } else if (option == "--seconds") {
      if (!parseNumber(value, options.seconds) || options.seconds <= 0) {
        error = "--seconds: not a positive duration: '" + value + "'";
        return false;
      }
    } else if (option == "--characters") {
      if (!parsePositiveInts(option, value, options.characterCounts, error)) return false;
    } else if (option == "--limit") {
      options.limits.clear();
      for (const std::string& item : splitList(value)) {
        const std::size_t equals = item.find('=');
        double bound = 0;
        if (equals == std::string::npos || equals == 0 ||
            !parseNumber(item.substr(equals + 1), bound)) {
          error = "--limit: not METRIC=BOUND: '" + item + "'";
          return false;
        }
        options.limits.emplace_back(item.substr(0, equals), bound);
      }
      if (options.limits.empty()) {
        error = "--limit: no value given";
        return false;
      }
    } else if (option == "--out") {
      options.outDir = value;
    }
  }
  return true;
}

}  // namespace pfxbench
