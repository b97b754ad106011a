#include "osdmra/codec/osz_format.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

#include "osdmra/base/error.h"

namespace osdmra {

namespace {

constexpr std::array<std::uint8_t, 8> kSignature = {0x89, 'O', 'S', 'Z', '\r', '\n', 0x1A, '\n'};
constexpr int kMaxLevels = 15;

struct Crc32Table {
  std::array<std::uint32_t, 256> entry{};
  Crc32Table() {
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
      entry[i] = c;
    }
  }
};

// Enum codes spelled out, so that reordering an enum never changes existing files.
int schemeCode(Scheme s) {
  return s == Scheme::Loop ? 0 : 1;
}
int kindCode(WaveletKind k) {
  return static_cast<int>(k);  // 0 lazy, 1 quasi, 2 pre, 3 fixed (decomposition.h)
}

// ---- Writing -----------------------------------------------------------------------

class Writer {
 public:
  std::vector<std::uint8_t> bytes;
  void u8(unsigned v) { bytes.push_back(static_cast<std::uint8_t>(v)); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8((v >> (8 * i)) & 0xFF);
  }
  void f32(float v) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    u32(u);
  }
  void raw(const std::uint8_t* p, std::size_t n) { bytes.insert(bytes.end(), p, p + n); }
  void crcFrom(std::size_t start) { u32(crc32(bytes.data() + start, bytes.size() - start)); }
};

void checkHeader(const OszFile& f) {
  const OszHeader& h = f.header;
  const auto finite = [](float v) { return std::isfinite(v); };
  if (h.levels < 1 || h.levels > kMaxLevels || h.baseFaces < 1 || h.baseVertices < 3 ||
      h.topPlane < -1 || h.topPlane > 29 || h.baseBits < 1 || h.baseBits > 31 ||
      h.wavelets.rings < 0 || h.wavelets.rings > 8 || !(h.step > 0) || !finite(h.step) ||
      !(h.levelGain >= 1 && h.levelGain <= 4) || !(h.tangentWeight > 0 && h.tangentWeight <= 1) ||
      !(h.tangentFloor > 0 && h.tangentFloor <= h.tangentWeight) ||
      !(h.bendGain >= 0 && h.bendGain <= 1e6) || !(h.baseStep > 0) || !finite(h.baseStep) ||
      !finite(h.baseOrigin[0]) || !finite(h.baseOrigin[1]) || !finite(h.baseOrigin[2]))
    throw Error("writeOsz: a header field is out of the format's range");
  if (f.coefficients.size() > UINT32_MAX || f.base.size() > UINT32_MAX - kHeadFixedBytes)
    throw Error("writeOsz: the stream is too large for the format");
}

}  // namespace

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc) {
  static const Crc32Table table;
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) crc = table.entry[(crc ^ data[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

int baseIndexBits(int baseVertices) {
  int bits = 1;
  while (bits < 31 && (1LL << bits) < baseVertices) ++bits;
  return bits;
}

std::size_t oszSize(std::size_t baseBytes, std::size_t coefficients) {
  const std::size_t blocks = (coefficients + kOszBlock - 1) / kOszBlock;
  return kSignature.size() + 1 + 12 + kHeadFixedBytes + baseBytes + 12 + coefficients + 4 * blocks;
}

std::vector<std::uint8_t> writeOsz(const OszFile& f) {
  checkHeader(f);
  const OszHeader& h = f.header;
  Writer w;
  w.raw(kSignature.data(), kSignature.size());
  w.u8(kOszFormatVersion);
  std::size_t start = w.bytes.size();
  w.raw(reinterpret_cast<const std::uint8_t*>("HEAD"), 4);
  w.u32(static_cast<std::uint32_t>(kHeadFixedBytes + f.base.size()));
  w.u8(schemeCode(h.scheme));
  w.u8(kindCode(h.wavelets.kind));
  w.u8(h.wavelets.rings);
  w.u8(h.levels);
  w.u32(h.baseVertices);
  w.u32(h.baseFaces);
  w.u8(static_cast<std::uint8_t>(static_cast<std::int8_t>(h.topPlane)));
  w.u8(h.baseBits);
  for (float v : {h.step, h.levelGain, h.tangentWeight, h.baseStep, h.baseOrigin[0],
                  h.baseOrigin[1], h.baseOrigin[2], h.tangentFloor, h.bendGain})
    w.f32(v);
  w.raw(f.base.data(), f.base.size());
  w.crcFrom(start);
  start = w.bytes.size();
  w.raw(reinterpret_cast<const std::uint8_t*>("COEF"), 4);
  w.u32(static_cast<std::uint32_t>(f.coefficients.size()));
  w.crcFrom(start);
  for (std::size_t at = 0; at < f.coefficients.size(); at += kOszBlock) {
    const std::size_t n = std::min(kOszBlock, f.coefficients.size() - at);
    w.raw(f.coefficients.data() + at, n);
    w.u32(crc32(f.coefficients.data() + at, n));
  }
  return std::move(w.bytes);
}

// ---- Reading -----------------------------------------------------------------------

namespace {

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size, const std::string& name)
      : data_(data), size_(size), name_(name) {}

  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return size_ - pos_; }
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw Error(name_ + ": byte " + std::to_string(at) + ": " + what);
  }
  // The HEAD chunk must be whole: nothing decodes without it.
  void need(std::size_t n, const std::string& field) const {
    if (remaining() < n)
      fail(pos_, "truncated in " + field + " (" + std::to_string(size_) +
                     " bytes; the header and base mesh must be complete before anything decodes)");
  }
  std::uint32_t u8(const std::string& field) {
    need(1, field);
    return data_[pos_++];
  }
  std::uint32_t u32(const std::string& field) {
    need(4, field);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t{data_[pos_ + i]} << (8 * i);
    pos_ += 4;
    return v;
  }
  float f32(const std::string& field) {
    const std::uint32_t u = u32(field);
    float v;
    std::memcpy(&v, &u, 4);
    return v;
  }
  const std::uint8_t* take(std::size_t n, const std::string& field) {
    need(n, field);
    pos_ += n;
    return data_ + pos_ - n;
  }
  const std::uint8_t* at(std::size_t offset) const { return data_ + offset; }

 private:
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
  std::string name_;
};

