// A scripted LD for tests of ldoem-scan and the hub (tests only; it answers like the device
// from spec 3 and D2..D4, it is not the project's device simulation). ScriptedLd turns one
// request payload into the reply payloads; ScriptedTransport puts it behind the TelegramTransport
// interface; TiltLptPort counts the D8 steps written to it; VirtualSleeper makes step timing
// instant. Ranges come from a function of (beam index, tilt half-steps) so that tests know
// every point the scan must produce.
#pragma once

#include <array>
#include <deque>
#include <map>
#include <memory>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/driver/lpt_port.hpp"
#include "ldoem/driver/tilt_stepper.hpp"
#include "ldoem/driver/transport.hpp"
#include "ldoem/protocol/lpt.hpp"
#include "ldoem/protocol/messages.hpp"

namespace ldoem::test {

using protocol::Bytes;

class TiltLptPort final : public driver::LptPort {
 public:
  driver::Status write_data(std::uint8_t value) override {
    std::lock_guard lock(mutex_);
    if (const auto pulse = detector_.on_write(base::SimTime{}, value)) {
      position_half_steps_ += protocol::direction_sign(pulse->direction) *
                              (pulse->mode == protocol::StepMode::half_step ? 1 : 2);
    }
    ++writes_;
    return driver::ok();
  }
  const std::string& name() const override { return name_; }
  std::int64_t position_half_steps() const {
    std::lock_guard lock(mutex_);
    return position_half_steps_;
  }
  std::size_t writes() const {
    std::lock_guard lock(mutex_);
    return writes_;
  }

 private:
  mutable std::mutex mutex_;
  protocol::StepEdgeDetector detector_;
  std::int64_t position_half_steps_ = 0;
  std::size_t writes_ = 0;
  std::string name_ = "lpt:test";
};

// Forwards to a shared TiltLptPort, so a test can read the position after the device is gone.
class SharedTiltPort final : public driver::LptPort {
 public:
  explicit SharedTiltPort(std::shared_ptr<TiltLptPort> port) : port_(std::move(port)) {}
  driver::Status write_data(std::uint8_t value) override { return port_->write_data(value); }
  const std::string& name() const override { return port_->name(); }

 private:
  std::shared_ptr<TiltLptPort> port_;
};

class VirtualSleeper final : public driver::Sleeper {
 public:
  base::SimTime now() override { return now_; }
  void sleep_until(base::SimTime time) override { now_ = std::max(now_, time); }

 private:
  base::SimTime now_{};
};

class ScriptedLd {
 public:
  using RangeFunction = std::function<std::uint16_t(std::uint32_t beam, std::int64_t tilt_half_steps)>;

  ScriptedLd(RangeFunction range, std::function<std::int64_t()> tilt) : range_(std::move(range)), tilt_(std::move(tilt)) {
    // D4 power-up table.
    sectors_[0] = {protocol::sector_function::kNormalMeasurement, 2160};
    sectors_[1] = {protocol::sector_function::kNoMeasurement, 3600};
  }

  // Service codes of the requests seen, in order.
  std::vector<std::uint16_t> requests;
  // When set, GET_PROFILE is refused with SERVICE_FAILURE reason wrong_state after this many.
  std::optional<std::size_t> refuse_profiles_after;

  // D11 faults, each at the n-th GET_PROFILE request (1-based):
  enum class Fault { drop_reply, truncate_reply, connection_lost, reset_spontaneous, motor_stall };
  std::map<std::size_t, Fault> faults_at_profile_request;
  // Set by connection_lost; the transport reports the reset once and the device is powered up
  // again (IDLE, RAM configuration lost).
  bool connection_lost = false;

  std::vector<Bytes> handle(protocol::ByteView payload) {
    auto request = protocol::decode_request(payload);
    if (!request) {
      return {protocol::encode_response(protocol::failure_reply(request.error()))};
    }
    requests.push_back(static_cast<std::uint16_t>(protocol::service_of(*request)));
    return std::visit([this](const auto& typed) { return answer(typed); }, *request);
  }

  protocol::SensorMode mode() const { return mode_; }
  const protocol::GlobalConfig& global() const { return global_; }
  std::size_t profiles_sent() const { return profiles_sent_; }

 private:
  using Sector = std::pair<std::uint16_t, std::uint16_t>;  // function, stop

  protocol::StatusBlock status() const { return protocol::make_status_block(mode_, motor_); }

