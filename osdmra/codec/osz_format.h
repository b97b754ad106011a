// The .osz container: a progressive wavelet geometry stream (codec.h) in checked
// chunks.
//
// Format version 3 (since 2026-12-03: tangential weights follow the surface's bend,
// two more reals in HEAD). Version 2 streams (2026-11-27 to 2026-12-03) are read
// too, as version 3 with the bend gain 0 and the floor at the tangential weight;
// version 1's (before 2026-11-27, signs coded without a context) are refused, naming
// the versions this build reads. Integers and reals are little-endian; reals are IEEE f32 (the
// encoder quantises with exactly the f32 values it writes, so both sides compute
// the same numbers).
//
//   offset  size  field
//   0       8     signature 89 4F 53 5A 0D 0A 1A 0A  ("\x89OSZ\r\n\x1a\n", as PNG's)
//   8       1     u8 format version (3)
//   9             HEAD chunk:
//           4       tag "HEAD"
//           4       u32 payload length L (kHeadFixedBytes + the coded base mesh)
//           1       u8 scheme: 0 loop, 1 linear
//           1       u8 wavelet kind: 0 lazy, 1 quasi, 2 pre, 3 fixed
//           1       u8 rings (0..8)
//           1       u8 levels J (1..15)
//           4       u32 n_0, base vertices (3 .. 3 F_0)
//           4       u32 F_0, base faces (>= 1; F_0 4^J <= the reader's face limit)
//           1       i8 top bit plane of the coefficients (-1 .. 29)
//           1       u8 bits per base coordinate (1..31)
//           4       f32 step: quantisation step of the weighted coefficients (> 0)
//           4       f32 level gain g (1..4): level j is weighted g^(J-1-j)
//           4       f32 tangential weight (0, 1], the largest
//           4       f32 base step (> 0)
//           12      f32 x 3 base origin
//           4       f32 tangential floor (0, tangential weight] (not in version 2)
//           4       f32 bend gain [0, 1e6] (not in version 2)
//           L - 50  the base mesh, range coded with even probabilities: 3 F_0 vertex
//                   indices of ceil(log2 n_0) bits, then 3 n_0 coordinates of the
//                   declared bits (origin + k * base step)
//           4       u32 CRC-32 of the tag, length and payload
//   then          COEF chunk:
//           4       tag "COEF"
//           4       u32 D, bytes of coefficient data
//           4       u32 CRC-32 of the tag and D
//           ...     the data in blocks of kOszBlock bytes (the last may be shorter),
//                   each followed by the u32 CRC-32 of its bytes
//   then    nothing (trailing bytes are an error)
//
// The coefficient data is one range-coded zerotree stream (zerotree.h), ordered
// coarse bit planes first, so any prefix of the file decodes: a file cut inside the
// COEF chunk gives its whole blocks (checked) and the bytes of the block it cuts
// (which no checksum can vouch for yet), and the decoder uses exactly what those
// bytes determine. A file cut before the end of HEAD cannot decode; every other
// departure from this layout is an Error naming the field and offset.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "osdmra/mra/decomposition.h"

namespace osdmra {

constexpr std::uint8_t kOszFormatVersion = 3;
/// Coefficient bytes per checksummed block.
constexpr std::size_t kOszBlock = 1024;
/// Bytes of the HEAD payload before the coded base mesh (42 in version 2).
constexpr std::size_t kHeadFixedBytes = 50;

/// The fields of the HEAD chunk.
struct OszHeader {
  Scheme scheme = Scheme::Loop;
  WaveletOptions wavelets;
  int levels = 1;
  int baseVertices = 0, baseFaces = 0;
  int topPlane = -1;
  int baseBits = 1;
  float step = 1, levelGain = 2, tangentWeight = 1, baseStep = 1;
  std::array<float, 3> baseOrigin{};
  /// Tangential weights are clamp(bendGain * bend, tangentFloor, tangentWeight).
  float tangentFloor = 1, bendGain = 0;
};

/// A parsed (or to-be-written) .osz stream.
struct OszFile {
  OszHeader header;
  std::vector<std::uint8_t> base;          ///< the coded base mesh
  std::vector<std::uint8_t> coefficients;  ///< the coefficient data present
  /// The file ends before its declared end (a prefix of a stream): the last block
  /// read, or the COEF header, is incomplete.
  bool cut = false;
};

/// Bits per base vertex index: ceil(log2 n_0), at least 1.
int baseIndexBits(int baseVertices);

/// The bytes of a .osz file holding `f` (whole: `cut` is ignored). Throws Error for
/// values the format cannot hold.
std::vector<std::uint8_t> writeOsz(const OszFile& f);

/// Size of the file writeOsz makes with `baseBytes` of coded base and `coefficients`
/// bytes of coefficient data.
std::size_t oszSize(std::size_t baseBytes, std::size_t coefficients);

/// Parses and checks a .osz file, or any prefix of one that holds its HEAD chunk.
/// Checks every count against what the bytes can hold before anything is allocated,
/// and refuses streams whose finest level would exceed `maxFaces` triangles. Throws
/// Error starting with `name` and naming the field and byte offset.
OszFile readOsz(const std::uint8_t* data, std::size_t size, const std::string& name,
                long long maxFaces);

/// CRC-32 (ISO-HDLC, as zlib and PNG): the chunk and block checksum.
std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0);

}  // namespace osdmra
