#include "osdmra/mra/mra_file.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <istream>
#include <ostream>
#include <utility>
#include <vector>

#include "osdmra/base/error.h"
#include "osdmra/base/file.h"

namespace osdmra {

namespace {

constexpr std::array<unsigned char, 8> kSignature = {0x89, 'M', 'R', 'A', '\r', '\n', 0x1A, '\n'};
constexpr int kMaxLevels = 15;
// Counts are u32 in the file but index Eigen matrices and int-based topology.
constexpr std::uint64_t kMaxCount = INT_MAX;

// ---------------------------------------------------------------------------------
// CRC-64/XZ, table-driven (reflected, so the table is built from the reversed
// ECMA-182 polynomial and bits are consumed least significant first).

struct Crc64Table {
  std::array<std::uint64_t, 256> entry{};
  Crc64Table() {
    constexpr std::uint64_t kReversedPoly = 0xC96C5795D7870F42ULL;
    for (std::uint64_t i = 0; i < 256; ++i) {
      std::uint64_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? (c >> 1) ^ kReversedPoly : c >> 1;
      entry[i] = c;
    }
  }
};

// ---------------------------------------------------------------------------------
// Enum codes. Spelled out rather than cast so that reordering an enum can never
// silently change the meaning of existing files. -1 marks a value outside the enum.

int schemeCode(Scheme s) {
  switch (s) {
    case Scheme::Loop:
      return 0;
    case Scheme::Linear:
      return 1;
  }
  return -1;
}

int kindCode(WaveletKind k) {
  switch (k) {
    case WaveletKind::Lazy:
      return 0;
    case WaveletKind::Quasi:
      return 1;
    case WaveletKind::Pre:
      return 2;
    case WaveletKind::Fixed:
      return 3;
  }
  return -1;
}

// ---------------------------------------------------------------------------------
// Sizes implied by the base mesh.

struct Shape {
  std::vector<std::uint64_t> detailRows;  // E_j for j < J
  std::uint64_t finestVertices = 0;       // n_J
  std::uint64_t finestFaces = 0;          // F_J
};

// Edge count of a triangle list whose indices are already known to be in range.
std::uint64_t countEdges(const Faces& F) {
  std::vector<std::uint64_t> keys;
  keys.reserve(static_cast<std::size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int i = 0; i < 3; ++i) {
      const auto a = static_cast<std::uint32_t>(F(f, i));
      const auto b = static_cast<std::uint32_t>(F(f, (i + 1) % 3));
      keys.push_back(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b));
    }
  std::sort(keys.begin(), keys.end());
  return static_cast<std::uint64_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
}

// Uniform 1-to-4 refinement adds one vertex per edge, splits every edge in two and
// adds three interior edges per face. With F_0 < 2^31 and J <= 15 nothing here can
// overflow: E_j <= 3 F_j <= 3 * 2^61.
Shape refinementShape(const Faces& F, std::uint64_t n0, int levels) {
  Shape s;
  std::uint64_t n = n0, faces = static_cast<std::uint64_t>(F.rows()), edges = countEdges(F);
  for (int j = 0; j < levels; ++j) {
    s.detailRows.push_back(edges);
    n += edges;
    edges = 2 * edges + 3 * faces;
    faces *= 4;
  }
  s.finestVertices = n;
  s.finestFaces = faces;
  return s;
}

// ---------------------------------------------------------------------------------
// Reading.

// Decodes a byte buffer that holds the whole file. Every accessor checks the
// remaining length first, so a short file is an Error at the field it cuts.
class Parser {
 public:
  Parser(const std::vector<unsigned char>& bytes, const std::string& source)
      : data_(bytes.data()), size_(bytes.size()), source_(source) {}

  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return size_ - pos_; }

  [[noreturn]] void fail(std::size_t at, const std::string& field, const std::string& what) const {
    throw Error(source_ + ": " + field + " at byte offset " + std::to_string(at) + ": " + what);
  }

  const unsigned char* take(std::size_t n, const std::string& field) {
    if (remaining() < n)
      throw Error(source_ + ": file truncated: " + field + " at byte offset " +
                  std::to_string(pos_) + " needs " + std::to_string(n) + " bytes, but only " +
                  std::to_string(remaining()) + " remain (file size " + std::to_string(size_) +
                  ")");
    const unsigned char* p = data_ + pos_;
    pos_ += n;
    return p;
  }

