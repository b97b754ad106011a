// A small JSON writer for the CLI's --json summaries: ordered keys, numbers written
// to round-trip, strings escaped. Output only; osdmra never parses JSON.
#pragma once

#include <charconv>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace osdmra::cli {

class Json {
 public:
  static Json object() { return Json('{'); }
  static Json array() { return Json('['); }

  Json& add(const std::string& key, const Json& value) { return raw(key, value.str()); }
  Json& add(const std::string& key, const std::string& value) { return raw(key, quote(value)); }
  Json& add(const std::string& key, const char* value) { return raw(key, quote(value)); }
  Json& add(const std::string& key, bool value) { return raw(key, value ? "true" : "false"); }
  Json& add(const std::string& key, double value) { return raw(key, number(value)); }
  Json& add(const std::string& key, long long value) { return raw(key, std::to_string(value)); }
  Json& add(const std::string& key, int value) { return raw(key, std::to_string(value)); }
  // Array elements.
  Json& push(const Json& value) { return raw("", value.str()); }
  Json& push(double value) { return raw("", number(value)); }
  Json& push(long long value) { return raw("", std::to_string(value)); }
  Json& push(int value) { return raw("", std::to_string(value)); }
  Json& push(const std::string& value) { return raw("", quote(value)); }

  std::string str() const { return open_ + body_ + (open_ == '{' ? '}' : ']'); }

  static std::string quote(const std::string& s) {
    std::string out = "\"";
    for (unsigned char c : s) {
      switch (c) {
        case '"':
          out += "\\\"";
          break;
        case '\\':
          out += "\\\\";
          break;
        case '\n':
          out += "\\n";
          break;
        case '\t':
          out += "\\t";
          break;
        case '\r':
          out += "\\r";
          break;
        default:
          if (c < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
          } else {
            out += static_cast<char>(c);
          }
      }
    }
    return out + "\"";
  }
  static std::string number(double v) {
    if (!std::isfinite(v)) return "null";  // JSON has no inf or nan
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
  }

 private:
  explicit Json(char open) : open_(open) {}
  Json& raw(const std::string& key, const std::string& value) {
    if (!body_.empty()) body_ += ", ";
    if (open_ == '{') body_ += quote(key) + ": ";
    body_ += value;
    return *this;
  }
  char open_;
  std::string body_;
};

}  // namespace osdmra::cli
