#include "bench_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <tuple>

namespace pfxbench {

namespace {

std::string formatNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

const char* metricUnit(const std::string& metric) {
  if (metric == "energy_drift" || metric == "momentum_drift") return "relative";
  if (metric == "escaped") return "bodies";
  if (metric == "bytes_per_body") return "bytes";
  if (metric.find("ms_per_step") != std::string::npos) return "ms";
  return "m";
}

// Order-keeping set of keys.
template <typename Key>
int indexOf(std::vector<Key>& keys, const Key& key) {
  const auto it = std::find(keys.begin(), keys.end(), key);
  if (it != keys.end()) return static_cast<int>(it - keys.begin());
  keys.push_back(key);
  return static_cast<int>(keys.size()) - 1;
}

using PanelKey = std::pair<std::string, std::string>;                   // variant, metric
using CurveKey = std::tuple<std::string, int, int, int>;                // engine, it, sub, thr

struct Panel {
  bool logY = false;
  int hidden = 0;  // points not drawn (not positive on a log axis, or not finite)
  std::vector<std::pair<int, int>> blocks;  // curve index, data block index
};

std::string curveTitle(const CurveKey& curve, bool showIterations, bool showSubsteps,
                       bool showThreads) {
  std::string title = std::get<0>(curve);
  if (showIterations) title += " it=" + std::to_string(std::get<1>(curve));
  if (showSubsteps) title += " sub=" + std::to_string(std::get<2>(curve));
  if (showThreads) title += " thr=" + std::to_string(std::get<3>(curve));
  return title;
}

bool plotScene(const std::string& scene, const std::vector<const ResultRow*>& rows,
               const std::string& dir) {
  std::vector<PanelKey> panelKeys;
  std::vector<CurveKey> curveKeys;
  std::vector<int> iterations, substeps, threads;
  for (const ResultRow* row : rows) {
    indexOf(panelKeys, PanelKey(row->variant, row->metric));
    indexOf(curveKeys, CurveKey(row->engine, row->iterations, row->substeps, row->threads));
    indexOf(iterations, row->iterations);
    indexOf(substeps, row->substeps);
    indexOf(threads, row->threads);
  }

  const std::string dataPath = dir + "/" + scene + ".dat";
  const std::string scriptPath = dir + "/" + scene + ".gp";
  std::ofstream data(dataPath);
  std::vector<Panel> panels(panelKeys.size());
  int block = 0;
  for (std::size_t p = 0; p < panelKeys.size(); ++p) {
    Panel& panel = panels[p];
    panel.logY = panelKeys[p].second != "escaped" &&
                 std::any_of(rows.begin(), rows.end(), [&](const ResultRow* r) {
                   return PanelKey(r->variant, r->metric) == panelKeys[p] && r->value > 0;
                 });
    for (std::size_t c = 0; c < curveKeys.size(); ++c) {
      std::vector<const ResultRow*> points;
      for (const ResultRow* r : rows) {
        if (PanelKey(r->variant, r->metric) != panelKeys[p] ||
            CurveKey(r->engine, r->iterations, r->substeps, r->threads) != curveKeys[c]) {
          continue;
        }
        const bool drawable = std::isfinite(r->value) && std::isfinite(r->wallSecondsPerSimSecond) &&
                              r->wallSecondsPerSimSecond > 0 && (!panel.logY || r->value > 0);
        if (drawable) {
          points.push_back(r);
        } else {
          ++panel.hidden;
        }
      }
      if (points.empty()) continue;
      // Along a curve the time step shrinks, so the line follows the sweep.
      std::sort(points.begin(), points.end(),
                [](const ResultRow* a, const ResultRow* b) { return a->dt > b->dt; });
      data << "# " << panelKeys[p].first << ' ' << panelKeys[p].second << ' '
           << std::get<0>(curveKeys[c]) << "\n";
      for (const ResultRow* r : points) {
        data << formatNumber(r->wallSecondsPerSimSecond) << ' ' << formatNumber(r->value) << ' '
             << formatNumber(r->dt) << "\n";
      }
      data << "\n\n";
      panel.blocks.emplace_back(static_cast<int>(c), block++);
    }
  }
  data.close();

  const int columns = panels.size() > 1 ? 2 : 1;
  const int rowsOfPanels = static_cast<int>((panels.size() + columns - 1) / columns);
  std::ofstream script(scriptPath);
  script << "set terminal pngcairo noenhanced size " << 560 * columns << "," << 400 * rowsOfPanels
         << " font \",9\"\n"
         << "set output \"" << dir << "/" << scene << ".png\"\n"
         << "set multiplot layout " << rowsOfPanels << "," << columns << " title \"" << scene
         << ": error against wall time (one point per time step)\"\n"
         << "set xlabel \"wall s per simulated s\"\nset logscale x\nset key top right\n"
         << "set grid\n";
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const Panel& panel = panels[p];
    std::string title = panelKeys[p].second;
    if (panelKeys[p].first != "-") title += " (" + panelKeys[p].first + ")";
    if (panel.hidden > 0) {
      title += ", " + std::to_string(panel.hidden) + (panel.logY ? " zero or NaN" : " NaN") +
               " points not drawn";
    }
    script << "set title \"" << title << "\"\n"
           << "set ylabel \"" << panelKeys[p].second << " (" << metricUnit(panelKeys[p].second)
           << ")\"\n"
           << (panel.logY ? "set logscale y\n" : "unset logscale y\n");
    if (panel.blocks.empty()) {
      script << "set label 1 \"nothing to draw\" at graph 0.5,0.5 center\n"
             << "set xrange [1:10]\nset yrange [0:1]\nplot -1 notitle\n"
             << "unset label 1\nset autoscale x\nset autoscale y\n";
      continue;
    }
    // Linetypes follow the curve, so that an engine keeps its colour in every panel.
    script << "plot ";
    for (std::size_t b = 0; b < panel.blocks.size(); ++b) {
      const CurveKey& curve = curveKeys[panel.blocks[b].first];
      script << (b ? ", \\\n     " : "") << "\"" << dataPath << "\" index "
             << panel.blocks[b].second << " using 1:2 with linespoints linetype "
             << panel.blocks[b].first + 1 << " title \""
             << curveTitle(curve, iterations.size() > 1, substeps.size() > 1, threads.size() > 1)
             << "\"";
    }
    script << "\n";
  }
  script << "unset multiplot\n";
  script.close();