// The format version, after the signature: 2 or 3.
int readSignature(Reader& r) {
  const std::size_t n = std::min(r.remaining(), kSignature.size());
  if (std::memcmp(r.at(0), kSignature.data(), n) != 0)
    r.fail(0, "not an osdmra compressed surface (.osz): the signature is missing");
  r.take(kSignature.size(), "signature");
  const std::size_t at = r.offset();
  const std::uint32_t version = r.u8("format version");
  if (version != 2 && version != kOszFormatVersion)
    r.fail(at, "format version " + std::to_string(version) + " (this build reads versions 2 and " +
                   std::to_string(kOszFormatVersion) + ")");
  return static_cast<int>(version);
}

// Bytes of HEAD's payload before the coded base mesh, by format version.
std::size_t headFixedBytes(int version) {
  return version == 2 ? kHeadFixedBytes - 8 : kHeadFixedBytes;
}

void expectTag(Reader& r, const char* tag) {
  const std::size_t at = r.offset();
  if (std::memcmp(r.take(4, std::string(tag) + " tag"), tag, 4) != 0)
    r.fail(at, std::string("expected the ") + tag + " chunk");
}

// The fixed fields of HEAD, each checked as it is read.
OszHeader readHeadFields(Reader& r, int version) {
  OszHeader h;
  std::size_t at = r.offset();
  const std::uint32_t scheme = r.u8("scheme"), kind = r.u8("wavelet kind");
  if (scheme > 1) r.fail(at, "scheme code " + std::to_string(scheme) + " (0 loop, 1 linear)");
  if (kind > 3)
    r.fail(at + 1, "wavelet kind " + std::to_string(kind) + " (0 lazy, 1 quasi, 2 pre, 3 fixed)");
  h.scheme = scheme == 0 ? Scheme::Loop : Scheme::Linear;
  h.wavelets.kind = static_cast<WaveletKind>(kind);
  at = r.offset();
  h.wavelets.rings = static_cast<int>(r.u8("rings"));
  if (h.wavelets.rings > 8) r.fail(at, "rings " + std::to_string(h.wavelets.rings) + " (0..8)");
  at = r.offset();
  h.levels = static_cast<int>(r.u8("levels"));
  if (h.levels < 1 || h.levels > kMaxLevels)
    r.fail(at, "levels " + std::to_string(h.levels) + " (1.." + std::to_string(kMaxLevels) + ")");
  at = r.offset();
  const std::uint32_t n0 = r.u32("base vertex count"), f0 = r.u32("base face count");
  if (f0 < 1 || f0 > INT_MAX) r.fail(at + 4, "base face count " + std::to_string(f0));
  if (n0 < 3 || n0 > 3ull * f0)
    r.fail(at, "base vertex count " + std::to_string(n0) + " (3.." + std::to_string(3ull * f0) +
                   " for " + std::to_string(f0) + " faces)");
  h.baseVertices = static_cast<int>(n0);
  h.baseFaces = static_cast<int>(f0);
  at = r.offset();
  h.topPlane = static_cast<std::int8_t>(r.u8("top plane"));
  if (h.topPlane < -1 || h.topPlane > 29) r.fail(at, "top plane " + std::to_string(h.topPlane));
  at = r.offset();
  h.baseBits = static_cast<int>(r.u8("base coordinate bits"));
  if (h.baseBits < 1 || h.baseBits > 31)
    r.fail(at, "base coordinate bits " + std::to_string(h.baseBits));
  at = r.offset();
  h.step = r.f32("step");
  h.levelGain = r.f32("level gain");
  h.tangentWeight = r.f32("tangential weight");
  h.baseStep = r.f32("base step");
  for (float& o : h.baseOrigin) o = r.f32("base origin");
  if (!(h.step > 0) || !std::isfinite(h.step)) r.fail(at, "step is not a positive number");
  if (!(h.levelGain >= 1 && h.levelGain <= 4)) r.fail(at + 4, "level gain outside [1, 4]");
  if (!(h.tangentWeight > 0 && h.tangentWeight <= 1))
    r.fail(at + 8, "tangential weight outside (0, 1]");
  if (!(h.baseStep > 0) || !std::isfinite(h.baseStep)) r.fail(at + 12, "base step is not positive");
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(h.baseOrigin[i])) r.fail(at + 16 + 4 * i, "base origin is not finite");
  h.tangentFloor = h.tangentWeight;  // version 2: one tangential weight
  if (version == 2) return h;
  at = r.offset();
  h.tangentFloor = r.f32("tangential floor");
  h.bendGain = r.f32("bend gain");
  if (!(h.tangentFloor > 0 && h.tangentFloor <= h.tangentWeight))
    r.fail(at, "tangential floor outside (0, tangential weight]");
  if (!(h.bendGain >= 0 && h.bendGain <= 1e6)) r.fail(at + 4, "bend gain outside [0, 1e6]");
  return h;
}

