#include "bench_particles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pfxbench {

namespace {

// The catenary through (-halfSpan, 0) and (halfSpan, 0) of the given length:
// y = c (cosh(x / c) - cosh(halfSpan / c)) with 2 c sinh(halfSpan / c) = length, c found
// by bisection on its logarithm.
double catenaryParameter(double halfSpan, double length) {
  double lo = 1e-3, hi = 1e3;
  for (int i = 0; i < 200; ++i) {
    const double c = std::sqrt(lo * hi);
    (2 * c * std::sinh(halfSpan / c) > length ? lo : hi) = c;
  }
  return std::sqrt(lo * hi);
}

double distance(const ParticlePoint& a, const ParticlePoint& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) +
                   (a.z - b.z) * (a.z - b.z));
}

struct ParticleEngine {
  const char* name;
  bool wanted;
};

std::vector<ParticleEngine> selectedEngines(const Options& options) {
  auto asked = [&](const char* name) {
    return options.engines.empty() ||
           std::find(options.engines.begin(), options.engines.end(), name) != options.engines.end();
  };
  std::vector<ParticleEngine> engines = {{"pfx", asked("pfx")}};
#ifdef PFX_BENCH_HAVE_BULLET
  engines.push_back({"bullet", asked("bullet")});
#else
  if (asked("bullet") && !options.engines.empty()) {
    std::fprintf(stderr,
                 "bullet: skipped, its library was not found when pfx_bench was configured\n");
  }
#endif
  return engines;
}

std::vector<double> timeSteps(const Options& options) {
  return options.timeStepsGiven ? options.timeSteps : std::vector<double>{1.0 / 60};
}

// The sweep of both engines on the rope: sub-steps times iterations per sub-step.
const SolverSetting kRopeSettings[] = {{1, 1},  {1, 5},  {1, 20}, {4, 1},  {4, 5},
                                       {4, 20}, {20, 1}, {20, 5}, {20, 20}};
const SolverSetting kPayloadSettings[] = {{4, 2}, {20, 20}};
// pfx's check on its own figures (see runRopeScene): at 20 sub-steps of 5 iterations.
constexpr double kRopeCheckError = 0.01;  // m

}  // namespace

std::vector<ParticlePoint> makeRopeStart() {
  const double drop = std::sqrt(0.25 * kRopeLength * kRopeLength - kRopeHalfSpan * kRopeHalfSpan);
  const int half = (kRopeParticles - 1) / 2;
  std::vector<ParticlePoint> points(kRopeParticles);
  for (int i = 0; i <= half; ++i) {
    const double t = double(i) / half;
    points[i] = {-kRopeHalfSpan * (1 - t), -drop * t, 0};
    points[kRopeParticles - 1 - i] = {kRopeHalfSpan * (1 - t), -drop * t, 0};
  }
  return points;
}

double catenaryError(const std::vector<ParticlePoint>& positions) {
  const double c = catenaryParameter(kRopeHalfSpan, kRopeLength);
  constexpr int kSamples = 20001;  // 80 um apart along x
  std::vector<ParticlePoint> curve(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    const double x = -kRopeHalfSpan + 2 * kRopeHalfSpan * k / (kSamples - 1);
    curve[k] = {x, c * (std::cosh(x / c) - std::cosh(kRopeHalfSpan / c)), 0};
  }
  double worst = 0;
  for (const ParticlePoint& p : positions) {
    double nearest = 1e300;
    for (const ParticlePoint& q : curve) nearest = std::min(nearest, distance(p, q));
    worst = std::max(worst, nearest);
  }
  return worst;
}

double ropeStretch(const std::vector<ParticlePoint>& positions, double restLength) {
  double length = 0;
  for (size_t i = 1; i < positions.size(); ++i) length += distance(positions[i - 1], positions[i]);
  return length / restLength - 1;
}

double clothPenetration(const std::vector<ParticlePoint>& positions) {
  double deepest = 0;
  for (const ParticlePoint& p : positions) {
    const ParticlePoint centre{0, kClothSphereRadius, 0};
    deepest = std::max({deepest, kClothSphereRadius - distance(p, centre), -p.y});
  }
  return deepest;
}