  const std::string command = "gnuplot \"" + scriptPath + "\"";
  if (std::system(command.c_str()) != 0) {
    std::fprintf(stderr, "gnuplot failed on %s\n", scriptPath.c_str());
    return false;
  }
  return true;
}

}  // namespace

void writeTsvHeader(std::ostream& out) {
  out << "scene\tengine\tvariant\tdt\tsubsteps\titerations\tthreads\twall_s_per_sim_s\tmetric\tvalue\n";
}

void writeTsvRow(std::ostream& out, const ResultRow& row) {
  out << row.scene << '\t' << row.engine << '\t' << row.variant << '\t' << formatNumber(row.dt)
      << '\t' << row.substeps << '\t' << row.iterations << '\t' << row.threads << '\t'
      << formatNumber(row.wallSecondsPerSimSecond) << '\t' << row.metric << '\t'
      << formatNumber(row.value) << '\n';
}

bool writePlots(const std::vector<ResultRow>& rows, const std::string& dir) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::fprintf(stderr, "gnuplot not found: no plots written (install gnuplot-nox)\n");
    return false;
  }
  std::vector<std::string> scenes;
  for (const ResultRow& row : rows) indexOf(scenes, row.scene);
  bool allDrawn = true;
  for (const std::string& scene : scenes) {
    std::vector<const ResultRow*> sceneRows;
    for (const ResultRow& row : rows) {
      if (row.scene == scene) sceneRows.push_back(&row);
    }
    allDrawn = plotScene(scene, sceneRows, dir) && allDrawn;
  }
  return allDrawn;
}

}  // namespace pfxbench
