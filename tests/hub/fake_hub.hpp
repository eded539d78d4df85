// Fake devices and a hub running on its own thread, shared by the hub's tests.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "ldoem/hub/hub_client.hpp"
#include "ldoem/hub/hub_server.hpp"

namespace ldoem::hub::hub_testing {

using driver::Clock;
using std::chrono::milliseconds;

// The deadline of every wait in the hub's tests: far beyond a loaded machine's need, but bounded.
inline Deadline soon() { return Clock::now() + milliseconds(10000); }

// Answers are functions of the device number and the request, so a reply shows where it came
// from: status byte 0 = device number, byte 1 = the ROTATE frequency asked for.
class FakeDevice final : public Device {
 public:
  explicit FakeDevice(std::uint8_t number) : number_(number) {}

  std::atomic<int> overlaps{0};
  std::atomic<int> calls{0};
  std::atomic<bool> fail_status{false};
  std::atomic<bool> motor_fault{false};  // status 0xB4; ROTATE fails with device_fault (D11)
  std::mutex gate;  // ROTATE waits while a test holds it
  std::atomic<int> rotate_started{0};
  std::atomic<bool> blocking_moves{false};
  std::atomic<int> moves_started{0};
  std::atomic<int> cancels{0};

  void cancel() override {
    ++cancels;
    std::lock_guard lock(cancel_mutex_);
    cancelled_ = true;
    cancel_wake_.notify_all();
  }

  Expected<DeviceInfo, DriverError> initialize(const InitializeRequest&) override {
    Guard guard(*this);
    return DeviceInfo{block(0), {{0x0001, "fake " + std::to_string(number_)}}};
  }
  Expected<StatusBlock, DriverError> rotate(std::uint16_t hz) override {
    ++rotate_started;
    std::lock_guard wait_for_gate(gate);
    Guard guard(*this);
    if (motor_fault.load()) {
      return driver::fail(*driver::device_fault_in(faulted(), "TRANS_ROTATE", "fake"));
    }
    return block(static_cast<std::uint8_t>(hz));
  }
  Expected<StatusBlock, DriverError> measure() override {
    Guard guard(*this);
    return block(0);
  }
  Expected<StatusBlock, DriverError> idle() override {
    Guard guard(*this);
    return block(0);
  }
  Expected<ProfileSample, DriverError> get_profile(std::chrono::milliseconds) override {
    Guard guard(*this);
    protocol::Profile profile;
    profile.format = protocol::kFormatRangeEcho;
    profile.profile_count = static_cast<std::uint16_t>(++profiles_);
    profile.status = block(0);
    return ProfileSample{profile, TiltPosition{position_}};
  }
  Expected<TiltPosition, DriverError> move_motor(const MotorMove& move) override {
    Guard guard(*this);
    if (blocking_moves.load()) {
      // A move that only ends when cancelled, like a real one at a very low rate.
      ++moves_started;
      std::unique_lock lock(cancel_mutex_);
      cancel_wake_.wait(lock, [this] { return cancelled_; });
      return driver::fail(driver::make_error(ErrorKind::interrupted, "move", "fake", "cancelled"));
    }
    position_ += protocol::direction_sign(move.direction) * static_cast<std::int64_t>(move.steps) *
                 (move.mode == StepMode::half_step ? 1 : 2);
    return TiltPosition{position_};
  }
  Expected<StatusBlock, DriverError> status() override {
    Guard guard(*this);
    if (fail_status.load()) {
      return driver::fail(driver::make_error(ErrorKind::timeout, "GET_STATUS", "fake", "scripted timeout"));
    }
    return motor_fault.load() ? faulted() : block(0);
  }

 private:
  // Counts calls that run while another one is still inside the device.
  struct Guard {
    explicit Guard(FakeDevice& device) : device_(device) {
      if (device_.inside_.exchange(true)) {
        ++device_.overlaps;
      }
      ++device_.calls;
      std::this_thread::yield();
    }
    ~Guard() { device_.inside_.store(false); }
    FakeDevice& device_;
  };

  static StatusBlock faulted() { return protocol::make_status_block(protocol::SensorMode::error, protocol::MotorMode::fault); }

  StatusBlock block(std::uint8_t detail) const {
    StatusBlock status = protocol::make_status_block(protocol::SensorMode::rotate, protocol::MotorMode::ok);
    status.unpublished = {number_, detail, 0};
    return status;
  }

  std::uint8_t number_;
  std::atomic<bool> inside_{false};
  std::mutex cancel_mutex_;
  std::condition_variable cancel_wake_;
  bool cancelled_ = false;
  std::int64_t position_ = 0;
  int profiles_ = 0;
};

struct RunningHub {
  std::vector<FakeDevice*> devices;
  std::unique_ptr<Hub> hub;
  std::thread loop;

  explicit RunningHub(std::size_t device_count, milliseconds max_age = milliseconds(0), std::size_t queue = 256)
      : RunningHub(device_count, settings_with(max_age, queue)) {}

  static HubSettings settings_with(milliseconds max_age, std::size_t queue) {
    HubSettings settings;
    settings.max_age = max_age;
    settings.queue_capacity = queue;
    return settings;
  }

  RunningHub(std::size_t device_count, HubSettings settings) {
    std::vector<DeviceSlot> slots;
    for (std::size_t i = 0; i < device_count; ++i) {
      auto device = std::make_unique<FakeDevice>(static_cast<std::uint8_t>(i + 1));
      devices.push_back(device.get());
      slots.push_back(DeviceSlot{"dev" + std::to_string(i + 1), std::move(device)});
    }
    settings.listen = ListenAddress{"127.0.0.1", 0};
    hub = std::make_unique<Hub>(settings, std::move(slots));
    if (!hub->listen()) {
      throw std::runtime_error("hub cannot listen");
    }
    loop = std::thread([this] { (void)hub->run(); });
  }

  ~RunningHub() {
    hub->request_stop();
    loop.join();
  }

  std::unique_ptr<HubClient> client() const {
    auto connected = HubClient::connect(ListenAddress{"127.0.0.1", hub->port()}, milliseconds(5000));
    if (!connected) {
      throw std::runtime_error(driver::describe(connected.error()));
    }
    return std::move(connected.value());
  }
};

}  // namespace ldoem::hub::hub_testing
