// The viewer without a window on screen (still an X display; Xvfb will do).
#pragma once

#include "options.h"

namespace viewer {

/// Renders o.mesh's level of detail to the PNG o.screenshot and prints what it shows.
int headless(const Options& o);

/// What a frame costs while the triangle slider is dragged (--bench-slider).
int benchSlider(const Options& o);

}  // namespace viewer
