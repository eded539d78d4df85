#include "ldoem/endpoints/counters.hpp"

#include <sstream>

namespace ldoem::endpoints {

Counters& Counters::operator+=(const Counters& o) {
  telegrams_received += o.telegrams_received;
  framing_errors += o.framing_errors;
  isotp_receive_errors += o.isotp_receive_errors;
  isotp_send_failures += o.isotp_send_failures;
  isotp_queue_overflows += o.isotp_queue_overflows;
  can_frames_backlogged += o.can_frames_backlogged;
  can_frames_dropped += o.can_frames_dropped;
  skipped_profiles += o.skipped_profiles;
  profiles_sent += o.profiles_sent;
  tcp_connections += o.tcp_connections;
  tcp_dropped_slow += o.tcp_dropped_slow;
  tcp_dropped_quiet += o.tcp_dropped_quiet;
  tcp_refused += o.tcp_refused;
  serial_overflows += o.serial_overflows;
  lpt_steps += o.lpt_steps;
  fault_injections += o.fault_injections;
  delayed_replies_dropped += o.delayed_replies_dropped;
  event_log_write_errors += o.event_log_write_errors;
  return *this;
}

std::string format_counters(const Counters& c) {
  std::ostringstream out;
  out << "counters: telegrams_received=" << c.telegrams_received << " framing_errors=" << c.framing_errors
      << " isotp_receive_errors=" << c.isotp_receive_errors << " isotp_send_failures=" << c.isotp_send_failures
      << " isotp_queue_overflows=" << c.isotp_queue_overflows << " can_frames_backlogged=" << c.can_frames_backlogged
      << " can_frames_dropped=" << c.can_frames_dropped
      << " skipped_profiles=" << c.skipped_profiles << " profiles_sent=" << c.profiles_sent
      << " tcp_connections=" << c.tcp_connections << " tcp_dropped_slow=" << c.tcp_dropped_slow
      << " tcp_dropped_quiet=" << c.tcp_dropped_quiet << " tcp_refused=" << c.tcp_refused
      << " serial_overflows=" << c.serial_overflows << " lpt_steps=" << c.lpt_steps
      << " fault_injections=" << c.fault_injections << " delayed_replies_dropped=" << c.delayed_replies_dropped
      << " event_log_write_errors=" << c.event_log_write_errors;
  return out.str();
}

}  // namespace ldoem::endpoints
