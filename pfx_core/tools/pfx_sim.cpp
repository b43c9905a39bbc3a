// pfx_sim: loads a URDF robot, a scene file (pfx XML or SDFormat) or both, optionally onto
// a ground plane and an OctoMap, or a world saved earlier; simulates it headless, prints
// per-step statistics as TSV on standard output and, on request, saves the world and
// writes a picture of the final scene.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx/high_level/pfx_world_batch.h"
#include "pfx/loaders/pfx_octomap_loader.h"
#include "pfx/loaders/pfx_scene_loader.h"
#include "pfx/loaders/pfx_urdf_loader.h"
#include "pfx_scene_picture.h"

using namespace pfx;

namespace {

const char* const kUsage =
    "usage: pfx_sim [URDF] [--world FILE] [--load FILE] [options]\n"
    "\n"
    "Loads the robot, the scene or the saved world, simulates it headless and prints one\n"
    "TSV row of statistics per step: step, time (s, simulated time since the world began,\n"
    "so a loaded world goes on from where it was saved), step_s (wall seconds of the step), "
    "pairs,\n"
    "contacts (points), max_penetration (m), max_joint_gap (m), energy_change (J),\n"
    "momentum_change (kg m/s), angular_momentum_change (kg m^2/s).\n"
    "\n"
    "A URDF robot falls along -Z. A scene file brings its own gravity, time step, sub-steps\n"
    "and iterations (--dt, --substeps and --iterations override them); the robot, when one\n"
    "is given too, is loaded after it.\n"
    "\n"
    "options:\n"
    "  --world FILE       a scene: pfx scene XML (<pfx_scene>), an SDFormat world (<sdf>),\n"
    "                     or a world saved with --save (as --load)\n"
    "  --load FILE        a world saved with --save, continued exactly where it was saved\n"
    "                     with its own parameters (no URDF, scene, ground, map, --dt,\n"
    "                     --substeps, --iterations or --sleep with it)\n"
    "  --save FILE        save the world after the run (pfx's serialization format)\n"
    "  --seconds S        simulated time (default 5)\n"
    "  --dt DT            time step in seconds (default 1/240)\n"
    "  --substeps N       solver sub-steps per step (default 1)\n"
    "  --iterations N     solver iterations per sub-step (default 10)\n"
    "  --threads N        step on N threads (default 1; 0: every core the process may\n"
    "                     use); the figures are the same bits whatever N, a saved world's\n"
    "                     too\n"
    "  --ground           a ground plane at z = 0\n"
    "  --octomap FILE     static geometry from an OctoMap (.bt or .ot)\n"
    "  --fixed-base       bolt the robot's root link to the world (a root without mass\n"
    "                     gets a fixed base anyway, with a warning)\n"
    "  --allow-missing-meshes  leave out collision meshes whose files are missing (with a\n"
    "                     warning) instead of failing\n"
    "  --no-self-collision  the robot's links never collide with each other (by default\n"
    "                     only links joined by a joint or overlapping at the start do not)\n"
    "  --sleep            let bodies at rest fall asleep (off: the statistics measure the\n"
    "                     solver on every step)\n"
    "  --drop-height H    start with the lowest point of the robot's collision shapes H m\n"
    "                     above z = 0 (default: as the URDF places it, or 0.05 m above the\n"
    "                     ground with --ground, free or fixed base)\n"
    "  --png OUT.png      write a picture of the final scene\n"
    "  --png-size WxH     size of the picture in pixels (default 1280x960)\n"
    "  --every N          print every N-th step only (default 1)\n"
    "  --quiet            print no statistics\n"
    "  --result FILE      after the run, write one JSON line: steps, simulated time, bodies,\n"
    "                     the last step's statistics and state_hash (FNV-1a of every body's\n"
    "                     state bits, as pfx.World.state_hash; equal hashes, equal bits)\n"
    "  -h, --help         this text\n"
    "\n"
    "One job of a list, for job arrays (Slurm, Kubernetes indexed Jobs, any scheduler):\n"
    "  pfx_sim --jobs LIST [--task-index N] [--result-dir DIR]\n"
    "  LIST holds one job per line, the options above separated by spaces (no quoting;\n"
    "  blank lines and lines starting with # are not jobs). Job N (from 0) runs as if its\n"
    "  line were the command line, and its result goes to DIR/task-N.json (default: the\n"
    "  current folder). N is --task-index, else the first set of PFX_TASK_INDEX,\n"
    "  SLURM_ARRAY_TASK_ID and JOB_COMPLETION_INDEX; one that is not a whole number in\n"
    "  range is refused before anything runs.\n"
    "\n"
    "Exit status: 0 on success, 1 when loading, stepping or writing fails, 2 on bad\n"
    "arguments.\n";

struct Options {
  std::string urdf;
  std::string world;  // a scene file, or a saved world (then in `load`)
  std::string load;
  std::string save;
  // Which of --dt, --substeps, --iterations and --sleep were given: they override a
  // scene file's physics.
  bool dtGiven = false, substepsGiven = false, iterationsGiven = false, sleepGiven = false;
  bool physicsGiven() const { return dtGiven || substepsGiven || iterationsGiven || sleepGiven; }
  double seconds = 5;
  double dt = 1.0 / 240.0;
  long substeps = 1;
  long iterations = 10;
  long threads = 1;
  bool threadsGiven = false;  // also for a scene file or a saved world
  bool ground = false;
  std::string octomap;
  bool fixedBase = false;
  bool selfCollision = true;
  bool allowMissingMeshes = false;
  bool sleep = false;
  bool hasDropHeight = false;
  double dropHeight = 0;
  std::string png;
  long pngWidth = 1280;
  long pngHeight = 960;
  long every = 1;
  bool quiet = false;
  std::string result;  // --result FILE
};

// Where a job list's task index comes from when --task-index is not given, in this order:
// pfx's own variable, then what Slurm job arrays and Kubernetes indexed Jobs set.
const char* const kTaskIndexVariables[] = {"PFX_TASK_INDEX", "SLURM_ARRAY_TASK_ID",
                                           "JOB_COMPLETION_INDEX"};

int usageError(const std::string& what) {
  std::fprintf(stderr, "pfx_sim: %s\n(pfx_sim --help lists the options)\n", what.c_str());
  return 2;
}

bool parseDouble(const char* text, double& value) {
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text, &end);
  return end != text && *end == '\0' && errno == 0 && std::isfinite(value);
}

