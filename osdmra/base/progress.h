// Progress reporting for long work: the library calls it, front ends draw it.
#pragma once

#include <functional>

namespace osdmra {

/// Called with a short stage name and the fraction done in [0, 1]. May be empty.
using Progress = std::function<void(const char* stage, double fraction)>;

}  // namespace osdmra
