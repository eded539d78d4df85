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
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ldoem/driver/error.hpp"
#include "ldoem/hub/device_vocabulary.hpp"
#include "ldoem/hub/hub_config.hpp"

namespace ldoem::hub {

// Limits that keep one client, idle or hostile, from locking out or starving the others
// (docs/hub.md, "Limits").
struct HubSettings {
  ListenAddress listen;
  std::chrono::milliseconds max_age = kDefaultMaxAge;
  std::size_t max_clients = 64;       // further connections get one ERR line and are closed
  // A client with nothing in flight that sends nothing for this long gets `* ERR timeout` and
  // is closed, so idle connections cannot hold every slot. 0: never.
  std::chrono::milliseconds idle_timeout{60000};
  std::size_t max_in_flight = 16;     // per client over all devices; more answer ERR busy
  std::size_t queue_capacity = 256;   // per BEMH; a full queue answers ERR busy
  // Request bytes read from one client per turn of the loop, so a flood cannot starve others.
  std::size_t read_budget_bytes = std::size_t{16} << 10;
  // With this many reply bytes waiting for a client, its requests are not read until half
  // of them are gone (a client that never reads stops being served, not the hub growing).
  std::size_t pause_reading_above = std::size_t{256} << 10;
  // Hard cap on a client's waiting reply bytes (replies of requests already in flight still
  // arrive while reading is paused); a client beyond it is dropped.
  std::size_t max_output_bytes = std::size_t{4} << 20;
  // After accept() fails for lack of descriptors (EMFILE, ENFILE) the listener rests this long,
  // or until a client leaves, instead of being polled in a busy loop.
  std::chrono::milliseconds accept_retry{100};
  // Warnings (rate-limited by the hub); empty: one line on stderr.
  std::function<void(const std::string&)> warn;
  // Called from the loop's own thread every heartbeat_interval while it turns (the systemd
  // watchdog ping: a stuck loop stops pinging). Empty or 0: never.
  std::function<void()> heartbeat;
  std::chrono::milliseconds heartbeat_interval{0};
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
  std::uint64_t closed_idle = 0;        // idle_timeout
  std::uint64_t closed_slow = 0;        // max_output_bytes
  std::uint64_t accept_pauses = 0;      // accept() out of descriptors
  std::uint64_t loop_turns = 0;         // epoll_wait returns: shows whether the loop spins
  std::uint64_t peak_output_bytes = 0;  // the most reply bytes ever waiting for one client
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
  // Thread-safe snapshot.
  HubCounters counters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::hub
