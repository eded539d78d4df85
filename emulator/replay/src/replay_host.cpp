#include "ldoem/replay/replay_host.hpp"

#include <deque>
#include <map>

#include "ldoem/daemon/endpoint_registry.hpp"
#include "ldoem/endpoints/host_endpoint.hpp"
#include "ldoem/io/event_loop.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/text.hpp"
#include "ldoem/scene/scene.hpp"

namespace ldoem::replay {

namespace ep = endpoints;
using protocol::ConnectionId;

struct ReplayHost::Impl final : ep::EndpointSink, ep::LptSink, ep::Scheduler {
  Impl(ReplayDevice device_in, std::ostream& log_stream, const ReplayOptions& options_in)
      : device(std::move(device_in)), options(options_in), logger(log_stream, options_in.endpoints.log_level) {}

  ReplayDevice device;
  ReplayOptions options;
  ep::Logger logger;
  std::unique_ptr<io::EventLoop> loop;
  io::MonotonicTime start = io::EventLoop::now();
  std::vector<std::unique_ptr<ep::HostEndpoint>> endpoints;
  std::map<protocol::Transport, ep::HostEndpoint*> route;
  std::optional<ep::EndpointContext> context;
  ep::Counters counters;
  std::uint64_t activity = 0;
  std::uint64_t next_key = 0;
  std::map<ep::Scheduler::Key, io::EventLoop::TimerId> timers;
  // Per connection: telegrams in sending order, each not before its time.
  std::map<ConnectionId, std::deque<ScheduledTelegram>> outgoing;
  std::map<ConnectionId, io::EventLoop::TimerId> wakeups;
  std::uint64_t lpt_writes = 0;

  // --- Scheduler (wall clock; the recorded delays are already scaled by the device) ---
  SimTime now() override { return std::chrono::duration_cast<SimTime>(io::EventLoop::now() - start); }
  SimTime at_wall_time(ep::WallTime wall) override { return std::chrono::duration_cast<SimTime>(wall - start); }
  Key add(SimTime at, Action action) override {
    const Key key{at, next_key++};
    const auto id = loop->add_timer_at(start + at, [this, key, action = std::move(action)] {
      timers.erase(key);
      action(now());
    });
    timers[key] = id;
    return key;
  }
  void cancel(const Key& key) override {
    if (const auto found = timers.find(key); found != timers.end()) {
      loop->cancel_timer(found->second);
      timers.erase(found);
    }
  }

  // --- EndpointSink ---
  void on_telegram(ConnectionId from, protocol::Bytes payload) override {
    ++counters.telegrams_received;
    ReplayAnswer answer = device.on_request(now(), payload);
    logger.log(ep::LogLevel::info, [&] { return protocol::to_string(from) + " -> " + protocol::format_telegram(payload); });
    if (answer.diagnostic) logger.log(ep::LogLevel::warn, protocol::to_string(from) + ": " + *answer.diagnostic);
    auto& queue = outgoing[from];
    for (auto& telegram : answer.telegrams) queue.push_back(std::move(telegram));
    pump(from);
  }
  void on_framing_error(ConnectionId from, const protocol::FramingError& error) override {
    ++counters.framing_errors;
    // D2: a broken frame is answered reason 5 (or 2 for a serial length mismatch), as the device would.
    const protocol::ServiceFailure failure{error.request_code, protocol::failure_reason_for_framing(error.detail)};
    outgoing[from].push_back({now(), protocol::encode_response(failure)});
    pump(from);
  }
  void on_connection_closed(ConnectionId connection) override {
    outgoing.erase(connection);
    if (const auto wake = wakeups.find(connection); wake != wakeups.end()) {
      loop->cancel_timer(wake->second);
      wakeups.erase(wake);
    }
  }

  // --- LptSink: the stepper's writes are accepted (a host must be able to write) and counted ---
  void on_register_write(SimTime, std::uint8_t) override { ++lpt_writes; }
  void set_initial_register(std::uint8_t) override {}
  void on_line_change(SimTime, std::uint8_t, bool) override { ++lpt_writes; }
  std::uint64_t steps_seen() const override { return lpt_writes; }

  // Sends what is due for `connection`, in order; wakes up for the next one.
  void pump(ConnectionId connection) {
    auto found = outgoing.find(connection);
    if (found == outgoing.end()) return;
    auto& queue = found->second;
    const auto endpoint = route.find(connection.kind);
    if (endpoint == route.end()) {
      queue.clear();
      return;
    }
    const SimTime t = now();
    while (!queue.empty() && queue.front().at <= t && !endpoint->second->busy(connection)) {
      endpoint->second->send(connection, queue.front().payload);
      queue.pop_front();
    }
    if (queue.empty() || wakeups.count(connection)) return;
    // Not due yet, or the endpoint is still sending the previous telegram: look again then.
    const SimTime next = std::max(queue.front().at, t + std::chrono::milliseconds(1));
    wakeups[connection] = loop->add_timer_at(start + next, [this, connection] {
      wakeups.erase(connection);
      pump(connection);
    });
  }
};

ReplayHost::ReplayHost(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ReplayHost::~ReplayHost() {
  for (auto& endpoint : impl_->endpoints) endpoint->close();
}

base::Expected<std::unique_ptr<ReplayHost>, ReplayStartFailure> ReplayHost::create(const ReplayOptions& options,
                                                                                       ReplayDevice device,
                                                                                       std::ostream& out,
                                                                                       std::ostream& log) {
  auto impl = std::make_unique<Impl>(std::move(device), log, options);
  auto loop = io::EventLoop::create();
  if (!loop) return base::Unexpected(ReplayStartFailure{1, "event loop: " + loop.error().message()});
  impl->loop = std::move(*loop);
  if (auto signals = impl->loop->stop_on_termination_signals(); !signals) {
    return base::Unexpected(ReplayStartFailure{1, "signals: " + signals.error().message()});
  }
  static const scene::Scene kNoScene{};  // the registry's CAN entry reads the scene's effects only
  const daemon::DeviceFacts facts{protocol::CanConfig{}, kNoScene};
  for (const auto& entry : daemon::endpoint_registry()) {
    if (auto endpoint = entry.make(options.endpoints, facts)) impl->endpoints.push_back(std::move(endpoint));
  }
  impl->context.emplace(ep::EndpointContext{*impl->loop, *impl, *impl, *impl, impl->logger, out, impl->counters,
                                            impl->activity});
  for (auto& endpoint : impl->endpoints) {
    if (auto failure = endpoint->open(*impl->context)) {
      return base::Unexpected(ReplayStartFailure{failure->usage_error ? 2 : 1, failure->message});
    }
    if (auto kind = endpoint->transport()) impl->route[*kind] = endpoint.get();
  }
  out << "ready" << std::endl;
  return std::unique_ptr<ReplayHost>(new ReplayHost(std::move(impl)));
}

int ReplayHost::run() {
  Impl& impl = *impl_;
  io::IoStatus status = impl.options.endpoints.timeout_s
                            ? impl.loop->run_for(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                  std::chrono::duration<double>(*impl.options.endpoints.timeout_s)))
                            : impl.loop->run();
  if (!status) {
    impl.logger.log(ep::LogLevel::error, "event loop: " + status.error().message());
    return 1;
  }
  if (auto signal = impl.loop->stop_signal()) return 128 + *signal;
  return 0;
}

const ReplayCounters& ReplayHost::counters() const { return impl_->device.counters(); }

}  // namespace ldoem::replay
