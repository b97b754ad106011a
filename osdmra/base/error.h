// osdmra::Error: the one exception type of the library.
//
// Every failure the library reports -- malformed input, inconsistent topology, a
// singular refinement block -- is an Error whose message names where it happened
// (file and line, element, level) and what is wrong. Front ends catch it and print
// what(); nothing in the library prints or exits by itself.
#pragma once

#include <stdexcept>
#include <string>

namespace osdmra {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace osdmra
