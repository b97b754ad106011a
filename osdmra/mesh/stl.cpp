// STL: reading (io.h says what is read). STL stores a soup of triangles, each with its
// own three corners; the mesh is made by merging corners at exactly the same position.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <istream>
#include <iterator>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "osdmra/mesh/detail/text.h"
#include "osdmra/mesh/io.h"

namespace osdmra {

using namespace detail;

namespace {

constexpr std::size_t kBinaryHeader = 84;  // 80 bytes of text, then the triangle count
constexpr std::size_t kBinaryTriangle = 50;

// Corners (flat xyz, three per triangle) merged where their positions are equal (-0
// and +0 alike), vertices numbered in the order of their first corner.
TriMesh fromSoup(const std::vector<double>& corners) {
  const std::size_t n = corners.size() / 3;
  auto at = [&](std::size_t c) {
    return std::array<double, 3>{corners[3 * c] + 0.0, corners[3 * c + 1] + 0.0,
                                 corners[3 * c + 2] + 0.0};
  };
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return at(a) < at(b); });
  std::vector<std::size_t> group(n);  // corner -> its group's first corner
  for (std::size_t i = 0; i < n; ++i)
    group[order[i]] = i > 0 && at(order[i]) == at(order[i - 1]) ? group[order[i - 1]] : order[i];
  std::vector<int> vertexOf(n, -1);
  std::vector<double> V;
  std::vector<int> F(n);
  for (std::size_t c = 0; c < n; ++c) {
    int& v = vertexOf[group[c]];
    if (v < 0) {
      v = static_cast<int>(V.size() / 3);
      V.insert(V.end(), corners.begin() + 3 * c, corners.begin() + 3 * c + 3);
    }
    F[c] = v;
  }
  TriMesh mesh;
  mesh.V = toPoints(V);
  mesh.F = toFaces(F);
  return mesh;
}

