#include "ldoem/daemon/replay_instance.hpp"

#include "ldoem/replay/replay_model.hpp"

namespace ldoem::daemon {

base::Expected<std::unique_ptr<DeviceInstance>, StartFailure> replay_instance(const Options& options,
                                                                              endpoints::Scheduler& scheduler,
                                                                              const endpoints::Logger& logger,
                                                                              std::ostream& report) {
  replay::ReplaySource source;
  source.capture = *options.replay_path;
  source.transport = options.replay_transport;
  source.capture_tcp_port = options.replay_port;
  // The recorded ISO-TP conversation is found on the first identifier pair --can names.
  if (!options.can_id_pairs.empty()) {
    source.can_ids = {options.can_id_pairs.front().request_id, options.can_id_pairs.front().response_id};
  }
  auto model = replay::load_replay_model(
      source, [&logger](const std::string& line) { logger.log(endpoints::LogLevel::warn, line); }, report);
  if (!model) return base::Unexpected(StartFailure{kExitUsageError, model.error()});
  return std::make_unique<DeviceInstance>(std::move(*model), scheduler, logger);
}

}  // namespace ldoem::daemon
