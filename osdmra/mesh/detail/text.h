// Helpers shared by the mesh readers (obj.cpp, off.cpp, ply.cpp): tokenising,
// exact number parsing, line counting, and the bounds that keep hostile input from
// turning into giant allocations. Internal: not installed.
#pragma once

#include <cstdint>
#include <istream>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/mesh/mesh.h"

namespace osdmra::detail {

/// Largest vertex index a file may use (Faces holds int).
constexpr long long kMaxIndex = std::numeric_limits<int>::max();

[[noreturn]] inline void fail(const std::string& message) {
  throw Error(message);
}

bool hostIsLittleEndian();

/// "source:line: ", the prefix of every text-format message.
std::string at(const std::string& source, long long line);

/// A token quoted for an error message: garbage input must not put control bytes
/// or megabytes of text into what() -- truncated and escaped.
std::string quote(std::string_view s);

bool isSpace(char c);
/// Splits a line at white space into `tokens` (views into `line`).
void tokenize(std::string_view line, std::vector<std::string_view>& tokens);
/// Drops a '#' comment (OBJ, OFF).
std::string_view stripComment(std::string_view line);

/// Locale-independent, exact (correctly rounded) decimal parsing. Accepts "nan"
/// and "inf" so that callers can say "not finite" instead of "not a number".
bool parseDouble(std::string_view s, double& value);
bool parseInt(std::string_view s, long long& value);

/// Bytes left in a seekable stream, or nothing (pipes): the bound that keeps a
/// corrupt header's counts from turning into giant allocations.
std::optional<std::uint64_t> remainingBytes(std::istream& in);
/// Reservation for `declared` items that cannot exceed what the input can hold.
std::size_t safeReserve(std::uint64_t declared, const std::optional<std::uint64_t>& remaining);

/// Line-by-line reader that counts lines and strips a trailing '\r' (CRLF files).
class LineReader {
 public:
  explicit LineReader(std::istream& in, long long firstLine = 0) : in_(in), line_(firstLine) {}
  bool next(std::string& line);
  long long line() const { return line_; }

 private:
  std::istream& in_;
  long long line_;
};

/// Flat xyz triples (or index triples) as an n x 3 matrix.
Points toPoints(const std::vector<double>& flat);
Faces toFaces(const std::vector<int>& flat);
bool allFinite(const std::vector<double>& values);
/// Throws "source: file is empty" (or a read error) before any parsing.
void requireNotEmpty(std::istream& in, const std::string& source);

}  // namespace osdmra::detail
