// The control unit: the LD-OEM itself, as a pure state machine (design.md convention 4).
//
//   (time, event) -> Actions{telegrams to send, timers to arm, flash image to store}
//
// Events: a request payload from a connection (handle_request), a timer it asked for
// (on_timer), a frame the deframer dropped (on_framing_error), a connection that closed
// (on_connection_closed). It never reads a clock, touches an fd or sleeps: `now` is simulated
// time (D7), passed in, and must not go backwards between calls.
//
// How the daemon drives it:
//   ControlUnit unit({flash config, identification, power-up time}, head_model, measurement);
//   on a telegram:   run(unit.handle_request(now, connection, payload, transport));
//   on a dropped frame: run(unit.on_framing_error(now, connection, framing_error));
//   at a timer:      run(unit.on_timer(now, id, transport));
//   on close:        run(unit.on_connection_closed(now, connection));
// where run() sends the telegrams in order (each in one piece, D10), drops the cancelled
// timers, arms the new ones (on_timer(at, id) when simulated time reaches `at`), saves
// and passes a new head target or CAN configuration on (ports.hpp Actions). Flash writes go to
// Setup::flash_store before the reply is built; Actions::flash_image reports what was stored.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ldoem/control/device_clock.hpp"
#include "ldoem/control/device_config.hpp"
#include "ldoem/control/device_model.hpp"
#include "ldoem/control/device_faults.hpp"
#include "ldoem/control/flash_image.hpp"
#include "ldoem/control/identification.hpp"
#include "ldoem/control/ports.hpp"
#include "ldoem/protocol/framing.hpp"
#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::control {

// Spec 5: the operating modes (the low nibble of the status byte, spec 2.4).
enum class DeviceMode : std::uint8_t { idle, rotate, measure, error };

std::string_view describe(DeviceMode mode);

// The head at a steady speed. Revolutions are counted per epoch (the time the head reached
// its speed); PROFILECOUNT = revolutions_before_epoch + k + 1 for revolution k (D3).
struct HeadState {
  std::uint16_t speed_hz = 0;  // 0 = stopped
  SimTime epoch_start{};
  std::uint64_t revolutions_before_epoch = 0;
  bool operator==(const HeadState&) const = default;
};

// A TRANS_ROTATE waiting for the head to reach speed (lead decision 4, D7): its reply is held
// until the timer fires.
struct SpinUp {
  std::uint16_t from_hz = 0;
  std::uint16_t to_hz = 0;
  SimTime reached_at{};
  TimerId timer;
  std::optional<ConnectionId> reply_to;  // empty once that connection closed
  bool operator==(const SpinUp&) const = default;
};

// One connection's GET_PROFILE (D10: profiles go only to the connection that asked).
struct ProfileStream {
  std::uint16_t format = 0;
  std::uint16_t profiles_wanted = 0;  // 0 = until CANCEL_PROFILE
  std::uint16_t profiles_sent = 0;    // PROFILESENT of the last one sent (D3: from 1)
  std::uint64_t next_revolution = 0;  // the next revolution (of the head epoch) it wants
  bool operator==(const ProfileStream&) const = default;
};

// The revolution whose profile is due when `timer` fires.
struct RevolutionTimer {
  TimerId timer;
  std::uint64_t revolution = 0;
  bool operator==(const RevolutionTimer&) const = default;
};

// A motor fault under way (D11): what the status nibble says now and the steps still to come.
struct MotorFaultCourse {
  MotorFault fault = MotorFault::stall;
  protocol::MotorMode nibble = protocol::MotorMode::ok;
  std::vector<MotorFaultStep> steps;  // in time order
  std::optional<TimerId> timer;       // fires at steps.front().at
  bool operator==(const MotorFaultCourse&) const = default;
};

// Everything the device is. A full reset (DO_RESET 0/1) makes it equal to the power-up state
// (tested), so every field added here must be set by power_up_state().
struct DeviceState {
  DeviceMode mode = DeviceMode::idle;
  HeadState head;
  std::optional<SpinUp> spin_up;
  std::map<ConnectionId, ProfileStream> streams;
  std::optional<RevolutionTimer> revolution_timer;
  DeviceConfig ram;
  DeviceConfig flash;
  DeviceClock clock;
  std::uint16_t port_value = 0;  // GET_SIGNAL / SET_SIGNAL (spec 3.3)
  std::optional<MotorFaultCourse> motor_fault;  // D11; a reset ends it (the hardware may not heal)
  bool operator==(const DeviceState&) const = default;
};

