#include "osdmra/io.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <istream>
#include <limits>
#include <optional>
#include <ostream>
#include <random>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "osdmra/error.h"

namespace osdmra {
namespace {

constexpr long long kMaxIndex = std::numeric_limits<int>::max();

// ---- Text helpers --------------------------------------------------------------

[[noreturn]] void fail(const std::string& message) {
  throw Error(message);
}

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

/// Line-by-line reader that counts lines and strips a trailing '\r' (CRLF files).
class LineReader {
 public:
  explicit LineReader(std::istream& in, long long firstLine = 0) : in_(in), line_(firstLine) {}

  bool next(std::string& line) {
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
  long long line() const { return line_; }

 private:
  std::istream& in_;
  long long line_;
};

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

// ---- OBJ -----------------------------------------------------------------------

// Statements that carry nothing osdmra needs (texture coordinates, grouping,
// materials, display attributes, points and polylines).
bool isIgnoredObjStatement(std::string_view k) {
  static const char* const ignored[] = {
      "vt",         "vp",        "l",      "p",      "g",     "o",        "s",        "mg",
      "usemtl",     "mtllib",    "usemap", "maplib", "bevel", "c_interp", "d_interp", "lod",
      "shadow_obj", "trace_obj", "ctech",  "stech",  "call",  "csh"};
  return std::any_of(std::begin(ignored), std::end(ignored), [&](const char* s) { return k == s; });
}

// Free-form geometry cannot be dropped silently: the mesh would lose surfaces.
bool isFreeFormObjStatement(std::string_view k) {
  static const char* const freeForm[] = {"cstype", "deg",  "bmat", "step", "curv", "curv2", "surf",
                                         "parm",   "trim", "hole", "scrv", "sp",   "end",   "con"};
  return std::any_of(std::begin(freeForm), std::end(freeForm),
                     [&](const char* s) { return k == s; });
}

/// Resolves one OBJ index (1-based, or negative = relative to the `count` elements
/// read so far) to 0-based. Positive indices may refer forward; the caller checks
/// them against the final count.
long long resolveObjIndex(std::string_view token, long long count, const char* what,
                          const std::string& source, long long line) {
  const auto where = [&] { return at(source, line); };  // error path only
  long long i = 0;
  if (!parseInt(token, i)) fail(where() + "bad " + what + " index " + quote(token));
  if (i == 0) fail(where() + what + " index 0 is invalid (OBJ indices start at 1)");
  const long long resolved = i > 0 ? i - 1 : count + i;
  if (resolved < 0)
    fail(where() + "relative " + what + " index " + std::to_string(i) +
         " reaches before the first " + what + " (only " + std::to_string(count) +
         " defined so far)");
  if (resolved >= kMaxIndex) fail(where() + what + " index " + std::to_string(i) + " is too large");
  return resolved;
}

}  // namespace

TriMesh readObj(std::istream& in, const std::string& source) {
  requireNotEmpty(in, source);
  std::vector<double> V, VN;
  std::vector<int> F, cornerNormal;  // cornerNormal: normal index per corner, -1 if none
  // Faces whose indices point past what was defined at their line (forward
  // references, rare but legal) are checked once the whole file is read.
  std::vector<std::pair<std::size_t, long long>> forwardRefs;  // (face, line)
  long long numTexCoords = 0;

  LineReader lines(in);
  std::string line, continued;
  std::vector<std::string_view> tokens;
  while (lines.next(line)) {
    const long long lineNo = lines.line();
    // A trailing backslash continues the statement on the next line.
    while (!line.empty() && line.back() == '\\' && lines.next(continued)) {
      line.back() = ' ';
      line += continued;
    }
    tokenize(stripComment(line), tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    // Built only on the error path: one allocation per line would be measurable.
    const auto where = [&] { return at(source, lineNo); };

    if (key == "v" || key == "vn") {
      const bool isNormal = key == "vn";
      if (tokens.size() < 4)
        fail(where() + (isNormal ? "normal" : "vertex") + " needs 3 coordinates, found " +
             std::to_string(tokens.size() - 1));
      std::array<double, 3> xyz{};
      for (std::size_t i = 1; i < tokens.size(); ++i) {
        double value = 0;
        if (!parseDouble(tokens[i], value)) fail(where() + quote(tokens[i]) + " is not a number");
        if (i <= 3) xyz[i - 1] = value;
      }
      if (isNormal) {
        VN.insert(VN.end(), xyz.begin(), xyz.end());
        continue;
      }
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(xyz[k]))
          fail(where() + "vertex has a non-finite coordinate " + quote(tokens[k + 1]));
      if (V.size() / 3 >= static_cast<std::size_t>(kMaxIndex)) fail(where() + "too many vertices");
      V.insert(V.end(), xyz.begin(), xyz.end());
    } else if (key == "f") {
      const std::size_t n = tokens.size() - 1;
      if (n > 3)
        fail(where() + "face has " + std::to_string(n) +
             " vertices; osdmra needs triangles (triangulate the mesh first)");
      if (n < 3) fail(where() + "face has " + std::to_string(n) + " vertices; a face needs 3");
      const long long numV = static_cast<long long>(V.size() / 3);
      const long long numN = static_cast<long long>(VN.size() / 3);
      const std::size_t face = F.size() / 3;
      if (face >= static_cast<std::size_t>(kMaxIndex / 3)) fail(where() + "too many faces");
      bool forward = false;
      for (std::size_t c = 1; c <= 3; ++c) {
        // Corner forms: v, v/t, v/t/n, v//n.
        std::array<std::string_view, 3> parts{};
        std::size_t numParts = 0;
        std::string_view rest = tokens[c];
        while (true) {
          const std::size_t slash = rest.find('/');
          if (numParts == 3) fail(where() + "bad face corner " + quote(tokens[c]));
          parts[numParts++] = rest.substr(0, slash);
          if (slash == std::string_view::npos) break;
          rest.remove_prefix(slash + 1);
        }
        if (parts[0].empty()) fail(where() + "bad face corner " + quote(tokens[c]));
        const long long v = resolveObjIndex(parts[0], numV, "vertex", source, lineNo);
        forward = forward || v >= numV;
        if (numParts >= 2 && !parts[1].empty())
          resolveObjIndex(parts[1], numTexCoords, "texture", source, lineNo);  // syntax only
        long long vn = -1;
        if (numParts == 3 && !parts[2].empty()) {
          vn = resolveObjIndex(parts[2], numN, "normal", source, lineNo);
          forward = forward || vn >= numN;
        }
        F.push_back(static_cast<int>(v));
        cornerNormal.push_back(static_cast<int>(vn));
      }
      if (forward) forwardRefs.emplace_back(face, lineNo);
    } else if (key == "vt") {
      ++numTexCoords;
    } else if (isIgnoredObjStatement(key)) {
      continue;
    } else if (isFreeFormObjStatement(key)) {
      fail(where() + "free-form geometry (" + quote(key) + ") is not supported; export triangles");
    } else {
      fail(where() + "unknown OBJ statement " + quote(key));
    }
  }

  const long long numV = static_cast<long long>(V.size() / 3);
  const long long numN = static_cast<long long>(VN.size() / 3);
  for (const auto& [face, lineNo] : forwardRefs)
    for (std::size_t c = 3 * face; c < 3 * face + 3; ++c) {
      if (F[c] >= numV)
        fail(at(source, lineNo) + "face refers to vertex " + std::to_string(F[c] + 1) +
             " but the file has only " + std::to_string(numV) + " vertices");
      if (cornerNormal[c] >= numN)
        fail(at(source, lineNo) + "face refers to normal " + std::to_string(cornerNormal[c] + 1) +
             " but the file has only " + std::to_string(numN) + " normals");
    }

  TriMesh mesh;
  mesh.V = toPoints(V);
  mesh.F = toFaces(F);
  // Per-vertex normals exist only if every corner names one and each vertex always
  // names the same one (split normals at creases have no per-vertex form).
  if (numN > 0 && numV > 0) {
    std::vector<int> normalOf(static_cast<std::size_t>(numV), -1);
    bool ok = true;
    for (std::size_t c = 0; c < F.size() && ok; ++c) {
      int& n = normalOf[static_cast<std::size_t>(F[c])];
      ok = cornerNormal[c] >= 0 && (n < 0 || n == cornerNormal[c]);
      n = cornerNormal[c];
    }
    ok = ok && std::find(normalOf.begin(), normalOf.end(), -1) == normalOf.end();
    if (ok) {
      Points N(numV, 3);
      for (Eigen::Index v = 0; v < numV; ++v)
        for (int k = 0; k < 3; ++k) N(v, k) = VN[3 * static_cast<std::size_t>(normalOf[v]) + k];
      if (N.allFinite()) mesh.N = std::move(N);
    }
  }
  return mesh;
}

// ---- OFF -----------------------------------------------------------------------

TriMesh readOff(std::istream& in, const std::string& source) {
  requireNotEmpty(in, source);
  LineReader lines(in);
  std::string line;
  std::vector<std::string_view> tokens;
  // Next line with content, comments removed; false at end of file.
  const auto nextContent = [&] {
    while (lines.next(line)) {
      tokenize(stripComment(line), tokens);
      if (!tokens.empty()) return true;
    }
    return false;
  };
  if (!nextContent()) fail(source + ": file has no content (only comments or blank lines)");

  // Header keyword: [ST][C][N][4][n]OFF; the keyword itself is optional.
  bool hasNormals = false;
  std::vector<std::string_view> counts;
  long long dummy = 0;
  const std::string_view key = tokens[0];
  if (parseInt(key, dummy)) {
    counts = tokens;  // no keyword: the counts come first
  } else {
    std::size_t p = 0;
    if (key.substr(p, 2) == "ST") p += 2;
    if (key.substr(p, 1) == "C") p += 1;
    if (key.substr(p, 1) == "N") {
      hasNormals = true;
      p += 1;
    }
    if (key.substr(p, 1) == "4" || key.substr(p, 1) == "n")
      fail(at(source, lines.line()) + quote(key) + ": only 3-dimensional OFF files are supported");
    if (key.substr(p, 3) != "OFF")
      fail(at(source, lines.line()) + "not an OFF file: expected an 'OFF' header, found " +
           quote(key));
    // Some exporters glue the counts to the keyword ("OFF8 12 0"); accept that.
    if (key.size() > p + 3) counts.push_back(key.substr(p + 3));
    counts.insert(counts.end(), tokens.begin() + 1, tokens.end());
    if (!counts.empty() && counts[0] == "BINARY")
      fail(at(source, lines.line()) + "binary OFF is not supported");
    if (counts.empty()) {
      if (!nextContent()) fail(at(source, lines.line()) + "missing vertex and face counts");
      counts = tokens;
    }
  }
  const std::string countsWhere = at(source, lines.line());
  if (counts.size() < 2 || counts.size() > 3)
    fail(countsWhere + "expected 'vertices faces [edges]' counts, found " +
         std::to_string(counts.size()) + " values");
  std::array<long long, 3> n{0, 0, 0};
  for (std::size_t i = 0; i < counts.size(); ++i)
    if (!parseInt(counts[i], n[i]) || n[i] < 0) fail(countsWhere + "bad count " + quote(counts[i]));
  const long long numV = n[0], numF = n[1];
  if (numV > kMaxIndex || numF > kMaxIndex / 3)
    fail(countsWhere + "counts too large: " + std::to_string(numV) + " vertices, " +
         std::to_string(numF) + " faces");
  // The shortest vertex line is "0 0 0" and the shortest face "3 0 1 2".
  const auto remaining = remainingBytes(in);
  if (remaining && static_cast<std::uint64_t>(5 * numV + 7 * numF) > *remaining)
    fail(countsWhere + "declares " + std::to_string(numV) + " vertices and " +
         std::to_string(numF) + " faces, more than the remaining " + std::to_string(*remaining) +
         " bytes can hold (truncated file or corrupt header)");

  std::vector<double> V, N;
  std::vector<int> F;
  V.reserve(3 * safeReserve(numV, remaining));
  if (hasNormals) N.reserve(3 * safeReserve(numV, remaining));
  F.reserve(3 * safeReserve(numF, remaining));
  const std::size_t wanted = hasNormals ? 6 : 3;
  for (long long v = 0; v < numV; ++v) {
    if (!nextContent())
      fail(at(source, lines.line()) + "file ends after " + std::to_string(v) + " of " +
           std::to_string(numV) + " vertices (truncated?)");
    const auto where = [&] { return at(source, lines.line()); };
    if (tokens.size() < wanted)
      fail(where() + "vertex " + std::to_string(v) + " needs " + std::to_string(wanted) +
           " values, found " + std::to_string(tokens.size()));
    for (std::size_t k = 0; k < wanted; ++k) {
      double value = 0;
      if (!parseDouble(tokens[k], value))
        fail(where() + "vertex " + std::to_string(v) + ": " + quote(tokens[k]) +
             " is not a number");
      if (k < 3 && !std::isfinite(value))
        fail(where() + "vertex " + std::to_string(v) + " has a non-finite coordinate " +
             quote(tokens[k]));
      (k < 3 ? V : N).push_back(value);
    }
  }
  for (long long f = 0; f < numF; ++f) {
    if (!nextContent())
      fail(at(source, lines.line()) + "file ends after " + std::to_string(f) + " of " +
           std::to_string(numF) + " faces (truncated?)");
    const auto where = [&] {
      return at(source, lines.line()) + "face " + std::to_string(f) + ": ";
    };
    long long count = 0;
    if (!parseInt(tokens[0], count)) fail(where() + "bad vertex count " + quote(tokens[0]));
    if (count != 3)
      fail(where() + "has " + std::to_string(count) + " vertices; osdmra needs triangles" +
           (count > 3 ? " (triangulate the mesh first)" : ""));
    if (tokens.size() < 4)
      fail(where() + "expected 3 vertex indices, found " + std::to_string(tokens.size() - 1));
    for (std::size_t c = 1; c <= 3; ++c) {
      long long index = 0;
      if (!parseInt(tokens[c], index)) fail(where() + "bad vertex index " + quote(tokens[c]));
      if (index < 0 || index >= numV)
        fail(where() + "vertex index " + std::to_string(index) + " is out of range (the file has " +
             std::to_string(numV) + " vertices)");
      F.push_back(static_cast<int>(index));
    }
    // Anything after the three indices is a face colour: ignored.
  }
  if (nextContent())
    fail(at(source, lines.line()) + "unexpected data after the last of " + std::to_string(numF) +
         " faces: " + quote(tokens[0]) + " (wrong counts in the header?)");

  TriMesh mesh;
  mesh.V = toPoints(V);
  mesh.F = toFaces(F);
  if (hasNormals && allFinite(N)) mesh.N = toPoints(N);
  return mesh;
}

// ---- PLY -----------------------------------------------------------------------

namespace {

enum class PlyType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parsePlyType(std::string_view name, PlyType& type) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [n, t] : names)
    if (name == n) {
      type = t;
      return true;
    }
  return false;
}

std::size_t plyTypeSize(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
      return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
      return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 8;
}

bool isIntegral(PlyType t) {
  return t != PlyType::Float32 && t != PlyType::Float64;
}

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// What the reader does with a property.
enum class PlyRole : std::uint8_t { Skip, X, Y, Z, NX, NY, NZ, FaceIndices };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // the item type, for lists
  bool isList = false;
  PlyType countType = PlyType::UInt8;
  PlyRole role = PlyRole::Skip;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  long long line = 0;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  long long lines = 0;  // header lines, so ascii data lines are numbered on from it
};

