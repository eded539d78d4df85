#include "ldoem/hub/backend_handler.hpp"

#include <utility>

namespace ldoem::hub {

BackEndHandler::BackEndHandler(std::string handler_id, std::string device_name, std::unique_ptr<Device> device,
                               BackendSettings settings, Completion on_done)
    : handler_id_(std::move(handler_id)),
      device_name_(std::move(device_name)),
      device_(std::move(device)),
      settings_(settings),
      on_done_(std::move(on_done)),
      worker_([this] { run(); }) {}

BackEndHandler::~BackEndHandler() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  device_->cancel();  // a long move must not hold up the shutdown
  worker_.join();
}

bool BackEndHandler::submit(BackendJob job) {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ || queue_.size() >= settings_.queue_capacity) {
      return false;
    }
    queue_.push_back(std::move(job));
  }
  wake_.notify_one();
  return true;
}

std::optional<CachedStatus> BackEndHandler::latest_status() const {
  std::lock_guard lock(mutex_);
  return latest_status_;
}

std::optional<CachedProfile> BackEndHandler::latest_profile() const {
  std::lock_guard lock(mutex_);
  return latest_profile_;
}

void BackEndHandler::run() {
  for (;;) {
    BackendJob job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (stopping_) {
        return;
      }
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    if (job.client_alive && !job.client_alive->load()) {
      continue;  // nobody would read the reply; do not move hardware for a departed client
    }
    job_error_.reset();
    HubReply reply = execute(job.request);
    executed_jobs_.fetch_add(1);
    std::optional<HubReply> notice = health_notice(reply);
    on_done_(BackendResult{std::move(job.frontend_id), device_name_, std::move(reply), std::move(notice)});
  }
}

std::vector<ReplyField> BackEndHandler::source_fields() const {
  return {{"handler", handler_id_}, {"source", "device"}};
}

void BackEndHandler::remember_status(const StatusBlock& status) {
  std::lock_guard lock(mutex_);
  latest_status_ = CachedStatus{status, Clock::now()};
}

std::optional<HubReply> BackEndHandler::health_notice(const HubReply& reply) {
  std::vector<ReplyField> fields{{"device", device_name_}, {"handler", handler_id_}};
  std::optional<DriverError> fault;
  if (job_error_ && (job_error_->kind == ErrorKind::device_fault || job_error_->kind == ErrorKind::connection_closed)) {
    fault = job_error_;
  } else if (reply.ok) {
    if (const auto status = status_from(reply)) {
      fault = driver::device_fault_in(*status, reply.command, device_name_);
    }
  }
  if (fault) {
    // The same fault seen again (by STATUS after ROTATE failed) is not news.
    const std::string what = std::string(error_kind_token(fault->kind)) + ":" +
                             std::to_string(fault->device_status.value_or(0));
    if (announced_fault_ == what) {
      return std::nullopt;  // said already; the asker has its own reply
    }
    announced_fault_ = what;
    fields.emplace_back("kind", std::string(error_kind_token(fault->kind)));
    fields.emplace_back("recovery", std::string(recovery_token(driver::recovery_for(*fault))));
    if (fault->device_status) {
      fields.emplace_back("status_byte", std::to_string(*fault->device_status));
    }
    fields.emplace_back("detail", describe(*fault));
    return ok_reply(std::string(kUnsolicitedId), "FAULT", std::move(fields));
  }
  if (reply.ok && announced_fault_) {
    announced_fault_.reset();
    return ok_reply(std::string(kUnsolicitedId), "RECOVERED", std::move(fields));
  }
  return std::nullopt;
}

HubReply BackEndHandler::device_error(const HubRequest& request, const DriverError& error) {
  job_error_ = error;
  return error_reply(request.id, std::string(error_kind_token(error.kind)),
                     device_name_ + " (" + handler_id_ + "): " + driver::describe(error));
}

HubReply BackEndHandler::reply_from_status(const HubRequest& request, const Expected<StatusBlock, DriverError>& result) {
  if (!result) {
    return device_error(request, result.error());
  }
  remember_status(*result);
  std::vector<ReplyField> fields = status_fields(*result);
  for (auto& field : source_fields()) {
    fields.push_back(std::move(field));
  }
  return ok_reply(request.id, std::string(command_name(request.command)), std::move(fields));
}

HubReply BackEndHandler::execute(const HubRequest& request) {
  if (changes_device(request.command)) {
    // A profile taken before a move or a state change no longer describes the device.
    std::lock_guard lock(mutex_);
    latest_profile_.reset();
  }
  const std::string name(command_name(request.command));
  const auto with_source = [this](std::vector<ReplyField> fields) {
    for (auto& field : source_fields()) {
      fields.push_back(std::move(field));
    }
    return fields;
  };
  if (const auto* init = std::get_if<InitializeRequest>(&request.command)) {
    auto info = device_->initialize(*init);
    if (!info) {
      return device_error(request, info.error());
    }
    remember_status(info->status);
    return ok_reply(request.id, name, with_source(info_fields(*info)));
  }
  if (const auto* rotate = std::get_if<RotateCommand>(&request.command)) {
    return reply_from_status(request, device_->rotate(rotate->frequency_hz));
  }
  if (std::holds_alternative<MeasureCommand>(request.command)) {
    return reply_from_status(request, device_->measure());
  }
  if (std::holds_alternative<IdleCommand>(request.command)) {
    return reply_from_status(request, device_->idle());
  }
  if (std::holds_alternative<StatusCommand>(request.command)) {
    return reply_from_status(request, device_->status());
  }
  if (std::holds_alternative<ProfileCommand>(request.command)) {
    auto sample = device_->get_profile(settings_.profile_timeout);
    if (!sample) {
      return device_error(request, sample.error());
    }
    {
      std::lock_guard lock(mutex_);
      latest_profile_ = CachedProfile{*sample, Clock::now()};
      if ((sample->profile.format & protocol::profile_bits::kSensorStatus) != 0) {
        latest_status_ = CachedStatus{sample->profile.status, Clock::now()};
      }
    }
    return ok_reply(request.id, name, with_source(profile_fields(*sample)));
  }
  if (const auto* move = std::get_if<MotorMove>(&request.command)) {
    auto tilt = device_->move_motor(*move);
    if (!tilt) {
      return device_error(request, tilt.error());
    }
    return ok_reply(request.id, name, with_source(tilt_fields(*tilt)));
  }
  return error_reply(request.id, "bad_request", name + " is not a device command");
}

}  // namespace ldoem::hub
