#include "ldoem/driver/scanner.hpp"

#include <algorithm>
#include <string>
#include <thread>
#include <utility>

#include "ldoem/protocol/service_codes.hpp"
#include "scanner_call.hpp"

namespace ldoem::driver {

namespace p = protocol;

namespace {

constexpr std::uint16_t kProfileCode = p::response_code(p::Service::get_profile);  // 0x8301
constexpr std::uint16_t kFailureCode = p::code_of(p::Service::service_failure);    // 0xFF00
constexpr std::uint16_t kGetProfileCode = p::code_of(p::Service::get_profile);
constexpr std::size_t kMaxStaleTelegrams = 64;  // per request; the rest wait for the next one

std::uint16_t code_of_request(const p::Request& request) { return p::code_of(p::service_of(request)); }

std::string milliseconds_text(std::chrono::milliseconds timeout) {
  return std::to_string(timeout.count()) + " ms";
}

}  // namespace

Scanner::Scanner(std::unique_ptr<TelegramTransport> transport, ScannerOptions options)
    : transport_(std::move(transport)), options_(std::move(options)), stream_format_(options_.stream_format) {}

Scanner::~Scanner() { close(); }

Deadline Scanner::now() const { return options_.clock ? options_.clock() : Clock::now(); }

// ------------------------------------------------------------------------------- errors

DriverError Scanner::error_for(ErrorKind kind, std::uint16_t request_code, std::string detail) const {
  DriverError error = make_error(kind, std::string(p::service_name(request_code)), transport_->name(),
                                 std::move(detail));
  error.request_code = request_code;
  return error;
}

// TelegramTransport errors name "send"/"receive"; the caller wants the service it asked for.
DriverError Scanner::annotate(DriverError error, std::uint16_t request_code) const {
  error.operation = std::string(p::service_name(request_code));
  error.object = transport_->name();
  error.request_code = request_code;
  return error;
}

Status Scanner::require_talking(std::uint16_t request_code) const {
  switch (state_) {
    case LifecycleState::connected:
    case LifecycleState::active:
      return ok();
    case LifecycleState::unconfigured:
      return fail(error_for(ErrorKind::wrong_state, request_code, "unconfigured: call connect() first"));
    case LifecycleState::closed:
      return fail(error_for(ErrorKind::wrong_state, request_code, "closed"));
  }
  return fail(error_for(ErrorKind::wrong_state, request_code));
}

// ------------------------------------------------------------------------ reply matching

void Scanner::take_stale_telegrams() {
  for (Bytes& telegram : transport_->take_arrived(kMaxStaleTelegrams)) {
    if (telegram.size() >= 2 && p::read_word_be(telegram, 0) == kProfileCode) {
      profiles_.push_back(std::move(telegram));
      ++counters_.profiles_queued;
      continue;
    }
    if (telegram.size() >= 2 && p::read_word_be(telegram, 0) == kFailureCode) {
      auto decoded = p::decode_response(telegram);
      const auto* failure = decoded ? std::get_if<p::ServiceFailure>(&*decoded) : nullptr;
      if (failure != nullptr && failure->request_code == kGetProfileCode) {
        stream_failure_ = *failure;
        continue;
      }
    }
    ++counters_.stale_replies;
  }
}

Status Scanner::send_request(const p::Request& request, Deadline deadline) {
  // Whatever arrived before the request cannot answer it (a duplicate, a reply too late).
  take_stale_telegrams();
  const Bytes payload = p::encode_request(request);
  auto sent = transport_->send(payload, deadline);
  if (!sent) {
    return fail(annotate(sent.error(), code_of_request(request)));
  }
  ++counters_.requests_sent;
  return ok();
}

Expected<Bytes, DriverError> Scanner::exchange(const p::Request& request, std::chrono::milliseconds timeout,
                                               bool allow_unconfigured) {
  const std::uint16_t code = code_of_request(request);
  if (!allow_unconfigured) {
    auto allowed = require_talking(code);
    if (!allowed) {
      return fail(allowed.error());
    }
  }
  const Deadline deadline = now() + timeout;
  auto sent = send_request(request, deadline);
  if (!sent) {
    return fail(sent.error());
  }
  return await_reply(code, deadline, timeout);
}

Expected<Bytes, DriverError> Scanner::await_reply(std::uint16_t request_code, Deadline deadline,
                                                  std::chrono::milliseconds timeout) {
  const std::uint16_t wanted = p::response_code(request_code);
  while (true) {
    auto telegram = transport_->receive(deadline);
    if (!telegram) {
      DriverError error = annotate(telegram.error(), request_code);
      if (error.kind == ErrorKind::timeout) {
        error.detail = "no reply within " + milliseconds_text(timeout);
      }
      return fail(std::move(error));
    }
    if (telegram->size() < 2) {
      ++counters_.skipped_telegrams;
      continue;
    }
    const std::uint16_t code = p::read_word_be(*telegram, 0);
    if (code == wanted) {
      ++counters_.replies_matched;
      return std::move(*telegram);
    }
    if (code == kProfileCode) {
      // Spec 3.5: replies and profiles interleave; a profile is data, never lost.
      profiles_.push_back(std::move(*telegram));
      ++counters_.profiles_queued;
      continue;
    }
    if (code == kFailureCode) {
      auto decoded = p::decode_response(*telegram);
      const auto* failure = decoded ? std::get_if<p::ServiceFailure>(&*decoded) : nullptr;
      if (failure != nullptr && failure->request_code == request_code) {
        DriverError error = error_for(ErrorKind::service_failure, request_code);
        error.failure_reason = failure->reason;
        return fail(std::move(error));
      }
      if (failure != nullptr && failure->request_code == kGetProfileCode) {
        stream_failure_ = *failure;  // the stream's answer: next_profile() reports it
        continue;
      }
    }
    ++counters_.skipped_telegrams;
  }
}

// ---------------------------------------------------------------------------- lifecycle

Status Scanner::set_state(LifecycleState target) {
  switch (plan_transition(state_, target)) {
    case LifecycleAction::none:
      return ok();
    case LifecycleAction::connect: {
      auto status = connect();
      return status ? ok() : fail(status.error());
    }
    case LifecycleAction::start_stream:
      return get_profile(0, options_.stream_format);
    case LifecycleAction::stop_stream: {
      auto cancelled = cancel_profile();
      return cancelled ? ok() : fail(cancelled.error());
    }
    case LifecycleAction::close:
      close();
      return ok();
    case LifecycleAction::stop_stream_then_close:
      (void)cancel_profile();  // best effort: we close whatever the device says
      close();
      return ok();
    case LifecycleAction::refuse:
      break;
  }
  DriverError error = make_error(ErrorKind::wrong_state, "set_state", transport_->name(),
                                 std::string(describe(state_)) + " -> " + std::string(describe(target)) +
                                     " is not a transition");
  return fail(std::move(error));
}

Expected<p::GetStatusReply, DriverError> Scanner::connect() {
  if (state_ == LifecycleState::closed) {
    return fail(error_for(ErrorKind::wrong_state, p::code_of(p::Service::get_status), "closed"));
  }
  auto status = call<p::GetStatusReply>(p::GetStatus{}, options_.request_timeout, /*allow_unconfigured=*/true);
  if (status && state_ == LifecycleState::unconfigured) {
    state_ = LifecycleState::connected;
  }
  return status;
}

void Scanner::sleep_for(std::chrono::milliseconds pause) const {
  if (options_.sleep) {
    options_.sleep(pause);
  } else {
    std::this_thread::sleep_for(pause);
  }
}

std::chrono::milliseconds reconnect_pause(const ReconnectPolicy& policy, std::uint32_t attempt) {
  const double factor = std::max(1.0, policy.backoff);
  double pause_ms = static_cast<double>(policy.interval.count());
  for (std::uint32_t k = 2; factor > 1.0 && k < attempt && pause_ms < static_cast<double>(policy.max_interval.count()); ++k) {
    pause_ms *= factor;
  }
  const auto pause = std::chrono::milliseconds(static_cast<std::int64_t>(pause_ms));
  return std::min(pause, std::max(policy.interval, policy.max_interval));
}

Expected<p::GetStatusReply, DriverError> Scanner::reconnect() {
  const std::uint16_t status_code = p::code_of(p::Service::get_status);
  if (!options_.reopen) {
    return fail(error_for(ErrorKind::unsupported, status_code, "reconnect: no way to reopen the transport"));
  }
  close();
  profiles_.clear();
  stream_failure_.reset();
  stream_profiles_left_ = 0;
  const std::uint32_t attempts = std::max<std::uint32_t>(1, options_.reconnect.attempts);
  DriverError last = error_for(ErrorKind::connection_closed, status_code);
  for (std::uint32_t attempt = 1; attempt <= attempts; ++attempt) {
    if (attempt > 1) {
      sleep_for(reconnect_pause(options_.reconnect, attempt));
    }
    auto opened = options_.reopen();
    if (!opened) {
      last = opened.error();
      continue;
    }
    transport_ = std::move(opened.value());
    state_ = LifecycleState::unconfigured;
    auto status = connect();
    if (status) {
      ++counters_.reconnects;
      return status;
    }
    last = status.error();
    close();
  }
  last.detail += (last.detail.empty() ? "" : "; ") + std::string("reconnect gave up after ") +
                 std::to_string(attempts) + " attempts";
  return fail(std::move(last));
}

void Scanner::close() {
  if (transport_ && state_ != LifecycleState::closed) {
    transport_->close();
  }
  state_ = LifecycleState::closed;
}

void Scanner::end_stream() {
  // D10: CANCEL_PROFILE, TRANS_ROTATE and DO_RESET stop the stream before their reply.
  if (state_ == LifecycleState::active) {
    state_ = LifecycleState::connected;
  }
  stream_profiles_left_ = 0;
}

// ------------------------------------------------------------------------- status group

Expected<p::GetStatusReply, DriverError> Scanner::get_status() {
  return call<p::GetStatusReply>(p::GetStatus{}, options_.request_timeout);
}

Expected<std::string, DriverError> Scanner::get_identification(std::uint16_t item) {
  auto reply = call<p::IdentificationReply>(p::GetIdentification{item}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  return std::move(reply->text);
}

Expected<std::vector<IdentificationEntry>, DriverError> Scanner::identify_all() {
  std::vector<IdentificationEntry> entries;
  for (std::uint16_t item : kIdentificationItems) {
    auto text = get_identification(item);
    if (!text) {
      return fail(text.error());
    }
    entries.push_back(IdentificationEntry{item, std::move(*text)});
  }
  return entries;
}

Expected<std::uint16_t, DriverError> Scanner::get_signal() {
  auto reply = call<p::GetSignalReply>(p::GetSignal{}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  return reply->value;
}

Status Scanner::set_signal(std::uint16_t port_value) {
  auto reply = call<p::SetSignalReply>(p::SetSignal{port_value}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  // Spec 3.3: S1 treats a non-zero byte at payload offset 2 (the WORD's high byte) as failure.
  if ((reply->value >> 8) != 0) {
    DriverError error = error_for(ErrorKind::refused, p::code_of(p::Service::set_signal));
    error.in_band_code = reply->value;
    return fail(std::move(error));
  }
  return ok();
}

// ------------------------------------------------------------------------ working group

Expected<p::StatusBlock, DriverError> Scanner::trans_idle() {
  auto reply = call<p::TransIdleReply>(p::TransIdle{}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  end_stream();
  return reply->status;
}

Status Scanner::check_device_status(const p::StatusBlock& status, std::uint16_t request_code) const {
  auto fault = device_fault_in(status, std::string(p::service_name(request_code)), transport_->name());
  if (!fault) {
    return ok();
  }
  fault->request_code = request_code;
  return fail(std::move(*fault));
}

Expected<p::StatusBlock, DriverError> Scanner::trans_rotate(std::uint16_t frequency_hz,
                                                            std::optional<std::chrono::milliseconds> timeout) {
  auto reply = call<p::TransRotateReply>(p::TransRotate{frequency_hz}, timeout.value_or(options_.rotate_timeout));
  if (!reply) {
    return fail(reply.error());
  }
  end_stream();
  if (auto healthy = check_device_status(reply->status, p::code_of(p::Service::trans_rotate)); !healthy) {
    return fail(healthy.error());  // D11: 84 03 .. B4 while a motor fault lasts
  }
  return reply->status;
}

Expected<p::StatusBlock, DriverError> Scanner::trans_measure() {
  auto reply = call<p::TransMeasureReply>(p::TransMeasure{}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  if (auto healthy = check_device_status(reply->status, p::code_of(p::Service::trans_measure)); !healthy) {
    return fail(healthy.error());
  }
  if (reply->return_code != p::measure_return::kOk) {
    DriverError error = error_for(ErrorKind::refused, p::code_of(p::Service::trans_measure));
    error.in_band_code = reply->return_code;
    return fail(std::move(error));
  }
  return reply->status;
}

Status Scanner::do_reset(std::uint16_t level) {
  auto reply = call<p::DoResetReply>(p::DoReset{level}, options_.request_timeout);
  if (!reply) {
    return fail(reply.error());
  }
  end_stream();
  if (reply->value != level) {
    return fail(error_for(ErrorKind::unexpected_reply, p::code_of(p::Service::do_reset),
                          "the reply echoes level " + std::to_string(reply->value)));
  }
  return ok();
}

// -------------------------------------------------------------------- measurement group

Status Scanner::get_profile(std::uint16_t count, std::uint16_t format) {
  auto allowed = require_talking(kGetProfileCode);
  if (!allowed) {
    return allowed;
  }
  auto sent = send_request(p::GetProfile{count, format}, now() + options_.request_timeout);
  if (!sent) {
    return sent;
  }
  stream_failure_.reset();
  stream_format_ = format;
  stream_profiles_left_ = count;
  state_ = LifecycleState::active;
  return ok();
}

Expected<p::Profile, DriverError> Scanner::deliver_profile(const Bytes& payload) {
  auto profile = p::decode_profile(payload);
  if (!profile) {
    DriverError error = error_for(ErrorKind::corrupted_reply, kGetProfileCode, "profile does not decode");
    error.decode_detail = profile.error();
    return fail(std::move(error));
  }
  ++counters_.profiles_delivered;
  if (stream_profiles_left_ > 0 && --stream_profiles_left_ == 0 && state_ == LifecycleState::active) {
    state_ = LifecycleState::connected;  // the n-th of n profiles: the device stops by itself
  }
  return std::move(*profile);
}

Expected<p::Profile, DriverError> Scanner::next_profile(Deadline deadline) {
  while (!profiles_.empty()) {
    Bytes payload = std::move(profiles_.front());
    profiles_.pop_front();
    if (payload.size() >= 4 && p::read_word_be(payload, 2) != stream_format_) {
      ++counters_.profiles_skipped;  // from an earlier stream with another format
      continue;
    }
    return deliver_profile(payload);
  }
  if (stream_failure_) {
    DriverError error = error_for(ErrorKind::service_failure, kGetProfileCode);
    error.failure_reason = stream_failure_->reason;
    stream_failure_.reset();
    if (state_ == LifecycleState::active) {
      state_ = LifecycleState::connected;
    }
    return fail(std::move(error));
  }
  if (state_ != LifecycleState::active) {
    return fail(error_for(ErrorKind::wrong_state, kGetProfileCode,
                          std::string(describe(state_)) + ": no profile stream running"));
  }
  while (true) {
    auto telegram = transport_->receive(deadline);
    if (!telegram) {
      DriverError error = annotate(telegram.error(), kGetProfileCode);
      if (error.kind == ErrorKind::timeout) {
        error.detail = "no profile before the deadline";
      }
      return fail(std::move(error));
    }
    if (telegram->size() < 2) {
      ++counters_.skipped_telegrams;
      continue;
    }
    const std::uint16_t code = p::read_word_be(*telegram, 0);
    if (code == kProfileCode) {
      if (telegram->size() >= 4 && p::read_word_be(*telegram, 2) != stream_format_) {
        ++counters_.profiles_skipped;
        continue;
      }
      return deliver_profile(*telegram);
    }
    if (code == kFailureCode) {
      auto decoded = p::decode_response(*telegram);
      const auto* failure = decoded ? std::get_if<p::ServiceFailure>(&*decoded) : nullptr;
      if (failure != nullptr && failure->request_code == kGetProfileCode) {
        DriverError error = error_for(ErrorKind::service_failure, kGetProfileCode);
        error.failure_reason = failure->reason;
        state_ = LifecycleState::connected;
        return fail(std::move(error));
      }
    }
    ++counters_.skipped_telegrams;
  }
}

Expected<p::StatusBlock, DriverError> Scanner::cancel_profile() {
  auto reply = call<p::CancelProfileReply>(p::CancelProfile{}, options_.request_timeout);
  if (!reply) {
    if (reply.error().kind == ErrorKind::service_failure) {
      end_stream();  // D2: no stream to cancel
    }
    return fail(reply.error());
  }
  end_stream();
  return reply->status;
}

}  // namespace ldoem::driver