/// One header line, at most `kMaxLine` bytes: a binary blob without newlines must
/// not be slurped whole into a string.
bool readHeaderLine(std::istream& in, std::string& line, const std::string& where) {
  constexpr std::size_t kMaxLine = 1 << 16;
  line.clear();
  std::streambuf* buf = in.rdbuf();
  while (true) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) return !line.empty();
    if (c == '\n') break;
    if (line.size() >= kMaxLine) fail(where + "header line too long (not a PLY file?)");
    line += static_cast<char>(c);
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

PlyHeader readPlyHeader(std::istream& in, const std::string& source) {
  PlyHeader header;
  std::string line;
  std::vector<std::string_view> tokens;
  long long& lineNo = header.lines;
  if (!readHeaderLine(in, line, at(source, 1)) || line != "ply")
    fail(at(source, 1) + "not a PLY file (the first line must be 'ply')");
  lineNo = 1;
  bool haveFormat = false;
  while (true) {
    if (!readHeaderLine(in, line, at(source, lineNo + 1)))
      fail(at(source, lineNo) + "header ends without 'end_header' (truncated file?)");
    ++lineNo;
    const std::string where = at(source, lineNo);
    tokenize(line, tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    if (key == "end_header") break;
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (haveFormat) fail(where + "second 'format' line");
      if (tokens.size() != 3) fail(where + "expected 'format <encoding> 1.0'");
      if (tokens[1] == "ascii")
        header.format = PlyFormat::Ascii;
      else if (tokens[1] == "binary_little_endian")
        header.format = PlyFormat::BinaryLittleEndian;
      else if (tokens[1] == "binary_big_endian")
        header.format = PlyFormat::BinaryBigEndian;
      else
        fail(where + "unknown PLY encoding " + quote(tokens[1]));
      haveFormat = true;
    } else if (key == "element") {
      if (tokens.size() != 3) fail(where + "expected 'element <name> <count>'");
      PlyElement e;
      e.name = std::string(tokens[1]);
      e.line = lineNo;
      const std::string_view c = tokens[2];
      const auto [end, ec] = std::from_chars(c.data(), c.data() + c.size(), e.count);
      if (ec != std::errc() || end != c.data() + c.size())
        fail(where + "bad element count " + quote(c));
      for (const PlyElement& other : header.elements)
        if (other.name == e.name) fail(where + "second element named " + quote(e.name));
      header.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (header.elements.empty()) fail(where + "property before any element");
      PlyProperty p;
      if (tokens.size() >= 2 && tokens[1] == "list") {
        if (tokens.size() != 5) fail(where + "expected 'property list <count type> <type> <name>'");
        if (!parsePlyType(tokens[2], p.countType))
          fail(where + "unknown property type " + quote(tokens[2]));
        if (!parsePlyType(tokens[3], p.type))
          fail(where + "unknown property type " + quote(tokens[3]));
        if (!isIntegral(p.countType))
          fail(where + "list count type must be an integer type, not " + quote(tokens[2]));
        p.isList = true;
        p.name = std::string(tokens[4]);
      } else {
        if (tokens.size() != 3) fail(where + "expected 'property <type> <name>'");
        if (!parsePlyType(tokens[1], p.type))
          fail(where + "unknown property type " + quote(tokens[1]));
        p.name = std::string(tokens[2]);
      }
      auto& properties = header.elements.back().properties;
      for (const PlyProperty& other : properties)
        if (other.name == p.name) fail(where + "second property named " + quote(p.name));
      properties.push_back(std::move(p));
    } else {
      fail(where + "unknown header line " + quote(key));
    }
  }
  if (!haveFormat) fail(at(source, lineNo) + "header has no 'format' line");
  return header;
}