  std::uint8_t u8(const std::string& field) { return *take(1, field); }
  std::uint32_t u32(const std::string& field) {
    const unsigned char* p = take(4, field);
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = v << 8 | p[i];
    return v;
  }
  std::int32_t i32(const std::string& field) { return static_cast<std::int32_t>(u32(field)); }
  std::uint64_t u64(const std::string& field) {
    const unsigned char* p = take(8, field);
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = v << 8 | p[i];
    return v;
  }
  double f64(const std::string& field) {
    const std::uint64_t bits = u64(field);
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }

  // Checks, before anything is allocated for them, that `count` elements of
  // `elementBytes` each can still be in the file.
  void checkFits(std::uint64_t count, std::size_t elementBytes, std::size_t at,
                 const std::string& field) const {
    if (count > kMaxCount)
      fail(at, field, std::to_string(count) + " exceeds the limit of " + std::to_string(kMaxCount));
    if (count * elementBytes > remaining())
      fail(at, field,
           std::to_string(count) + " elements need " + std::to_string(count * elementBytes) +
               " bytes, but only " + std::to_string(remaining()) +
               " remain (the file is truncated or the count is corrupt)");
  }

  // Reads `rows` x 3 finite doubles (rows already checked by checkFits).
  Points points(std::uint64_t rows, const std::string& field) {
    Points P(static_cast<Eigen::Index>(rows), 3);
    for (Eigen::Index r = 0; r < P.rows(); ++r)
      for (int c = 0; c < 3; ++c) {
        const std::size_t at = pos_;
        const double v = f64(field);
        if (!std::isfinite(v))
          fail(at, field,
               "row " + std::to_string(r) + " column " + std::to_string(c) + " is not finite");
        P(r, c) = v;
      }
    return P;
  }

  // Reads `rows` x 3 vertex indices in 0..numVertices-1, no face repeating a vertex.
  Faces faces(std::uint64_t rows, std::uint64_t numVertices, const std::string& field) {
    Faces F(static_cast<Eigen::Index>(rows), 3);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      const std::size_t at = pos_;
      for (int c = 0; c < 3; ++c) {
        const std::int32_t v = i32(field);
        if (v < 0 || static_cast<std::uint64_t>(v) >= numVertices)
          fail(at, field,
               "face " + std::to_string(f) + " corner " + std::to_string(c) + " is vertex " +
                   std::to_string(v) + ", outside 0.." + std::to_string(numVertices - 1));
        F(f, c) = v;
      }
      if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0))
        fail(at, field, "face " + std::to_string(f) + " repeats a vertex");
    }
    return F;
  }

 private:
  const unsigned char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  const std::string& source_;
};

void checkSignature(const std::vector<unsigned char>& b, const std::string& source) {
  const std::size_t n = std::min(b.size(), kSignature.size());
  const auto mismatch =
      std::mismatch(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n), kSignature.begin());
  if (mismatch.first == b.begin() + static_cast<std::ptrdiff_t>(n)) {
    if (n == kSignature.size()) return;
    if (n == 0) throw Error(source + ": not an osdmra coefficient file (the file is empty)");
    throw Error(source + ": file truncated at byte offset " + std::to_string(n) +
                " inside the 8-byte signature");
  }
  const auto at = static_cast<std::size_t>(mismatch.first - b.begin());
  // Bytes 4..7 exist to detect exactly this: a file that was an .mra file until a
  // text-mode transfer rewrote its line endings.
  if (at >= 4)
    throw Error(source + ": not an osdmra coefficient file: signature damaged at byte offset " +
                std::to_string(at) + " (line endings converted by a text-mode transfer?)");
  throw Error(source + ": not an osdmra coefficient file (signature mismatch at byte offset " +
              std::to_string(at) + ")");
}

