#include "ldoem/daemon/daemon.hpp"

#include <csignal>
#include <cstdio>
#include <cstring>
#include <iterator>

#include <pthread.h>
#include <map>
#include <sstream>
#include <vector>

#include "ldoem/control/control_unit.hpp"
#include "ldoem/control/flash_image.hpp"
#include "ldoem/control/revolution_timing.hpp"
#include "ldoem/control/scene_defaults.hpp"
#include "ldoem/daemon/can_bus_pacer.hpp"
#include "ldoem/daemon/file_flash_store.hpp"
#include "ldoem/daemon/head_track.hpp"
#include "ldoem/daemon/isotp_channel.hpp"
#include "ldoem/daemon/logger.hpp"
#include "ldoem/daemon/output_queue.hpp"
#include "ldoem/daemon/scene_adapters.hpp"
#include "ldoem/daemon/sim_clock.hpp"
#include "ldoem/daemon/tilt_track.hpp"
#include "ldoem/io/can_interface.hpp"
#include "ldoem/io/can_socket.hpp"
#include "ldoem/io/event_loop.hpp"
#include "ldoem/io/gpio_lines.hpp"
#include "ldoem/io/pseudo_terminal.hpp"
#include "ldoem/io/tcp.hpp"
#include "ldoem/motor/tilt_motor.hpp"
#include "ldoem/protocol/serial_framing.hpp"
#include "ldoem/world/scene_caster.hpp"
#include "ldoem/protocol/tcp_framing.hpp"
#include "ldoem/protocol/text.hpp"
#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/sensor/sensor_model.hpp"

namespace ldoem::daemon {

using control::ConnectionId;
using control::TransportKind;
using protocol::Bytes;
using protocol::ByteView;
using protocol::Unexpected;

namespace {

// Bytes read from one stream per loop round: a chatty host cannot starve the others.
constexpr std::size_t kReadBudgetBytes = 65536;
// With nothing to simulate, a virtual-time daemon waits this long for a host per round.
constexpr std::chrono::milliseconds kVirtualIdleWait{50};
// SIGINT/SIGTERM stop the loop (exit 128 + N), SIGUSR1 dumps the counters.
constexpr int kHandledSignals[] = {SIGINT, SIGTERM, SIGUSR1};
// With --virtual-time, a deadline that waits for a host (ISO-TP N_Bs/N_Cr, D1) is only jumped to
// after the host has been silent this long on the wall clock: a real host needs wall time to answer.
constexpr std::chrono::seconds kVirtualHostGrace{1};
// D8 gpio back end: line names of the gpio-sim chip, in DATA0..2 order.
const std::vector<std::string> kLptLineNames{"DIR", "CLK", "MODE"};
constexpr std::uint8_t kLptLineBits[] = {protocol::kLptDirectionBit, protocol::kLptClockBit, protocol::kLptModeBit};

std::string hex_id(std::uint16_t id) {
  char text[8];
  std::snprintf(text, sizeof text, "%03X", id);
  return text;
}

}  // namespace

std::string format_counters(const DaemonCounters& c) {
  std::ostringstream out;
  out << "counters: telegrams_received=" << c.telegrams_received << " framing_errors=" << c.framing_errors
      << " isotp_receive_errors=" << c.isotp_receive_errors << " isotp_send_failures=" << c.isotp_send_failures
      << " isotp_queue_overflows=" << c.isotp_queue_overflows << " can_frames_backlogged=" << c.can_frames_backlogged
      << " skipped_profiles=" << c.skipped_profiles << " profiles_sent=" << c.profiles_sent
      << " tcp_connections=" << c.tcp_connections << " tcp_dropped_slow=" << c.tcp_dropped_slow
      << " serial_overflows=" << c.serial_overflows << " lpt_steps=" << c.lpt_steps;
  return out.str();
}

// ------------------------------------------------------------------------------------ endpoints

struct TcpClient {
  io::TcpConnection connection;
  protocol::TcpDeframer deframer;
  OutputQueue output;
};

struct TcpServer {
  io::TcpListener listener;
  std::map<std::uint32_t, TcpClient> clients;
  std::uint32_t next_index = 1;
};

struct SerialPort {
  io::PseudoTerminal pty;
  protocol::SerialDeframer deframer;
  OutputQueue output;
};

struct CanBus {
  io::CanRawSocket socket;
  std::vector<IsoTpChannel> channels;  // channel i is ConnectionId{can, i + 1}
  std::vector<std::optional<DeadlineQueue::Key>> scheduled_polls;  // the one queued poll per channel
  std::deque<protocol::CanFrame> backlog;  // frames the interface's queue refused
  bool first_pair_from_flash = true;       // pair 1 follows SET_CONFIG key 2 (D1)
  std::optional<CanBusPacer> pacer;        // D9 bus_timing only: frames leave at the bit rate
  std::optional<SimTime> pacer_scheduled;  // the pacer's release deadline already queued
  IsoTpChannelCounters retired;            // counts of channels replaced by a new CAN configuration
};

// ------------------------------------------------------------------------------------- the core

struct Daemon::Impl final : control::TransportQuery {
  Options options;
  scene::Scene scene;
  std::ostream& out;
  Logger logger;
  std::unique_ptr<io::EventLoop> loop;
  SimClock clock = SimClock::virtual_clock();
  DeadlineQueue deadlines;
  std::optional<io::EventLoop::TimerId> wall_timer;
  std::optional<SimTime> wall_timer_for;

