// The .mra coefficient file: one Decomposition, stored exactly (bit for bit).
//
// Format version 1. All integers and doubles are little-endian, packed with no
// padding; "count" fields are u32 and never exceed 2^31 - 1.
//
//   offset  size        field
//   0       8           signature 89 4D 52 41 0D 0A 1A 0A  ("\x89MRA\r\n\x1a\n")
//   8       4  u32      format version (1)
//   12      1  u8       scheme: 0 loop, 1 linear
//   13      1  u8       wavelet kind: 0 lazy, 1 quasi, 2 pre, 3 fixed
//   14      4  i32      rings (>= 0)
//   18      4  u32      levels J (0..15)
//   22      4  count    n_0, base vertex count
//   26      4  count    F_0, base face count (>= 1)
//   30      12 F_0      base faces, i32 x 3 per face, indices in 0..n_0-1
//   ..      24 n_0      base positions c^0, f64 x 3 per vertex
//   then for j = 0..J-1:
//           4  count    rows of d^j; must equal E_j, the edge count of M^j
//           24 rows     d^j, f64 x 3 per row
//   then    4  count    inputOrder length: 0 (absent) or n_J
//           4  each     inputOrder, i32, a permutation of 0..n_J-1
//   then    4  count    inputFaces rows: 0 (absent) or F_J = 4^J F_0
//           12 each     inputFaces, i32 x 3, indices in 0..n_J-1
//   then    8  u64      CRC-64/XZ of every byte before it
//
// The detail counts follow from the base mesh alone: uniform 1-to-4 refinement of
// a triangle mesh gives n_{j+1} = n_j + E_j, F_{j+1} = 4 F_j and
// E_{j+1} = 2 E_j + 3 F_j, so the reader knows every size before it allocates.
//
// The signature follows PNG's design: the non-ASCII first byte catches 7-bit
// transfers, and CR LF, ^Z, LF catch line-ending conversion and text-mode reads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <string>

#include "osdmra/mra/decomposition.h"

namespace osdmra {

/// The format version this build writes; it reads exactly this version.
constexpr std::uint32_t kMraFormatVersion = 1;

/// Writes `d` to `path` atomically: the bytes go to a temporary file in the same
/// directory which then replaces `path`, so `path` is never half-written.
/// Throws Error, naming `path`, when `d` is inconsistent (the same checks readMra
/// makes, so every file written can be read back) or the file cannot be written.
void writeMra(const std::string& path, const Decomposition& d);
/// Same, to a binary stream; `name` labels error messages.
void writeMra(std::ostream& out, const Decomposition& d, const std::string& name = "<stream>");

/// Reads and fully checks a .mra file. Throws Error, naming `path` and the field
/// and byte offset at fault, for a foreign or truncated file, an unsupported
/// version, an inconsistent or out-of-range value, a checksum mismatch or trailing
/// bytes. Never allocates more than the file's size justifies.
Decomposition readMra(const std::string& path);
/// Same, from a binary stream read to its end; `name` labels error messages.
Decomposition readMra(std::istream& in, const std::string& name = "<stream>");

/// CRC-64/XZ (ECMA-182 polynomial, reflected, init and xorout all ones), the .mra
/// trailer checksum. Chainable: crc64(b, nb, crc64(a, na)) == crc64 of a then b.
std::uint64_t crc64(const void* data, std::size_t size, std::uint64_t crc = 0);

}  // namespace osdmra
