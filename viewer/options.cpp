#include "options.h"

#include <cstdio>

#include "args.h"
#include "osdmra/base/error.h"
#include "remesh_flags.h"

namespace viewer {

const char* const kUsage =
    "usage: osdmra-viewer [MESH] [options]\n"
    "\n"
    "Shows levels of detail of MESH (a triangle mesh with subdivision connectivity;\n"
    "default: the bundled igea-oct6.obj) beside the full-resolution surface.\n"
    "\n"
    "  --budget N          triangle budget of the level of detail (default 4054)\n"
    "  --epsilon E         keep coefficients of importance >= E instead of a budget\n"
    "  --scheme S          loop (default) or linear (polyhedral)\n"
    "  --rings R           quasi-wavelet rings, 0..4 (default 1)\n"
    "  --placement P       surface (default), fit, closest or levels (fitted once per\n"
    "                      level during the analysis: as fast to re-extract as surface);\n"
    "                      the fitted ones move vertices off the surface to bring the\n"
    "                      faces closer, so --color error (a vertex's distance) is warmer\n"
    "  --remesh            MESH has no subdivision connectivity: remesh it first\n"
    "                      (osdmra remesh) with --base-faces N (default 300),\n"
    "                      --levels J (default 5) and --feature-angle A (default 70);\n"
    "                      --min-component-faces F drops components under F faces;\n"
    "                      --max-faces N splits a base larger than asked fewer times;\n"
    "                      --smoothing-sweeps S (default 10, 0: none) evens the sampling;\n"
    "                      --stages vertex|auto|mesh, --retriangulation error|shape: how\n"
    "                      close to MESH the base is (defaults as lod's: vertex, error)\n"
    "                      --samples N: samples a side of the distance to MESH it\n"
    "                      reports (default 100000), --seed S their seed (default 1)\n"
    "  --view V            front (default), side, top or iso\n"
    "  --color C           plain (default), level or error\n"
    "  --error-scale P     error colouring: red at P percent of the diagonal (default 0.2)\n"
    "  --layout L          split (default: original left, level of detail right) or lod\n"
    "  --wireframe         draw the edges over the surface\n"
    "  --smooth            draw the truncated surface as Loop limit patches (OpenSubdiv)\n"
    "  --tess L            tessellation level of the smooth mode, 1..32 (default 1)\n"
    "  --smooth-level J    control mesh level of the smooth mode (default: finest)\n"
    "  --screenshot OUT    headless: render to the PNG OUT and exit\n"
    "  --size WxH          headless image size (default 1200x600; with --bench-slider\n"
    "                      the window size, default 1600x900 as the interactive one)\n"
    "  --bench-slider K    headless: after the analysis, move the triangle slider through\n"
    "                      K log-spaced values up to all triangles and back, as a drag,\n"
    "                      and report the frame times (extraction, upload, draw); exit\n"
    "  --json              with --bench-slider: one JSON object, with every step\n"
    "  --no-pane-cache     redraw the original's pane every frame instead of keeping it\n"
    "                      as an image while the camera and display options are unchanged\n"
    "\n"
    "Interactive: drag to rotate, right-drag to pan, wheel to zoom, P saves a PNG,\n"
    "Esc quits.\n";

namespace {

using osdmra::Error;

ColorMode parseColor(const std::string& s) {
  if (s == "plain") return ColorMode::Plain;
  if (s == "level") return ColorMode::Level;
  if (s == "error") return ColorMode::Value;
  throw Error("--color must be plain, level or error, got '" + s + "'");
}

void parseSize(const std::string& s, Options& o) {
  int w = 0, h = 0;
  char extra = 0;
  if (std::sscanf(s.c_str(), "%dx%d%c", &w, &h, &extra) != 2 || w < 16 || h < 16 || w > 8192 ||
      h > 8192)
    throw Error("--size needs WxH with 16..8192 pixels each, got '" + s + "'");
  o.width = w, o.height = h;
}

// What the analysis is and which level of detail is shown.
void parseAnalysis(const osdmra::cli::Args& args, Options& o) {
  if (args.has("budget") && args.has("epsilon"))
    throw Error("give --budget or --epsilon, not both");
  if (args.has("epsilon")) {
    o.selection.kind = Selection::Epsilon;
    o.selection.epsilon = args.real("epsilon", 0, 0, 1e300);
  }
  o.selection.budget = args.integer("budget", o.selection.budget, 1, 1LL << 40);
  o.request.scheme = osdmra::parseScheme(args.get("scheme", "loop"));
  o.request.rings = static_cast<int>(args.integer("rings", o.request.rings, 0, 4));
  o.request.placement = osdmra::parsePlacement(args.get("placement", "surface"));
  osdmra::InputOptions& in = o.request.input;
  in.remesh = args.has("remesh");
  in.remeshing = osdmra::cli::remeshOptions(args, true);  // as lod's
  in.distance = osdmra::cli::distanceOptions(args);
  in.minComponentFaces =
      static_cast<int>(args.integer("min-component-faces", in.minComponentFaces, 0, 1 << 30));
}

// How it is drawn.
void parseDisplay(const osdmra::cli::Args& args, Options& o) {
  const std::string view = args.get("view", "front");
  if (!parseView(view, o.view))
    throw Error("--view must be front, side, top or iso, got '" + view + "'");
  o.color = parseColor(args.get("color", "plain"));
  o.errorPercent = args.real("error-scale", o.errorPercent, 0, 1e300);
  if (!(o.errorPercent > 0)) throw Error("--error-scale needs a positive percentage");
  const std::string layout = args.get("layout", "split");
  if (layout != "split" && layout != "lod")
    throw Error("--layout must be split or lod, got '" + layout + "'");
  o.draw.split = layout == "split";
  o.draw.wireframe = args.has("wireframe");
  o.draw.smooth = args.has("smooth");
  o.draw.tessLevel = static_cast<float>(args.integer("tess", 1, 1, 32));
  o.smoothLevel = static_cast<int>(args.integer("smooth-level", -1, 0, 15));
  o.draw.cacheReference = !args.has("no-pane-cache");
}

// Headless modes: a screenshot, or the slider benchmark.
void parseHeadless(const osdmra::cli::Args& args, Options& o) {
  if (args.has("screenshot")) {
    o.screenshot = args.get("screenshot");
    if (o.screenshot.empty()) throw Error("--screenshot needs a file name");
  }
  o.benchSteps = static_cast<int>(args.integer("bench-slider", 0, 2, 100000));
  o.json = args.has("json");
  if (o.benchSteps && !o.screenshot.empty())
    throw Error("--bench-slider and --screenshot cannot be combined");
  if (o.json && !o.benchSteps) throw Error("--json needs --bench-slider");
  if (o.benchSteps && o.selection.kind == Selection::Epsilon)
    throw Error("--bench-slider moves the triangle slider; --epsilon does not apply");
  if (args.has("size"))
    parseSize(args.get("size"), o);
  else if (o.benchSteps)
    o.width = 1600, o.height = 900;
}

}  // namespace

Options parseOptions(const std::vector<std::string>& argv) {
  const osdmra::cli::Args args(
      "", argv,
      osdmra::cli::withRemeshOptions({"budget", "epsilon", "scheme", "rings", "placement", "levels",
                                      "view", "color", "error-scale", "layout", "tess",
                                      "smooth-level", "screenshot", "size", "bench-slider",
                                      "samples", "seed"}),
      {"remesh", "wireframe", "smooth", "json", "no-pane-cache", "help", "h"},
      "osdmra-viewer --help");
  Options o;
  o.help = args.has("help") || args.has("h");
  if (args.positional().size() > 1)
    throw Error("more than one mesh given ('" + args.positional()[0] + "' and '" +
                args.positional()[1] + "')");
  if (!args.positional().empty()) o.mesh = args.positional()[0];
  parseAnalysis(args, o);
  parseDisplay(args, o);
  parseHeadless(args, o);
  return o;
}

}  // namespace viewer
