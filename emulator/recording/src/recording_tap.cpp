#include "ldoem/recording/recording_tap.hpp"

namespace ldoem::recording {
void RecordingTap::on_connection_closed(protocol::ConnectionId connection, base::SimTime at, bool reset) {
  if (!failed_) {
    if (const capture::Written closed = recorder_.connection_closed(at, connection.kind, connection.index, reset);
        !closed) {
      failed_ = true;
      logger_.log(endpoints::LogLevel::error, "--record: " + closed.error() + "; recording stopped, the device goes on");
    }
  }
  if (next_) next_->on_connection_closed(connection, at, reset);
}

void RecordingTap::record(const endpoints::WireTelegram& telegram) {
  if (failed_) return;
  const capture::Written written = recorder_.record(telegram.at, telegram.connection.kind,
                                                    telegram.connection.index, telegram.direction, telegram.payload);
  if (!written) {
    failed_ = true;
    logger_.log(endpoints::LogLevel::error, "--record: " + written.error() + "; recording stopped, the device goes on");
    return;
  }
  ++recorded_;
}

endpoints::WireVerdict RecordingTap::on_telegram(endpoints::WireTelegram& telegram) {
  if (telegram.direction == protocol::WireDirection::host_to_device) {
    record(telegram);
    return next_ ? next_->on_telegram(telegram) : endpoints::WireVerdict::pass;
  }
  const endpoints::WireVerdict verdict = next_ ? next_->on_telegram(telegram) : endpoints::WireVerdict::pass;
  if (verdict == endpoints::WireVerdict::pass) record(telegram);
  return verdict;
}

}  // namespace ldoem::recording