Decomposition parse(const std::vector<unsigned char>& bytes, const std::string& source) {
  checkSignature(bytes, source);
  Parser p(bytes, source);
  Decomposition d;
  p.take(kSignature.size(), "signature");

  std::size_t at = p.offset();
  const std::uint32_t version = p.u32("format version");
  if (version != kMraFormatVersion)
    p.fail(at, "format version",
           "version " + std::to_string(version) + " is not supported (this build reads version " +
               std::to_string(kMraFormatVersion) + " only)");

  at = p.offset();
  switch (p.u8("scheme")) {
    case 0:
      d.scheme = Scheme::Loop;
      break;
    case 1:
      d.scheme = Scheme::Linear;
      break;
    default:
      p.fail(at, "scheme", "code " + std::to_string(bytes[at]) + " is not 0 (loop) or 1 (linear)");
  }
  at = p.offset();
  switch (p.u8("wavelet kind")) {
    case 0:
      d.wavelets.kind = WaveletKind::Lazy;
      break;
    case 1:
      d.wavelets.kind = WaveletKind::Quasi;
      break;
    case 2:
      d.wavelets.kind = WaveletKind::Pre;
      break;
    case 3:
      d.wavelets.kind = WaveletKind::Fixed;
      break;
    default:
      p.fail(at, "wavelet kind",
             "code " + std::to_string(bytes[at]) +
                 " is not 0 (lazy), 1 (quasi), 2 (pre) or 3 (fixed)");
  }
  at = p.offset();
  d.wavelets.rings = p.i32("rings");
  if (d.wavelets.rings < 0) p.fail(at, "rings", std::to_string(d.wavelets.rings) + " is negative");
  at = p.offset();
  const std::uint32_t levels = p.u32("levels");
  if (levels > kMaxLevels)
    p.fail(at, "levels", std::to_string(levels) + " is outside 0.." + std::to_string(kMaxLevels));
  d.levels = static_cast<int>(levels);

  // Base mesh. Positions follow the faces, so the vertex count is only bounded here
  // by what remains; the exact end is checked when the positions are read.
  at = p.offset();
  const std::uint32_t n0 = p.u32("base vertex count");
  p.checkFits(n0, 24, at, "base vertex count");
  at = p.offset();
  const std::uint32_t f0 = p.u32("base face count");
  if (f0 == 0) p.fail(at, "base face count", "the base mesh has no faces");
  p.checkFits(f0, 12, at, "base face count");
  d.baseFaces = p.faces(f0, n0, "base faces");
  d.base = p.points(n0, "base positions");
  {
    // Topology (manifoldness, orientation, unreferenced vertices) is validate()'s job;
    // Hierarchy expects a validated base mesh.
    TriMesh mesh{std::move(d.base), std::move(d.baseFaces), Points()};
    validate(mesh, source + ": base mesh");
    d.base = std::move(mesh.V);
    d.baseFaces = std::move(mesh.F);
  }

  const Shape shape = refinementShape(d.baseFaces, n0, d.levels);
  d.details.reserve(levels);
  for (std::uint32_t j = 0; j < levels; ++j) {
    const std::string field = "level " + std::to_string(j) + " detail count";
    at = p.offset();
    const std::uint32_t rows = p.u32(field);
    if (rows != shape.detailRows[j])
      p.fail(at, field,
             std::to_string(rows) + " rows, but uniform refinement of M^" + std::to_string(j) +
                 " adds one vertex per edge: " + std::to_string(shape.detailRows[j]));
    p.checkFits(rows, 24, at, field);
    d.details.push_back(p.points(rows, "level " + std::to_string(j) + " details"));
  }

  at = p.offset();
  const std::uint32_t orderCount = p.u32("inputOrder count");
  if (orderCount != 0 && orderCount != shape.finestVertices)
    p.fail(at, "inputOrder count",
           std::to_string(orderCount) + " is neither 0 (absent) nor the " +
               std::to_string(shape.finestVertices) + " vertices of level " +
               std::to_string(levels));
  p.checkFits(orderCount, 4, at, "inputOrder count");
  if (orderCount > 0) {
    d.inputOrder.resize(orderCount);
    std::vector<char> seen(orderCount, 0);
    for (std::uint32_t i = 0; i < orderCount; ++i) {
      at = p.offset();
      const std::int32_t v = p.i32("inputOrder");
      if (v < 0 || static_cast<std::uint32_t>(v) >= orderCount)
        p.fail(at, "inputOrder",
               "entry " + std::to_string(i) + " is " + std::to_string(v) + ", outside 0.." +
                   std::to_string(orderCount - 1));
      if (seen[static_cast<std::size_t>(v)])
        p.fail(at, "inputOrder",
               "entry " + std::to_string(i) + " repeats " + std::to_string(v) +
                   " (not a permutation)");
      seen[static_cast<std::size_t>(v)] = 1;
      d.inputOrder[i] = v;
    }
  }

  at = p.offset();
  const std::uint32_t faceCount = p.u32("inputFaces count");
  if (faceCount != 0 && faceCount != shape.finestFaces)
    p.fail(at, "inputFaces count",
           std::to_string(faceCount) + " is neither 0 (absent) nor the " +
               std::to_string(shape.finestFaces) + " faces of level " + std::to_string(levels));
  p.checkFits(faceCount, 12, at, "inputFaces count");
  if (faceCount > 0) d.inputFaces = p.faces(faceCount, shape.finestVertices, "inputFaces");

  at = p.offset();
  const std::uint64_t stored = p.u64("checksum");
  const std::uint64_t computed = crc64(bytes.data(), at);
  if (stored != computed) {
    char hex[64];
    std::snprintf(hex, sizeof hex, "stored %016llx, computed %016llx",
                  static_cast<unsigned long long>(stored),
                  static_cast<unsigned long long>(computed));
    p.fail(at, "checksum", std::string("checksum mismatch: file is corrupt (") + hex + ")");
  }
  if (p.remaining() > 0)
    p.fail(p.offset(), "end of data",
           std::to_string(p.remaining()) + " trailing bytes after the checksum");
  return d;
}

