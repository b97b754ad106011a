#include "osdmra/codec/range_coder.h"

namespace osdmra {

using range_coder_detail::kTop;

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

std::uint32_t RangeDecoder::decodeBits(int count) {
  std::uint32_t v = 0;
  for (int i = 0; i < count; ++i) v = (v << 1) | static_cast<std::uint32_t>(decodeEven());
  return v;
}

}  // namespace osdmra
