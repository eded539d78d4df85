#include <gtest/gtest.h>

#include <cerrno>
#include <string>

#include "ldoem/driver/error.hpp"
#include "ldoem/driver/lifecycle.hpp"

namespace ldoem::driver {
namespace {

TEST(DriverError, WireOutcomes_AreRetryable) {
  EXPECT_TRUE(is_retryable(ErrorKind::timeout));
  EXPECT_TRUE(is_retryable(ErrorKind::busy));
  EXPECT_TRUE(is_retryable(ErrorKind::interrupted));
  EXPECT_TRUE(is_retryable(ErrorKind::framing));
  EXPECT_TRUE(is_retryable(ErrorKind::corrupted_reply));
  EXPECT_TRUE(is_retryable(ErrorKind::connection_closed));  // after a reconnect
}

TEST(DriverError, DeviceAndCallerOutcomes_AreFinal) {
  for (ErrorKind kind : {ErrorKind::service_failure, ErrorKind::device_fault,
                         ErrorKind::unexpected_reply, ErrorKind::refused, ErrorKind::system,
                         ErrorKind::unsupported, ErrorKind::invalid_argument, ErrorKind::wrong_state}) {
    EXPECT_FALSE(is_retryable(kind)) << describe(kind);
  }
}

TEST(SystemError, ErrnoValues_MapToKinds) {
  EXPECT_EQ(system_error("write", "x", EAGAIN).kind, ErrorKind::busy);
  EXPECT_EQ(system_error("write", "x", EBUSY).kind, ErrorKind::busy);
  EXPECT_EQ(system_error("write", "x", ENOBUFS).kind, ErrorKind::busy);
  EXPECT_EQ(system_error("write", "x", EINTR).kind, ErrorKind::interrupted);
  EXPECT_EQ(system_error("write", "x", EPIPE).kind, ErrorKind::connection_closed);
  EXPECT_EQ(system_error("open", "x", ENOENT).kind, ErrorKind::system);
  EXPECT_EQ(system_error("open", "x", ENOENT).system_errno, ENOENT);
}

TEST(DescribeDriverError, ServiceFailure_NamesOperationObjectAndReason) {
  DriverError error = make_error(ErrorKind::service_failure, "GET_PROFILE", "tcp:127.0.0.1:49152");
  error.request_code = 0x0301;
  error.failure_reason = protocol::FailureReason::wrong_state;
  const std::string line = describe(error);
  EXPECT_EQ(line.rfind("GET_PROFILE tcp:127.0.0.1:49152: SERVICE_FAILURE from the device: request 0x0301, reason 0x0003", 0), 0u)
      << line;
  EXPECT_EQ(line.find('\n'), std::string::npos);
}

TEST(DescribeDriverError, Refused_ShowsTheInBandCode) {
  DriverError error = make_error(ErrorKind::refused, "TRANS_MEASURE", "can:vcan0");
  error.in_band_code = 2;
  EXPECT_EQ(describe(error), "TRANS_MEASURE can:vcan0: refused by the device: code 2");
}

TEST(DescribeDriverError, SystemError_EndsWithStrerror) {
  EXPECT_EQ(describe(system_error("open", "/dev/nothing", ENOENT)),
            "open /dev/nothing: system error: No such file or directory");
}

TEST(DescribeDriverError, MultiLineDetail_StaysOneLine) {
  EXPECT_EQ(describe(make_error(ErrorKind::timeout, "a", "b", "x\ny")), "a b: timeout: x y");
}

// Every (current, target) pair of the lifecycle, in one table (design.md convention 2).
TEST(PlanTransition, EveryPair_HasTheDocumentedAction) {
  using S = LifecycleState;
  using A = LifecycleAction;
  struct Row {
    S from;
    S to;
    A action;
  };
  const Row rows[] = {
      {S::unconfigured, S::unconfigured, A::none},
      {S::unconfigured, S::connected, A::connect},
      {S::unconfigured, S::active, A::refuse},
      {S::unconfigured, S::closed, A::close},
      {S::connected, S::unconfigured, A::refuse},
      {S::connected, S::connected, A::none},
      {S::connected, S::active, A::start_stream},
      {S::connected, S::closed, A::close},
      {S::active, S::unconfigured, A::refuse},
      {S::active, S::connected, A::stop_stream},
      {S::active, S::active, A::none},
      {S::active, S::closed, A::stop_stream_then_close},
      {S::closed, S::unconfigured, A::refuse},
      {S::closed, S::connected, A::refuse},
      {S::closed, S::active, A::refuse},
      {S::closed, S::closed, A::none},
  };
  for (const Row& row : rows) {
    EXPECT_EQ(plan_transition(row.from, row.to), row.action)
        << describe(row.from) << " -> " << describe(row.to);
  }
}

}  // namespace
}  // namespace ldoem::driver
