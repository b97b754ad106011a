// osdmra-viewer: levels of detail of a wavelet-analysed subdivision surface, drawn
// beside the original at the same projected size (the paper's Figures 8-10).
//
//   osdmra-viewer [MESH] [options]                 interactive (interactive.cpp)
//   osdmra-viewer [MESH] --screenshot OUT.png ...  headless: render, write, exit
//   osdmra-viewer [MESH] --bench-slider K ...      headless: time a slider drag
//                                                  (both in headless.cpp)
//
// This file only starts up: options (options.cpp), the default mesh, the mode.
// Errors from anywhere are printed as "osdmra-viewer: <message>" with exit 1.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "allocator.h"
#include "args.h"
#include "headless.h"
#include "interactive.h"
#include "options.h"
#include "osdmra/base/bundled_data.h"
#include "osdmra/base/error.h"

int main(int argc, char** argv) {
  osdmra::cli::keepFreedMemory();
  try {
    viewer::Options o = viewer::parseOptions(std::vector<std::string>(argv + 1, argv + argc));
    if (o.help) {
      std::fputs(viewer::kUsage, stdout);
      return 0;
    }
    if (o.mesh.empty()) o.mesh = osdmra::bundledDataPath();
    o.request.path = o.mesh;
    if (o.benchSteps) return viewer::benchSlider(o);
    return o.screenshot.empty() ? viewer::interactive(o) : viewer::headless(o);
  } catch (const osdmra::Error& e) {
    std::fprintf(stderr, "osdmra-viewer: %s\n", osdmra::cli::withFlagNames(e.what()).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "osdmra-viewer: %s\n", e.what());
  }
  return 1;
}