// ---------------------------------------------------------------------------------
// Writing.

// Refuses anything readMra would refuse, so that a written file always reads back.
void checkWritable(const Decomposition& d, const std::string& target) {
  const auto bad = [&](const std::string& what) {
    throw Error(target + ": cannot write decomposition: " + what);
  };
  if (schemeCode(d.scheme) < 0) bad("unknown scheme value");
  if (kindCode(d.wavelets.kind) < 0) bad("unknown wavelet kind value");
  if (d.wavelets.rings < 0) bad("rings " + std::to_string(d.wavelets.rings) + " is negative");
  if (d.levels < 0 || d.levels > kMaxLevels)
    bad("levels " + std::to_string(d.levels) + " is outside 0.." + std::to_string(kMaxLevels));
  if (d.details.size() != static_cast<std::size_t>(d.levels))
    bad(std::to_string(d.details.size()) +
        " detail levels for levels = " + std::to_string(d.levels));
  const std::uint64_t n0 = static_cast<std::uint64_t>(d.base.rows());
  if (d.baseFaces.rows() == 0) bad("the base mesh has no faces");
  if (n0 > kMaxCount || static_cast<std::uint64_t>(d.baseFaces.rows()) > kMaxCount)
    bad("the base mesh is too large");
  const auto checkFaces = [&](const Faces& F, std::uint64_t n, const std::string& what) {
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      for (int c = 0; c < 3; ++c)
        if (F(f, c) < 0 || static_cast<std::uint64_t>(F(f, c)) >= n)
          bad(what + " face " + std::to_string(f) + " has vertex " + std::to_string(F(f, c)) +
              ", outside 0.." + std::to_string(static_cast<long long>(n) - 1));
      if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0))
        bad(what + " face " + std::to_string(f) + " repeats a vertex");
    }
  };
  const auto checkFinite = [&](const Points& P, const std::string& what) {
    if (!P.allFinite()) bad(what + " contain a non-finite value");
  };
  checkFaces(d.baseFaces, n0, "base");
  checkFinite(d.base, "base positions");
  validate(TriMesh{d.base, d.baseFaces, Points()}, target + ": base mesh");

  const Shape shape = refinementShape(d.baseFaces, n0, d.levels);
  for (int j = 0; j < d.levels; ++j) {
    const auto& D = d.details[static_cast<std::size_t>(j)];
    if (static_cast<std::uint64_t>(D.rows()) != shape.detailRows[static_cast<std::size_t>(j)])
      bad("level " + std::to_string(j) + " has " + std::to_string(D.rows()) +
          " detail rows, but M^" + std::to_string(j) + " has " +
          std::to_string(shape.detailRows[static_cast<std::size_t>(j)]) + " edges");
    checkFinite(D, "level " + std::to_string(j) + " details");
  }
  if (shape.finestVertices > kMaxCount || shape.finestFaces > kMaxCount)
    bad("level " + std::to_string(d.levels) + " is too large for the format");
  if (!d.inputOrder.empty()) {
    if (d.inputOrder.size() != shape.finestVertices)
      bad("inputOrder has " + std::to_string(d.inputOrder.size()) + " entries, but level " +
          std::to_string(d.levels) + " has " + std::to_string(shape.finestVertices) + " vertices");
    std::vector<char> seen(d.inputOrder.size(), 0);
    for (std::size_t i = 0; i < d.inputOrder.size(); ++i) {
      const int v = d.inputOrder[i];
      if (v < 0 || static_cast<std::size_t>(v) >= seen.size() || seen[static_cast<std::size_t>(v)])
        bad("inputOrder is not a permutation (entry " + std::to_string(i) + " is " +
            std::to_string(v) + ")");
      seen[static_cast<std::size_t>(v)] = 1;
    }
  }
  if (d.inputFaces.rows() != 0) {
    if (static_cast<std::uint64_t>(d.inputFaces.rows()) != shape.finestFaces)
      bad("inputFaces has " + std::to_string(d.inputFaces.rows()) + " rows, but level " +
          std::to_string(d.levels) + " has " + std::to_string(shape.finestFaces) + " faces");
    checkFaces(d.inputFaces, shape.finestVertices, "inputFaces");
  }
}

