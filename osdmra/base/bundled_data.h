// Where the bundled data (data/ in the sources, share/osdmra when installed) is.
#pragma once

#include <string>

namespace osdmra {

/// Path of a bundled file, e.g. "igea-oct6.obj" (the default mesh of the demo and
/// the viewer): looked up in $OSDMRA_DATA, then the source tree's data/, then the
/// installed share/osdmra. Throws Error naming the file when it is in none of them.
std::string bundledDataPath(const std::string& name = "igea-oct6.obj");

}  // namespace osdmra
