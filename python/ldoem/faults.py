"""The fault matrix: every D11 kind that applies to a transport (docs/faults.md "Kinds"), each at
three trigger points, as control-socket fault entries; and how a scenario's run is judged.

Trigger points (each an `on` trigger: the fault starts with the host's nth request of a service,
so a run is the same under virtual time whatever the machine's speed):
  during_init            the host's first GET_STATUS (libldoem's connect, S1's first request)
  while_streaming        the host's first GET_PROFILE: the fault meets the stream as it starts
                         (a per-layer client such as ldoem-scan: its first layer)
  during_config_write    the host's first SET_CONFIG
A driver that never sends that request never meets the fault: the scenario says `not triggered`.

The LPT faults (lpt_lose_steps, lpt_jam) are left out: the stepper has no encoder (D8), so no
host can tell, and there is nothing to judge.
"""

import dataclasses

# The emulator's catalogue (emulator/faults, fault_kind.hpp), written at build time: a kind the
# emulator gains is in the matrix with no edit here.
from ._fault_catalogue import FAULT_CATALOGUE

# The host transports the matrix runs on: the LPT kinds are left out (above).
_HOST_TRANSPORTS = ("tcp", "serial", "can")

DEVICE_KINDS = tuple(name for name, fault_class, _, _ in FAULT_CATALOGUE if fault_class == "device")
# Each wire kind that applies to a host transport, with the transports it applies to.
WIRE_KINDS = {name: tuple(transport for transport in transports if transport in _HOST_TRANSPORTS)
              for name, fault_class, transports, _ in FAULT_CATALOGUE
              if fault_class == "wire" and any(transport in _HOST_TRANSPORTS for transport in transports)}
_LASTING_DEVICE_KINDS = frozenset(name for name, fault_class, _, one_shot in FAULT_CATALOGUE
                                  if fault_class == "device" and not one_shot)

# What the device does after the fault is final for a job: libldoem says reset_device (D11).
FINAL_KINDS = ("motor_stall", "motor_overspeed", "encoder_error")

# Each kind's parameters in the matrix: short, and over within a second of device time where the
# kind has a duration, so that a driver that retries can succeed. A kind not listed takes its
# defaults (a wire fault acts on one telegram), except that a device fault that is not one-shot
# lasts 1 s (without a duration it would stay until cleared).
PARAMETERS = {
    "motor_stall": {"duration_s": 1},
    "motor_overspeed": {"duration_s": 1},
    "encoder_error": {"duration_s": 1},
    "power_cycle": {"off_s": 1},
    "reset_spontaneous": {},
    "blind": {"from_deg": 350, "to_deg": 10, "duration_s": 1},
    "window_dirt": {"fraction": 0.5, "duration_s": 1},
    "drop_reply": {},
    "delay_reply": {"delay_s": 1},
    "duplicate_reply": {},
    "truncate_reply": {"bytes_kept": 4},
    "garbage": {"bytes": 8},
    "corrupt_checksum": {},
    "tcp_reset": {},
    "tcp_stall": {"duration_s": 1},
    "bandwidth": {"bytes_per_s": 2000, "duration_s": 1},
    "isotp_drop_cf": {},
    "isotp_repeat_cf": {},
    "isotp_bad_sn": {},
    "isotp_fc_overflow": {},
    "isotp_fc_wait": {"duration_s": 1},
    "can_silence": {"duration_s": 1},
}

TRIGGERS = {
    "during_init": {"service": "GET_STATUS", "nth": 1},
    "while_streaming": {"service": "GET_PROFILE", "nth": 1},
    "during_config_write": {"service": "SET_CONFIG", "nth": 1},
}


def kinds_for(transport):
    """The D11 kinds that apply to a host transport, device kinds first."""
    return list(DEVICE_KINDS) + [kind for kind, transports in WIRE_KINDS.items() if transport in transports]


@dataclasses.dataclass(frozen=True)
class Scenario:
    transport: str
    kind: str
    trigger: str

    @property
    def id(self):
        return f"{self.transport}-{self.kind}-{self.trigger}"

    def fault(self):
        """The inject-fault arguments (without kind)."""
        default = {"duration_s": 1} if self.kind in _LASTING_DEVICE_KINDS else {}
        entry = dict(PARAMETERS.get(self.kind, default))
        entry["on"] = dict(TRIGGERS[self.trigger])
        if self.kind in WIRE_KINDS:
            entry["transport"] = self.transport
        return entry


