// `ldoem-emud --record FILE` (docs/capture.md): a WireTap (emulator/host/endpoints) that writes
// every telegram in and out of the device, on every transport, to a capture with its device time
// (D7). Telegrams from hosts are recorded as they arrived (before any later tap); telegrams to
// hosts as they leave (after the next tap, so a wire fault that drops or alters one shows in the
// capture). A write error is logged once and ends the recording; the device goes on.
#pragma once

#include <string>

#include "ldoem/capture/telegram_recorder.hpp"
#include "ldoem/endpoints/logger.hpp"
#include "ldoem/endpoints/wire_tap.hpp"

namespace ldoem::recording {

class RecordingTap final : public endpoints::WireTap {
 public:
  RecordingTap(capture::CaptureWriter& writer, capture::RecorderCanIds can_ids, const endpoints::Logger& logger,
               endpoints::WireTap* next = nullptr)
      : recorder_(writer, can_ids), logger_(logger), next_(next) {}

  endpoints::WireVerdict on_telegram(endpoints::WireTelegram& telegram) override;
  void on_connection_closed(control::ConnectionId connection, base::SimTime at, bool reset) override;
  std::uint64_t recorded() const { return recorded_; }
  bool failed() const { return failed_; }

 private:
  void record(const endpoints::WireTelegram& telegram);

  capture::TelegramRecorder recorder_;
  const endpoints::Logger& logger_;
  endpoints::WireTap* next_;
  std::uint64_t recorded_ = 0;
  bool failed_ = false;
};

}  // namespace ldoem::recording