/// Wires the header to what osdmra reads: roles for x, y, z, nx, ny, nz and the
/// face index list, with the checks that need the whole header.
void assignPlyRoles(PlyHeader& header, const std::string& source) {
  PlyElement* vertex = nullptr;
  for (PlyElement& e : header.elements) {
    const std::string where = at(source, e.line) + "element " + quote(e.name) + ": ";
    if (e.properties.empty() && e.count > 0) fail(where + "has no properties");
    if (e.name == "vertex") {
      vertex = &e;
      if (e.count > static_cast<std::uint64_t>(kMaxIndex))
        fail(where + std::to_string(e.count) + " vertices are more than osdmra can index");
      static const std::pair<const char*, PlyRole> roles[] = {
          {"x", PlyRole::X},   {"y", PlyRole::Y},   {"z", PlyRole::Z},
          {"nx", PlyRole::NX}, {"ny", PlyRole::NY}, {"nz", PlyRole::NZ}};
      int found = 0, normals = 0;
      for (PlyProperty& p : e.properties)
        for (const auto& [name, role] : roles)
          if (p.name == name) {
            if (p.isList) fail(where + "property " + quote(p.name) + " is a list");
            p.role = role;
            (role <= PlyRole::Z ? found : normals) += 1;
          }
      if (found != 3) fail(where + "needs properties x, y and z");
      if (normals != 3)  // a partial normal is no normal
        for (PlyProperty& p : e.properties)
          if (p.role >= PlyRole::NX && p.role <= PlyRole::NZ) p.role = PlyRole::Skip;
    } else if (e.name == "face") {
      if (e.count > static_cast<std::uint64_t>(kMaxIndex / 3))
        fail(where + std::to_string(e.count) + " faces are more than osdmra can index");
      PlyProperty* indices = nullptr;
      for (PlyProperty& p : e.properties)
        if (p.name == "vertex_indices" || p.name == "vertex_index") {
          if (indices) fail(where + "has both vertex_indices and vertex_index");
          indices = &p;
        }
      if (!indices) fail(where + "has no 'vertex_indices' list");
      if (!indices->isList) fail(where + quote(indices->name) + " must be a list");
      if (!isIntegral(indices->type))
        fail(where + quote(indices->name) + " must have an integer index type");
      indices->role = PlyRole::FaceIndices;
    }
  }
  if (!vertex) fail(at(source, header.lines) + "no 'vertex' element");
}

