// PLY, ascii and binary: reading and writing (io.h says what is read).

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
TriMesh readPlyData(Source& src, const PlyHeader& header, const ReadOptions& options,
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
  std::vector<PolygonFan> fans;  // polygons read as fans (ReadOptions::triangulate)

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
          if (n < 3 || (n > 3 && !options.triangulate))
            src.error("has " + std::to_string(n) + " vertices; osdmra needs triangles" +
                      (n > 3 ? " (triangulate the mesh first; remesh and --remesh read polygons as "
                               "triangles)"
                             : ""));
          // A polygon (with ReadOptions::triangulate) is the fan from its first corner;
          // its corners are read as they come, so a false count costs only the bytes
          // the file has.
          if (n > 3)
            fans.push_back({F.size() / 3, static_cast<int>(std::min<long long>(n, kMaxIndex))});
          int first = -1, previous = -1;
          for (long long c = 0; c < n; ++c) {
            const long long index = src.readInt(p.type);
            if (index < 0 || static_cast<std::uint64_t>(index) >= numV)
              src.error("vertex index " + std::to_string(index) +
                        " is out of range (the file has " + std::to_string(numV) + " vertices)");
            if (c >= 2) F.insert(F.end(), {first, previous, static_cast<int>(index)});
            (c == 0 ? first : previous) = static_cast<int>(index);
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

  unfoldPolygonFans(V, F, fans);
  TriMesh mesh;
  mesh.V = toPoints(V);
  mesh.F = toFaces(F);
  if (hasNormals && allFinite(N)) mesh.N = toPoints(N);
  return mesh;
}

}  // namespace

TriMesh readPly(std::istream& in, const std::string& source, const ReadOptions& options) {
  requireNotEmpty(in, source);
  PlyHeader header = readPlyHeader(in, source);
  assignPlyRoles(header, source);
  const auto remaining = remainingBytes(in);
  if (remaining) checkPlySizes(header, *remaining, source);
  if (header.format == PlyFormat::Ascii) {
    PlyAsciiSource src(in, header.lines, source);
    return readPlyData(src, header, options, remaining);
  }
  PlyBinarySource src(in, header.format == PlyFormat::BinaryBigEndian, source);
  return readPlyData(src, header, options, remaining);
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

}  // namespace osdmra
