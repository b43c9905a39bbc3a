// pfx_sim: loads a URDF robot, a scene file (pfx XML or SDFormat) or both, optionally onto
// a ground plane and an OctoMap, or a world saved earlier; simulates it headless, prints
// per-step statistics as TSV on standard output and, on request, saves the world and
// writes a picture of the final scene.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_serialize.h"
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
    "  -h, --help         this text\n"
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
};

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
    } else if (arg == "--octomap" || arg == "--png" || arg == "--world" || arg == "--load" ||
               arg == "--save") {
      if (!value(text)) return usageError(arg + " needs a file name");
      if (*text == '\0') return usageError(arg + " needs a file name");
      (arg == "--octomap" ? options.octomap
       : arg == "--png"   ? options.png
       : arg == "--world" ? options.world
       : arg == "--load"  ? options.load
                          : options.save) = text;
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
  param.measureConservation = true;  // the TSV reports the energy and momentum changes
  return param;
}

// Loads the scene file with its physics, or, where the command line overrides some of
// them, once more into a world initialized with the file's physics and the overrides.
PfxInt32 loadScene(PfxWorld& world, const Options& options, PfxSceneModel& scene,
                   std::string& message) {
  PfxSceneLoadParam load;
  if (const PfxInt32 err = pfxLoadSceneFile(world, options.world, load, scene, &message);
      err != PFX_OK || !options.physicsGiven()) {
    return err;
  }
  const PfxWorldParam param = overriddenParam(scene.worldParam, options);
  if (const PfxInt32 err = world.initialize(param); err != PFX_OK) {
    message = std::string("--dt, --substeps or --iterations rejected: ") + pfxErrorString(err);
    return err;
  }
  scene = PfxSceneModel();
  load.applyPhysics = false;
  return pfxLoadSceneFile(world, options.world, load, scene, &message);
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (const int status = parseArguments(argc, argv, options); status >= 0) return status;

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
    if (const PfxInt32 err = pfxLoadWorld(world, savedWorld.c_str(), savedMeshes, &message);
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

  if (!options.png.empty()) {
    PfxScenePicture picture(PfxUInt32(options.pngWidth), PfxUInt32(options.pngHeight));
    if (picture.draw(world, options.png, &message) != PFX_OK) {
      std::fprintf(stderr, "pfx_sim: %s\n", message.c_str());
      return 1;
    }
  }
  return 0;
}
