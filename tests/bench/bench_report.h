// The benchmark's output: TSV rows (one per run and metric) and, per scene, a gnuplot
// script and the PNG it draws of error against wall time, log-log, one curve per engine.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace pfxbench {

struct ResultRow {
  std::string scene;
  std::string engine;
  std::string variant;
  double dt = 0;
  int substeps = 1;
  int iterations = 1;
  int threads = 1;
  double wallSecondsPerSimSecond = 0;
  std::string metric;
  double value = 0;
};

void writeTsvHeader(std::ostream& out);
void writeTsvRow(std::ostream& out, const ResultRow& row);

// Writes DIR/<scene>.dat, DIR/<scene>.gp and runs gnuplot on the latter for every scene
// in `rows`. Says on stderr what it could not draw; false if gnuplot is missing or failed.
bool writePlots(const std::vector<ResultRow>& rows, const std::string& dir);

}  // namespace pfxbench