  static std::vector<Bytes> one(const protocol::Response& response) { return {protocol::encode_response(response)}; }

  std::vector<Bytes> failure(std::uint16_t code, protocol::FailureReason reason) const {
    return one(protocol::ServiceFailure{code, reason});
  }

  std::vector<Bytes> answer(const protocol::GetStatus&) { return one(protocol::GetStatusReply{status(), {}}); }
  std::vector<Bytes> answer(const protocol::GetIdentification& get) {
    return one(protocol::IdentificationReply{get.item == protocol::ident_item::kSensorName ? "LD-OEM1000" : "0000000"});
  }
  std::vector<Bytes> answer(const protocol::GetConfig& get) {
    if (get.key != static_cast<std::uint16_t>(protocol::ConfigKey::global)) {
      return failure(0x0204, protocol::FailureReason::out_of_range);
    }
    return one(protocol::GetConfigReply{global_});
  }
  std::vector<Bytes> answer(const protocol::SetConfig& set) {
    if (mode_ != protocol::SensorMode::idle) {
      return one(protocol::SetConfigReply{protocol::kSetConfigRefused});
    }
    if (const auto* global = std::get_if<protocol::GlobalConfig>(&set.body)) {
      global_ = *global;
    }
    return one(protocol::SetConfigReply{protocol::kSetConfigSuccess});
  }
  std::vector<Bytes> answer(const protocol::SetFunction& set) {
    if (set.sector > 7 || mode_ == protocol::SensorMode::measure) {
      return one(protocol::SetFunctionReply{protocol::kSetFunctionInvalid});
    }
    sectors_[set.sector] = {set.function, set.stop_ticks};
    return one(protocol::SetFunctionReply{set.sector});
  }
  std::vector<Bytes> answer(const protocol::GetFunction& get) {
    return one(protocol::GetFunctionReply{get.sector, sectors_[get.sector].first, sectors_[get.sector].second});
  }
  std::vector<Bytes> answer(const protocol::TransRotate&) {
    if (mode_ == protocol::SensorMode::error) {
      return failure(0x0403, protocol::FailureReason::wrong_state);
    }
    if (motor_ != protocol::MotorMode::ok) {
      return one(protocol::TransRotateReply{protocol::make_status_block(protocol::SensorMode::error, motor_)});
    }
    mode_ = protocol::SensorMode::rotate;
    return one(protocol::TransRotateReply{status()});
  }
  std::vector<Bytes> answer(const protocol::TransMeasure&) {
    if (mode_ == protocol::SensorMode::idle) {
      return failure(0x0403, protocol::FailureReason::wrong_state);
    }
    mode_ = protocol::SensorMode::measure;
    return one(protocol::TransMeasureReply{status(), protocol::measure_return::kOk});
  }
  std::vector<Bytes> answer(const protocol::TransIdle&) {
    if (mode_ == protocol::SensorMode::measure) {
      return failure(0x0402, protocol::FailureReason::wrong_state);
    }
    mode_ = protocol::SensorMode::idle;
    return one(protocol::TransIdleReply{status()});
  }
  std::vector<Bytes> answer(const protocol::DoReset& reset) {
    mode_ = protocol::SensorMode::idle;
    return one(protocol::DoResetReply{reset.level});
  }
  std::vector<Bytes> answer(const protocol::CancelProfile&) { return one(protocol::CancelProfileReply{status()}); }
  std::vector<Bytes> answer(const protocol::GetProfile& get) {
    if (const auto fault = faults_at_profile_request.find(++profile_requests_); fault != faults_at_profile_request.end()) {
      switch (fault->second) {
        case Fault::drop_reply:
          return {};
        case Fault::truncate_reply: {
          Bytes cut = protocol::encode_response(make_profile(get.format, 1));
          cut.resize(10);
          return {cut};
        }
        case Fault::connection_lost:
          connection_lost = true;
          mode_ = protocol::SensorMode::idle;
          global_ = protocol::GlobalConfig{};
          return {};
        case Fault::reset_spontaneous:
          mode_ = protocol::SensorMode::idle;
          return {};
        case Fault::motor_stall:
          mode_ = protocol::SensorMode::error;
          motor_ = protocol::MotorMode::fault;
          return {};
      }
    }
    if (mode_ != protocol::SensorMode::measure ||
        (refuse_profiles_after && profiles_sent_ >= *refuse_profiles_after)) {
      return failure(0x0301, protocol::FailureReason::wrong_state);
    }
    std::vector<Bytes> profiles;
    for (std::uint16_t i = 0; i < std::max<std::uint16_t>(get.profile_count, 1); ++i) {
      profiles.push_back(protocol::encode_response(make_profile(get.format, static_cast<std::uint16_t>(i + 1))));
    }
    return profiles;
  }
  template <class Other>
  std::vector<Bytes> answer(const Other&) {
    return failure(0, protocol::FailureReason::unknown_service);
  }