// Serialises little-endian through a sink in 64 KiB chunks, keeping a running CRC.
class Encoder {
 public:
  using Sink = std::function<void(const unsigned char*, std::size_t)>;
  explicit Encoder(Sink sink) : sink_(std::move(sink)) { buf_.reserve(kChunk); }

  void u8(std::uint8_t v) { put(&v, 1); }
  void u32(std::uint32_t v) {
    unsigned char b[4];
    for (int i = 0; i < 4; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
    put(b, 4);
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void u64(std::uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
    put(b, 8);
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void bytes(const unsigned char* p, std::size_t n) { put(p, n); }
  void points(const Points& P) {
    for (Eigen::Index r = 0; r < P.rows(); ++r)
      for (int c = 0; c < 3; ++c) f64(P(r, c));
  }
  void faces(const Faces& F) {
    for (Eigen::Index r = 0; r < F.rows(); ++r)
      for (int c = 0; c < 3; ++c) i32(F(r, c));
  }
  // Appends the CRC of everything written so far and hands the rest to the sink.
  void finish() {
    flush();
    u64(crc_);
    flush();
  }

 private:
  static constexpr std::size_t kChunk = 1 << 16;
  void put(const unsigned char* p, std::size_t n) {
    buf_.insert(buf_.end(), p, p + n);
    if (buf_.size() >= kChunk) flush();
  }
  void flush() {
    crc_ = crc64(buf_.data(), buf_.size(), crc_);
    sink_(buf_.data(), buf_.size());
    buf_.clear();
  }
  Sink sink_;
  std::vector<unsigned char> buf_;
  std::uint64_t crc_ = 0;
};

void encode(const Decomposition& d, Encoder& e) {
  e.bytes(kSignature.data(), kSignature.size());
  e.u32(kMraFormatVersion);
  e.u8(static_cast<std::uint8_t>(schemeCode(d.scheme)));
  e.u8(static_cast<std::uint8_t>(kindCode(d.wavelets.kind)));
  e.i32(d.wavelets.rings);
  e.u32(static_cast<std::uint32_t>(d.levels));
  e.u32(static_cast<std::uint32_t>(d.base.rows()));
  e.u32(static_cast<std::uint32_t>(d.baseFaces.rows()));
  e.faces(d.baseFaces);
  e.points(d.base);
  for (const Points& D : d.details) {
    e.u32(static_cast<std::uint32_t>(D.rows()));
    e.points(D);
  }
  e.u32(static_cast<std::uint32_t>(d.inputOrder.size()));
  for (int v : d.inputOrder) e.i32(v);
  e.u32(static_cast<std::uint32_t>(d.inputFaces.rows()));
  e.faces(d.inputFaces);
  e.finish();
}

std::string errnoText(int err) {
  return std::strerror(err);
}

}  // namespace

std::uint64_t crc64(const void* data, std::size_t size, std::uint64_t crc) {
  static const Crc64Table table;
  const auto* p = static_cast<const unsigned char*>(data);
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) crc = table.entry[(crc ^ p[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

void writeMra(std::ostream& out, const Decomposition& d, const std::string& name) {
  checkWritable(d, name);
  Encoder e([&](const unsigned char* p, std::size_t n) {
    out.write(reinterpret_cast<const char*>(p), static_cast<std::streamsize>(n));
    if (!out) throw Error(name + ": write failed");
  });
  encode(d, e);
  out.flush();
  if (!out) throw Error(name + ": write failed");
}

void writeMra(const std::string& path, const Decomposition& d) {
  checkWritable(d, path);
  writeFileAtomically(path, [&](std::ostream& out) { writeMra(out, d, path); });
}

Decomposition readMra(std::istream& in, const std::string& name) {
  // The header comes first so that a foreign file fails before it is read whole.
  std::vector<unsigned char> bytes(kSignature.size() + 4);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw Error(name + ": read error");
  checkSignature(bytes, name);

  // The rest grows with the data actually read, never with a count from the file:
  // through a fixed buffer, so that a small file costs little (growing `bytes` by a
  // zero-filled 1 MiB chunk per read cleared a megabyte for every file).
  unsigned char chunk[1 << 16];
  while (in) {
    in.read(reinterpret_cast<char*>(chunk), static_cast<std::streamsize>(sizeof chunk));
    bytes.insert(bytes.end(), chunk, chunk + in.gcount());
  }
  if (in.bad()) throw Error(name + ": read error");
  return parse(bytes, name);
}

Decomposition readMra(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open for reading: " + errnoText(errno));
  return readMra(in, path);
}

}  // namespace osdmra
