// The range coder (codec/range_coder.h): exact round trips, sizes near the entropy,
// and truncated streams that decode exactly the decisions they determine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "osdmra/codec/range_coder.h"

namespace osdmra {
namespace {

struct Message {
  std::vector<int> bits;     ///< the decisions
  std::vector<int> context;  ///< which BitModel codes each decision
  double entropyBits = 0;    ///< -sum log2 P(bit) under the true source
};

/// Decisions from `contexts` Bernoulli sources with P(1) spread over (0, pMax].
Message skewedSource(int count, int contexts, double pMax, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<double> p1(contexts);
  for (int c = 0; c < contexts; ++c) p1[c] = pMax * (c + 1) / contexts;
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_int_distribution<int> pick(0, contexts - 1);
  Message m;
  for (int i = 0; i < count; ++i) {
    const int c = pick(rng);
    const int bit = u(rng) < p1[c];
    m.bits.push_back(bit);
    m.context.push_back(c);
    m.entropyBits -= std::log2(bit ? p1[c] : 1 - p1[c]);
  }
  return m;
}

std::vector<std::uint8_t> encode(const Message& m, int contexts) {
  RangeEncoder enc;
  std::vector<BitModel> models(contexts);
  for (std::size_t i = 0; i < m.bits.size(); ++i) enc.encode(models[m.context[i]], m.bits[i]);
  return enc.finish();
}

/// The decisions decoded before the decoder is exhausted (all of them, at most).
std::vector<int> decode(const std::vector<std::uint8_t>& bytes, std::size_t size, const Message& m,
                        int contexts) {
  RangeDecoder dec(bytes.data(), size);
  std::vector<BitModel> models(contexts);
  std::vector<int> out;
  for (std::size_t i = 0; i < m.bits.size(); ++i) {
    const int bit = dec.decode(models[m.context[i]]);
    if (dec.exhausted()) break;
    out.push_back(bit);
  }
  return out;
}

TEST(RangeCoder, SkewedContextsRoundTripNearTheEntropy) {
  for (double pMax : {0.5, 0.1, 0.01}) {
    const int contexts = 8;
    const Message m = skewedSource(200000, contexts, pMax, 7);
    const std::vector<std::uint8_t> bytes = encode(m, contexts);
    EXPECT_EQ(decode(bytes, bytes.size(), m, contexts), m.bits) << pMax;
    // An adaptive model pays for tracking: a moving average with rate 1/128 has
    // variance about p(1-p)/256, which costs 1/(512 ln 2) = 0.0028 bits per decision
    // over the entropy whatever p is; learning and the flush add a few dozen bytes.
    const double bits = 8.0 * bytes.size(), excess = (bits - m.entropyBits) / m.bits.size();
    EXPECT_LT(excess, 0.0028 * 1.1 + 160.0 / m.bits.size())
        << "pMax " << pMax << " excess " << excess;
    EXPECT_GT(excess, 0.0) << "pMax " << pMax;  // no free lunch
  }
}

TEST(RangeCoder, NearlyCertainDecisionsCostAlmostNothing) {
  // 16-bit probabilities: 100,000 zeros in one context fit in a few dozen bytes
  // (11-bit LZMA models would need about 250).
  Message m;
  m.bits.assign(100000, 0);
  m.context.assign(100000, 0);
  const std::vector<std::uint8_t> bytes = encode(m, 1);
  EXPECT_LT(bytes.size(), 40u);
  EXPECT_EQ(decode(bytes, bytes.size(), m, 1), m.bits);
}

TEST(RangeCoder, EvenBitsAndRawValuesRoundTrip) {
  std::mt19937 rng(3);
  std::vector<std::uint32_t> values;
  std::vector<int> widths;
  RangeEncoder enc;
  BitModel model;
  for (int i = 0; i < 5000; ++i) {
    const int w = 1 + static_cast<int>(rng() % 32);
    const std::uint32_t v = w == 32 ? rng() : rng() & ((1u << w) - 1);
    values.push_back(v);
    widths.push_back(w);
    enc.encodeBits(v, w);
    enc.encode(model, static_cast<int>(v & 1));  // interleaved with modelled bits
  }
  const std::size_t estimate = enc.size();
  const std::vector<std::uint8_t> bytes = enc.finish();
  EXPECT_LE(bytes.size(), estimate);
  RangeDecoder dec(bytes.data(), bytes.size());
  BitModel dmodel;
  for (std::size_t i = 0; i < values.size(); ++i) {
    ASSERT_EQ(dec.decodeBits(widths[i]), values[i]) << i;
    ASSERT_EQ(dec.decode(dmodel), static_cast<int>(values[i] & 1)) << i;
  }
  EXPECT_FALSE(dec.exhausted());
}

TEST(RangeCoder, EveryPrefixDecodesExactlyWhatItDetermines) {
  const int contexts = 4;
  const Message m = skewedSource(20000, contexts, 0.2, 11);
  // After decision k the encoder could stop with enc.size() bytes, and the final
  // stream agrees with that one on every byte that fixes decision k: so a prefix of
  // that many bytes must decode decisions 0..k.
  RangeEncoder enc;
  std::vector<BitModel> models(contexts);
  std::vector<std::size_t> sizeAfter;
  for (std::size_t i = 0; i < m.bits.size(); ++i) {
    enc.encode(models[m.context[i]], m.bits[i]);
    sizeAfter.push_back(enc.size());
  }
  const std::vector<std::uint8_t> bytes = enc.finish();
  std::size_t previous = 0;
  for (std::size_t size = 0; size <= bytes.size(); ++size) {
    const std::vector<int> got = decode(bytes, size, m, contexts);
    // A prefix of the message, never a guess ...
    ASSERT_LE(got.size(), m.bits.size());
    ASSERT_TRUE(std::equal(got.begin(), got.end(), m.bits.begin())) << "size " << size;
    // ... that grows with the bytes given ...
    ASSERT_GE(got.size(), previous) << "size " << size;
    previous = got.size();
    // ... and holds every decision the bytes determine.
    const auto determined = static_cast<std::size_t>(
        std::upper_bound(sizeAfter.begin(), sizeAfter.end(), size) - sizeAfter.begin());
    ASSERT_GE(got.size(), determined) << "size " << size;
  }
  EXPECT_EQ(previous, m.bits.size());  // the whole stream decodes everything
}

TEST(RangeCoder, GarbageDecodesWithoutFault) {
  // Any bytes are a valid input: the decoder returns bits (never crashes), and the
  // container's checksums are what tell garbage apart.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::uint8_t> bytes(rng() % 64);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    RangeDecoder dec(bytes.data(), bytes.size());
    BitModel model;
    for (int i = 0; i < 1000; ++i) {
      const int bit = i % 3 ? dec.decode(model) : dec.decodeEven();
      ASSERT_TRUE(bit == 0 || bit == 1);
    }
  }
}

}  // namespace
}  // namespace osdmra