float littleEndianFloat(const char* bytes) {
  std::uint32_t bits = 0;
  for (int i = 3; i >= 0; --i) bits = bits << 8 | static_cast<unsigned char>(bytes[i]);
  float value = 0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::vector<double> readBinaryCorners(std::istream& in, const std::string& head,
                                      const std::optional<std::uint64_t>& remaining,
                                      const std::string& source) {
  if (head.size() < kBinaryHeader)
    fail(source + ": too short for a binary STL file (" + std::to_string(head.size()) +
         " bytes; the header alone has 84) and not an ASCII one (no 'solid')");
  std::uint64_t count = 0;
  for (int i = 3; i >= 0; --i) count = count << 8 | static_cast<unsigned char>(head[80 + i]);
  if (remaining && *remaining != kBinaryTriangle * count)
    fail(source + ": binary STL declares " + std::to_string(count) + " triangles (" +
         std::to_string(kBinaryTriangle * count) + " bytes) but " + std::to_string(*remaining) +
         " bytes follow its header (truncated or corrupt?)");
  std::vector<double> corners;
  if (remaining) corners.reserve(9 * count);  // the size checked above vouches for it
  char t[kBinaryTriangle];
  for (std::uint64_t i = 0; i < count; ++i) {
    if (!in.read(t, kBinaryTriangle))
      fail(source + ": file ends in triangle " + std::to_string(i) + " of " +
           std::to_string(count) + " (truncated?)");
    for (int k = 0; k < 9; ++k) {  // the facet normal (bytes 0-11) is not read
      const double x = littleEndianFloat(t + 12 + 4 * k);
      if (!std::isfinite(x))
        fail(source + ": triangle " + std::to_string(i) + " has a non-finite coordinate");
      corners.push_back(x);
    }
  }
  if (in.peek() != std::char_traits<char>::eof())
    fail(source + ": data after the " + std::to_string(count) + " triangles the header declares");
  return corners;
}

std::vector<double> readAsciiCorners(std::istream& in, const std::string& source) {
  LineReader lines(in);
  std::string line;
  std::vector<std::string_view> tokens;
  std::vector<double> corners;
  enum class In { File, Solid, Facet, Loop } state = In::File;
  int loopCorners = 0;
  while (lines.next(line)) {
    tokenize(line, tokens);
    if (tokens.empty()) continue;
    const std::string_view k = tokens[0];
    const auto where = [&] { return at(source, lines.line()); };
    const auto expect = [&](bool ok, const char* what) {
      if (!ok) fail(where() + quote(k) + " " + what);
    };
    if (k == "solid") {
      expect(state == In::File, "inside a solid");
      state = In::Solid;
    } else if (k == "endsolid") {
      expect(state == In::Solid, "outside a solid, or inside a facet");
      state = In::File;
    } else if (k == "facet") {
      expect(state == In::Solid, "outside a solid, or inside a facet");
      state = In::Facet;
    } else if (k == "outer") {
      expect(state == In::Facet && tokens.size() == 2 && tokens[1] == "loop",
             "is not 'outer loop' at the start of a facet");
      state = In::Loop;
      loopCorners = 0;
    } else if (k == "vertex") {
      expect(state == In::Loop, "outside a facet's loop");
      if (tokens.size() != 4) fail(where() + "vertex needs 3 coordinates");
      if (++loopCorners > 3) fail(where() + "facet has more than 3 vertices; STL has triangles");
      for (int c = 1; c <= 3; ++c) {
        double x = 0;
        if (!parseDouble(tokens[c], x)) fail(where() + quote(tokens[c]) + " is not a number");
        if (!std::isfinite(x)) fail(where() + "vertex has a non-finite coordinate");
        corners.push_back(x);
      }
    } else if (k == "endloop") {
      expect(state == In::Loop, "outside a facet's loop");
      if (loopCorners != 3)
        fail(where() + "facet has " + std::to_string(loopCorners) + " vertices; it needs 3");
      state = In::Facet;
    } else if (k == "endfacet") {
      expect(state == In::Facet, "outside a facet, or inside its loop");
      state = In::Solid;
    } else {
      fail(where() + "unknown ASCII STL keyword " + quote(k));
    }
  }
  if (state != In::File)
    fail(at(source, lines.line()) + "file ends inside a " +
         (state == In::Solid ? "solid" : "facet") + " (truncated?)");
  return corners;
}

}  // namespace

TriMesh readStl(std::istream& in, const std::string& source, const ReadOptions&) {
  requireNotEmpty(in, source);
  const std::optional<std::uint64_t> size = remainingBytes(in);
  std::string head(kBinaryHeader, '\0');
  in.read(head.data(), static_cast<std::streamsize>(kBinaryHeader));
  head.resize(static_cast<std::size_t>(in.gcount()));
  // Binary files may start with "solid" too: the size settles it where it is known.
  std::uint64_t count = 0;
  if (head.size() == kBinaryHeader)
    for (int i = 3; i >= 0; --i) count = count << 8 | static_cast<unsigned char>(head[80 + i]);
  const bool binarySize =
      size && head.size() == kBinaryHeader && *size == kBinaryHeader + kBinaryTriangle * count;
  // Otherwise ASCII is text from its first byte ("solid"); a binary header, count and
  // floats have bytes that are not.
  const bool printable = std::all_of(head.begin(), head.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u >= 0x20 && u < 0x7f) || u == '\n' || u == '\r' || u == '\t';
  });
  const bool ascii = !binarySize && printable && head.compare(0, 5, "solid") == 0;
  std::vector<double> corners;
  if (ascii) {
    // The text read so far, then the rest (an ASCII file is read whole, as text).
    std::string text = head;
    text.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad()) fail(source + ": read error");
    std::istringstream rest(text);
    corners = readAsciiCorners(rest, source);
  } else {
    std::optional<std::uint64_t> remaining;
    if (size) remaining = *size - head.size();
    corners = readBinaryCorners(in, head, remaining, source);
  }
  if (corners.size() / 9 >= static_cast<std::size_t>(kMaxIndex / 3))
    fail(source + ": too many triangles");
  return fromSoup(corners);
}

}  // namespace osdmra
