// Shared by the Scanner tests (scanner_test.cpp: lifecycle and every service's bytes;
// scanner_replies_test.cpp: profile streams, reply matching, timeouts): spec-vector payloads and
// the ScannerTest fixture, a Scanner over a FakeTransport that answers from a script. In a named
// namespace: GoogleTest wants one fixture type for the suite across both files.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "fake_transport.hpp"
#include "ldoem/driver/scanner.hpp"
#include "test_support.hpp"

namespace ldoem::driver::scanner_test {

namespace p = protocol;
using test::encoded;
using test::FakeTransport;
using test::kStatusIdle;
using test::SpecVectors;
using test::tcp_payload;

inline Bytes request_payload(const std::string& name) { return tcp_payload(SpecVectors::get().request(name)); }
inline Bytes reply_payload(const std::string& name) { return tcp_payload(SpecVectors::get().reply(name)); }

inline Bytes failure(std::uint16_t request_code, p::FailureReason reason) {
  return encoded(p::Response{p::ServiceFailure{request_code, reason}});
}

inline const Bytes kProfileRange = reply_payload(
    "Profile 0x39FF: sent 1, count 100, layer 0, sector 0, step 0.5°, 3 points, t 0x1234→0x1236 ms, 0°→1°, "
    "distances 1 m / 2.5 m / 0");
inline const Bytes kCancelReply = reply_payload("CANCEL_PROFILE, MEASURE");

class ScannerTest : public ::testing::Test {
 protected:
  using Script = std::map<Bytes, std::vector<FakeTransport::Incoming>>;

  ScannerTest() { rebuild(); }

  // A fresh Scanner whose transport answers each request from `script_` (looked up by the
  // request payload at send time, so tests may add rows later).
  void rebuild(ScannerOptions options = {}) {
    auto transport = std::make_unique<FakeTransport>(log_, [this](const Bytes& request) {
      auto found = script_.find(request);
      return found == script_.end() ? std::vector<FakeTransport::Incoming>{} : found->second;
    });
    fake_ = transport.get();
    options.clock = [this] { return t0_; };
    scanner_ = std::make_unique<Scanner>(std::move(transport), options);
  }

  void on(const Bytes& request, std::vector<FakeTransport::Incoming> replies) { script_[request] = std::move(replies); }

  void connect() {
    on(request_payload("GET_STATUS"), {kStatusIdle});
    ASSERT_TRUE(scanner_->connect());
    log_.sent.clear();
    log_.send_deadlines.clear();
    log_.receive_deadlines.clear();
  }

  void start_stream(std::uint16_t count = 0) {
    ASSERT_TRUE(scanner_->get_profile(count, p::kFormatRange));
    ASSERT_EQ(scanner_->state(), LifecycleState::active);
  }

  const Bytes& last_sent() const { return log_.sent.back(); }

  FakeTransport::Log log_;
  FakeTransport* fake_ = nullptr;
  Script script_;
  Deadline t0_ = Deadline(std::chrono::hours(7));
  std::unique_ptr<Scanner> scanner_;
};

}  // namespace ldoem::driver::scanner_test
