// A binary range coder with context-adaptive bit models: the entropy coder of the
// .osz geometry codec (codec.h).
//
// The coder is LZMA's (Pavlov; the carry-propagating range coder of Subbotin and
// Martin's "range encoding", 1979): a 32-bit range, a 33-bit low with a pending
// 0xFF run for carries, bytes out most significant first. Probabilities are 16-bit,
// so a decision of probability 0.999 costs 0.0015 bits rather than the 0.02 bits an
// 11-bit model allows; zerotree coders make millions of such decisions.
//
// Each BitModel is one context: an adaptive estimate of P(bit = 0), updated after
// every decision with a rate that starts fast (the first decisions of a context say
// most about it) and settles to 1/128 (after Witten, Neal and Cleary, "Arithmetic
// coding for data compression", 1987, and AV1's counter-based adaptation).
//
// Truncation. A stream cut at any byte still tells exactly which of its first
// decisions it determines: the decoder runs two code registers, one reading the
// missing bytes as 0x00 and one as 0xFF. Every continuation of the prefix lies
// between those two values, so while both decode the same bit, that bit is the
// encoder's; at the first disagreement the prefix says no more, and the decoder
// reports itself exhausted instead of guessing. A complete (flushed) stream never
// disagrees. This is what lets every prefix of an .osz stream decode to the exact
// surface its bits describe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace osdmra {

/// One adaptive context: the probability that the next bit is 0.
struct BitModel {
  /// The estimate in 1/2^kStateBits. Kept finer than the 16 bits coded, so that
  /// slow adaptation (shift 7) still moves it and it can approach 0 or 1 closely.
  static constexpr int kStateBits = 28;
  static constexpr std::uint32_t kOne = 1u << kStateBits;
  std::uint32_t state = kOne / 2;
  std::uint8_t seen = 0;  ///< decisions so far, saturating: sets the adaptation rate
  inline void update(int bit);
  /// The coded probability of 0 in 1/65536, clamped away from 0 and 1.
  inline std::uint32_t p0() const;
};

class RangeEncoder {
 public:
  /// Codes `bit` (0 or 1) with the context `m`, then adapts `m`.
  inline void encode(BitModel& m, int bit);
  /// Codes `bit` with probability 1/2 and no context (signs, raw values).
  void encodeEven(int bit);
  /// Codes the low `count` bits of `value` (count <= 32), most significant first,
  /// each with probability 1/2.
  void encodeBits(std::uint32_t value, int count);

  /// Bytes the stream would have if it were finished now (an upper bound, exact to
  /// within the 4 bytes of the flush).
  std::size_t size() const { return out_.size() + pending_ + 4; }
  /// Flushes and returns the stream; the encoder must not be used afterwards.
  std::vector<std::uint8_t> finish();

 private:
  void code(std::uint32_t bound, int bit);
  void shiftLow();

  std::uint64_t low_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint8_t cache_ = 0;
  std::uint64_t pending_ = 1;  ///< bytes held back for a carry: cache_ then 0xFF runs
  bool first_ = true;          ///< LZMA's first byte is always 0 and is not written
  std::vector<std::uint8_t> out_;
};

class RangeDecoder {
 public:
  /// Decodes from `size` bytes at `data` (not copied; they must outlive the decoder).
  /// The bytes may be any prefix of an encoder's output (see the file comment).
  RangeDecoder(const std::uint8_t* data, std::size_t size);

  /// Decodes one bit with the context `m` and adapts `m`; 0, without adapting, once
  /// exhausted().
  inline int decode(BitModel& m);
  /// Decodes a bit coded by encodeEven.
  int decodeEven() { return decide(range_ >> 1); }
  /// Decodes `count` bits coded by encodeBits.
  std::uint32_t decodeBits(int count);

  /// True once a decision was asked for that the bytes given do not determine (a cut
  /// stream); every bit returned before that is exactly the encoder's.
  bool exhausted() const { return exhausted_; }

 private:
  inline int decide(std::uint32_t bound);
  std::uint8_t byteAt(std::size_t i, std::uint8_t pad) const { return i < size_ ? data_[i] : pad; }

  const std::uint8_t* data_;
  std::size_t size_, next_ = 0;
  std::uint32_t range_ = 0xFFFFFFFFu;
  std::uint32_t low_ = 0, high_ = 0;  ///< code registers: missing bytes as 0x00, 0xFF
  bool exhausted_ = false;
};

// ---- Inline definitions: a call per decision would cost as much as the decision ----

namespace range_coder_detail {

inline constexpr std::uint32_t kTop = 1u << 24;  // renormalise when the range drops below
// Coded probabilities stay inside [kMinP, 65536 - kMinP], so neither outcome ever costs
// more than log2(65536 / 31) = 11 bits and every bound is a proper sub-range.
inline constexpr std::uint32_t kMinP = 31;

// Adaptation shift by how many decisions the context has seen: fast at first (2 below
// 4, 3 below 12, 4 below 28, 5 below 60, 6 below 124), then 7, a window of about 128
// decisions, which follows the drift of a zerotree's statistics from one bit plane to
// the next. A table: this runs once per decision.
struct AdaptShifts {
  std::uint8_t shift[256];
  constexpr AdaptShifts() : shift() {
    for (int seen = 0; seen < 256; ++seen)
      shift[seen] = seen < 4     ? 2
                    : seen < 12  ? 3
                    : seen < 28  ? 4
                    : seen < 60  ? 5
                    : seen < 124 ? 6
                                 : 7;
  }
};
inline constexpr AdaptShifts kAdaptShifts{};

inline int adaptShift(std::uint8_t seen) {
  return kAdaptShifts.shift[seen];
}

}  // namespace range_coder_detail

inline void BitModel::update(int bit) {
  const int shift = range_coder_detail::adaptShift(seen);
  seen += seen < 255;
  // Both moves computed and one kept: the bit is as good as random to a branch predictor.
  const std::uint32_t down = state - (state >> shift), up = state + ((kOne - state) >> shift);
  state = bit ? down : up;
}

inline std::uint32_t BitModel::p0() const {
  const std::uint32_t p = state >> (kStateBits - 16);
  using range_coder_detail::kMinP;
  return p < kMinP ? kMinP : p > 65536 - kMinP ? 65536 - kMinP : p;
}

inline void RangeEncoder::encode(BitModel& m, int bit) {
  code((range_ >> 16) * m.p0(), bit);
  m.update(bit);
}

inline int RangeDecoder::decide(std::uint32_t bound) {
  if (exhausted_) return 0;
  // Both registers are offsets from the interval's low end; the true stream lies
  // between them, so equal answers are the encoder's answer.
  const int bit = low_ >= bound;
  if (bit != (high_ >= bound)) {
    exhausted_ = true;
    return 0;
  }
  // Without a branch on the bit (see BitModel::update).
  const std::uint32_t taken = bit ? bound : 0;
  low_ -= taken;
  high_ -= taken;
  range_ = bit ? range_ - bound : bound;
  while (range_ < range_coder_detail::kTop) {
    range_ <<= 8;
    low_ = (low_ << 8) | byteAt(next_, 0x00);
    high_ = (high_ << 8) | byteAt(next_, 0xFF);
    ++next_;
  }
  return bit;
}

inline int RangeDecoder::decode(BitModel& m) {
  const int bit = decide((range_ >> 16) * m.p0());
  if (!exhausted_) m.update(bit);
  return bit;
}

}  // namespace osdmra