double clothStretch(const std::vector<ParticlePoint>& positions, int side) {
  const double rest = kClothSize / (side - 1);
  double sum = 0;
  int count = 0;
  for (int j = 0; j < side; ++j) {
    for (int i = 0; i < side; ++i) {
      const ParticlePoint& p = positions[i + j * side];
      if (i + 1 < side) sum += distance(p, positions[i + 1 + j * side]) / rest - 1, ++count;
      if (j + 1 < side) sum += distance(p, positions[i + (j + 1) * side]) / rest - 1, ++count;
    }
  }
  return sum / count;
}

bool allFinite(const std::vector<ParticlePoint>& positions) {
  for (const ParticlePoint& p : positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  }
  return true;
}

int runRopeScene(const Options& options, std::vector<ResultRow>& rows) {
  const double seconds = options.seconds > 0 ? options.seconds : 20;
  int failures = 0;
  std::fprintf(
      stderr,
      "rope: 2 m, 41 particles of 10 g between pins 1.6 m apart, %.3g s settled\n"
      "  engine       dt      sub  it  catenary error (mm)  stretch (%%)  cpu ms per sim s\n",
      seconds);
  for (const double dt : timeSteps(options)) {
    for (const ParticleEngine& engine : selectedEngines(options)) {
      if (!engine.wanted) continue;
      const bool pfx = std::string(engine.name) == "pfx";
      for (const bool tethers : pfx ? std::vector<bool>{false, true} : std::vector<bool>{false}) {
        for (const SolverSetting& setting : kRopeSettings) {
          RopeFigures figures;
          std::string error;
          const bool ran = pfx ? runPfxRope(dt, seconds, setting, tethers, figures, error)
                               : runBulletRope(dt, seconds, setting, figures, error);
          if (!ran) {
            std::fprintf(stderr, "rope %s: FAILED: %s\n", engine.name, error.c_str());
            ++failures;
            continue;
          }
          const std::string name = std::string(engine.name) + (tethers ? "+tether" : "");
          std::fprintf(stderr, "  %-11s  %-6.4g  %3d  %2d  %19.3f  %11.4f  %16.2f%s\n",
                       name.c_str(), dt, setting.substeps, setting.iterations,
                       1e3 * figures.catenaryError, 100 * figures.stretch,
                       1e3 * figures.cpuPerSimSecond, figures.finite ? "" : "  NOT FINITE");
          if (pfx && (!figures.finite || (setting.substeps == 20 && setting.iterations == 5 &&
                                          !(figures.catenaryError < kRopeCheckError)))) {
            std::fprintf(stderr, "rope %s: FAILED its check (finite, within %g m at 20 x 5)\n",
                         name.c_str(), kRopeCheckError);
            ++failures;
          }
          const std::string variant = std::to_string(kRopeParticles) + (tethers ? "_tethers" : "");
          auto row = [&](const char* metric, double value) {
            rows.push_back({kRopeSceneName, engine.name, variant, dt, setting.substeps,
                            setting.iterations, 1, figures.cpuPerSimSecond, metric, value});
          };
          row("catenary_error", figures.catenaryError);
          row("stretch", figures.stretch);
          row("finite", figures.finite ? 1 : 0);
        }
      }
    }
  }
  std::fprintf(stderr,
               "rope payload: 1 m, 21 particles of 1 g, 20 kg at the end, released horizontal, "
               "%.3g s\n  engine       dt      sub  it  largest stretch (%%)  cpu ms per sim s\n",
               seconds);
  for (const double dt : timeSteps(options)) {
    for (const ParticleEngine& engine : selectedEngines(options)) {
      if (!engine.wanted) continue;
      const bool pfx = std::string(engine.name) == "pfx";
      for (const bool tethers : pfx ? std::vector<bool>{false, true} : std::vector<bool>{false}) {
        for (const SolverSetting& setting : kPayloadSettings) {
          RopeFigures figures;
          std::string error;
          const bool ran = pfx ? runPfxPayload(dt, seconds, setting, tethers, figures, error)
                               : runBulletPayload(dt, seconds, setting, figures, error);
          if (!ran) {
            std::fprintf(stderr, "rope payload %s: FAILED: %s\n", engine.name, error.c_str());
            ++failures;
            continue;
          }
          const std::string name = std::string(engine.name) + (tethers ? "+tether" : "");
          std::fprintf(stderr, "  %-11s  %-6.4g  %3d  %2d  %19.3f  %16.2f%s\n", name.c_str(), dt,
                       setting.substeps, setting.iterations, 100 * figures.stretch,
                       1e3 * figures.cpuPerSimSecond, figures.finite ? "" : "  NOT FINITE");
          if (pfx && !figures.finite) ++failures;
          const std::string variant = tethers ? "payload_tethers" : "payload";
          auto row = [&](const char* metric, double value) {
            rows.push_back({kRopeSceneName, engine.name, variant, dt, setting.substeps,
                            setting.iterations, 1, figures.cpuPerSimSecond, metric, value});
          };
          row("stretch", figures.stretch);
          row("finite", figures.finite ? 1 : 0);
        }
      }
    }
  }
  return failures;
}