/// Rejects declared counts that the remaining bytes cannot hold, before anything
/// is reserved: "element vertex 4000000000" in a 200-byte file is an error, not
/// a 96 GB allocation.
void checkPlySizes(const PlyHeader& header, std::uint64_t remaining, const std::string& source) {
  const bool ascii = header.format == PlyFormat::Ascii;
  // Ascii: every value is at least one character plus one separator, and the last
  // value of the file needs no separator.
  std::uint64_t budget = remaining + (ascii ? 1 : 0);
  for (const PlyElement& e : header.elements) {
    std::uint64_t minRow = 0;
    for (const PlyProperty& p : e.properties) {
      const std::uint64_t values = p.role == PlyRole::FaceIndices ? 4 : 1;  // count + 3
      if (ascii)
        minRow += 2 * values;
      else if (p.isList)
        minRow += plyTypeSize(p.countType) + (values - 1) * plyTypeSize(p.type);
      else
        minRow += plyTypeSize(p.type);
    }
    if (minRow > 0 && e.count > budget / minRow)
      fail(at(source, e.line) + "element " + quote(e.name) + " declares " +
           std::to_string(e.count) + " entries, but the " + std::to_string(remaining) +
           " bytes after the header hold at most " + std::to_string(budget / minRow) +
           " of them (truncated file or corrupt header)");
    budget -= e.count * minRow;
  }
}