  std::unique_ptr<raycast::OdeWorld> world;
  std::unique_ptr<raycast::EmbreeRayCaster> caster;
  std::unique_ptr<world::SceneCaster> moving_caster;  // D12: only when the scene moves
  std::unique_ptr<sensor::SensorModel> sensor;
  std::unique_ptr<TiltTrack> tilt;
  std::optional<LptDriveBoard> board;
  std::unique_ptr<SpinUpHeadModel> head;
  std::unique_ptr<HeadTrack> head_track;  // D9 head_dynamics only
  // The control unit's head target last passed to head_track: (target Hz, epoch or reach time).
  std::pair<std::uint16_t, SimTime> mirrored_head_target{0, SimTime::zero()};
  std::unique_ptr<SceneMeasurement> measurement;
  std::unique_ptr<control::FlashStore> flash;
  std::unique_ptr<control::ControlUnit> unit;
  protocol::CanConfig applied_can_config;

  std::optional<TcpServer> tcp;
  std::optional<SerialPort> serial;
  std::optional<CanBus> can;
  std::optional<io::PseudoTerminal> lpt_pty;
  std::optional<io::GpioLineReader> lpt_gpio;

  DaemonCounters counters;
  std::uint64_t activity = 0;  // fd callbacks that did something (virtual time: is anything ready?)
  WallTime last_activity_wall{};
  std::optional<int> stop_signal;
  bool fatal = false;

  Impl(Options options_in, scene::Scene scene_in, std::ostream& out_in, std::ostream& log_in)
      : options(std::move(options_in)), scene(std::move(scene_in)), out(out_in), logger(log_in, options.log_level) {}

  // --- TransportQuery (D10 busy) ---
  bool busy(ConnectionId connection) const override {
    switch (connection.kind) {
      case TransportKind::tcp: {
        if (!tcp) return false;
        const auto client = tcp->clients.find(connection.index);
        return client != tcp->clients.end() && !client->second.output.empty();
      }
      case TransportKind::serial:
        return serial && !serial->output.empty();
      case TransportKind::can: {
        if (!can || connection.index < 1 || connection.index > can->channels.size()) return false;
        const IsoTpChannel& channel = can->channels[connection.index - 1];
        // With bus_timing a telegram is still being sent while its frames wait for the bus.
        return channel.busy() || (can->pacer && can->pacer->pending_for(channel.config().ids.response_id));
      }
    }
    return false;
  }

  SimTime now() { return clock.now(io::EventLoop::now()); }

  bool waiting_for_host() const {
    if (!can) return false;
    for (const IsoTpChannel& channel : can->channels) {
      // A host cannot answer a frame the paced bus has not delivered yet: jump to its release.
      const bool frames_on_the_way = can->pacer && can->pacer->pending_for(channel.config().ids.response_id);
      if (channel.waiting_for_host() && !frames_on_the_way) return true;
    }
    return false;
  }

  // --- building ---
  std::optional<StartFailure> build_models();
  std::optional<StartFailure> open_endpoints();
  std::optional<StartFailure> open_tcp();
  std::optional<StartFailure> open_serial();
  std::optional<StartFailure> open_can();
  std::optional<StartFailure> open_lpt();

  // --- the control unit's events ---
  void deliver(ConnectionId from, const Bytes& payload);
  void framing_error(ConnectionId from, const protocol::FramingError& error);
  void perform(const control::Actions& actions);
  void follow_head_target(SimTime at);
  void send_telegram(const control::OutgoingTelegram& telegram);
  void after_event();

  // --- per transport ---
  void on_listener_ready();
  void on_tcp_client_ready(std::uint32_t index, io::Readiness readiness);
  void send_tcp(std::uint32_t index, ByteView frame);
  void flush_tcp(std::uint32_t index);
  void close_tcp(std::uint32_t index, std::string_view why);
  void on_serial_ready(io::Readiness readiness);
  void send_serial(ByteView bytes);
  void flush_serial();
  void on_can_ready(io::Readiness readiness);
  void handle_channel_output(std::size_t channel, IsoTpChannelOutput output);
  void schedule_channel_poll(std::size_t channel);
  void transmit_can(const std::vector<protocol::CanFrame>& frames);
  void release_paced_frames(SimTime at);
  void flush_can_backlog();
  void apply_can_config_changes();
  void set_can_filters();
  void on_lpt_pty_ready();
  void on_lpt_gpio_ready();