// D4: IDLE, motor stopped, clock 0 at `now`, RAM = flash, nothing running.
DeviceState power_up_state(SimTime now, const DeviceConfig& flash);

// The emulated LD-OEM: the daemon's default device model (device_model.hpp).
class ControlUnit final : public DeviceModel {
 public:
  struct Setup {
    DeviceConfig flash = factory_config();  // what flash holds at power-up (load_flash_or)
    IdentificationTexts identification = default_identification();
    SimTime power_up_time{};
    // Where a service's flash write is stored, before its reply (must outlive the unit; null:
    // nowhere, every write succeeds). A write it refuses leaves RAM and flash as they were and
    // the host gets the service's error (docs/decisions-local.md L-flash-1), never a success.
    FlashStore* flash_store = nullptr;
  };

  // head and measurement must outlive the control unit.
  ControlUnit(Setup setup, const HeadModel& head, MeasurementSource& measurement);

  // One request payload (service WORD first, framing removed). Every request is answered in
  // the returned Actions, except GET_PROFILE (its answer is the profile stream, spec 3.5) and a
  // TRANS_ROTATE that has to wait for the head (its reply comes from on_timer).
  Actions handle_request(SimTime now, ConnectionId from, protocol::ByteView payload,
                         const TransportQuery& transport) override;

  // A timer from an earlier Actions. `transport` answers D10's busy question for profiles.
  Actions on_timer(SimTime now, TimerId timer, const TransportQuery& transport) override;

  // D2: a frame the deframer dropped is answered SERVICE_FAILURE with the reason
  // protocol::failure_reason_for_framing gives (5, or 2 for a serial length mismatch) and the
  // request code the frame carried (0 when none).
  Actions on_framing_error(SimTime now, ConnectionId from, const protocol::FramingError& error) override;

  // Stops the connection's stream; a held TRANS_ROTATE reply for it is dropped (the head still
  // spins up). The Actions name the revolution timer that no stream needs any more.
  Actions on_connection_closed(SimTime now, ConnectionId connection) override;

  // D11 device faults (control_unit_faults.cpp). The motor fault is a hardware condition: it
  // survives DO_RESET and power cycles until clear_motor_fault(). With `decelerates` (the scene
  // has head_dynamics) a stall coasts down through the head model (nibble 0x4 below 90 % of
  // nominal, 0xB stopped); without, the head stops at once (0xB). ERROR follows one revolution
  // after the nibble turns non-zero (encoder_error: at once). A running stream stops at once.
  // A latent fault (head not spinning) shows when the device next tries to spin: TRANS_ROTATE
  // is answered at once with ERROR and the fault's nibble.
  Actions inject_motor_fault(SimTime now, MotorFault fault, bool decelerates);
  void clear_motor_fault() { hardware_motor_fault_.reset(); }
  std::optional<MotorFault> hardware_motor_fault() const { return hardware_motor_fault_; }
  // reset_spontaneous: DO_RESET level 0 that nobody asked for (no reply; streams stop).
  Actions spontaneous_reset(SimTime now);
  // power_cycle: the daemon drops every connection; at power-on the device is in the D4
  // power-up state with flash kept (RAM configuration lost).
  Actions power_on(SimTime now);
  // blind / window_dirt, applied to every profile after measuring (empty: nothing to do).
  void set_beam_faults(BeamFaults faults) { beam_faults_ = std::move(faults); }

  const DeviceState& state() const { return state_; }
  const Diagnostics& diagnostics() const override { return diagnostics_; }
  const protocol::CanConfig& can_config() const override { return state_.ram.can; }
  // The status byte any reply would carry now (spec 2.4).
  protocol::StatusByte status_byte() const;
  // The whole state and the diagnostics as text, one field per line, for test failure messages
  // and the daemon's state dump. Deterministic; shows the clock as read at `now`.
  std::string dump(SimTime now) const;