/// Shared state of both data readers: where we are, for error messages.
class PlyDataSource {
 public:
  explicit PlyDataSource(const std::string& source) : source_(source) {}
  const std::string* element = nullptr;
  std::uint64_t index = 0;

 protected:
  std::string context(const std::string& prefix) const {
    return prefix + (element ? *element + " " + std::to_string(index) + ": " : std::string());
  }
  const std::string& source_;
};

/// Binary data, buffered: values are at most 8 bytes, so a small refillable buffer
/// serves every read without per-value stream calls.
class PlyBinarySource : public PlyDataSource {
 public:
  PlyBinarySource(std::istream& in, bool bigEndian, const std::string& source)
      : PlyDataSource(source), in_(in), buf_(1 << 16), swap_(bigEndian == hostIsLittleEndian()) {}

  [[noreturn]] void error(const std::string& what) const { fail(context(source_ + ": ") + what); }

  double readReal(PlyType t) {
    const unsigned char* p = take(plyTypeSize(t));
    switch (t) {
      case PlyType::Float32:
        return load<float>(p);
      case PlyType::Float64:
        return load<double>(p);
      default:
        return static_cast<double>(decodeInt(t, p));
    }
  }

  long long readInt(PlyType t) { return decodeInt(t, take(plyTypeSize(t))); }

  void skip(PlyType t, std::uint64_t count) {
    const std::uint64_t size = plyTypeSize(t);
    if (count > std::numeric_limits<std::uint64_t>::max() / size) error("list too long");
    std::uint64_t bytes = count * size;
    while (bytes > 0) {
      if (pos_ == end_ && !refill(1)) error("file ends inside this entry (truncated?)");
      const std::uint64_t n = std::min<std::uint64_t>(bytes, end_ - pos_);
      pos_ += static_cast<std::size_t>(n);
      bytes -= n;
    }
  }

  void finish() {
    if (pos_ < end_ || refill(1)) {
      element = nullptr;
      error("unexpected data after the last element (wrong counts in the header?)");
    }
  }

 private:
  // Makes at least n bytes available at pos_; false at end of input.
  bool refill(std::size_t n) {
    if (end_ - pos_ >= n) return true;
    std::memmove(buf_.data(), buf_.data() + pos_, end_ - pos_);
    end_ -= pos_;
    pos_ = 0;
    while (end_ < n && in_) {
      in_.read(reinterpret_cast<char*>(buf_.data() + end_),
               static_cast<std::streamsize>(buf_.size() - end_));
      end_ += static_cast<std::size_t>(in_.gcount());
    }
    if (in_.bad()) error("read error");
    return end_ >= n;
  }

  const unsigned char* take(std::size_t n) {
    if (end_ - pos_ < n && !refill(n)) error("file ends inside this entry (truncated?)");
    const unsigned char* p = buf_.data() + pos_;
    pos_ += n;
    return p;
  }

