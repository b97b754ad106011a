// Command-line arguments of osdmra's front ends (the osdmra tool's subcommands and
// osdmra-viewer): positionals plus --options, each option declared with whether it
// takes a value. Anything undeclared, missing or malformed is an Error that names
// the option.
#pragma once

#include <charconv>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "osdmra/base/error.h"

namespace osdmra::cli {

class Args {
 public:
  /// `valued`: options that take a value; `flags`: options that do not. Messages
  /// start with "command: " (nothing when `command` is empty) and send the user to
  /// `help` (default: "osdmra <command> --help").
  Args(const std::string& command, const std::vector<std::string>& argv,
       const std::set<std::string>& valued, const std::set<std::string>& flags,
       const std::string& help = "")
      : command_(command.empty() ? "" : command + ": "),
        help_(help.empty() ? "osdmra " + command + " --help" : help) {
    for (std::size_t i = 0; i < argv.size(); ++i) {
      const std::string& a = argv[i];
      const bool isLong = a.size() > 2 && a.compare(0, 2, "--") == 0;
      const bool isShort = a.size() == 2 && a[0] == '-' && a[1] != '-';
      if (isLong || isShort) {
        std::string name = a.size() == 2 ? a.substr(1) : a.substr(2);
        std::string value;
        const auto eq = name.find('=');
        const bool inlineValue = eq != std::string::npos;
        if (inlineValue) {
          value = name.substr(eq + 1);
          name = name.substr(0, eq);
        }
        if (name == "o") name = "output";
        if (valued.count(name)) {
          if (!inlineValue) {
            if (i + 1 >= argv.size()) throw Error(command_ + "option --" + name + " needs a value");
            value = argv[++i];
          }
          values_[name] = value;
        } else if (flags.count(name) && !inlineValue) {
          values_[name] = "";
        } else {
          throw Error(command_ + "unknown option '" + a + "' (see " + help_ + ")");
        }
      } else {
        positional_.push_back(a);
      }
    }
  }

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  const std::vector<std::string>& positional() const { return positional_; }

  std::string get(const std::string& name, const std::string& fallback = "") const {
    auto it = values_.find(name);
    return it == values_.end() ? fallback : it->second;
  }
  std::string require(const std::string& name) const {
    if (!has(name)) throw Error(command_ + "missing required option --" + name);
    return get(name);
  }
  long long integer(const std::string& name, long long fallback, long long lo, long long hi) const {
    if (!has(name)) return fallback;
    const std::string s = get(name);
    long long v = 0;
    auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size())
      throw Error(command_ + "--" + name + " expects an integer, got '" + s + "'");
    if (v < lo || v > hi)
      throw Error(command_ + "--" + name + " must be in " + std::to_string(lo) + ".." +
                  std::to_string(hi) + ", got " + s);
    return v;
  }
  double real(const std::string& name, double fallback, double lo, double hi) const {
    if (!has(name)) return fallback;
    const std::string s = get(name);
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (...) {
      used = 0;
    }
    if (used != s.size() || s.empty() || !(v == v))
      throw Error(command_ + "--" + name + " expects a number, got '" + s + "'");
    if (v < lo || v > hi)
      throw Error(command_ + "--" + name + " must be in [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "], got " + s);
    return v;
  }
  /// Exactly `n` positional arguments, described by `what` for the message.
  void expectPositional(std::size_t n, const std::string& what) const {
    if (positional_.size() != n)
      throw Error(command_ + "expected " + what + " (got " + std::to_string(positional_.size()) +
                  " positional arguments)");
  }

 private:
  std::string command_, help_;
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
};

/// A library message with the library's option names (RemeshOptions::baseFaces, ...)
/// replaced by the front ends' flags (--base-faces, ...).
inline std::string withFlagNames(std::string message) {
  static const std::pair<const char*, const char*> names[] = {
      {"RemeshOptions::baseFaces", "--base-faces"},
      {"RemeshOptions::levels", "--levels"},
      {"RemeshOptions::featureAngle", "--feature-angle"},
      {"RemeshOptions::maxFaces", "--max-faces"},
      {"InputOptions::minComponentFaces", "--min-component-faces"},
      {"AnalysisOptions::levels", "--levels"},
  };
  for (const auto& [option, flag] : names)
    for (std::size_t at = message.find(option); at != std::string::npos;
         at = message.find(option, at))
      message.replace(at, std::char_traits<char>::length(option), flag);
  return message;
}

}  // namespace osdmra::cli
