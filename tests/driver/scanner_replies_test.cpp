// Scanner over a scripted transport, in time: profile streams, matching replies among profiles
// and unrelated telegrams, D2 failures naming our request, and timeouts. Lifecycle and each
// service's bytes: scanner_test.cpp.
#include "ldoem/driver/scanner.hpp"

#include <gtest/gtest.h>

#include "scanner_test_fixture.hpp"
#include "test_support.hpp"

namespace ldoem::driver {
namespace {

namespace p = protocol;
using namespace scanner_test;
using test::kStatusIdle;
using namespace std::chrono_literals;

TEST_F(ScannerTest, ProfileStream_DeliversProfilesAndCancelStops) {
  connect();
  on(request_payload("GET_PROFILE stream 0x39FF"), {kProfileRange, kProfileRange});
  on(request_payload("CANCEL_PROFILE"), {kCancelReply});
  start_stream();
  EXPECT_EQ(last_sent(), request_payload("GET_PROFILE stream 0x39FF"));
  for (int i = 0; i < 2; ++i) {
    auto profile = scanner_->next_profile(t0_ + 1s);
    ASSERT_TRUE(profile) << describe(profile.error());
    ASSERT_EQ(profile->sectors.size(), 1u);
    ASSERT_EQ(profile->sectors[0].points.size(), 3u);
    EXPECT_EQ(profile->sectors[0].points[1].distance_q8_m, 0x0280);  // 2.5 m
    EXPECT_EQ(profile->profile_count, 100);
  }
  auto cancelled = scanner_->cancel_profile();
  ASSERT_TRUE(cancelled);
  EXPECT_EQ(cancelled->status.sensor, p::SensorMode::measure);
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
  EXPECT_EQ(last_sent(), request_payload("CANCEL_PROFILE"));
}

TEST_F(ScannerTest, FiniteProfileRequest_ReturnsToConnectedAfterTheLast) {
  connect();
  on(request_payload("GET_PROFILE 1 × 0x39FF"), {kProfileRange});
  start_stream(1);
  EXPECT_EQ(last_sent(), request_payload("GET_PROFILE 1 × 0x39FF"));
  ASSERT_TRUE(scanner_->next_profile(t0_ + 1s));
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
  auto more = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(more);
  EXPECT_EQ(more.error().kind, ErrorKind::wrong_state);
}

TEST_F(ScannerTest, ProfileOfAnotherFormat_IsSkippedAndCounted) {
  connect();
  on(request_payload("GET_PROFILE stream 0x39FF"), {reply_payload(
      "Profile 0x3DFF: same header, 2 points at 180°/180.5°, (1 m, echo 200), (2.5 m, echo 80)"), kProfileRange});
  start_stream();
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_TRUE(profile);
  EXPECT_EQ(profile->format, p::kFormatRange);
  EXPECT_EQ(scanner_->counters().profiles_skipped, 1u);
}

TEST_F(ScannerTest, NextProfileWithoutStream_IsWrongState) {
  connect();
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(profile);
  EXPECT_EQ(profile.error().kind, ErrorKind::wrong_state);
}

// ------------------------------------------------------------------------ reply matching

TEST_F(ScannerTest, ProfilesArrivingWhileAwaitingAReply_AreQueuedNotLost) {
  connect();
  start_stream();
  // The clock request's reply comes behind two profiles and an unrelated telegram.
  on(request_payload("GET_SYNC_CLOCK"),
     {kProfileRange, kProfileRange, reply_payload("GET_SIGNAL port 0x01"), reply_payload("GET_SYNC_CLOCK 0x1234 ms")});
  auto clock = scanner_->get_sync_clock();
  ASSERT_TRUE(clock) << describe(clock.error());
  EXPECT_EQ(*clock, 0x1234);
  EXPECT_EQ(scanner_->queued_profiles(), 2u);
  EXPECT_EQ(scanner_->counters().skipped_telegrams, 1u);
  const std::size_t receives_before = log_.receive_deadlines.size();
  EXPECT_TRUE(scanner_->next_profile(t0_ + 1s));
  EXPECT_TRUE(scanner_->next_profile(t0_ + 1s));
  EXPECT_EQ(log_.receive_deadlines.size(), receives_before);  // both came from the queue
  EXPECT_EQ(scanner_->counters().profiles_delivered, 2u);
}

TEST_F(ScannerTest, UnrelatedTelegrams_AreSkippedUntilOurReply) {
  connect();
  on(request_payload("GET_SIGNAL"), {Bytes{0x81}, reply_payload("GET_STATUS, IDLE, motor OK"),
                                     failure(0x0203, p::FailureReason::wrong_state),
                                     reply_payload("GET_SIGNAL port 0x01")});
  auto port = scanner_->get_signal();
  ASSERT_TRUE(port);
  EXPECT_EQ(*port, 1);
  EXPECT_EQ(scanner_->counters().skipped_telegrams, 3u);
}

TEST_F(ScannerTest, ServiceFailureNamingOurRequest_IsTypedFinalError) {
  connect();
  on(request_payload("SET_TIME_ABS 1000 ms"), {failure(0x0203, p::FailureReason::wrong_state)});
  auto result = scanner_->set_time_abs(1000);
  ASSERT_FALSE(result);
  EXPECT_EQ(result.error().kind, ErrorKind::service_failure);
  EXPECT_EQ(result.error().request_code, 0x0203);
  EXPECT_EQ(result.error().failure_reason, p::FailureReason::wrong_state);
  EXPECT_FALSE(is_retryable(result.error()));
  EXPECT_NE(describe(result.error()).find("SET_TIME_ABS fake:scripted"), std::string::npos);
}

TEST_F(ScannerTest, ServiceFailureForGetProfile_SurfacesFromNextProfile) {
  connect();
  on(request_payload("GET_PROFILE stream 0x39FF"), {failure(0x0301, p::FailureReason::out_of_range)});
  start_stream();
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(profile);
  EXPECT_EQ(profile.error().kind, ErrorKind::service_failure);
  EXPECT_EQ(profile.error().failure_reason, p::FailureReason::out_of_range);
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
}

TEST_F(ScannerTest, ServiceFailureForGetProfileWhileAwaitingAnother_IsKeptForNextProfile) {
  connect();
  start_stream();
  on(request_payload("GET_SIGNAL"), {failure(0x0301, p::FailureReason::wrong_state), reply_payload("GET_SIGNAL port 0x01")});
  ASSERT_TRUE(scanner_->get_signal());
  auto profile = scanner_->next_profile(t0_ + 1s);
  ASSERT_FALSE(profile);
  EXPECT_EQ(profile.error().kind, ErrorKind::service_failure);
  EXPECT_EQ(profile.error().request_code, 0x0301);
}

TEST_F(ScannerTest, ReplyThatDoesNotDecode_IsRetryableCorruptedReply) {
  connect();
  on(request_payload("GET_SYNC_CLOCK"), {Bytes{0x82, 0x05, 0x12}});
  auto clock = scanner_->get_sync_clock();
  ASSERT_FALSE(clock);
  EXPECT_EQ(clock.error().kind, ErrorKind::corrupted_reply);
  EXPECT_TRUE(is_retryable(clock.error()));
  EXPECT_EQ(clock.error().decode_detail, p::DecodeError::bad_length);
}

// ------------------------------------------------------------------------------- timeouts

TEST_F(ScannerTest, NoReply_TimesOutAfterFiveSecondsWithOneAttempt) {
  connect();
  script_.erase(request_payload("GET_STATUS"));  // the device stays silent from now on
  auto status = scanner_->get_status();
  ASSERT_FALSE(status);
  EXPECT_EQ(status.error().kind, ErrorKind::timeout);
  EXPECT_TRUE(is_retryable(status.error()));
  EXPECT_EQ(status.error().operation, "GET_STATUS");
  EXPECT_EQ(log_.sent.size(), 1u);  // no hidden retry
  ASSERT_FALSE(log_.receive_deadlines.empty());
  EXPECT_EQ(log_.send_deadlines.back(), t0_ + 5s);
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 5s);
  EXPECT_EQ(describe(status.error()), "GET_STATUS fake:scripted: timeout: no reply within 5000 ms");
}

TEST_F(ScannerTest, TransRotate_WaitsTenSecondsByDefaultOrAsAsked) {
  connect();
  ASSERT_FALSE(scanner_->trans_rotate());
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 10s);
  ASSERT_FALSE(scanner_->trans_rotate(0, 3s));
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 3s);
}