  template <class T>
  T load(const unsigned char* p) const {
    unsigned char bytes[sizeof(T)];
    if (swap_)
      std::reverse_copy(p, p + sizeof(T), bytes);
    else
      std::memcpy(bytes, p, sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

  long long decodeInt(PlyType t, const unsigned char* p) const {
    switch (t) {
      case PlyType::Int8:
        return load<std::int8_t>(p);
      case PlyType::UInt8:
        return load<std::uint8_t>(p);
      case PlyType::Int16:
        return load<std::int16_t>(p);
      case PlyType::UInt16:
        return load<std::uint16_t>(p);
      case PlyType::Int32:
        return load<std::int32_t>(p);
      case PlyType::UInt32:
        return load<std::uint32_t>(p);
      default:
        error("expected an integer");  // unreachable: the header checks types
    }
  }

  std::istream& in_;
  std::vector<unsigned char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  bool swap_ = false;
};

/// Ascii data: whitespace-separated values in any line layout, as the PLY format
/// allows; messages name the line of the offending value.
class PlyAsciiSource : public PlyDataSource {
 public:
  PlyAsciiSource(std::istream& in, long long headerLines, const std::string& source)
      : PlyDataSource(source), lines_(in, headerLines) {}

  [[noreturn]] void error(const std::string& what) const {
    fail(context(at(source_, lines_.line())) + what);
  }

  double readReal(PlyType t) {
    const std::string_view token = next();
    double value = 0;
    if (isIntegral(t)) return static_cast<double>(toInt(t, token));
    if (!parseDouble(token, value)) error(quote(token) + " is not a number");
    return value;
  }

  long long readInt(PlyType t) { return toInt(t, next()); }

  void skip(PlyType, std::uint64_t count) {
    for (std::uint64_t i = 0; i < count; ++i) next();
  }

  void finish() {
    if (i_ < tokens_.size() || nextLineWithTokens()) {
      element = nullptr;
      error("unexpected data after the last element: " + quote(tokens_[i_]) +
            " (wrong counts in the header?)");
    }
  }

 private:
  bool nextLineWithTokens() {
    while (lines_.next(line_)) {
      tokenize(line_, tokens_);
      i_ = 0;
      if (!tokens_.empty()) return true;
    }
    return false;
  }

  std::string_view next() {
    if (i_ == tokens_.size() && !nextLineWithTokens())
      error("file ends inside this entry (truncated?)");
    return tokens_[i_++];
  }

  long long toInt(PlyType t, std::string_view token) const {
    long long value = 0;
    if (!parseInt(token, value)) error(quote(token) + " is not an integer");
    static const std::pair<long long, long long> ranges[] = {
        {-128, 127},    {0, 255}, {-32768, 32767}, {0, 65535}, {INT32_MIN, INT32_MAX},
        {0, UINT32_MAX}};
    const auto [lo, hi] = ranges[static_cast<int>(t)];
    if (value < lo || value > hi) error(quote(token) + " does not fit the property's type");
    return value;
  }

  LineReader lines_;
  std::string line_;
  std::vector<std::string_view> tokens_;
  std::size_t i_ = 0;
};

template <class Source>
TriMesh readPlyData(Source& src, const PlyHeader& header,
                    const std::optional<std::uint64_t>& remaining) {
  std::uint64_t numV = 0;
  bool hasNormals = false;
  for (const PlyElement& e : header.elements)
    if (e.name == "vertex") {
      numV = e.count;
      for (const PlyProperty& p : e.properties) hasNormals = hasNormals || p.role == PlyRole::NX;
    }
  std::vector<double> V, N;
  std::vector<int> F;

  for (const PlyElement& e : header.elements) {
    src.element = &e.name;
    const bool isVertex = e.name == "vertex", isFace = e.name == "face";
    if (isVertex) {
      V.reserve(3 * safeReserve(e.count, remaining));
      if (hasNormals) N.reserve(3 * safeReserve(e.count, remaining));
    }
    if (isFace) F.reserve(3 * safeReserve(e.count, remaining));
    for (std::uint64_t i = 0; i < e.count; ++i) {
      src.index = i;
      std::array<double, 6> xyz{};  // x y z nx ny nz
      for (const PlyProperty& p : e.properties) {
        if (p.role == PlyRole::FaceIndices) {
          const long long n = src.readInt(p.countType);
          if (n != 3)
            src.error("has " + std::to_string(n) + " vertices; osdmra needs triangles" +
                      (n > 3 ? " (triangulate the mesh first)" : ""));
          for (int c = 0; c < 3; ++c) {
            const long long index = src.readInt(p.type);
            if (index < 0 || static_cast<std::uint64_t>(index) >= numV)
              src.error("vertex index " + std::to_string(index) +
                        " is out of range (the file has " + std::to_string(numV) + " vertices)");
            F.push_back(static_cast<int>(index));
          }
        } else if (p.isList) {
          const long long n = src.readInt(p.countType);
          if (n < 0) src.error("list " + quote(p.name) + " has negative length");
          src.skip(p.type, static_cast<std::uint64_t>(n));
        } else if (p.role != PlyRole::Skip) {
          xyz[static_cast<int>(p.role) - static_cast<int>(PlyRole::X)] = src.readReal(p.type);
        } else {
          src.skip(p.type, 1);
        }
      }
      if (isVertex) {
        for (int k = 0; k < 3; ++k)
          if (!std::isfinite(xyz[k]))
            src.error(std::string("coordinate ") + "xyz"[k] + " is not finite");
        V.insert(V.end(), xyz.begin(), xyz.begin() + 3);
        if (hasNormals) N.insert(N.end(), xyz.begin() + 3, xyz.end());
      }
    }
  }
  src.finish();

  TriMesh mesh;
  mesh.V = toPoints(V);
  mesh.F = toFaces(F);
  if (hasNormals && allFinite(N)) mesh.N = toPoints(N);
  return mesh;
}

}  // namespace

TriMesh readPly(std::istream& in, const std::string& source) {
  requireNotEmpty(in, source);
  PlyHeader header = readPlyHeader(in, source);
  assignPlyRoles(header, source);
  const auto remaining = remainingBytes(in);
  if (remaining) checkPlySizes(header, *remaining, source);
  if (header.format == PlyFormat::Ascii) {
    PlyAsciiSource src(in, header.lines, source);
    return readPlyData(src, header, remaining);
  }
  PlyBinarySource src(in, header.format == PlyFormat::BinaryBigEndian, source);
  return readPlyData(src, header, remaining);
}

// ---- Writers ------------------------------------------------------------------

namespace {

/// Buffered output: formatting into a string and writing large chunks keeps the
/// writers fast, and avoids iostream number formatting, which follows the global
/// locale (a German locale would write "0,5").
class OutBuffer {
 public:
  explicit OutBuffer(std::ostream& out) : out_(out) { buf_.reserve(kChunk + 64); }

