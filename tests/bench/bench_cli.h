// The command line of pfx_bench. Every option takes a comma-separated list, so that a
// sweep over iterations, sub-steps or threads is as easy as one over time steps.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace pfxbench {

struct Options {
  std::vector<std::string> scenes;   // empty: every scene
  std::vector<std::string> engines;  // empty: every engine that was built
  std::vector<double> timeSteps{1.0 / 30, 1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960};
  // Whether --dt was given: scenes with a time step of their own (characters, rope, cloth)
  // keep it unless it was.
  bool timeStepsGiven = false;
  std::vector<int> iterations{10};
  std::vector<int> substeps{1};
  std::vector<int> threads{1};
  double seconds = 0;  // 0: each scene's own duration
  std::vector<int> characterCounts{100, 1000};  // the characters scene's runs
  std::string outDir;  // empty: TSV on stdout only
  // Runs that differ only in their number of threads must end in bit-identical states;
  // a run that does not fails the benchmark.
  bool sameBits = false;
  // --limit: a run whose figure of the named metric is above the bound, or not a number
  // (a run that blew up), fails the benchmark.
  std::vector<std::pair<std::string, double>> limits;
  bool help = false;
};

const char* usage();

// False with a message for anything it cannot read (unknown option, bad number).
bool parseOptions(int argc, const char* const* argv, Options& options, std::string& error);

}  // namespace pfxbench
