// A scripted TelegramTransport for Scanner tests (tests only: the driver ships no mock). Each sent
// payload is recorded with its deadline; a responder decides which telegrams (or errors) the
// following receive() calls return. An empty inbox answers receive() with a timeout.
#pragma once

#include <deque>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "ldoem/driver/transport.hpp"

namespace ldoem::driver::test {

class FakeTransport final : public TelegramTransport {
 public:
  using Incoming = std::variant<Bytes, DriverError>;
  using Responder = std::function<std::vector<Incoming>(const Bytes& request)>;

  struct Log {
    std::vector<Bytes> sent;
    std::vector<Deadline> send_deadlines;
    std::vector<Deadline> receive_deadlines;
    bool closed = false;
  };

  FakeTransport(Log& log, Responder responder) : log_(log), responder_(std::move(responder)) {}

  void push(Incoming incoming) { inbox_.push_back(std::move(incoming)); }

  Status send(ByteView payload, Deadline deadline) override {
    Bytes request(payload.begin(), payload.end());
    log_.sent.push_back(request);
    log_.send_deadlines.push_back(deadline);
    if (responder_) {
      for (auto& incoming : responder_(request)) {
        inbox_.push_back(std::move(incoming));
      }
    }
    return ok();
  }

  Expected<Bytes, DriverError> receive(Deadline deadline) override {
    log_.receive_deadlines.push_back(deadline);
    if (inbox_.empty()) {
      return fail(make_error(ErrorKind::timeout, "receive", name_, "script ran dry"));
    }
    Incoming next = std::move(inbox_.front());
    inbox_.pop_front();
    if (auto* error = std::get_if<DriverError>(&next)) {
      return fail(*error);
    }
    return std::get<Bytes>(std::move(next));
  }

  void close() override { log_.closed = true; }
  const std::string& name() const override { return name_; }
  TransportCounters counters() const override { return {}; }

 private:
  Log& log_;
  Responder responder_;
  std::deque<Incoming> inbox_;
  std::string name_ = "fake:scripted";
};

}  // namespace ldoem::driver::test
