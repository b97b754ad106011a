#include "osdmra/base/bundled_data.h"

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "osdmra/base/error.h"

#ifndef OSDMRA_DATA_DIR
#define OSDMRA_DATA_DIR ""
#endif
#ifndef OSDMRA_INSTALL_DATA_DIR
#define OSDMRA_INSTALL_DATA_DIR ""
#endif

namespace osdmra {

std::string bundledDataPath(const std::string& name) {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("OSDMRA_DATA")) dirs.push_back(env);
  dirs.push_back(OSDMRA_DATA_DIR);
  dirs.push_back(OSDMRA_INSTALL_DATA_DIR);
  for (const std::string& d : dirs) {
    if (d.empty()) continue;
    const std::filesystem::path p = std::filesystem::path(d) / name;
    if (std::filesystem::exists(p)) return p.string();
  }
  throw Error("cannot find the bundled file " + name +
              " (set OSDMRA_DATA to the data/ directory of the osdmra sources)");
}

}  // namespace osdmra
