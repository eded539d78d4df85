// The client side of the hub's line protocol: HubClient (one TCP connection, request ids
// assigned here, replies matched by id) and HubDevice, a Device whose every call is one hub
// request, so that ldoem-scan runs the same acquisition directly or through a hub.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ldoem/driver/transport.hpp"
#include "ldoem/hub/device_vocabulary.hpp"
#include "ldoem/hub/listen_address.hpp"
#include "ldoem/hub/hub_protocol.hpp"

namespace ldoem::hub {

using driver::Deadline;

class HubClient {
 public:
  // Connects and reads the greeting (`* OK HELLO femh=F3 ...`) before `timeout`.
  static Expected<std::unique_ptr<HubClient>, DriverError> connect(const ListenAddress& address,
                                                                   std::chrono::milliseconds timeout);
  ~HubClient();
  HubClient(const HubClient&) = delete;
  HubClient& operator=(const HubClient&) = delete;

  // One request line (the line feed is added).
  driver::Status send_line(const std::string& line, Deadline deadline);
  // The next reply line from the hub, whatever its id.
  Expected<HubReply, DriverError> receive(Deadline deadline);
  // Sends the request with a fresh id ("c1", "c2", ...) and returns the reply carrying that
  // id; replies to other ids that arrive meanwhile are kept for their own call, unsolicited
  // notices (`* OK FAULT ...`, `* OK RECOVERED ...`) for take_notices().
  Expected<HubReply, DriverError> call(const std::string& device, const HubCommand& command, Deadline deadline);
  // The notices call() has kept (at most kMaxKeptNotices, the newest), oldest first; clears them.
  std::vector<HubReply> take_notices();
  static constexpr std::size_t kMaxKeptNotices = 64;

  // The FEMH id the hub gave this connection.
  const std::string& frontend_id() const { return frontend_id_; }
  const std::string& name() const { return name_; }

 private:
  HubClient(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  Expected<std::string, DriverError> read_line(Deadline deadline);
  void keep_notice(HubReply notice);

  int fd_;
  std::string name_;
  std::string frontend_id_;
  std::string input_;
  std::uint64_t next_id_ = 1;
  std::map<std::string, HubReply> early_replies_;
  std::deque<HubReply> notices_;
};

struct HubDeviceOptions {
  // Each call waits this long for its reply, plus the motion time or profile wait it asks for.
  std::chrono::milliseconds call_timeout{15000};
};

class HubDevice final : public Device {
 public:
  HubDevice(std::unique_ptr<HubClient> client, std::string device, HubDeviceOptions options = {});

  Expected<DeviceInfo, DriverError> initialize(const InitializeRequest& request) override;
  Expected<StatusBlock, DriverError> rotate(std::uint16_t frequency_hz) override;
  Expected<StatusBlock, DriverError> measure() override;
  Expected<StatusBlock, DriverError> idle() override;
  // Always asks for a new profile (GET2DPROFILE 0): a cached one may predate a move.
  Expected<ProfileSample, DriverError> get_profile(std::chrono::milliseconds timeout) override;
  Expected<TiltPosition, DriverError> move_motor(const MotorMove& move) override;
  Expected<StatusBlock, DriverError> status() override;

 private:
  Expected<HubReply, DriverError> call(const HubCommand& command, std::chrono::milliseconds extra_wait);
  Expected<StatusBlock, DriverError> status_call(const HubCommand& command, std::chrono::milliseconds extra_wait);
  DriverError bad_reply(const HubReply& reply) const;

  std::unique_ptr<HubClient> client_;
  std::string device_;
  std::string object_;  // "hub:HOST:PORT/DEVICE" in errors
  HubDeviceOptions options_;
};

}  // namespace ldoem::hub