bool parseLong(const char* text, long& value) {
  char* end = nullptr;
  errno = 0;
  value = std::strtol(text, &end, 10);
  return end != text && *end == '\0' && errno == 0;
}

// Returns -1 when the arguments are fine, else the exit status.
int parseArguments(int argc, char** argv, Options& options) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char*& out) {
      if (i + 1 >= argc) return false;
      out = argv[++i];
      return true;
    };
    const char* text = nullptr;
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--ground") {
      options.ground = true;
    } else if (arg == "--sleep") {
      options.sleep = true;
      options.sleepGiven = true;
    } else if (arg == "--fixed-base") {
      options.fixedBase = true;
    } else if (arg == "--no-self-collision") {
      options.selfCollision = false;
    } else if (arg == "--allow-missing-meshes") {
      options.allowMissingMeshes = true;
    } else if (arg == "--quiet") {
      options.quiet = true;
    } else if (arg == "--seconds" || arg == "--dt" || arg == "--drop-height") {
      double number = 0;
      if (!value(text)) return usageError(arg + " needs a value");
      if (!parseDouble(text, number)) return usageError(arg + ": not a number: " + text);
      if (arg == "--seconds") {
        if (number < 0) return usageError("--seconds must not be negative");
        options.seconds = number;
      } else if (arg == "--dt") {
        if (!(number > 0) || number > 1) return usageError("--dt must be in (0, 1] s");
        options.dt = number;
        options.dtGiven = true;
      } else {
        options.dropHeight = number;
        options.hasDropHeight = true;
      }
    } else if (arg == "--substeps" || arg == "--iterations" || arg == "--every") {
      long number = 0;
      if (!value(text)) return usageError(arg + " needs a value");
      if (!parseLong(text, number) || number < 1 || number > 1000) {
        return usageError(arg + " must be a whole number from 1 to 1000: " + text);
      }
      (arg == "--substeps"     ? options.substeps
       : arg == "--iterations" ? options.iterations
                               : options.every) = number;
      if (arg == "--substeps") options.substepsGiven = true;
      if (arg == "--iterations") options.iterationsGiven = true;
    } else if (arg == "--threads") {
      if (!value(text)) return usageError("--threads needs a value");
      if (!parseLong(text, options.threads) || options.threads < 0 ||
          options.threads > long(PFX_MAX_THREADS)) {
        return usageError("--threads must be a whole number from 0 to " +
                          std::to_string(PFX_MAX_THREADS) + ": " + text);
      }
      options.threadsGiven = true;
    } else if (arg == "--octomap" || arg == "--png" || arg == "--world" || arg == "--load" ||
               arg == "--save" || arg == "--result") {
      if (!value(text)) return usageError(arg + " needs a file name");
      if (*text == '\0') return usageError(arg + " needs a file name");
      (arg == "--octomap" ? options.octomap
       : arg == "--png"   ? options.png
       : arg == "--world" ? options.world
       : arg == "--load"  ? options.load
       : arg == "--save"  ? options.save
                          : options.result) = text;
    } else if (arg == "--jobs" || arg == "--task-index" || arg == "--result-dir") {
      return usageError(arg + " selects a job from a list: give it before anything else, "
                        "not inside a job");
    } else if (arg == "--png-size") {
      if (!value(text)) return usageError("--png-size needs WxH");
      const char* x = std::strchr(text, 'x');
      const std::string w = x ? std::string(text, x) : std::string();
      if (!x || !parseLong(w.c_str(), options.pngWidth) || !parseLong(x + 1, options.pngHeight) ||
          options.pngWidth < 16 || options.pngHeight < 16 || options.pngWidth > 8192 ||
          options.pngHeight > 8192) {
        return usageError(std::string("--png-size must be WxH, 16 to 8192 pixels: ") + text);
      }
    } else if (!arg.empty() && arg[0] == '-') {
      return usageError("unknown option " + arg);
    } else if (options.urdf.empty()) {
      options.urdf = arg;
    } else {
      return usageError("more than one URDF given: " + options.urdf + ", " + arg);
    }
  }
  if (!options.load.empty() && !options.world.empty()) {
    return usageError("--load and --world both name a world: give one");
  }
  if (!options.load.empty() &&
      (!options.urdf.empty() || options.ground || !options.octomap.empty() ||
       options.physicsGiven() || options.fixedBase || options.hasDropHeight)) {
    return usageError(
        "--load continues a saved world as it was: no URDF, --ground, "
        "--octomap, --fixed-base, --drop-height, --dt, --substeps, --iterations "
        "or --sleep with it");
  }
  if (options.urdf.empty() && options.world.empty() && options.load.empty()) {
    return usageError("no URDF, --world or --load given");
  }
  if (options.seconds / options.dt > 1e8) return usageError("--seconds / --dt is too many steps");
  return -1;
}