int runClothScene(const Options& options, std::vector<ResultRow>& rows) {
  const double seconds = options.seconds > 0 ? options.seconds : 3;
  // The same four passes over the links: pfx in 4 sub-steps of 1 iteration, Bullet in one
  // step of 4 position iterations, its usual way to spend them.
  const SolverSetting pfxSetting{4, 1}, bulletSetting{1, 4};
  int failures = 0;
  std::fprintf(stderr,
               "cloth: 2 m square, 1 kg, dropped on a sphere and the ground, %.3g s, one thread\n"
               "  engine  size     dt      sub  it  ms/step mean  median  deepest (mm)  "
               "stretch (%%)\n",
               seconds);
  for (const double dt : timeSteps(options)) {
    for (const int side : {64, 128}) {
      for (const ParticleEngine& engine : selectedEngines(options)) {
        if (!engine.wanted) continue;
        const bool pfx = std::string(engine.name) == "pfx";
        const SolverSetting& setting = pfx ? pfxSetting : bulletSetting;
        ClothFigures figures;
        std::string error;
        const bool ran = pfx ? runPfxCloth(side, dt, seconds, setting, figures, error)
                             : runBulletCloth(side, dt, seconds, setting, figures, error);
        const std::string variant = std::to_string(side) + "x" + std::to_string(side);
        if (!ran) {
          std::fprintf(stderr, "cloth %s %s: FAILED: %s\n", engine.name, variant.c_str(),
                       error.c_str());
          ++failures;
          continue;
        }
        std::fprintf(stderr, "  %-6s  %-7s  %-6.4g  %3d  %2d  %12.3f  %6.3f  %12.2f  %11.3f%s\n",
                     engine.name, variant.c_str(), dt, setting.substeps, setting.iterations,
                     figures.stepMsMean, figures.stepMsMedian, 1e3 * figures.penetration,
                     100 * figures.stretch, figures.finite ? "" : "  NOT FINITE");
        if (pfx && (!figures.finite || !(figures.penetration < kClothThickness))) {
          std::fprintf(stderr, "cloth pfx %s: FAILED its check (finite, no centre %g m deep)\n",
                       variant.c_str(), kClothThickness);
          ++failures;
        }
        auto row = [&](const char* metric, double value) {
          rows.push_back({kClothSceneName, engine.name, variant, dt, setting.substeps,
                          setting.iterations, 1, figures.cpuPerSimSecond, metric, value});
        };
        row("step_ms_mean", figures.stepMsMean);
        row("step_ms_median", figures.stepMsMedian);
        row("penetration_max", figures.penetration);
        row("stretch", figures.stretch);
        row("finite", figures.finite ? 1 : 0);
      }
    }
  }
  return failures;
}

}  // namespace pfxbench
