#include "osdmra/mesh/detail/text.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <system_error>

namespace osdmra::detail {

bool hostIsLittleEndian() {
  const std::uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

/// "source:line: ", the prefix of every text-format message.
std::string at(const std::string& source, long long line) {
  return source + ":" + std::to_string(line) + ": ";
}

/// A token quoted for an error message: garbage input must not put control bytes
/// or megabytes of text into what() -- truncate and escape.
std::string quote(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string q = "'";
  for (std::size_t i = 0; i < s.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      q += static_cast<char>(c);
    } else {
      static const char* hex = "0123456789abcdef";
      q += "\\x";
      q += hex[c >> 4];
      q += hex[c & 15];
    }
  }
  if (s.size() > kMax) q += "...";
  return q + "'";
}

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > begin) tokens.push_back(line.substr(begin, i - begin));
  }
}

/// Drops a '#' comment (OBJ, OFF).
std::string_view stripComment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

/// from_chars rejects a leading '+', which text writers do emit; accept one.
bool stripPlus(std::string_view& s) {
  if (!s.empty() && s[0] == '+') {
    s.remove_prefix(1);
    if (s.empty() || s[0] == '+' || s[0] == '-') return false;
  }
  return !s.empty();
}

/// Locale-independent, exact (correctly rounded) decimal parsing. Accepts "nan"
/// and "inf" so that callers can say "not finite" instead of "not a number".
bool parseDouble(std::string_view s, double& value) {
  if (!stripPlus(s)) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return ec == std::errc() && end == s.data() + s.size();
}

bool parseInt(std::string_view s, long long& value) {
  if (!stripPlus(s)) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  return ec == std::errc() && end == s.data() + s.size();
}

/// Bytes left in a seekable stream, or nothing (pipes): the bound that keeps a
/// corrupt header's counts from turning into giant allocations.
std::optional<std::uint64_t> remainingBytes(std::istream& in) {
  if (!in.good()) return std::nullopt;
  const std::streampos here = in.tellg();
  if (here == std::streampos(-1)) return std::nullopt;
  in.seekg(0, std::ios::end);
  const std::streampos end = in.tellg();
  in.clear();
  in.seekg(here);
  if (end == std::streampos(-1) || end < here || !in) {
    in.clear();
    return std::nullopt;
  }
  return static_cast<std::uint64_t>(end - here);
}

/// Reservation for `declared` items that cannot exceed what the input can hold.
std::size_t safeReserve(std::uint64_t declared, const std::optional<std::uint64_t>& remaining) {
  const std::uint64_t cap = remaining ? *remaining : (std::uint64_t(1) << 16);
  return static_cast<std::size_t>(std::min(declared, cap));
}

bool LineReader::next(std::string& line) {
  if (!std::getline(in_, line)) {
    if (in_.bad()) fail("read error");
    return false;
  }
  ++line_;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  // Windows editors may start a text file with a UTF-8 byte order mark.
  if (line_ == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
  return true;
}

/// Copies flat xyz triples into an n x 3 matrix.
Points toPoints(const std::vector<double>& flat) {
  Points P(static_cast<Eigen::Index>(flat.size() / 3), 3);
  std::copy(flat.begin(), flat.end(), P.data());
  return P;
}

Faces toFaces(const std::vector<int>& flat) {
  Faces F(static_cast<Eigen::Index>(flat.size() / 3), 3);
  std::copy(flat.begin(), flat.end(), F.data());
  return F;
}

bool allFinite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); });
}

void requireNotEmpty(std::istream& in, const std::string& source) {
  if (in.peek() == std::char_traits<char>::eof()) {
    if (in.bad()) fail(source + ": read error");
    fail(source + ": file is empty");
  }
}

}  // namespace osdmra::detail
