#include "recording_transport.hpp"

#include <iostream>
#include <optional>

#include "ldoem/capture/capture_writer.hpp"
#include "ldoem/capture/telegram_recorder.hpp"

namespace ldoem::conformance {
namespace {

// The one capture file of a run: opened with the first transport, closed at exit.
struct RunRecording {
  std::unique_ptr<capture::CaptureWriter> writer;
  std::optional<capture::TelegramRecorder> recorder;
  driver::Clock::time_point start = driver::Clock::now();
  std::uint32_t connections = 0;
  bool failed = false;

  void record(protocol::Transport transport, std::uint32_t connection, protocol::WireDirection direction,
              protocol::ByteView payload) {
    if (failed || !recorder) return;
    const auto time = std::chrono::duration_cast<base::SimTime>(driver::Clock::now() - start);
    if (const capture::Written written = recorder->record(time, transport, connection, direction, payload); !written) {
      std::cerr << "ldoem-conformance: --record: " << written.error() << " (recording stopped)\n";
      failed = true;
    }
  }
};

RunRecording& run_recording() {
  static RunRecording recording;
  return recording;
}

class RecordingTransport final : public driver::TelegramTransport {
 public:
  RecordingTransport(std::unique_ptr<driver::TelegramTransport> inner, protocol::Transport transport, std::uint32_t connection)
      : inner_(std::move(inner)), transport_(transport), connection_(connection) {}

  driver::Status send(protocol::ByteView payload, driver::Deadline deadline) override {
    driver::Status sent = inner_->send(payload, deadline);
    if (sent) run_recording().record(transport_, connection_, protocol::WireDirection::host_to_device, payload);
    return sent;
  }
  base::Expected<protocol::Bytes, driver::DriverError> receive(driver::Deadline deadline) override {
    auto received = inner_->receive(deadline);
    if (received) run_recording().record(transport_, connection_, protocol::WireDirection::device_to_host, *received);
    return received;
  }
  void close() override { inner_->close(); }
  const std::string& name() const override { return inner_->name(); }
  driver::TransportCounters counters() const override { return inner_->counters(); }

 private:
  std::unique_ptr<driver::TelegramTransport> inner_;
  protocol::Transport transport_;
  std::uint32_t connection_;
};

}  // namespace

base::Expected<std::unique_ptr<driver::TelegramTransport>, std::string> open_suite_transport(const SuiteOptions& options) {
  auto transport = driver::open_transport(*options.endpoint);
  if (!transport) return base::Unexpected(driver::describe(transport.error()));
  if (!options.record) return std::move(*transport);
  RunRecording& recording = run_recording();
  if (!recording.writer) {
    auto writer = capture::CaptureWriter::open({*options.record, 0, 1, "ldoem-conformance"});
    if (!writer) return base::Unexpected("--record: " + writer.error());
    recording.writer = std::move(*writer);
    capture::RecorderCanIds ids;
    if (const auto* can = std::get_if<driver::CanEndpoint>(&*options.endpoint)) ids = {can->request_id, can->response_id};
    recording.recorder.emplace(*recording.writer, ids);
  }
  return std::unique_ptr<driver::TelegramTransport>(
      new RecordingTransport(std::move(*transport), driver::transport_of(*options.endpoint), recording.connections++));
}

}  // namespace ldoem::conformance