void checkSizes(Reader& r, const OszHeader& h, std::size_t baseBytes, std::size_t at,
                long long maxFaces) {
  // Raw bits cost exactly one bit each in the range coder, so the coded base is at
  // least this long: this bounds F_0 and n_0 by the file's size.
  const double bits =
      3.0 * h.baseFaces * baseIndexBits(h.baseVertices) + 3.0 * h.baseVertices * h.baseBits;
  if (8.0 * (static_cast<double>(baseBytes) + 1) < bits)
    r.fail(at, "the base mesh needs " + std::to_string(static_cast<long long>(bits / 8)) +
                   " bytes for " + std::to_string(h.baseFaces) + " faces and " +
                   std::to_string(h.baseVertices) + " vertices, the chunk has " +
                   std::to_string(baseBytes));
  if (static_cast<double>(h.baseFaces) * std::pow(4.0, h.levels) > static_cast<double>(maxFaces))
    r.fail(at, std::to_string(h.baseFaces) + " base faces refined " + std::to_string(h.levels) +
                   " times exceed the limit of " + std::to_string(maxFaces) + " triangles");
}

OszHeader readHead(Reader& r, int version, std::vector<std::uint8_t>& base, long long maxFaces) {
  const std::size_t fixed = headFixedBytes(version);
  const std::size_t start = r.offset();
  expectTag(r, "HEAD");
  const std::size_t lengthAt = r.offset();
  const std::uint32_t length = r.u32("HEAD length");
  if (length < fixed) r.fail(lengthAt, "HEAD length " + std::to_string(length));
  r.need(length + 4, "the HEAD chunk");  // before any field is trusted
  const std::uint32_t expected = crc32(r.at(start), 8 + length);
  const OszHeader h = readHeadFields(r, version);
  const std::uint8_t* coded = r.take(length - fixed, "base mesh");
  const std::size_t crcAt = r.offset();
  if (r.u32("HEAD checksum") != expected) r.fail(crcAt, "HEAD checksum mismatch: corrupt header");
  checkSizes(r, h, length - fixed, lengthAt, maxFaces);
  base.assign(coded, coded + (length - fixed));
  return h;
}