 private:
  // What every service handler gets: the time, the requester and the Actions being built.
  struct Event {
    SimTime now;
    ConnectionId from;
    Actions& out;
  };

  // One overload per request (spec 3.2). Status/configuration/time services live in
  // control_unit_services.cpp, transitions and reset in control_unit_motion.cpp, profiles in
  // control_unit_profiles.cpp.
  void serve(const Event& event, const protocol::GetIdentification& request);
  void serve(const Event& event, const protocol::GetStatus& request);
  void serve(const Event& event, const protocol::GetSignal& request);
  void serve(const Event& event, const protocol::SetSignal& request);
  void serve(const Event& event, const protocol::SetConfig& request);
  void serve(const Event& event, const protocol::GetConfig& request);
  void serve(const Event& event, const protocol::SetTimeAbs& request);
  void serve(const Event& event, const protocol::SetTimeRel& request);
  void serve(const Event& event, const protocol::GetSyncClock& request);
  void serve(const Event& event, const protocol::SetFilter& request);
  void serve(const Event& event, const protocol::SetFunction& request);
  void serve(const Event& event, const protocol::GetFunction& request);
  void serve(const Event& event, const protocol::GetProfile& request);
  void serve(const Event& event, const protocol::CancelProfile& request);
  void serve(const Event& event, const protocol::DoReset& request);
  void serve(const Event& event, const protocol::TransIdle& request);
  void serve(const Event& event, const protocol::TransRotate& request);
  void serve(const Event& event, const protocol::TransMeasure& request);

  void reply(const Event& event, const protocol::Response& response);
  void fail(const Event& event, protocol::Service service, protocol::FailureReason reason);
  TimerId arm_timer(Actions& out, SimTime at);
  // Stores `flash` as the new flash content (through Setup::flash_store) and emits the image
  // when it changed. False when the store refused it: state_.flash is then unchanged.
  [[nodiscard]] bool write_flash(Actions& out, const DeviceConfig& flash);
  protocol::StatusBlock status_block() const;

  // Head and revolutions (control_unit_motion.cpp).
  void end_head_epoch(SimTime now);  // counts the revolutions of the epoch that ends now
  void stop_head(SimTime now);
  void begin_spin(const Event& event, std::uint16_t to_hz);
  void complete_spin(SimTime now, Actions& out);

  // Faults (control_unit_faults.cpp).
  bool allowed_in_error(std::uint16_t request_code) const;
  void start_motor_fault(SimTime now, MotorFault fault, bool decelerates, Actions& out);
  void run_motor_fault_steps(SimTime now, Actions& out);
  void enter_error(SimTime now, Actions& out);
  void apply_beam_faults(std::uint64_t revolution, std::span<const BeamQuery> beams,
                         std::span<BeamReturn> returns) const;

  // Profiles (control_unit_profiles.cpp).
  void stop_all_streams();
  void ensure_revolution_timer(Actions& out);
  void emit_profiles(SimTime now, std::uint64_t revolution, const TransportQuery& transport, Actions& out);
  std::size_t profile_payload_bytes(std::uint16_t format) const;

  // The timers this unit still wants (spin-up, next revolution).
  std::vector<TimerId> live_timers() const;
  // Ends every event: names the timers that became stale and a changed head target or CAN
  // configuration, so that the daemon never has to compare states. `fired` is the timer this
  // event is (already off the daemon's queue).
  void report_changes(Actions& out, const std::vector<TimerId>& live_before, std::optional<TimerId> fired);

  Setup setup_;
  const HeadModel& head_;
  MeasurementSource& measurement_;
  DeviceState state_;
  Diagnostics diagnostics_;
  std::optional<MotorFault> hardware_motor_fault_;
  BeamFaults beam_faults_;
  std::uint64_t next_timer_id_ = 1;  // not device state: ids must never repeat, even across resets
  // What the daemon was last told (not device state): the head target as (speed, spin-up reach
  // time or epoch start), and the RAM CAN configuration.
  std::pair<std::uint16_t, SimTime> reported_head_target_{0, SimTime::zero()};
  protocol::CanConfig reported_can_config_;
};

}  // namespace ldoem::control
