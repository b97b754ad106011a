// The viewer in a window on screen.
#pragma once

#include "options.h"

namespace viewer {

/// Opens the window and runs until it is closed (Esc).
int interactive(const Options& o);

}  // namespace viewer