// A scene file is XML; anything else given to --world is taken for a saved world, whose
// reader says so when it is not one.
bool looksLikeXml(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return false;  // the saved world's reader names the file it cannot open
  int c = std::fgetc(file);
  if (c == 0xEF) {  // a UTF-8 byte order mark
    std::fgetc(file);
    std::fgetc(file);
    c = std::fgetc(file);
  }
  while (c == ' ' || c == '\t' || c == '\r' || c == '\n') c = std::fgetc(file);
  std::fclose(file);
  return c == '<';
}

PfxWorldParam overriddenParam(PfxWorldParam param, const Options& options) {
  if (options.dtGiven) param.timeStep = PfxFloat(options.dt);
  if (options.substepsGiven) param.subStep = PfxUInt32(options.substeps);
  if (options.iterationsGiven) param.iteration = PfxUInt32(options.iterations);
  if (options.sleepGiven) param.enableSleep = options.sleep;
  if (options.threadsGiven) param.numThreads = PfxUInt32(options.threads);
  param.measureConservation = true;  // the TSV reports the energy and momentum changes
  return param;
}

// Loads the scene file with its physics, or, where the command line overrides some of
// them, once more into a world initialized with the file's physics and the overrides.
PfxInt32 loadScene(PfxWorld& world, const Options& options, PfxSceneModel& scene,
                   std::string& message) {
  PfxSceneLoadParam load;
  if (const PfxInt32 err = pfxLoadSceneFile(world, options.world, load, scene, &message);
      err != PFX_OK || !(options.physicsGiven() || options.threadsGiven)) {
    return err;
  }
  const PfxWorldParam param = overriddenParam(scene.worldParam, options);
  if (const PfxInt32 err = world.initialize(param); err != PFX_OK) {
    message = std::string("--dt, --substeps, --iterations or --threads rejected: ") +
              pfxErrorString(err);
    return err;
  }
  scene = PfxSceneModel();
  load.applyPhysics = false;
  return pfxLoadSceneFile(world, options.world, load, scene, &message);
}