  void text(std::string_view s) {
    buf_ += s;
    maybeFlush();
  }
  /// Shortest decimal that reads back as exactly `x` (std::to_chars round-trip
  /// guarantee): as exact as %.17g, without its noise digits.
  void real(double x) {
    char digits[32];
    const auto r = std::to_chars(digits, digits + sizeof digits, x);
    buf_.append(digits, r.ptr);
    maybeFlush();
  }
  void integer(long long i) {
    char digits[24];
    const auto r = std::to_chars(digits, digits + sizeof digits, i);
    buf_.append(digits, r.ptr);
    maybeFlush();
  }
  /// Space-separated values.
  void reals(const double* x, int n) {
    for (int k = 0; k < n; ++k) {
      if (k) buf_ += ' ';
      real(x[k]);
    }
  }
  void integers(const int* x, int n, long long offset) {
    for (int k = 0; k < n; ++k) {
      if (k) buf_ += ' ';
      integer(x[k] + offset);
    }
  }
  template <class T>
  void littleEndian(T value) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (!hostIsLittleEndian()) std::reverse(bytes, bytes + sizeof(T));
    buf_.append(reinterpret_cast<const char*>(bytes), sizeof(T));
    maybeFlush();
  }
  void flush() {
    out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
    out_.flush();
    if (!out_) fail("write failed");
  }

 private:
  static constexpr std::size_t kChunk = 1 << 20;
  void maybeFlush() {
    if (buf_.size() < kChunk) return;
    out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
    if (!out_) fail("write failed");
  }
  std::ostream& out_;
  std::string buf_;
};

/// The writers refuse what the readers would reject, so every file osdmra writes
/// reads back.
void checkWritable(const TriMesh& mesh) {
  const Eigen::Index nv = mesh.V.rows();
  for (Eigen::Index v = 0; v < nv; ++v)
    if (!mesh.V.row(v).allFinite())
      fail("cannot write vertex " + std::to_string(v) + ": non-finite coordinate");
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f)
    for (int i = 0; i < 3; ++i)
      if (mesh.F(f, i) < 0 || mesh.F(f, i) >= nv)
        fail("cannot write face " + std::to_string(f) + ": vertex index " +
             std::to_string(mesh.F(f, i)) + " is out of range (" + std::to_string(nv) +
             " vertices)");
}

bool writesNormals(const TriMesh& mesh, const WriteOptions& opts) {
  return opts.writeNormals && mesh.V.rows() > 0 && mesh.N.rows() == mesh.V.rows();
}

}  // namespace

void writeObj(std::ostream& out, const TriMesh& mesh, const WriteOptions& opts) {
  checkWritable(mesh);
  const bool normals = writesNormals(mesh, opts);
  OutBuffer o(out);
  o.text("# osdmra: ");
  o.integer(mesh.V.rows());
  o.text(" vertices, ");
  o.integer(mesh.F.rows());
  o.text(" triangles\n");
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    o.text("v ");
    o.reals(mesh.V.row(v).data(), 3);
    o.text("\n");
  }
  if (normals)
    for (Eigen::Index v = 0; v < mesh.N.rows(); ++v) {
      o.text("vn ");
      o.reals(mesh.N.row(v).data(), 3);
      o.text("\n");
    }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    o.text("f");
    for (int i = 0; i < 3; ++i) {
      const long long index = mesh.F(f, i) + 1LL;  // OBJ counts from 1
      o.text(" ");
      o.integer(index);
      if (normals) {  // normal k belongs to vertex k
        o.text("//");
        o.integer(index);
      }
    }
    o.text("\n");
  }
  o.flush();
}