  // --- time ---
  void fire_due(SimTime now);
  void arm_wall_timer();
  void stop_loop() { loop->stop(); }
  int run();
  void save_flash();
  void on_signal(int signal_number);
  void collect_counters();
};

std::optional<StartFailure> Daemon::Impl::build_models() {
  if (options.seed) {
    scene.seed = *options.seed;
  }
  std::optional<WorldTiming> world_timing;
  if (scene.moves()) {  // D12; a scene in which nothing moves builds none of it
    moving_caster = std::make_unique<world::SceneCaster>(scene);
    sensor = std::make_unique<sensor::SensorModel>(scene, *moving_caster);
    world_timing = WorldTiming{[this](double t0_s, double t1_s) { moving_caster->prepare(t0_s, t1_s); },
                               scene.world.beam_time};
  } else {
    world = std::make_unique<raycast::OdeWorld>(scene);
    caster = std::make_unique<raycast::EmbreeRayCaster>(*world);
    sensor = std::make_unique<sensor::SensorModel>(scene, *caster);
  }
  tilt = std::make_unique<TiltTrack>(motor::make_tilt_motor(scene));
  board.emplace(*tilt);
  head = std::make_unique<SpinUpHeadModel>(scene.scanner.head);
  if (scene.effects.has(scene::Effect::head_dynamics)) {
    head_track = std::make_unique<HeadTrack>(scene.scanner.head);
  }
  measurement = std::make_unique<SceneMeasurement>(
      *sensor, *tilt, scene.effects.has(scene::Effect::sweep_motion),
      [this](std::uint64_t revolution, SimTime first_beam_time) {
        // D9: without sweep_motion the tilt is frozen at the revolution's start.
        const control::HeadState& head_state = unit->state().head;
        if (head_state.speed_hz == 0 || revolution <= head_state.revolutions_before_epoch) {
          return first_beam_time;
        }
        const std::uint64_t k = revolution - head_state.revolutions_before_epoch - 1;
        return control::revolution_time(head_state.epoch_start, head_state.speed_hz, k, 0);
      },
      head_track.get(), std::move(world_timing));

  if (options.flash_mode == FlashMode::file) {
    flash = std::make_unique<FileFlashStore>(options.flash_path);
  } else {
    flash = std::make_unique<control::MemoryFlashStore>();
  }
  const control::FlashLoadResult loaded =
      control::load_flash_or(*flash, control::device_config_from(scene.scanner.flash));
  if (loaded.problem && loaded.problem->kind != control::FlashErrorKind::empty) {
    logger.log(LogLevel::warn, "flash " + options.flash_path.string() + ":" + std::to_string(loaded.problem->line) +
                                   ": " + std::string(control::describe(loaded.problem->kind)) +
                                   "; starting from the scene's defaults (D4)");
  }
  control::ControlUnit::Setup setup;
  setup.flash = loaded.config;
  setup.identification = control::identification_from(scene.scanner.identification);
  setup.power_up_time = SimTime::zero();
  unit = std::make_unique<control::ControlUnit>(std::move(setup), *head, *measurement);
  applied_can_config = unit->state().ram.can;
  return std::nullopt;
}

std::optional<StartFailure> Daemon::Impl::open_endpoints() {
  auto created = io::EventLoop::create();
  if (!created) {
    return StartFailure{kExitRuntimeFailure, created.error().message()};
  }
  loop = std::move(*created);
  if (auto watched = loop->on_signals(std::vector<int>(std::begin(kHandledSignals), std::end(kHandledSignals)), [this](int number) { on_signal(number); });
      !watched) {
    return StartFailure{kExitRuntimeFailure, watched.error().message()};
  }
  for (auto opener : {&Impl::open_can, &Impl::open_tcp, &Impl::open_serial, &Impl::open_lpt}) {
    if (auto failure = (this->*opener)()) {
      return failure;
    }
  }
  return std::nullopt;
}

std::optional<StartFailure> Daemon::Impl::open_tcp() {
  if (!options.tcp) return std::nullopt;
  auto listener = io::TcpListener::listen(options.tcp->port, options.tcp->address);
  if (!listener) {
    return StartFailure{kExitUsageError, listener.error().message()};
  }
  tcp.emplace(TcpServer{std::move(*listener), {}, 1});
  if (auto watched = loop->watch(tcp->listener.fd(), io::Interest::readable, [this](io::Readiness) { on_listener_ready(); });
      !watched) {
    return StartFailure{kExitRuntimeFailure, watched.error().message()};
  }
  out << "tcp " << tcp->listener.address() << ':' << tcp->listener.port() << '\n';
  return std::nullopt;
}

std::optional<StartFailure> Daemon::Impl::open_serial() {
  if (!options.serial_pty) return std::nullopt;
  auto pty = io::PseudoTerminal::open(*options.serial_pty);
  if (!pty) {
    return StartFailure{kExitUsageError, pty.error().message()};
  }
  serial.emplace(SerialPort{std::move(*pty), protocol::SerialDeframer(), OutputQueue()});
  if (auto watched = loop->watch(serial->pty.fd(), io::Interest::readable, [this](io::Readiness r) { on_serial_ready(r); });
      !watched) {
    return StartFailure{kExitRuntimeFailure, watched.error().message()};
  }
  out << "serial " << serial->pty.peer_path() << ' ' << options.serial_pty->string() << '\n';
  return std::nullopt;
}

std::optional<StartFailure> Daemon::Impl::open_can() {
  if (!options.can_interface) return std::nullopt;
  const std::string& name = *options.can_interface;
  if (auto status = io::check_can_interface(name); !status) {
    return StartFailure{kExitUsageError, status.error().message()};
  }
  auto socket = io::CanRawSocket::open(name);
  if (!socket) {
    return StartFailure{kExitUsageError, socket.error().message()};
  }
  can.emplace(CanBus{std::move(*socket), {}, {}, {}, options.can_id_pairs.empty(), {}, {}, {}});
  const protocol::CanConfig& ram = unit->state().ram.can;
  if (scene.effects.has(scene::Effect::bus_timing)) {
    can->pacer.emplace(can_bit_rate_bps(ram.bitrate_code));  // D1 BITRATE, D9
  }
  std::vector<CanIdPair> pairs = options.can_id_pairs;
  if (pairs.empty()) {
    pairs.push_back(CanIdPair{ram.request_id, ram.response_id});  // D1 via flash
  }
  for (const CanIdPair& pair : pairs) {
    IsoTpChannelConfig config;
    config.ids = pair;
    config.block_size = static_cast<std::uint8_t>(ram.block_size);
    config.st_min = std::chrono::milliseconds(ram.st_min_ms);
    can->channels.emplace_back(config);
    can->scheduled_polls.emplace_back();
  }
  set_can_filters();
  if (auto watched = loop->watch(can->socket.fd(), io::Interest::readable, [this](io::Readiness r) { on_can_ready(r); });
      !watched) {
    return StartFailure{kExitRuntimeFailure, watched.error().message()};
  }
  for (const IsoTpChannel& channel : can->channels) {
    out << "can " << name << ' ' << hex_id(channel.config().ids.request_id) << ':'
        << hex_id(channel.config().ids.response_id) << '\n';
  }
  return std::nullopt;
}

std::optional<StartFailure> Daemon::Impl::open_lpt() {
  if (!options.lpt) return std::nullopt;
  if (options.lpt->backend == LptBackend::pty) {
    auto pty = io::PseudoTerminal::open(std::filesystem::path(options.lpt->target));
    if (!pty) {
      return StartFailure{kExitUsageError, pty.error().message()};
    }
    lpt_pty.emplace(std::move(*pty));
    if (auto watched = loop->watch(lpt_pty->fd(), io::Interest::readable, [this](io::Readiness) { on_lpt_pty_ready(); });
        !watched) {
      return StartFailure{kExitRuntimeFailure, watched.error().message()};
    }
    out << "lpt " << lpt_pty->peer_path() << ' ' << options.lpt->target << '\n';
    return std::nullopt;
  }
  auto reader = io::GpioLineReader::open(options.lpt->target, kLptLineNames);
  if (!reader) {
    return StartFailure{kExitUsageError, reader.error().message()};
  }
  lpt_gpio.emplace(std::move(*reader));
  auto levels = lpt_gpio->levels();
  if (!levels) {
    return StartFailure{kExitUsageError, levels.error().message()};
  }
  std::uint8_t initial = 0;
  for (std::size_t i = 0; i < levels->size() && i < std::size(kLptLineBits); ++i) {
    if ((*levels)[i] != 0) initial |= kLptLineBits[i];
  }
  board.emplace(*tilt, initial);  // the lines' levels before any edge (D8)
  for (const int fd : lpt_gpio->event_fds()) {
    if (auto watched = loop->watch(fd, io::Interest::readable, [this](io::Readiness) { on_lpt_gpio_ready(); });
        !watched) {
      return StartFailure{kExitRuntimeFailure, watched.error().message()};
    }
  }
  out << "lpt gpio " << lpt_gpio->chip_name() << '\n';
  return std::nullopt;
}

// ------------------------------------------------------------------------- control unit events

void Daemon::Impl::deliver(ConnectionId from, const Bytes& payload) {
  // D8: a host pulses the stepper, then asks for the next profile. When the register bytes and
  // the request are ready in the same loop round, epoll may hand us the request first, and the
  // profile would be measured at the old tilt (with virtual time, at once). Bytes that are
  // already readable were written before this telegram: they count first.
  if (lpt_pty) on_lpt_pty_ready();
  ++counters.telegrams_received;
  logger.log(LogLevel::info, control::to_string(from) + " -> " + protocol::format_telegram(payload));
  const SimTime at = now();
  perform(unit->handle_request(at, from, payload, *this));
  follow_head_target(at);
  apply_can_config_changes();
}

void Daemon::Impl::framing_error(ConnectionId from, const protocol::FramingError& error) {
  ++counters.framing_errors;
  logger.log(LogLevel::info, control::to_string(from) + " -> framing error: " +
                                 std::string(protocol::describe(error.detail)));
  const SimTime at = now();
  perform(unit->on_framing_error(at, from, error));
  follow_head_target(at);
}

void Daemon::Impl::perform(const control::Actions& actions) {
  for (const control::OutgoingTelegram& telegram : actions.telegrams) {
    send_telegram(telegram);
  }
  for (const control::TimerRequest& timer : actions.timers) {
    deadlines.add(timer.at, [this, id = timer.id](SimTime at) {
      perform(unit->on_timer(at, id, *this));
      follow_head_target(at);
    });
  }
  if (actions.flash_image) {
    flash->save(*actions.flash_image);
    if (auto* file = dynamic_cast<FileFlashStore*>(flash.get()); file && !file->last_error().empty()) {
      logger.log(LogLevel::error, file->last_error());
    }
  }
}

// D9 head_dynamics: the ripple model follows every change of the head's target that the control
// unit makes (a spin-up starts with its SpinUp record; a stop ends the epoch at `at`). A spin-up
// that completes keeps its key (to_hz, reached_at), so completion is not a new target.
void Daemon::Impl::follow_head_target(SimTime at) {
  if (!head_track) return;
  const control::DeviceState& state = unit->state();
  const std::pair<std::uint16_t, SimTime> target =
      state.spin_up ? std::pair{state.spin_up->to_hz, state.spin_up->reached_at}
                    : std::pair{state.head.speed_hz, state.head.epoch_start};
  if (target == mirrored_head_target) return;
  mirrored_head_target = target;
  head_track->set_target(at, target.first);
}

void Daemon::Impl::send_telegram(const control::OutgoingTelegram& telegram) {
  const bool is_profile = telegram.kind == control::TelegramKind::profile;
  logger.log(is_profile ? LogLevel::debug : LogLevel::info,
             control::to_string(telegram.to) + " <- " + protocol::format_telegram(telegram.payload));
  switch (telegram.to.kind) {
    case TransportKind::tcp:
      send_tcp(telegram.to.index, protocol::encode_tcp_frame(telegram.payload));
      break;
    case TransportKind::serial:
      send_serial(protocol::encode_serial_reply(telegram.payload));  // all packages, one write (D10)
      break;
    case TransportKind::can: {
      const std::size_t channel = telegram.to.index - 1;
      if (can && channel < can->channels.size()) {
        handle_channel_output(channel, can->channels[channel].send(now(), telegram.payload));
      }
      break;
    }
  }
}

void Daemon::Impl::after_event() {
  const control::Diagnostics& diagnostics = unit->diagnostics();
  counters.skipped_profiles = diagnostics.skipped_profiles;
  counters.profiles_sent = diagnostics.profiles_sent;
  if (options.count_profiles && diagnostics.profiles_sent >= *options.count_profiles) {
    stop_loop();
  }
  if (!clock.is_virtual()) {
    arm_wall_timer();
  }
}

// ----------------------------------------------------------------------------------------- TCP

void Daemon::Impl::on_listener_ready() {
  ++activity;
  for (;;) {
    auto accepted = tcp->listener.accept();
    if (!accepted) {
      logger.log(LogLevel::warn, accepted.error().message());
      return;
    }
    if (!accepted->has_value()) {
      return;
    }
    const std::uint32_t index = tcp->next_index++;
    const int fd = (*accepted)->fd();
    logger.log(LogLevel::info, "tcp#" + std::to_string(index) + " connected from " + (*accepted)->peer());
    tcp->clients.emplace(index, TcpClient{std::move(**accepted), protocol::TcpDeframer(), OutputQueue()});
    ++counters.tcp_connections;
    if (auto watched = loop->watch(fd, io::Interest::readable,
                                   [this, index](io::Readiness r) { on_tcp_client_ready(index, r); });
        !watched) {
      close_tcp(index, watched.error().message());
    }
  }
}

void Daemon::Impl::on_tcp_client_ready(std::uint32_t index, io::Readiness readiness) {
  ++activity;
  const ConnectionId connection{TransportKind::tcp, index};
  if (readiness.writable) {
    flush_tcp(index);
  }
  std::size_t budget = kReadBudgetBytes;
  while (budget > 0) {
    const auto client = tcp->clients.find(index);
    if (client == tcp->clients.end()) {
      return;  // dropped while serving its own telegrams
    }
    auto received = client->second.connection.receive(budget);
    if (!received) {
      close_tcp(index, received.error().message());
      return;
    }
    if (received->bytes.empty()) {
      if (received->peer_closed) {
        close_tcp(index, "peer closed");
      }
      break;
    }
    budget -= std::min(budget, received->bytes.size());
    const auto events = client->second.deframer.feed(received->bytes);
    for (const protocol::DeframerEvent& event : events) {
      if (!tcp->clients.count(index)) {
        return;
      }
      if (const auto* telegram = std::get_if<protocol::Telegram>(&event)) {
        deliver(connection, telegram->payload);
      } else {
        framing_error(connection, std::get<protocol::FramingError>(event));
      }
    }
    if (received->peer_closed) {
      close_tcp(index, "peer closed");
      return;
    }
  }
}

void Daemon::Impl::send_tcp(std::uint32_t index, ByteView frame) {
  const auto client = tcp ? tcp->clients.find(index) : decltype(tcp->clients.end()){};
  if (!tcp || client == tcp->clients.end()) {
    return;  // the connection closed before its reply was ready
  }
  if (!client->second.output.push(frame)) {
    ++counters.tcp_dropped_slow;
    close_tcp(index, "output queue over " + std::to_string(client->second.output.max_bytes()) +
                         " bytes (host does not read)");
    return;
  }
  flush_tcp(index);
}

void Daemon::Impl::flush_tcp(std::uint32_t index) {
  const auto client = tcp->clients.find(index);
  if (client == tcp->clients.end()) return;
  OutputQueue& output = client->second.output;
  while (!output.empty()) {
    // One send per telegram while the kernel has room (D10, spec 6: no gap inside a frame).
    auto sent = client->second.connection.send(output.front());
    if (!sent) {
      close_tcp(index, sent.error().message());
      return;
    }
    if (*sent == 0) break;
    output.consume(*sent);
  }
  const io::Interest interest = output.empty() ? io::Interest::readable : io::Interest::readable | io::Interest::writable;
  (void)loop->change_interest(client->second.connection.fd(), interest);
}

void Daemon::Impl::close_tcp(std::uint32_t index, std::string_view why) {
  const auto client = tcp->clients.find(index);
  if (client == tcp->clients.end()) return;
  logger.log(LogLevel::info, "tcp#" + std::to_string(index) + " closed: " + std::string(why));
  loop->unwatch(client->second.connection.fd());
  tcp->clients.erase(client);
  unit->on_connection_closed(ConnectionId{TransportKind::tcp, index});
}

// -------------------------------------------------------------------------------------- serial

void Daemon::Impl::on_serial_ready(io::Readiness readiness) {
  ++activity;
  if (readiness.writable) {
    flush_serial();
  }
  auto received = serial->pty.receive(kReadBudgetBytes);
  if (!received) {
    logger.log(LogLevel::warn, received.error().message());
    return;
  }
  const ConnectionId connection{TransportKind::serial, 1};
  for (const protocol::DeframerEvent& event : serial->deframer.feed(received->bytes)) {
    if (const auto* telegram = std::get_if<protocol::Telegram>(&event)) {
      deliver(connection, telegram->payload);
    } else {
      framing_error(connection, std::get<protocol::FramingError>(event));
    }
  }
}

void Daemon::Impl::send_serial(ByteView bytes) {
  if (!serial->output.push(bytes)) {
    // Nobody reads the line: a real LD would lose the bytes on the wire as well.
    ++counters.serial_overflows;
    serial->output.clear();
    return;
  }
  flush_serial();
}

void Daemon::Impl::flush_serial() {
  while (!serial->output.empty()) {
    auto sent = serial->pty.send(serial->output.front());
    if (!sent) {
      logger.log(LogLevel::warn, sent.error().message());
      break;
    }
    if (*sent == 0) break;
    serial->output.consume(*sent);
  }
  (void)loop->change_interest(serial->pty.fd(), serial->output.empty() ? io::Interest::readable
                                                                      : io::Interest::readable | io::Interest::writable);
}

// ----------------------------------------------------------------------------------------- CAN

void Daemon::Impl::on_can_ready(io::Readiness readiness) {
  ++activity;
  if (readiness.writable) {
    flush_can_backlog();
  }
  for (int frames_this_round = 0; frames_this_round < 256; ++frames_this_round) {
    auto frame = can->socket.receive();
    if (!frame) {
      logger.log(LogLevel::warn, frame.error().message());
      return;
    }
    if (!frame->has_value()) return;
    for (std::size_t channel = 0; channel < can->channels.size(); ++channel) {
      if (can->channels[channel].accepts(**frame)) {
        handle_channel_output(channel, can->channels[channel].on_frame(now(), **frame));
        break;
      }
    }
  }
}

void Daemon::Impl::handle_channel_output(std::size_t channel, IsoTpChannelOutput output) {
  transmit_can(output.frames);
  schedule_channel_poll(channel);
  for (const Bytes& telegram : output.telegrams) {
    deliver(ConnectionId{TransportKind::can, static_cast<std::uint32_t>(channel + 1)}, telegram);
  }
}

void Daemon::Impl::schedule_channel_poll(std::size_t channel) {
  if (!can || channel >= can->channels.size()) return;
  const auto due = can->channels[channel].deadline();
  auto& scheduled = can->scheduled_polls[channel];
  if (scheduled && due && scheduled->first == *due) return;
  // Exactly the channel's own deadline stays queued: a transfer that ended (or a timer that moved)
  // leaves no stale poll behind, which with virtual time would jump the clock by N_Bs/N_Cr (D1,
  // D7) after every multi-frame telegram, so that a scan over CAN would see other revolutions
  // (and other D6 noise) than the same scan over TCP.
  if (scheduled) {
    deadlines.cancel(*scheduled);
    scheduled.reset();
  }
  if (!due) return;
  scheduled = deadlines.add(*due, [this, channel](SimTime now_at) {
    can->scheduled_polls[channel].reset();  // this entry has just been taken off the queue
    handle_channel_output(channel, can->channels[channel].poll(now_at));
  });
}

void Daemon::Impl::transmit_can(const std::vector<protocol::CanFrame>& frames) {
  if (can->pacer) {
    const SimTime at = now();
    for (const protocol::CanFrame& frame : frames) {
      can->pacer->push(at, frame);
    }
    release_paced_frames(at);
    return;
  }
  for (const protocol::CanFrame& frame : frames) {
    can->backlog.push_back(frame);
  }
  flush_can_backlog();
}

// D9 bus_timing: frames whose last bit is on the bus go to the socket; the next one is a deadline.
void Daemon::Impl::release_paced_frames(SimTime at) {
  for (const protocol::CanFrame& frame : can->pacer->take_due(at)) {
    can->backlog.push_back(frame);
  }
  flush_can_backlog();
  const std::optional<SimTime> due = can->pacer->deadline();
  if (!due || (can->pacer_scheduled && *can->pacer_scheduled <= *due)) return;
  can->pacer_scheduled = *due;
  deadlines.add(*due, [this, scheduled_for = *due](SimTime now_at) {
    if (can->pacer_scheduled == scheduled_for) can->pacer_scheduled.reset();
    release_paced_frames(now_at);
  });
}

void Daemon::Impl::flush_can_backlog() {
  while (!can->backlog.empty()) {
    auto sent = can->socket.send(can->backlog.front());
    if (!sent) {
      logger.log(LogLevel::warn, sent.error().message());
      can->backlog.pop_front();
      continue;
    }
    if (*sent == io::SendOutcome::queue_full) {
      ++counters.can_frames_backlogged;
      break;
    }
    can->backlog.pop_front();
  }
  (void)loop->change_interest(can->socket.fd(), can->backlog.empty() ? io::Interest::readable
                                                                    : io::Interest::readable | io::Interest::writable);
}

void Daemon::Impl::apply_can_config_changes() {
  const protocol::CanConfig& ram = unit->state().ram.can;
  if (ram == applied_can_config) return;
  applied_can_config = ram;
  if (!can) return;
  if (can->pacer) {
    can->pacer->set_bit_rate(can_bit_rate_bps(ram.bitrate_code));  // frames from now on (D1, D9)
  }
  // D1: SET_CONFIG key 0x0002 (or a reset to flash) moves the first host's pair and sets our
  // BS/STmin; the reply that confirmed it already left on the old identifiers.
  for (std::size_t channel = 0; channel < can->channels.size(); ++channel) {
    IsoTpChannelConfig config = can->channels[channel].config();
    if (channel == 0) {
      config.ids = CanIdPair{ram.request_id, ram.response_id};
    }
    config.block_size = static_cast<std::uint8_t>(ram.block_size);
    config.st_min = std::chrono::milliseconds(ram.st_min_ms);
    const IsoTpChannelCounters& old = can->channels[channel].counters();
    can->retired.receive_errors += old.receive_errors;
    can->retired.send_failures += old.send_failures;
    can->retired.queue_overflows += old.queue_overflows;
    can->channels[channel] = IsoTpChannel(config);
    if (can->scheduled_polls[channel]) deadlines.cancel(*can->scheduled_polls[channel]);
    can->scheduled_polls[channel].reset();
  }
  set_can_filters();
  logger.log(LogLevel::info, "can pair 1 now " + hex_id(ram.request_id) + ":" + hex_id(ram.response_id));
}

void Daemon::Impl::set_can_filters() {
  std::vector<io::CanIdFilter> filters;
  for (const IsoTpChannel& channel : can->channels) {
    filters.push_back(io::exact_standard_id(channel.config().ids.request_id));
  }
  if (auto status = can->socket.set_filters(filters); !status) {
    logger.log(LogLevel::warn, status.error().message());
  }
}

// ----------------------------------------------------------------------------------------- LPT

void Daemon::Impl::on_lpt_pty_ready() {
  ++activity;
  auto received = lpt_pty->receive(kReadBudgetBytes);
  if (!received) {
    logger.log(LogLevel::warn, received.error().message());
    return;
  }
  const SimTime at = now();  // D8: time-stamped on arrival
  for (const std::uint8_t value : received->bytes) {
    board->on_register_write(at, value);
  }
  counters.lpt_steps = board->steps_seen();
}

void Daemon::Impl::on_lpt_gpio_ready() {
  ++activity;
  auto events = lpt_gpio->read_events();
  if (!events) {
    logger.log(LogLevel::warn, events.error().message());
    return;
  }
  for (const io::GpioEdgeEvent& edge : *events) {
    if (edge.line_index >= std::size(kLptLineBits)) continue;
    // Kernel timestamps are CLOCK_MONOTONIC, the wall clock the simulated one runs on (D7).
    const SimTime at = clock.now(WallTime(std::chrono::duration_cast<WallTime::duration>(edge.timestamp)));
    board->on_line_change(at, kLptLineBits[edge.line_index], edge.edge == io::Edge::rising);
  }
  counters.lpt_steps = board->steps_seen();
}

// ---------------------------------------------------------------------------------------- time

void Daemon::Impl::fire_due(SimTime at) {
  while (auto entry = deadlines.pop_due(at)) {
    entry->second(at);
  }
}

void Daemon::Impl::arm_wall_timer() {
  const std::optional<SimTime> earliest = deadlines.earliest();
  if (earliest == wall_timer_for) return;
  if (wall_timer) {
    loop->cancel_timer(*wall_timer);
    wall_timer.reset();
  }
  wall_timer_for = earliest;
  if (!earliest) return;
  wall_timer = loop->add_timer_at(clock.wall_deadline(*earliest, io::EventLoop::now()), [this, due = *earliest] {
    wall_timer.reset();
    wall_timer_for.reset();
    clock.advance_to(due);  // the wall deadline is rounded up; never let rounding make it early
    fire_due(now());
    after_event();
  });
}

void Daemon::Impl::on_signal(int signal_number) {
  if (signal_number == SIGUSR1) {
    collect_counters();
    logger.log(LogLevel::error, format_counters(counters));  // asked for: shown at every level
    return;
  }
  stop_signal = signal_number;
  stop_loop();
}

// The counters kept elsewhere (control unit, ISO-TP channels) into the one DaemonCounters line.
void Daemon::Impl::collect_counters() {
  counters.skipped_profiles = unit->diagnostics().skipped_profiles;
  counters.profiles_sent = unit->diagnostics().profiles_sent;
  if (!can) return;
  IsoTpChannelCounters sum = can->retired;
  for (const IsoTpChannel& channel : can->channels) {
    sum.receive_errors += channel.counters().receive_errors;
    sum.send_failures += channel.counters().send_failures;
    sum.queue_overflows += channel.counters().queue_overflows;
  }
  counters.isotp_receive_errors = sum.receive_errors;
  counters.isotp_send_failures = sum.send_failures;
  counters.isotp_queue_overflows = sum.queue_overflows;
}

void Daemon::Impl::save_flash() {
  if (options.flash_mode != FlashMode::file) return;
  flash->save(control::serialise_flash_image(unit->state().flash));
  if (auto* file = dynamic_cast<FileFlashStore*>(flash.get()); file && !file->last_error().empty()) {
    logger.log(LogLevel::error, file->last_error());
  }
}

int Daemon::Impl::run() {
  if (options.timeout_s) {
    loop->add_timer_after(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(*options.timeout_s)),
                          [this] { stop_loop(); });
  }
  if (clock.is_virtual()) {
    while (!loop->stop_requested()) {
      const std::uint64_t before = activity;
      if (auto status = loop->run_once(std::chrono::nanoseconds::zero()); !status) {
        logger.log(LogLevel::error, status.error().message());
        fatal = true;
        break;
      }
      fire_due(now());
      if (activity != before) {
        last_activity_wall = io::EventLoop::now();
      } else if (!loop->stop_requested()) {
        const bool host_grace = waiting_for_host() && io::EventLoop::now() - last_activity_wall < kVirtualHostGrace;
        if (const auto earliest = deadlines.earliest(); earliest && !host_grace) {
          clock.advance_to(*earliest);  // D7 virtual clock: nothing is ready, jump ahead
          fire_due(now());
        } else if (auto status = loop->run_once(kVirtualIdleWait); !status) {
          logger.log(LogLevel::error, status.error().message());
          fatal = true;
          break;
        }
        // A host heard during the idle wait is activity too: without this, a request that
        // arrived there started its reply's N_Bs wait with an old last_activity_wall, and the
        // clock jumped over the host's flow control at once (D1 send failure).
        if (activity != before) last_activity_wall = io::EventLoop::now();
      }
      after_event();
    }
  } else {
    // Every fd callback ends in the control unit; re-arm after each loop round.
    while (!loop->stop_requested()) {
      after_event();
      if (auto status = loop->run_once(std::chrono::seconds(1)); !status) {
        logger.log(LogLevel::error, status.error().message());
        fatal = true;
        break;
      }
    }
  }
  if (tcp) {
    for (auto& [index, client] : tcp->clients) {
      flush_tcp(index);
    }
  }
  save_flash();
  collect_counters();
  logger.log(LogLevel::info, format_counters(counters));
  if (stop_signal) return kExitSignalBase + *stop_signal;
  return fatal ? kExitRuntimeFailure : kExitOk;
}

