// Helpers shared by the mesh writers: a buffered, locale-independent output of
// exact decimals and little-endian binary, and the check that what is written will
// read back. Internal: not installed.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstring>
#include <ostream>
#include <string>
#include <string_view>

#include "osdmra/mesh/detail/text.h"
#include "osdmra/mesh/io.h"

namespace osdmra::detail {

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
/// reads back: throws Error naming the first non-finite vertex or bad index.
void checkWritable(const TriMesh& mesh);
/// Whether the writers emit normals: asked for, and one per vertex.
bool writesNormals(const TriMesh& mesh, const WriteOptions& opts);

}  // namespace osdmra::detail