void writeOff(std::ostream& out, const TriMesh& mesh, const WriteOptions& opts) {
  checkWritable(mesh);
  const bool normals = writesNormals(mesh, opts);
  OutBuffer o(out);
  o.text(normals ? "NOFF\n" : "OFF\n");
  o.integer(mesh.V.rows());
  o.text(" ");
  o.integer(mesh.F.rows());
  o.text(" 0\n");
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    o.reals(mesh.V.row(v).data(), 3);
    if (normals) {
      o.text(" ");
      o.reals(mesh.N.row(v).data(), 3);
    }
    o.text("\n");
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    o.text("3 ");
    o.integers(mesh.F.row(f).data(), 3, 0);
    o.text("\n");
  }
  o.flush();
}

void writePly(std::ostream& out, const TriMesh& mesh, const WriteOptions& opts) {
  checkWritable(mesh);
  const bool normals = writesNormals(mesh, opts);
  const bool ascii = opts.plyEncoding == PlyEncoding::Ascii;
  OutBuffer o(out);
  o.text(ascii ? "ply\nformat ascii 1.0\n" : "ply\nformat binary_little_endian 1.0\n");
  o.text("comment written by osdmra\nelement vertex ");
  o.integer(mesh.V.rows());
  o.text("\nproperty double x\nproperty double y\nproperty double z\n");
  if (normals) o.text("property double nx\nproperty double ny\nproperty double nz\n");
  o.text("element face ");
  o.integer(mesh.F.rows());
  o.text("\nproperty list uchar int vertex_indices\nend_header\n");
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    if (ascii) {
      o.reals(mesh.V.row(v).data(), 3);
      if (normals) {
        o.text(" ");
        o.reals(mesh.N.row(v).data(), 3);
      }
      o.text("\n");
    } else {
      for (int k = 0; k < 3; ++k) o.littleEndian(mesh.V(v, k));
      if (normals)
        for (int k = 0; k < 3; ++k) o.littleEndian(mesh.N(v, k));
    }
  }
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    if (ascii) {
      o.text("3 ");
      o.integers(mesh.F.row(f).data(), 3, 0);
      o.text("\n");
    } else {
      o.littleEndian(std::uint8_t{3});
      for (int i = 0; i < 3; ++i) o.littleEndian(static_cast<std::int32_t>(mesh.F(f, i)));
    }
  }
  o.flush();
}

// ---- Files and dispatch ----------------------------------------------------------

MeshFormat meshFormatFromPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".off") return MeshFormat::Off;
  if (ext == ".ply") return MeshFormat::Ply;
  fail(path + ": unknown mesh format " + (ext.empty() ? "(no extension)" : quote(ext)) +
       "; expected .obj, .off or .ply");
}

TriMesh readMesh(std::istream& in, MeshFormat format, const std::string& source) {
  switch (format) {
    case MeshFormat::Obj:
      return readObj(in, source);
    case MeshFormat::Off:
      return readOff(in, source);
    case MeshFormat::Ply:
      return readPly(in, source);
  }
  fail(source + ": unknown mesh format");
}

TriMesh readMesh(const std::string& path) {
  const MeshFormat format = meshFormatFromPath(path);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail(path + ": is a directory, not a mesh file");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path + ": cannot open: " + (errno ? std::strerror(errno) : "unknown error"));
  try {
    return readMesh(in, format, path);
  } catch (const Error& e) {
    // LineReader and OutBuffer report bare "read error"s; give them the file.
    if (std::string_view(e.what()).rfind(path, 0) == 0) throw;
    throw Error(path + ": " + e.what());
  }
}

TriMesh readValidMesh(const std::string& path) {
  TriMesh mesh = readMesh(path);
  validate(mesh, path);
  return mesh;
}

void writeMesh(std::ostream& out, MeshFormat format, const TriMesh& mesh,
               const WriteOptions& opts) {
  switch (format) {
    case MeshFormat::Obj:
      return writeObj(out, mesh, opts);
    case MeshFormat::Off:
      return writeOff(out, mesh, opts);
    case MeshFormat::Ply:
      return writePly(out, mesh, opts);
  }
}

void writeMesh(const std::string& path, const TriMesh& mesh, const WriteOptions& opts) {
  namespace fs = std::filesystem;
  const MeshFormat format = meshFormatFromPath(path);
  try {
    checkWritable(mesh);  // before touching the file system
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }

  // A name no concurrent writer (thread or process) picks: a random 64-bit tag.
  static std::atomic<std::uint64_t> counter{0};
  std::random_device entropy;
  const std::uint64_t tag =
      (std::uint64_t{entropy()} << 32) ^ entropy() ^
      static_cast<std::uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
      (counter.fetch_add(1) * 0x9e3779b97f4a7c15ULL);
  const fs::path target(path);
  fs::path tmp = target;
  tmp += ".tmp-" + std::to_string(tag);

  // Removes the temporary file on every failure path.
  struct TmpGuard {
    const fs::path& p;
    bool armed = true;
    ~TmpGuard() {
      std::error_code ignored;
      if (armed) fs::remove(p, ignored);
    }
  } guard{tmp};

  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      fail(path + ": cannot create temporary file " + tmp.string() + ": " +
           (errno ? std::strerror(errno) : "unknown error"));
    try {
      writeMesh(out, format, mesh, opts);
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
    out.close();
    if (!out) fail(path + ": write failed (disk full?)");
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) fail(path + ": cannot replace the file: " + ec.message());
  guard.armed = false;
}

}  // namespace osdmra
