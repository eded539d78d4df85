// Random valid requests and responses (fixed seed) survive encode -> decode unchanged, and
// decode -> encode reproduces the bytes.
#include <random>

#include "ldoem/protocol/messages.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

class Generator {
 public:
  explicit Generator(std::uint32_t seed) : rng_(seed) {}

  std::uint16_t word() { return static_cast<std::uint16_t>(rng_()); }
  std::uint16_t below(unsigned bound) { return static_cast<std::uint16_t>(rng_() % bound); }
  bool coin() { return (rng_() & 1) != 0; }
  template <class T>
  T pick(std::initializer_list<T> options) {
    return options.begin()[rng_() % options.size()];
  }

  ConfigBody config(bool allow_pad) {
    switch (below(5)) {
      case 0: return SerialConfig{word(), word(), word(), word()};
      case 1: return CanConfig{word(), word(), word(), word(), word()};
      case 2: return EthernetConfig{{word(), word(), word(), word()}, {word(), word(), word(), word()},
                                    {word(), word(), word(), word()}, word(), word()};
      case 3: return GlobalConfig{word(), word(), word(), allow_pad && coin()};
      default: return InterlaceConfig{word()};
    }
  }

  StatusBlock status() {
    return StatusBlock{{static_cast<std::uint8_t>(word()), static_cast<std::uint8_t>(word()), 0},
                       StatusByte::from_byte(static_cast<std::uint8_t>(word()))};
  }

  Request request() {
    switch (below(18)) {
      case 0: return GetIdentification{pick<std::uint16_t>({0x00, 0x01, 0x02, 0x03, 0x04, 0x10, 0x11, 0x12, 0x20, 0x21, 0x22})};
      case 1: return GetStatus{coin()};
      case 2: return GetSignal{coin()};
      case 3: return SetSignal{word()};
      case 4: return SetConfig{config(true)};
      case 5: return GetConfig{pick<std::uint16_t>({0x01, 0x02, 0x05, 0x10, 0x11})};
      case 6: return SetTimeAbs{word()};
      case 7: return SetTimeRel{static_cast<std::int16_t>(word())};
      case 8: return GetSyncClock{coin()};
      case 9: return SetFilter{1, below(2)};
      case 10: return SetFunction{word(), word(), word(), word()};
      case 11: return GetFunction{below(8)};
      case 12: return GetProfile{word(), word()};
      case 13: return CancelProfile{coin()};
      case 14: return DoReset{pick<std::uint16_t>({0, 1, 2, 0x10})};
      case 15: return TransIdle{coin()};
      case 16: return TransRotate{word()};
      default: return TransMeasure{coin()};
    }
  }

  Response response() {
    switch (below(18)) {
      case 0: {
        std::string text(below(20), ' ');
        for (auto& c : text) c = static_cast<char>(1 + below(255));  // any byte but NUL (D3)
        return IdentificationReply{text};
      }
      case 1: {
        Bytes extra(below(3) * 2);
        for (auto& byte : extra) byte = static_cast<std::uint8_t>(word());
        return GetStatusReply{status(), extra};
      }
      case 2: return GetSignalReply{word()};
      case 3: return SetSignalReply{word()};
      case 4: return SetConfigReply{word()};
      case 5: return GetConfigReply{config(false)};
      case 6: return SetTimeAbsReply{word()};
      case 7: return SetTimeRelReply{word()};
      case 8: return SyncClockReply{word()};
      case 9: return SetFilterReply{word()};
      case 10: return SetFunctionReply{word()};
      case 11: return GetFunctionReply{word(), word(), word()};
      case 12: return CancelProfileReply{status()};
      case 13: return DoResetReply{word()};
      case 14: return TransIdleReply{status()};
      case 15: return TransRotateReply{status()};
      case 16: return TransMeasureReply{status(), word()};
      default: return ServiceFailure{word(), static_cast<FailureReason>(word())};
    }
  }

 private:
  std::mt19937 rng_;
};

TEST(RequestRoundTrip, RandomRequests_SurviveEncodeDecode) {
  Generator generate(42);
  for (int trial = 0; trial < 3000; ++trial) {
    const Request request = generate.request();
    const Bytes payload = encode_request(request);
    const auto decoded = decode_request(payload);
    ASSERT_TRUE(decoded.has_value()) << format_telegram(payload) << ": " << describe(decoded.error().detail);
    EXPECT_EQ(*decoded, request);
    EXPECT_EQ(encode_request(*decoded), payload);
  }
}

TEST(ResponseRoundTrip, RandomResponses_SurviveEncodeDecode) {
  Generator generate(4242);
  for (int trial = 0; trial < 3000; ++trial) {
    const Response response = generate.response();
    const Bytes payload = encode_response(response);
    const auto decoded = decode_response(payload);
    ASSERT_TRUE(decoded.has_value()) << format_telegram(payload) << ": " << describe(decoded.error());
    EXPECT_EQ(*decoded, response);
    EXPECT_EQ(encode_response(*decoded), payload);
  }
}

// Any payload: decode never crashes, and whatever decodes re-encodes to the same bytes.
TEST(DecodeRandomBytes, WhateverDecodes_ReencodesIdentically) {
  std::mt19937 rng(99);
  const std::uint16_t codes[] = {0x0101, 0x0102, 0x0201, 0x0202, 0x020A, 0x0301, 0x0401, 0x0404,
                                 0x8101, 0x8102, 0x8202, 0x8301, 0x8404, 0xFF00};
  for (int trial = 0; trial < 5000; ++trial) {
    Bytes payload;
    append_word_be(payload, codes[rng() % std::size(codes)]);
    const std::size_t extra = rng() % 24;
    for (std::size_t i = 0; i < extra; ++i) payload.push_back(static_cast<std::uint8_t>(rng() % 3 == 0 ? rng() : 0));
    if (const auto request = decode_request(payload)) {
      EXPECT_EQ(encode_request(*request), payload);
    }
    // A GET_IDENTIFICATION reply drops what follows a NUL; everything else is exact.
    const auto response = decode_response(payload);
    if (response && !std::holds_alternative<IdentificationReply>(*response)) {
      EXPECT_EQ(encode_response(*response), payload);
    }
  }
}

}  // namespace
}  // namespace ldoem::protocol