// ------------------------------------------------------------------------------------- Daemon

Daemon::Daemon(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Daemon::~Daemon() = default;

protocol::Expected<std::unique_ptr<Daemon>, StartFailure> Daemon::create(Options options, scene::Scene scene,
                                                                         std::ostream& out, std::ostream& log) {
  // Block the daemon's signals before any thread exists (Embree and TBB start workers while the
  // scene is built): threads inherit the mask, so the signals reach only the loop's signalfd and
  // never kill the process before the flash is saved.
  sigset_t handled;
  sigemptyset(&handled);
  for (const int number : kHandledSignals) sigaddset(&handled, number);
  if (const int error = ::pthread_sigmask(SIG_BLOCK, &handled, nullptr); error != 0) {
    return Unexpected(StartFailure{kExitRuntimeFailure, std::string("pthread_sigmask: ") + std::strerror(error)});
  }
  auto impl = std::make_unique<Impl>(std::move(options), std::move(scene), out, log);
  if (auto failure = impl->build_models()) return Unexpected(std::move(*failure));
  if (auto failure = impl->open_endpoints()) return Unexpected(std::move(*failure));
  // Simulated time 0 = power-up (D4) = the moment the endpoints are open.
  impl->clock = impl->options.virtual_time ? SimClock::virtual_clock()
                                           : SimClock::scaled(io::EventLoop::now(), impl->options.time_scale);
  out << "ready" << std::endl;
  return std::unique_ptr<Daemon>(new Daemon(std::move(impl)));
}

int Daemon::run() { return impl_->run(); }

DaemonCounters Daemon::counters() const {
  impl_->collect_counters();
  return impl_->counters;
}

std::optional<std::uint16_t> Daemon::tcp_port() const {
  if (!impl_->tcp) return std::nullopt;
  return impl_->tcp->listener.port();
}

}  // namespace ldoem::daemon