// FNV-1a's state hash as 16 hex digits, as pfx.sweep reports it.
std::string hexHash(PfxUInt64 hash) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

int writeResult(const std::string& path, const PfxWorld& world, long steps, long taskIndex,
                const std::string& job) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) {
    std::fprintf(stderr, "pfx_sim: %s: cannot be opened for writing: %s\n", path.c_str(),
                 std::strerror(errno));
    return 1;
  }
  const PfxWorldStats& stats = world.getStats();
  std::fprintf(file, "{");
  if (taskIndex >= 0) {
    // The job's arguments are plain words (no quotes: the list has none), escaped for JSON.
    std::string escaped;
    for (const char c : job) {
      if (c == '"' || c == '\\') escaped += '\\';
      escaped += c;
    }
    std::fprintf(file, "\"task\": %ld, \"job\": \"%s\", ", taskIndex, escaped.c_str());
  }
  std::fprintf(file,
               "\"steps\": %ld, \"simulated_time\": %.17g, \"num_bodies\": %u, "
               "\"pairs\": %u, \"contacts\": %u, \"max_penetration\": %.9g, "
               "\"max_joint_gap\": %.9g, \"state_hash\": \"%s\"}\n",
               steps, world.getSimulatedTime(), world.getNumRigidBodies(), stats.numPairs,
               stats.numContactPoints, double(stats.maxPenetration), double(stats.maxJointGap),
               hexHash(pfxHashRigidStates(world)).c_str());
  if (std::fclose(file) != 0) {
    std::fprintf(stderr, "pfx_sim: %s: writing failed\n", path.c_str());
    return 1;
  }
  return 0;
}

// A job list's task: which line to run, and where its result goes.
struct Task {
  long index = -1;  // -1: not a job of a list
  std::string job;  // the line's text
  std::vector<std::string> words;
  std::string resultDir = ".";
};

// The task index from --task-index or the environment, checked against the list's length.
// Returns -1 when fine, else the exit status, having said why.
int resolveTaskIndex(const char* given, std::size_t numJobs, const std::string& list,
                     long& index) {
  std::string source = "--task-index";
  const char* text = given;
  if (!text) {
    for (const char* variable : kTaskIndexVariables) {
      const char* value = std::getenv(variable);
      if (value && *value) {
        source = variable;
        text = value;
        break;
      }
    }
  }
  if (!text) {
    return usageError("--jobs: no task index: give --task-index or set PFX_TASK_INDEX, "
                      "SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX");
  }
  if (!parseLong(text, index)) {
    return usageError(std::string("task index '") + text + "' (from " + source +
                      ") is not a whole number");
  }
  if (index < 0) {
    return usageError("task index " + std::to_string(index) + " (from " + source + ") is negative");
  }
  if (std::size_t(index) >= numJobs) {
    return usageError("task index " + std::to_string(index) + " (from " + source +
                      ") is out of range: " + list + " holds " + std::to_string(numJobs) +
                      " jobs" + (numJobs ? ", 0 to " + std::to_string(numJobs - 1) : std::string()));
  }
  return -1;
}

