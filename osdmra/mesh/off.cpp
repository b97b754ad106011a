// OFF: reading and writing (io.h says what is read).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "osdmra/mesh/detail/out_buffer.h"
#include "osdmra/mesh/detail/polygons.h"
#include "osdmra/mesh/detail/text.h"
#include "osdmra/mesh/io.h"

namespace osdmra {

using namespace detail;

TriMesh readOff(std::istream& in, const std::string& source, const ReadOptions& options) {
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
  std::vector<PolygonFan> fans;  // polygons read as fans (ReadOptions::triangulate)
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
    if (count < 3 || (count > 3 && !options.triangulate))
      fail(where() + "has " + std::to_string(count) + " vertices; osdmra needs triangles" +
           (count > 3
                ? " (triangulate the mesh first; remesh and --remesh read polygons as triangles)"
                : ""));
    if (static_cast<long long>(tokens.size()) - 1 < count)
      fail(where() + "expected " + std::to_string(count) + " vertex indices, found " +
           std::to_string(tokens.size() - 1));
    if (count > 3) fans.push_back({F.size() / 3, static_cast<int>(count)});
    int first = -1, previous = -1;
    for (long long c = 1; c <= count; ++c) {
      long long index = 0;
      if (!parseInt(tokens[c], index)) fail(where() + "bad vertex index " + quote(tokens[c]));
      if (index < 0 || index >= numV)
        fail(where() + "vertex index " + std::to_string(index) + " is out of range (the file has " +
             std::to_string(numV) + " vertices)");
      // A polygon (with ReadOptions::triangulate) is the fan from its first corner.
      if (c >= 3) F.insert(F.end(), {first, previous, static_cast<int>(index)});
      (c == 1 ? first : previous) = static_cast<int>(index);
    }
    // Anything after the indices is a face colour: ignored.
  }
  if (nextContent())
    fail(at(source, lines.line()) + "unexpected data after the last of " + std::to_string(numF) +
         " faces: " + quote(tokens[0]) + " (wrong counts in the header?)");

  unfoldPolygonFans(V, F, fans);
  TriMesh mesh;
  mesh.V = toPoints(V);
  mesh.F = toFaces(F);
  if (hasNormals && allFinite(N)) mesh.N = toPoints(N);
  return mesh;
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

}  // namespace osdmra
