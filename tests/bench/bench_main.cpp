// pfx_bench: error against run time for pfx and its peers, on the same scenes in the same
// run. See bench_cli.cpp for the command line and bench_engine.h for what each engine is
// set to.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "bench_batch.h"
#include "bench_characters.h"
#include "bench_cli.h"
#include "bench_engine.h"
#include "bench_mesh_floor.h"
#include "bench_octomap.h"
#include "bench_particles.h"
#include "bench_rays.h"
#include "bench_report.h"
#include "bench_run.h"
#include "bench_scene.h"
#include "bench_serialize.h"

using namespace pfxbench;

namespace {

// Scenes that measure something other than stepping (load times, a world written and read
// back), that step pfx alone, that drive each engine through its own character controller,
// or that step particles, which the rigid-body engine adapters do not hold: bench_octomap.h,
// bench_mesh_floor.h, bench_serialize.h, bench_characters.h, bench_particles.h,
// bench_batch.h.
struct ApartScene {
  const char* name;
  // Appends its rows, returns its failures.
  int (*run)(const Options& options, std::vector<ResultRow>& rows);
};
const ApartScene kApartScenes[] = {
    {kOctomapSceneName,
     [](const Options&, std::vector<ResultRow>& rows) { return runOctomapScene(rows); }},
    {kMeshFloorSceneName,
     [](const Options&, std::vector<ResultRow>& rows) { return runMeshFloorScene(rows); }},
    {kSerializeSceneName,
     [](const Options&, std::vector<ResultRow>& rows) { return runSerializeScene(rows); }},
    {kCharactersSceneName, runCharactersScene},
    {kBatchSceneName, runBatchScene},
    {kRopeSceneName, runRopeScene},
    {kClothSceneName, runClothScene},
};

struct Job {
  const Scene* scene;
  const EngineInfo* engine;
  EngineSettings settings;
  double seconds;
};

std::string describeTimeStep(double dt) {
  const double rate = 1 / dt;
  char text[48];
  if (std::abs(rate - std::round(rate)) < 1e-6 * rate) {
    std::snprintf(text, sizeof(text), "1/%.0f", rate);
  } else {
    std::snprintf(text, sizeof(text), "%.6g", dt);
  }
  return text;
}

std::string describeJobWithoutThreads(const Job& job) {
  std::string text = job.scene->name;
  if (job.scene->variant != "-") text += "/" + job.scene->variant;
  return text + " " + job.engine->name + " dt=" + describeTimeStep(job.settings.dt) +
         " it=" + std::to_string(job.settings.iterations) +
         " sub=" + std::to_string(job.settings.substeps);
}

std::string describeJob(const Job& job) {
  return describeJobWithoutThreads(job) + " thr=" + std::to_string(job.settings.threads);
}

// The engines asked for (all known ones by default) that were built; says on stderr which
// are skipped. False for a name the benchmark does not know.
bool selectEngines(const Options& options, std::vector<const EngineInfo*>& selected) {
  std::vector<std::string> names = options.engines;
  if (names.empty()) {
    for (const EngineInfo& info : knownEngines()) names.push_back(info.name);
  }
  for (const std::string& name : names) {
    const EngineInfo* found = nullptr;
    for (const EngineInfo& info : knownEngines()) {
      if (name == info.name) found = &info;
    }
    if (!found) {
      std::fprintf(stderr, "unknown engine '%s' (known:", name.c_str());
      for (const EngineInfo& info : knownEngines()) std::fprintf(stderr, " %s", info.name);
      std::fprintf(stderr, ")\n");
      return false;
    }
    if (!found->create) {
      std::fprintf(stderr, "%s: skipped, its library was not found when pfx_bench was configured\n",
                   name.c_str());
      continue;
    }
    selected.push_back(found);
  }
  return true;
}

bool selectScenes(const Options& options, std::vector<Scene>& scenes) {
  const std::vector<std::string>& names = options.scenes.empty() ? sceneNames() : options.scenes;
  for (const std::string& name : names) {
    std::vector<Scene> variants;
    if (!buildScene(name, variants)) {
      std::fprintf(stderr, "unknown scene '%s' (known:", name.c_str());
      for (const std::string& known : sceneNames()) std::fprintf(stderr, " %s", known.c_str());
      std::fprintf(stderr, ")\n");
      return false;
    }
    if (variants.empty()) {
      std::fprintf(stderr, "scene '%s' could not be built\n", name.c_str());
      return false;
    }
    scenes.insert(scenes.end(), variants.begin(), variants.end());
  }
  return true;
}

std::vector<Job> planJobs(const Options& options, const std::vector<Scene>& scenes,
                          const std::vector<const EngineInfo*>& engines) {
  std::vector<Job> jobs;
  std::set<std::string> warned;
  for (const Scene& scene : scenes) {
    for (const EngineInfo* engine : engines) {
      for (double dt : options.timeSteps) {
        for (int iterations : options.iterations) {
          for (int substeps : options.substeps) {
            for (int threads : options.threads) {
              if (threads > engine->maxThreads) {
                const std::string key = std::string(engine->name) + std::to_string(threads);
                if (warned.insert(key).second) {
                  std::fprintf(stderr, "%s: skipped with %d threads, it runs on %d here\n",
                               engine->name, threads, engine->maxThreads);
                }
                continue;
              }
              const double seconds = options.seconds > 0 ? options.seconds : scene.duration;
              jobs.push_back({&scene, engine, {dt, substeps, iterations, threads}, seconds});
            }
          }
        }
      }
    }
  }
  return jobs;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::string error;
  if (!parseOptions(argc, argv, options, error)) {
    std::fprintf(stderr, "%s\n%s", error.c_str(), usage());
    return 2;
  }
  if (options.help) {
    std::printf("%s", usage());
    return 0;
  }
  // The rays scene and those of kApartScenes do not step engines side by side: they run
  // apart, after the stepping scenes.
  const bool fullSweep = options.scenes.empty();
  std::vector<const ApartScene*> apartScenes;
  for (const ApartScene& apart : kApartScenes) {
    const auto named = std::remove(options.scenes.begin(), options.scenes.end(),
                                   std::string(apart.name));
    if (fullSweep || named != options.scenes.end()) apartScenes.push_back(&apart);
    options.scenes.erase(named, options.scenes.end());
  }
  RaySceneRequest rays;
  if (fullSweep || !options.scenes.empty()) {
    if (!takeRaySceneRequest(options.scenes, options.engines, rays, error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 2;
    }
  } else {
    rays.otherScenes = false;
  }
  for (const auto& [name, bound] : options.limits) {
    Metric metric;
    if (!metricByName(name, metric)) {
      std::fprintf(stderr, "--limit: unknown metric '%s'\n", name.c_str());
      return 2;
    }
  }
  std::vector<const EngineInfo*> engines;
  std::vector<Scene> scenes;
  if (rays.otherScenes && (!selectEngines(options, engines) || !selectScenes(options, scenes))) {
    return 2;
  }
  const std::vector<Job> jobs = planJobs(options, scenes, engines);

  std::ofstream tsvFile;
  if (!options.outDir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.outDir, ec);
    tsvFile.open(options.outDir + "/results.tsv");
    if (!tsvFile) {
      std::fprintf(stderr, "cannot write %s/results.tsv\n", options.outDir.c_str());
      return 2;
    }
    writeTsvHeader(tsvFile);
  }
  writeTsvHeader(std::cout);
  std::cout.flush();

  double totalWork = 0;
  for (const Job& job : jobs) totalWork += runWork(*job.scene, job.settings, job.seconds);
  Progress progress(totalWork);
  std::vector<ResultRow> rows;
  // --same-bits: the first finished run of each scene, engine and setting, by thread count.
  std::map<std::string, std::pair<int, std::uint64_t>> firstDigests;
  int failures = 0;
  int stopped = 0;
  for (const Job& job : jobs) {
    const std::string label = describeJob(job);
    progress.setLabel(label);
    const RunResult result = runScene(*job.engine, *job.scene, job.settings, job.seconds, progress);
    if (result.skipped) {
      progress.log(label + ": skipped: " + result.error);
      continue;
    }
    if (!result.ok) {
      ++failures;
      progress.log(label + ": FAILED: " + result.error);
      continue;
    }
    char timing[160];
    std::snprintf(timing, sizeof(timing),
                  ": %.4f ms per step, %.5f wall s per simulated s, %.4f CPU ms per step",
                  1e3 * result.wallSecondsPerSimSecond * job.settings.dt,
                  result.wallSecondsPerSimSecond,
                  1e3 * result.cpuSecondsPerSimSecond * job.settings.dt);
    progress.log(label + timing);
    if (result.stopped) {
      ++stopped;
      progress.log(label + ": " + result.error + "; its figures are NaN");
    }
    for (const auto& [metric, value] : result.metrics) {
      const ResultRow row{job.scene->name, job.engine->name, job.scene->variant, job.settings.dt,
                          job.settings.substeps, job.settings.iterations, job.settings.threads,
                          result.wallSecondsPerSimSecond, metricName(metric), value};
      writeTsvRow(std::cout, row);
      if (tsvFile) writeTsvRow(tsvFile, row);
      rows.push_back(row);
      for (const auto& [name, bound] : options.limits) {
        if (name != row.metric || value <= bound) continue;
        ++failures;
        char text[160];
        std::snprintf(text, sizeof(text), ": %s %.6g is beyond the limit %.6g", name.c_str(),
                      value, bound);
        progress.log(label + text);
      }
    }
    if (options.sameBits && !result.stopped) {
      const std::string group = describeJobWithoutThreads(job);
      const auto first = firstDigests.emplace(group, std::make_pair(job.settings.threads,
                                                                   result.stateDigest));
      const bool same = first.first->second.second == result.stateDigest;
      char text[160];
      std::snprintf(text, sizeof(text), ": final state digest %016llx, %s %d thread(s)",
                    static_cast<unsigned long long>(result.stateDigest),
                    same ? "the same bits as with" : "DIFFERENT BITS from",
                    first.first->second.first);
      progress.log(label + text);
      if (!same) ++failures;
      const ResultRow row{job.scene->name, job.engine->name, job.scene->variant, job.settings.dt,
                          job.settings.substeps, job.settings.iterations, job.settings.threads,
                          result.wallSecondsPerSimSecond, "same_bits", same ? 1.0 : 0.0};
      writeTsvRow(std::cout, row);
      if (tsvFile) writeTsvRow(tsvFile, row);
    }
    std::cout.flush();
  }
  progress.finish();
  if (rays.wanted) {
    std::vector<ResultRow> rayRows;
    failures += runRayScene(rays, rayRows);
    for (const ResultRow& row : rayRows) {
      writeTsvRow(std::cout, row);
      if (tsvFile) writeTsvRow(tsvFile, row);
    }
    std::cout.flush();
  }
  for (const ApartScene* apart : apartScenes) {
    std::vector<ResultRow> apartRows;
    failures += apart->run(options, apartRows);
    for (const ResultRow& row : apartRows) {
      writeTsvRow(std::cout, row);
      if (tsvFile) writeTsvRow(tsvFile, row);
    }
    std::cout.flush();
  }
  if (!options.outDir.empty()) {
    tsvFile.close();
    writePlots(rows, options.outDir);
  }
  if (stopped > 0) std::fprintf(stderr, "%d run(s) stopped by their engine (figures NaN)\n", stopped);
  if (failures > 0) std::fprintf(stderr, "%d run(s) failed\n", failures);
  return failures > 0 ? 1 : 0;
}
