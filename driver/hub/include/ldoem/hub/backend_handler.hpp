// BEMH: the back-end message handler of one device (the paper's generic interface). It owns
// the Device, serialises every access to it through one bounded FIFO and one worker thread,
// and keeps the device's latest status and profile so that front-end handlers can answer
// from them while they are fresh. It cannot tell a physical device from a virtual one.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "ldoem/driver/transport.hpp"
#include "ldoem/hub/device_vocabulary.hpp"
#include "ldoem/hub/hub_config.hpp"
#include "ldoem/hub/hub_protocol.hpp"

namespace ldoem::hub {

using driver::Clock;

struct CachedStatus {
  StatusBlock status;
  Clock::time_point taken_at;
};

struct CachedProfile {
  ProfileSample sample;
  Clock::time_point taken_at;
};

struct BackendJob {
  std::string frontend_id;  // the FEMH that asked; its client gets the reply
  // Cleared by the hub when the client goes; such jobs are dropped unexecuted.
  std::shared_ptr<const std::atomic<bool>> client_alive;
  HubRequest request;
};

struct BackendResult {
  std::string frontend_id;
  std::string device;
  HubReply reply;
  // An unsolicited line for every client (`* OK FAULT ...`, `* OK RECOVERED ...`), when this job
  // changed what the hub knows of the device's health.
  std::optional<HubReply> notice;
};

struct BackendSettings {
  std::size_t queue_capacity = 256;
  std::chrono::milliseconds profile_timeout = kDefaultProfileTimeout;
};

class BackEndHandler {
 public:
  // Called on the worker thread for every executed job.
  using Completion = std::function<void(BackendResult)>;

  BackEndHandler(std::string handler_id, std::string device_name, std::unique_ptr<Device> device,
                 BackendSettings settings, Completion on_done);
  // Cancels the device's move in progress (Device::cancel), drops queued jobs, joins the worker.
  ~BackEndHandler();
  BackEndHandler(const BackEndHandler&) = delete;
  BackEndHandler& operator=(const BackEndHandler&) = delete;

  // Queues the job; false when the queue holds queue_capacity jobs already (busy).
  bool submit(BackendJob job);

  std::optional<CachedStatus> latest_status() const;
  std::optional<CachedProfile> latest_profile() const;

  const std::string& handler_id() const { return handler_id_; }
  const std::string& device_name() const { return device_name_; }
  std::uint64_t executed_jobs() const { return executed_jobs_.load(); }

 private:
  void run();
  HubReply execute(const HubRequest& request);
  HubReply reply_from_status(const HubRequest& request, const Expected<StatusBlock, DriverError>& result);
  HubReply device_error(const HubRequest& request, const DriverError& error);
  std::vector<ReplyField> source_fields() const;
  void remember_status(const StatusBlock& status);
  // The notice the outcome of a job calls for: FAULT when the device shows a fault it did not
  // show before (a faulted status, a device_fault error, a lost connection), RECOVERED when a
  // later job succeeds with a healthy status.
  std::optional<HubReply> health_notice(const HubReply& reply);

  const std::string handler_id_;
  const std::string device_name_;
  std::unique_ptr<Device> device_;
  const BackendSettings settings_;
  const Completion on_done_;

  mutable std::mutex mutex_;  // guards everything below up to the thread
  std::condition_variable wake_;
  std::deque<BackendJob> queue_;
  bool stopping_ = false;
  std::optional<CachedStatus> latest_status_;
  std::optional<CachedProfile> latest_profile_;
  std::atomic<std::uint64_t> executed_jobs_{0};
  // Worker thread only: the error of the job being executed, and the fault last announced.
  std::optional<DriverError> job_error_;
  std::optional<std::string> announced_fault_;

  std::thread worker_;  // last: starts after every other member exists
};

}  // namespace ldoem::hub
