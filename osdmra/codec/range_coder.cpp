#include "osdmra/codec/range_coder.h"

namespace osdmra {

namespace {

constexpr std::uint32_t kTop = 1u << 24;  // renormalise when the range drops below
// Coded probabilities stay inside [kMinP, 65536 - kMinP], so neither outcome ever costs
// more than log2(65536 / 31) = 11 bits and every bound is a proper sub-range.
constexpr std::uint32_t kMinP = 31;

// Adaptation shift by how many decisions the context has seen: fast at first, then
// 1/64 (a window of about 64 decisions, which follows the drift of a zerotree's
// statistics from one bit plane to the next).
int adaptShift(std::uint8_t seen) {
  if (seen < 4) return 2;
  if (seen < 12) return 3;
  if (seen < 28) return 4;
  if (seen < 60) return 5;
  if (seen < 124) return 6;
  return 7;
}

}  // namespace

void BitModel::update(int bit) {
  const int shift = adaptShift(seen);
  if (seen < 255) ++seen;
  if (bit)
    state -= state >> shift;
  else
    state += (kOne - state) >> shift;
}

std::uint32_t BitModel::p0() const {
  const std::uint32_t p = state >> (kStateBits - 16);
  return p < kMinP ? kMinP : p > 65536 - kMinP ? 65536 - kMinP : p;
}

// ---- Encoder -------------------------------------------------------------------------

void RangeEncoder::shiftLow() {
  // A byte can leave once no carry can reach it: low below 0xFF000000, or a carry
  // that has just happened (bit 32 set) and resolves the pending run.
  if (static_cast<std::uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    const auto carry = static_cast<std::uint8_t>(low_ >> 32);
    std::uint8_t byte = cache_;
    do {
      if (first_)
        first_ = false;
      else
        out_.push_back(static_cast<std::uint8_t>(byte + carry));
      byte = 0xFF;
    } while (--pending_ != 0);
    cache_ = static_cast<std::uint8_t>(low_ >> 24);
  }
  ++pending_;
  low_ = (low_ & 0x00FFFFFFu) << 8;
}

void RangeEncoder::code(std::uint32_t bound, int bit) {
  if (bit) {
    low_ += bound;
    range_ -= bound;
  } else {
    range_ = bound;
  }
  while (range_ < kTop) {
    range_ <<= 8;
    shiftLow();
  }
}

void RangeEncoder::encode(BitModel& m, int bit) {
  code((range_ >> 16) * m.p0(), bit);
  m.update(bit);
}

void RangeEncoder::encodeEven(int bit) {
  code(range_ >> 1, bit);
}

void RangeEncoder::encodeBits(std::uint32_t value, int count) {
  for (int i = count - 1; i >= 0; --i) encodeEven((value >> i) & 1);
}

std::vector<std::uint8_t> RangeEncoder::finish() {
  for (int i = 0; i < 5; ++i) shiftLow();
  return std::move(out_);
}

// ---- Decoder -------------------------------------------------------------------------

RangeDecoder::RangeDecoder(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {
  for (int i = 0; i < 4; ++i, ++next_) {
    low_ = (low_ << 8) | byteAt(next_, 0x00);
    high_ = (high_ << 8) | byteAt(next_, 0xFF);
  }
}

int RangeDecoder::decide(std::uint32_t bound) {
  if (exhausted_) return 0;
  // Both registers are offsets from the interval's low end; the true stream lies
  // between them, so equal answers are the encoder's answer.
  const int bit = low_ >= bound;
  if (bit != (high_ >= bound)) {
    exhausted_ = true;
    return 0;
  }
  if (bit) {
    low_ -= bound;
    high_ -= bound;
    range_ -= bound;
  } else {
    range_ = bound;
  }
  while (range_ < kTop) {
    range_ <<= 8;
    low_ = (low_ << 8) | byteAt(next_, 0x00);
    high_ = (high_ << 8) | byteAt(next_, 0xFF);
    ++next_;
  }
  return bit;
}

int RangeDecoder::decode(BitModel& m) {
  const int bit = decide((range_ >> 16) * m.p0());
  if (!exhausted_) m.update(bit);
  return bit;
}

int RangeDecoder::decodeEven() {
  return decide(range_ >> 1);
}

std::uint32_t RangeDecoder::decodeBits(int count) {
  std::uint32_t v = 0;
  for (int i = 0; i < count; ++i) v = (v << 1) | static_cast<std::uint32_t>(decodeEven());
  return v;
}

}  // namespace osdmra
