// The hub: a TCP front end (loopback by default) speaking the line protocol of
// hub_protocol.hpp, one FEMH (front-end message handler) per client connection and one BEMH
// (backend_handler.hpp) per device. One epoll loop owns every socket; BEMH workers hand their
// replies back through a queue and an eventfd, so only the loop writes to clients and a reply
// reaches exactly the client whose request it answers.
//
// Handler ids are unique for the life of the hub and never reused: FEMHs are F1, F2, ... in
// order of connection, BEMHs B1, B2, ... in configuration order.
//
// Freshness: a FEMH answers STATUS and GET2DPROFILE from its device's latest data when that
// data is at most MAX_AGE old (the request's argument, else HubSettings::max_age) and the
// client has no earlier request to that device still in flight (so a client's own
// MOVEMOTOR ... GET2DPROFILE sequence never sees a profile from before its move).
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ldoem/driver/error.hpp"
#include "ldoem/hub/device_vocabulary.hpp"
#include "ldoem/hub/hub_config.hpp"

namespace ldoem::hub {

struct HubSettings {
  ListenAddress listen;
  std::chrono::milliseconds max_age = kDefaultMaxAge;
  std::size_t max_clients = 64;       // further connections get one ERR line and are closed
  std::size_t queue_capacity = 256;   // per BEMH; a full queue answers ERR busy
  std::size_t max_output_bytes = std::size_t{64} << 20;  // a client that reads nothing is dropped
};

struct DeviceSlot {
  std::string name;
  std::unique_ptr<Device> device;
  std::chrono::milliseconds profile_timeout = kDefaultProfileTimeout;
};

struct HubCounters {
  std::uint64_t clients_accepted = 0;
  std::uint64_t requests = 0;
  std::uint64_t answered_from_cache = 0;
  std::uint64_t forwarded = 0;
  std::uint64_t errors = 0;
};

class Hub {
 public:
  Hub(HubSettings settings, std::vector<DeviceSlot> devices);
  ~Hub();
  Hub(const Hub&) = delete;
  Hub& operator=(const Hub&) = delete;

  // Binds and listens (port 0: an ephemeral port; see port()).
  driver::Status listen();
  std::uint16_t port() const;

  // Serves until request_stop() or until `extra_stop_fd` (e.g. a signalfd) is readable.
  driver::Status run(int extra_stop_fd = -1);
  // Thread-safe; run() returns soon after.
  void request_stop();

  // (device name, BEMH id) in configuration order.
  std::vector<std::pair<std::string, std::string>> devices() const;
  // Read after run() has returned (or from the loop's thread).
  HubCounters counters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::hub
