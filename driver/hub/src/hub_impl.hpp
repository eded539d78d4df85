// The hub's loop state, shared by hub_server.cpp (sockets, the loop, accepting, reading and
// writing) and hub_requests.cpp (requests, the freshness cache, replies from the workers).
#pragma once

#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "ldoem/base/warning_throttle.hpp"
#include "ldoem/hub/backend_handler.hpp"
#include "ldoem/hub/hub_protocol.hpp"
#include "ldoem/hub/hub_server.hpp"
#include "client_send_buffer.hpp"

namespace ldoem::hub {
// epoll tags; client tags start above them and are never reused.
inline constexpr std::uint64_t kListenTag = 1;
inline constexpr std::uint64_t kWakeTag = 2;
inline constexpr std::uint64_t kExtraStopTag = 3;
inline constexpr std::uint64_t kFirstClientTag = 16;
// One warning of a kind per this period at most; the next one says how many were held back.
inline constexpr std::chrono::milliseconds kWarnPeriod{10000};

struct HubConnection {
  int fd = -1;
  std::string frontend_id;  // FEMH id
  std::string input;
  ClientSendBuffer output;
  bool discarding_long_line = false;
  bool reading_paused = false;     // too many reply bytes waiting (HubSettings::pause_reading_above)
  std::uint32_t watched_events = 0;
  Clock::time_point last_activity;
  std::size_t total_in_flight = 0;
  std::map<std::string, std::size_t> in_flight;  // device -> requests queued or running
  std::shared_ptr<std::atomic<bool>> alive = std::make_shared<std::atomic<bool>>(true);
};

struct AtomicCounters {
  std::atomic<std::uint64_t> clients_accepted{0}, requests{0}, answered_from_cache{0}, forwarded{0}, errors{0},
      closed_idle{0}, closed_slow{0}, accept_pauses{0}, loop_turns{0}, peak_output_bytes{0};
};


struct Hub::Impl {
  HubSettings settings;
  std::vector<std::unique_ptr<BackEndHandler>> handlers;
  std::unordered_map<std::string, BackEndHandler*> handler_by_device;

  int listen_fd = -1;
  int epoll_fd = -1;
  int wake_fd = -1;
  std::uint16_t bound_port = 0;
  std::atomic<bool> stop_requested{false};
  bool accepting = true;
  Clock::time_point next_heartbeat;
  Clock::time_point accept_resumes_at;
  base::WarningThrottle accept_warning{kWarnPeriod};  // says a repeated accept error once per period

  std::mutex completions_mutex;
  std::deque<BackendResult> completions;

  std::unordered_map<std::uint64_t, HubConnection> clients;  // by epoll tag
  std::unordered_map<std::string, std::uint64_t> tag_by_frontend;
  std::vector<std::uint64_t> resume_parsing;  // clients whose reading was just unpaused
  std::uint64_t next_tag = kFirstClientTag;
  std::uint64_t next_frontend_number = 1;
  AtomicCounters counters;

  Impl(HubSettings hub_settings, std::vector<DeviceSlot> devices) : settings(std::move(hub_settings)) {
    wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    std::size_t number = 1;
    for (DeviceSlot& slot : devices) {
      BackendSettings backend{settings.queue_capacity, slot.profile_timeout};
      auto handler = std::make_unique<BackEndHandler>("B" + std::to_string(number++), slot.name,
                                                      std::move(slot.device), backend,
                                                      [this](BackendResult result) { complete(std::move(result)); });
      handler_by_device[slot.name] = handler.get();
      handlers.push_back(std::move(handler));
    }
  }

  ~Impl() {
    handlers.clear();  // cancels moves and joins the workers before the queue they post to goes away
    for (auto& [tag, client] : clients) {
      ::close(client.fd);
    }
    for (int fd : {listen_fd, epoll_fd, wake_fd}) {
      if (fd >= 0) {
        ::close(fd);
      }
    }
  }

  // Worker threads.
  void complete(BackendResult result);
  void wake() const {
    const std::uint64_t one = 1;
    (void)!::write(wake_fd, &one, sizeof one);
  }

  // ------------------------------------------------------------------------ the loop's side
  driver::Status listen();
  void watch(int operation, int fd, std::uint64_t tag, std::uint32_t events) const;
  driver::Status run(int extra_stop_fd);
  // Until the next idle deadline or the listener's rest ends; -1 when nothing is due.
  int wait_timeout_ms() const;
  void close_idle_clients();
  void beat_heart();
  void pause_accepting(int error);
  void resume_accepting();
  void accept_clients();
  void drop_client(std::uint64_t tag);
  void serve_client(std::uint64_t tag, std::uint32_t events);
  // At most read_budget_bytes per turn: epoll is level-triggered, so the rest is read on the
  // next turn, after every other ready client had its share.
  void read_client(std::uint64_t tag);
  void take_lines(std::uint64_t tag);
  void send_reply(std::uint64_t tag, const HubReply& reply);
  void flush(std::uint64_t tag);

  // hub_requests.cpp: requests, the cache and replies from the workers.
  void handle_line(std::uint64_t tag, const std::string& line);
  bool answer_from_cache(std::uint64_t tag, const HubRequest& request, const BackEndHandler& handler);
  void deliver_completions();
};

}  // namespace ldoem::hub
