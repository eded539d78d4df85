#include "runner.hpp"

#include "cases.hpp"
#include "ldoem/driver/transport.hpp"
#include "recording_transport.hpp"
#include "session.hpp"
#include "timing_probe.hpp"

namespace ldoem::conformance {
namespace {

std::vector<const Case*> select(const std::vector<Case>& cases, const SuiteOptions& options, protocol::Transport kind) {
  std::vector<const Case*> selected;
  for (const Case& c : cases) {
    const std::string name = std::string(protocol::transport_name(kind)) + "/" + c.name;
    // matches_any is true for an empty list (no --filter: all), so an empty --exclude is checked first.
    const bool excluded = !options.excludes.empty() && matches_any(options.excludes, name);
    if (c.applies_to(kind, options.target) && matches_any(options.filters, name) && !excluded) selected.push_back(&c);
  }
  return selected;
}

// After a failed case the link may hold late replies, or be closed by a raw-session case.
void recover(Session& session, std::ostream& err) {
  try {
    session.drain(std::max(std::chrono::milliseconds(200), session.wall_for(SimMilliseconds(500))));
  } catch (const CaseFailed&) {
    try {
      session.reopen_transport();
    } catch (const CaseFailed& reopen) {
      err << "ldoem-conformance: " << reopen.what() << '\n';
    }
  }
}

}  // namespace

void list_cases(const SuiteOptions& options, const VectorTable& vectors, std::ostream& out) {
  const std::vector<Case> cases = all_cases(vectors);
  std::vector<protocol::Transport> kinds{protocol::Transport::tcp, protocol::Transport::can, protocol::Transport::serial};
  if (options.endpoint) kinds = {driver::transport_of(*options.endpoint)};
  for (protocol::Transport kind : kinds) {
    for (const Case* c : select(cases, options, kind)) out << protocol::transport_name(kind) << '/' << c->name << '\n';
  }
}

int run_cases(const SuiteOptions& options, const VectorTable& vectors, std::ostream& out, std::ostream& err) {
  // A --filter or --exclude that selects nothing is a typo, not a green run.
  const std::vector<Case> cases = all_cases(vectors);
  const protocol::Transport kind = driver::transport_of(*options.endpoint);
  if (select(cases, options, kind).empty()) {
    err << "ldoem-conformance: --filter/--exclude select no " << protocol::transport_name(kind)
        << " case (--list with the same options shows what they select)\n";
    return kExitUsageError;
  }
  auto transport = open_suite_transport(options);
  if (!transport) {
    err << "ldoem-conformance: " << transport.error() << '\n';
    out << summary_line(0, 1, 0) << '\n';
    return kExitFailed;
  }
  Session session(std::move(*transport), options, vectors);
  int passed = 0;
  int failed = 0;
  int inconclusive = 0;
  for (const Case* c : select(cases, options, kind)) {
    const std::string name = std::string(protocol::transport_name(kind)) + "/" + c->name;
    const std::uint64_t dropped_before = session.transport_counters().dropped_frames;
    // Every case runs with the probe: its verdict decides a failure of the host's side (a wall-
    // clock check, a wait that timed out, telegrams the link lost), never a device-clock one.
    std::optional<SchedulingProbe> probe;
    if (!options.virtual_time) probe.emplace();
    try {
      if (c->needs_baseline) {
        try {
          session.restore_baseline();
        } catch (const CaseFailed& baseline) {
          throw CaseFailed(std::string("baseline: ") + baseline.what(), baseline.detail());
        }
      }
      c->run(session);
      out << "PASS " << name << std::endl;
      ++passed;
    } catch (const CaseFailed& failure) {
      std::optional<std::string> busy;
      if (const auto* wall = dynamic_cast<const WallClockFailed*>(&failure); wall != nullptr && probe) {
        busy = machine_busy(probe->stop(), wall->tolerance_ms());
      }
      if (busy && !options.strict_timing) {
        // Not a verdict on the device: the machine could not keep the time the check needs.
        out << "INCONCLUSIVE " << name << " (" << *busy << "): " << failure.what() << '\n' << std::flush;
        ++inconclusive;
        recover(session, err);
        continue;
      }
      out << "FAIL " << name << ": " << failure.what() << '\n' << failure.detail();
      if (busy) out << "    (--strict-timing: " << *busy << ")\n";
      // Telegrams our own transport dropped (bad checksum/CRC, broken ISO-TP sequence) point at
      // the link rather than at the device's logic.
      const std::uint64_t dropped = session.transport_counters().dropped_frames - dropped_before;
      if (dropped > 0) out << "    (the transport dropped " << dropped << " broken telegram(s) during this case)\n";
      out << std::flush;
      ++failed;
      recover(session, err);
    }
  }
  out << summary_line(passed, failed, inconclusive) << std::endl;
  return failed == 0 ? kExitAllPassed : kExitFailed;
}

}  // namespace ldoem::conformance