TEST_F(ScannerTest, ConfiguredRequestTimeout_IsUsed) {
  ScannerOptions options;
  options.request_timeout = 250ms;
  rebuild(options);
  on(request_payload("GET_STATUS"), {kStatusIdle});
  ASSERT_TRUE(scanner_->connect());
  EXPECT_EQ(log_.receive_deadlines.back(), t0_ + 250ms);
}

TEST_F(ScannerTest, TransportErrorWhileWaiting_IsReturnedUnderTheServiceName) {
  connect();
  on(request_payload("GET_SIGNAL"), {make_error(ErrorKind::connection_closed, "receive", "x", "peer closed")});
  auto port = scanner_->get_signal();
  ASSERT_FALSE(port);
  EXPECT_EQ(port.error().kind, ErrorKind::connection_closed);
  EXPECT_EQ(port.error().operation, "GET_SIGNAL");
  EXPECT_EQ(port.error().object, "fake:scripted");
}

TEST_F(ScannerTest, TransRotateInActive_EndsTheStream) {
  connect();
  start_stream();
  on(request_payload("TRANS_ROTATE (flash speed)"), {reply_payload("TRANS_ROTATE → ROTATE, motor OK")});
  ASSERT_TRUE(scanner_->trans_rotate());
  EXPECT_EQ(scanner_->state(), LifecycleState::connected);
}

}  // namespace
}  // namespace ldoem::driver
