// osdmra-viewer's command line: what to show and how, parsed by the same argument
// helper as the osdmra tool (cli/args.h).
#pragma once

#include <string>

#include "app.h"
#include "camera.h"
#include "renderer.h"

namespace viewer {

extern const char* const kUsage;

struct Options {
  std::string mesh;  ///< empty: the bundled head
  Selection selection;
  AnalysisRequest request;
  View view = View::Front;
  DrawSettings draw;
  ColorMode color = ColorMode::Plain;
  double errorPercent = 0.2;
  int smoothLevel = -1;
  std::string screenshot;
  int width = 1200, height = 600;
  int benchSteps = 0;  ///< --bench-slider K; 0: not benchmarking
  bool json = false;
  bool help = false;
};

/// Parses the arguments after the program name; throws osdmra::Error naming the
/// option that is wrong.
Options parseOptions(const std::vector<std::string>& argv);

}  // namespace viewer