def scenarios(transport="tcp", kinds=None, triggers=None):
    """Every scenario of a transport, or those of the given kinds and trigger points."""
    chosen_kinds = kinds_for(transport)
    if kinds:
        unknown = [kind for kind in kinds if kind not in chosen_kinds]
        if unknown:
            raise ValueError(f"kinds {unknown} do not apply to {transport} (they do: {chosen_kinds})")
        chosen_kinds = [kind for kind in chosen_kinds if kind in kinds]
    chosen_triggers = list(triggers) if triggers else list(TRIGGERS)
    for trigger in chosen_triggers:
        if trigger not in TRIGGERS:
            raise ValueError(f"unknown trigger point {trigger!r} (known: {list(TRIGGERS)})")
    return [Scenario(transport, kind, trigger) for kind in chosen_kinds for trigger in chosen_triggers]


@dataclasses.dataclass
class Outcome:
    """What the device did in a scenario's run."""
    scenario: Scenario
    triggered: bool = False
    events: list = dataclasses.field(default_factory=list)
    profiles_sent: int = 0
    profiles_after_fault: object = None  # None: no fault acted
    daemon_exit: object = None  # ldoem-emud's exit status when it died during the run
    refusals: list = dataclasses.field(default_factory=list)  # (time s, request code, D2 reason)

    @property
    def device(self):
        """One line: which events the fault caused."""
        names = [event["event"] for event in self.events if event["event"] not in ("CONNECTION_OPENED", "CONNECTION_CLOSED")]
        text = " ".join(names) if names else "no fault event"
        if self.refusals:
            refused = ", ".join(f"0x{code:04X} reason {reason}" for _, code, reason in self.refusals[:5])
            more = f" and {len(self.refusals) - 5} more" if len(self.refusals) > 5 else ""
            text += f"; refused: {refused}{more}"
        if self.daemon_exit is not None:
            text += f"; ldoem-emud DIED (exit status {self.daemon_exit})"
        return text

    @property
    def recovered(self):
        return self.profiles_after_fault is not None and self.profiles_after_fault > 0

    def summary(self):
        if not self.triggered:
            return f"{self.scenario.id}: not triggered (the driver never sent {TRIGGERS[self.scenario.trigger]['service']})"
        flow = "profiles flowed again" if self.recovered else "no profile after the fault"
        return f"{self.scenario.id}: {self.device}; {flow} ({self.profiles_after_fault} after, {self.profiles_sent} in all)"


FAULT_MARKS = ("FAULT_INJECTED", "FAULT_CLEARED", "POWER_ON")


def _seconds(event):
    stamp = event.get("timestamp", {})
    return stamp.get("seconds", 0) + stamp.get("microseconds", 0) / 1e6


def outcome_of(scenario, emulator):
    """The Outcome of a run on `emulator` (started with record=True for the profile count): its
    counters while it still runs, then it is stopped and its event log and recording read.
    profiles_after_fault counts the profiles sent after the last fault event (injection, clearing
    or power-on), both on the device clock; None without a fault or a TCP recording."""
    outcome = Outcome(scenario)
    if emulator.running:
        try:
            outcome.profiles_sent = emulator.query_status()["counters"]["profiles_sent"]
        except Exception:  # noqa: BLE001 - a daemon that dies now is reported below
            pass
    else:
        outcome.daemon_exit = emulator.process.returncode if emulator.process else emulator.returncode
    emulator.stop()
    outcome.events = emulator.event_log()
    marks = [_seconds(event) for event in outcome.events if event["event"] in FAULT_MARKS]
    outcome.triggered = any(event["event"] == "FAULT_INJECTED" for event in outcome.events)
    outcome.refusals = emulator.refusals() or []
    times = emulator.profile_times()
    if outcome.triggered and times is not None:
        outcome.profiles_after_fault = sum(1 for t in times if t > marks[-1])
    return outcome