// The coefficient data present, block by block; a cut file keeps what it has.
void readCoefficients(Reader& r, OszFile& f) {
  if (r.remaining() < 12) {  // cut inside the COEF header: no coefficients yet
    f.cut = true;            // a whole file always has the COEF header
    r.take(r.remaining(), "COEF header");
    return;
  }
  const std::size_t start = r.offset();
  expectTag(r, "COEF");
  const std::uint32_t declared = r.u32("COEF length");
  const std::size_t crcAt = r.offset();
  if (r.u32("COEF checksum") != crc32(r.at(start), 8))
    r.fail(crcAt, "COEF header checksum mismatch");
  const std::size_t blocks = (declared + kOszBlock - 1) / kOszBlock;
  const std::size_t full = declared + 4 * blocks;
  if (r.remaining() > full) r.fail(start + 12 + full, "trailing bytes after the stream");
  f.coefficients.reserve(std::min<std::size_t>(declared, r.remaining()));
  if (r.remaining() < full) f.cut = true;
  for (std::size_t b = 0; b < blocks && r.remaining() > 0; ++b) {
    const std::size_t at = r.offset();
    const std::size_t n = std::min(kOszBlock, declared - b * kOszBlock);
    const std::size_t present = std::min(n, r.remaining());
    const std::uint8_t* data = r.take(present, "coefficients");
    f.coefficients.insert(f.coefficients.end(), data, data + present);
    if (r.remaining() < 4) {  // cut inside this block or its checksum: unverifiable
      f.cut = true;
      r.take(r.remaining(), "coefficients");
      break;
    }
    if (r.u32("block checksum") != crc32(data, n))
      r.fail(at, "coefficient block " + std::to_string(b) + " checksum mismatch: corrupt data");
  }
}

}  // namespace

OszFile readOsz(const std::uint8_t* data, std::size_t size, const std::string& name,
                long long maxFaces) {
  Reader r(data, size, name);
  const int version = readSignature(r);
  OszFile f;
  f.header = readHead(r, version, f.base, maxFaces);
  readCoefficients(r, f);
  return f;
}

}  // namespace osdmra
