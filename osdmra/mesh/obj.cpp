// Wavefront OBJ: reading and writing (io.h says what is read).

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

namespace {

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

TriMesh readObj(std::istream& in, const std::string& source, const ReadOptions& options) {
  requireNotEmpty(in, source);
  std::vector<double> V, VN;
  std::vector<int> F, cornerNormal;  // cornerNormal: normal index per corner, -1 if none
  // Faces whose indices point past what was defined at their line (forward
  // references, rare but legal) are checked once the whole file is read.
  std::vector<std::pair<std::size_t, long long>> forwardRefs;  // (face, line)
  long long numTexCoords = 0;
  std::vector<std::pair<int, int>> corners;  // of the face being read: (vertex, normal)
  std::vector<PolygonFan> fans;

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
      if (n > 3 && !options.triangulate)
        fail(where() + "face has " + std::to_string(n) +
             " vertices; osdmra needs triangles (triangulate the mesh first; remesh and --remesh "
             "read polygons as triangles)");
      if (n < 3) fail(where() + "face has " + std::to_string(n) + " vertices; a face needs 3");
      const long long numV = static_cast<long long>(V.size() / 3);
      const long long numN = static_cast<long long>(VN.size() / 3);
      bool forward = false;
      corners.clear();
      for (std::size_t c = 1; c <= n; ++c) {
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
        corners.emplace_back(static_cast<int>(v), static_cast<int>(vn));
      }
      // A polygon (with ReadOptions::triangulate) is the fan from its first corner,
      // unfolded once the positions are all known.
      if (n > 3) fans.push_back({F.size() / 3, static_cast<int>(n)});
      for (std::size_t k = 1; k + 1 < n; ++k) {
        const std::size_t face = F.size() / 3;
        if (face >= static_cast<std::size_t>(kMaxIndex / 3)) fail(where() + "too many faces");
        for (const std::size_t c : {std::size_t{0}, k, k + 1}) {
          F.push_back(corners[c].first);
          cornerNormal.push_back(corners[c].second);
        }
        if (forward) forwardRefs.emplace_back(face, lineNo);
      }
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

  unfoldPolygonFans(V, F, fans);
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

}  // namespace osdmra