  // Spec 3.5/3.6: one block per initialised sector; sector i runs from the previous stop plus
  // one step to its own stop, sector 0 from the last initialised sector's stop (wrapping).
  protocol::Profile make_profile(std::uint16_t format, std::uint16_t sent) {
    ++profiles_sent_;
    protocol::Profile profile;
    profile.format = format;
    profile.profile_sent = sent;
    profile.profile_count = static_cast<std::uint16_t>(profiles_sent_);
    profile.status = status();
    std::size_t used = 0;
    while (used < 8 && sectors_[used].first != protocol::sector_function::kNotInitialised) {
      ++used;
    }
    const std::int64_t step = global_.angle_step_ticks;
    const std::int64_t tilt = tilt_();
    std::uint32_t beam = 0;
    constexpr std::int64_t kTurn = base::kTicksPerTurn;
    for (std::size_t s = 0; s < used; ++s) {
      protocol::SectorBlock block;
      block.sector_num = static_cast<std::uint16_t>(s);
      block.dir_step_ticks = static_cast<std::uint16_t>(step);
      const std::int64_t previous = s == 0 ? sectors_[used - 1].second - kTurn : sectors_[s - 1].second;
      const std::int64_t start = previous + step;
      const std::int64_t stop = sectors_[s].second;
      block.start_dir_ticks = static_cast<std::uint16_t>((start + kTurn) % kTurn);
      block.end_dir_ticks = static_cast<std::uint16_t>(stop % kTurn);
      if (sectors_[s].first == protocol::sector_function::kNormalMeasurement) {
        for (std::int64_t angle = start; angle <= stop; angle += step) {
          protocol::ProfilePoint point;
          point.distance_q8_m = range_(beam, tilt);
          point.direction_ticks = static_cast<std::uint16_t>((angle + kTurn) % kTurn);
          point.echo = static_cast<std::uint16_t>(100 + beam);
          block.points.push_back(point);
          ++beam;
        }
      }
      profile.sectors.push_back(block);
    }
    return profile;
  }

  RangeFunction range_;
  std::function<std::int64_t()> tilt_;
  protocol::SensorMode mode_ = protocol::SensorMode::idle;
  protocol::MotorMode motor_ = protocol::MotorMode::ok;
  std::size_t profile_requests_ = 0;
  protocol::GlobalConfig global_;
  std::array<Sector, 8> sectors_{};
  std::size_t profiles_sent_ = 0;
};

// The scripted LD behind the TelegramTransport interface (replies queue up at send time).
class ScriptedTransport final : public driver::TelegramTransport {
 public:
  explicit ScriptedTransport(ScriptedLd& device) : device_(device) {}
  driver::Status send(protocol::ByteView payload, driver::Deadline) override {
    for (Bytes& reply : device_.handle(payload)) {
      inbox_.push_back(std::move(reply));
    }
    return driver::ok();
  }
  driver::Expected<Bytes, driver::DriverError> receive(driver::Deadline) override {
    if (device_.connection_lost) {
      device_.connection_lost = false;
      closed_ = true;
      return driver::fail(driver::make_error(driver::ErrorKind::connection_closed, "receive", name_, "reset"));
    }
    if (closed_) {
      return driver::fail(driver::make_error(driver::ErrorKind::connection_closed, "receive", name_, "closed"));
    }
    if (inbox_.empty()) {
      return driver::fail(driver::make_error(driver::ErrorKind::timeout, "receive", name_, "nothing scripted"));
    }
    Bytes next = std::move(inbox_.front());
    inbox_.pop_front();
    return next;
  }
  void close() override {}
  const std::string& name() const override { return name_; }
  driver::TransportCounters counters() const override { return {}; }

 private:
  ScriptedLd& device_;
  bool closed_ = false;
  std::deque<Bytes> inbox_;
  std::string name_ = "scripted:ld";
};

}  // namespace ldoem::test