// pfx_sim --jobs LIST [--task-index N] [--result-dir DIR]: picks the job's line. Returns -1
// when the command line is not a job list's or the task is ready, else the exit status.
int selectTask(int argc, char** argv, Task& task) {
  if (argc < 2 || std::string(argv[1]) != "--jobs") return -1;
  std::string list;
  const char* given = nullptr;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg != "--jobs" && arg != "--task-index" && arg != "--result-dir") {
      return usageError("--jobs takes only --task-index N and --result-dir DIR besides the "
                        "list (the job's options go in its line): " + arg);
    }
    if (i + 1 >= argc) return usageError(arg + " needs a value");
    const char* value = argv[++i];
    if (arg == "--jobs") list = value;
    if (arg == "--task-index") given = value;
    if (arg == "--result-dir") task.resultDir = value;
  }
  std::ifstream file(list);
  if (!file) {
    std::fprintf(stderr, "pfx_sim: %s: cannot be opened for reading\n", list.c_str());
    return 1;
  }
  std::vector<std::string> jobs;
  for (std::string line; std::getline(file, line);) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::size_t last = line.find_last_not_of(" \t\r");
    jobs.push_back(line.substr(first, last - first + 1));
  }
  if (const int status = resolveTaskIndex(given, jobs.size(), list, task.index); status >= 0) {
    return status;
  }
  task.job = jobs[task.index];
  std::istringstream words(task.job);
  for (std::string word; words >> word;) task.words.push_back(word);
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  Task task;
  if (const int status = selectTask(argc, argv, task); status >= 0) return status;
  std::vector<char*> jobArgs;
  if (task.index >= 0) {
    jobArgs.push_back(argv[0]);
    for (std::string& word : task.words) jobArgs.push_back(word.data());
    argc = int(jobArgs.size());
    argv = jobArgs.data();
  }
  Options options;
  if (const int status = parseArguments(argc, argv, options); status >= 0) return status;
  if (task.index >= 0) {
    if (!options.result.empty()) {
      return usageError("job " + std::to_string(task.index) +
                        ": --result is given by --result-dir for a job of a list");
    }
    options.result = task.resultDir + "/task-" + std::to_string(task.index) + ".json";
  }

  // Declared before the world, which points into their meshes, so that it goes first.
  PfxSerializedMeshes savedMeshes;
  PfxSceneModel scene;
  PfxWorld world;
  std::string message;
  std::string savedWorld = options.load;
  if (!options.world.empty() && !looksLikeXml(options.world)) savedWorld = options.world;
  if (!savedWorld.empty()) {
    if (options.physicsGiven()) {
      return usageError(
          "a saved world runs with its own parameters: no --dt, --substeps, "
          "--iterations or --sleep with it");
    }
    PfxLoadWorldOptions loadOptions;
    loadOptions.keepSavedNumThreads = !options.threadsGiven;
    loadOptions.numThreads = PfxUInt32(options.threads);
    if (const PfxInt32 err =
            pfxLoadWorld(world, savedWorld.c_str(), savedMeshes, &message, loadOptions);
        err != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: %s: %s\n", savedWorld.c_str(),
                   message.empty() ? pfxErrorString(err) : message.c_str());
      return 1;
    }
  } else {
    PfxWorldParam param;
    param.gravity = PfxVector3(0, 0, PfxFloat(-9.80665));
    param.timeStep = PfxFloat(options.dt);
    param.subStep = PfxUInt32(options.substeps);
    param.iteration = PfxUInt32(options.iterations);
    param.measureConservation = true;
    param.enableSleep = options.sleep;
    param.numThreads = PfxUInt32(options.threads);
    if (const PfxInt32 err = world.initialize(param); err != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: world parameters rejected: %s\n", pfxErrorString(err));
      return 1;
    }
    if (!options.world.empty()) {
      if (const PfxInt32 err = loadScene(world, options, scene, message); err != PFX_OK) {
        std::fprintf(stderr, "pfx_sim: %s\n",
                     message.empty() ? pfxErrorString(err) : message.c_str());
        return 1;
      }
      for (const std::string& warning : scene.warnings) {
        std::fprintf(stderr, "pfx_sim: warning: %s\n", warning.c_str());
      }
    }
  }

  if (options.ground) {
    PfxBodyInit ground;
    ground.mass = 0;
    ground.position = PfxVector3(0, 0, PfxFloat(-0.5));
    if (const PfxInt32 err = pfxAddBody(world, pfxMakeShape(PfxBox(50, 50, PfxFloat(0.5))), ground);
        err != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: cannot add the ground: %s\n", pfxErrorString(err));
      return 1;
    }
  }
  std::unique_ptr<PfxOctomap> map;
  if (!options.octomap.empty()) {
    map = std::make_unique<PfxOctomap>();
    if (const PfxInt32 err =
            pfxLoadOctomapFile(world, options.octomap, PfxOctomapLoadParam(), *map, &message);
        err != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: %s\n",
                   message.empty() ? pfxErrorString(err) : message.c_str());
      return 1;
    }
  }

  PfxUrdfModel model;
  if (!options.urdf.empty()) {
    PfxUrdfLoadParam load;
    load.fixedBase = options.fixedBase;
    load.disableSelfCollision = !options.selfCollision;
    load.allowMissingMeshes = options.allowMissingMeshes;
    load.placeAboveGround = options.hasDropHeight || options.ground;
    if (options.hasDropHeight) load.groundClearance = PfxFloat(options.dropHeight);
    if (const PfxInt32 err = pfxLoadUrdfFile(world, options.urdf, load, model, &message);
        err != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: %s\n",
                   message.empty() ? pfxErrorString(err) : message.c_str());
      return 1;
    }
    for (const std::string& warning : model.warnings) {
      std::fprintf(stderr, "pfx_sim: warning: %s\n", warning.c_str());
    }
  }
  const double dt = world.getParam().timeStep;
  if (options.seconds / dt > 1e8) {
    std::fprintf(stderr, "pfx_sim: --seconds %g at the world's dt %g s is too many steps\n",
                 options.seconds, dt);
    return 2;
  }
  const long steps = std::lround(options.seconds / dt);
  if (!options.quiet) {
    std::printf(
        "step\ttime\tstep_s\tpairs\tcontacts\tmax_penetration\tmax_joint_gap\t"
        "energy_change\tmomentum_change\tangular_momentum_change\n");
  }
  for (long step = 1; step <= steps; ++step) {
    if (const PfxInt32 err = world.step(); err != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: step %ld failed: %s\n", step, pfxErrorString(err));
      return 1;
    }
    if (options.quiet || (step % options.every != 0 && step != steps)) continue;
    const PfxWorldStats& stats = world.getStats();
    std::printf("%ld\t%.6f\t%.3e\t%u\t%u\t%.3e\t%.3e\t%.3e\t%.3e\t%.3e\n", step,
                world.getSimulatedTime(), stats.stepSeconds, stats.numPairs, stats.numContactPoints,
                double(stats.maxPenetration), double(stats.maxJointGap), stats.energyChange,
                stats.linearMomentumChange, stats.angularMomentumChange);
  }
  std::fflush(stdout);

  if (!options.save.empty()) {
    if (const PfxInt32 err = pfxSaveWorld(world, options.save.c_str(), &message); err != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: %s: %s\n", options.save.c_str(),
                   message.empty() ? pfxErrorString(err) : message.c_str());
      return 1;
    }
  }

  if (!options.result.empty()) {
    if (const int status = writeResult(options.result, world, steps, task.index, task.job)) {
      return status;
    }
  }

  if (!options.png.empty()) {
    PfxScenePicture picture(PfxUInt32(options.pngWidth), PfxUInt32(options.pngHeight));
    if (picture.draw(world, options.png, &message) != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: %s\n", message.c_str());
      return 1;
    }
  }
  return 0;
}
