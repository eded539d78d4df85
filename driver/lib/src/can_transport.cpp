// ISO-TP over CAN_RAW (D1). The state machines are protocol/'s; this file owns the socket and
// the clock: it reads CLOCK_MONOTONIC, hands the time to the machines and puts their frames
// on the bus.
#include "ldoem/driver/can_transport.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "fd_util.hpp"

namespace ldoem::driver {
namespace {

using protocol::CanFrame;
using base::SimTime;

// How long one wait for a full transmit queue lasts before write() is tried again: ENOBUFS
// is not signalled through poll(2).
constexpr std::chrono::milliseconds kTxQueueRetry{1};

// With our flow control at BS 0 / STmin 0 (D1) a peer may send a whole telegram back to back;
// a 5.8 kB profile is over 800 frames, and the kernel drops frames once a CAN_RAW socket's
// receive buffer is full (each frame costs about 1 kB of it). Ask for room for a few of them.
constexpr int kReceiveBufferBytes = 4 * 1024 * 1024;

// Best effort: SO_RCVBUFFORCE passes net.core.rmem_max when we may (CAP_NET_ADMIN), else
// SO_RCVBUF gets what the limit allows. Neither failing is an error: the default still works
// for peers that pace themselves.
void enlarge_receive_buffer(int fd) {
  if (::setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &kReceiveBufferBytes, sizeof kReceiveBufferBytes) != 0) {
    (void)::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &kReceiveBufferBytes, sizeof kReceiveBufferBytes);
  }
}

Deadline deadline_at(SimTime time) {
  return Deadline(std::chrono::duration_cast<Clock::duration>(time));
}

can_frame to_socketcan(const CanFrame& frame) {
  can_frame raw{};
  raw.can_id = frame.id & CAN_SFF_MASK;
  raw.len = std::min<std::uint8_t>(frame.length, CAN_MAX_DLEN);
  std::memcpy(raw.data, frame.data.data(), raw.len);
  return raw;
}

std::optional<CanFrame> from_socketcan(const can_frame& raw) {
  if ((raw.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) != 0) {
    return std::nullopt;  // D1 uses 11-bit data frames only
  }
  CanFrame frame;
  frame.id = raw.can_id & CAN_SFF_MASK;
  frame.length = std::min<std::uint8_t>(raw.len, CAN_MAX_DLEN);
  std::memcpy(frame.data.data(), raw.data, frame.length);
  return frame;
}

DriverError send_error(protocol::IsoTpSendError error, const std::string& object) {
  switch (error) {
    case protocol::IsoTpSendError::busy:
      return make_error(ErrorKind::busy, "send", object, "an ISO-TP message is still being sent");
    case protocol::IsoTpSendError::empty_message:
    case protocol::IsoTpSendError::too_large:
      return make_error(ErrorKind::invalid_argument, "send", object, std::string(protocol::describe(error)));
    case protocol::IsoTpSendError::timeout:
      return make_error(ErrorKind::timeout, "send", object, "no ISO-TP flow control within N_Bs (D1)");
    case protocol::IsoTpSendError::overflow:
      return make_error(ErrorKind::refused, "send", object, "the device answered flow control overflow");
    case protocol::IsoTpSendError::invalid_flow_status:
      return make_error(ErrorKind::framing, "send", object, "flow control with a reserved flow status");
    case protocol::IsoTpSendError::too_many_waits:
      // Like a missing flow control: the device did not take the request in time (retryable).
      return make_error(ErrorKind::timeout, "send", object,
                        "the device answered flow control WAIT more than N_WFTmax times in a row");
  }
  return make_error(ErrorKind::system, "send", object);
}

protocol::IsoTpSenderConfig sender_config(const CanEndpoint& endpoint, const IsoTpOptions& options) {
  protocol::IsoTpSenderConfig config;
  config.data_id = endpoint.request_id;
  config.pad_frames = options.pad_frames;
  config.n_bs_timeout = options.timeout;
  config.max_wait_frames = options.max_wait_frames;
  return config;
}

protocol::IsoTpReceiverConfig receiver_config(const CanEndpoint& endpoint, const IsoTpOptions& options) {
  protocol::IsoTpReceiverConfig config;
  config.flow_control_id = endpoint.request_id;
  config.block_size = options.block_size;
  config.st_min = options.st_min;
  config.n_cr_timeout = options.timeout;
  config.pad_frames = options.pad_frames;
  return config;
}

}  // namespace

SimTime monotonic_now() {
  return std::chrono::duration_cast<SimTime>(Clock::now().time_since_epoch());
}

CanIsoTpTransport::CanIsoTpTransport(int fd, std::string name, const CanEndpoint& endpoint,
                                     IsoTpOptions options)
    : fd_(fd),
      name_(std::move(name)),
      sender_(sender_config(endpoint, options)),
      receiver_(receiver_config(endpoint, options)) {}

CanIsoTpTransport::~CanIsoTpTransport() { close(); }

Expected<std::unique_ptr<CanIsoTpTransport>, DriverError> CanIsoTpTransport::open(const CanEndpoint& endpoint,
                                                                                  IsoTpOptions options) {
  const std::string object = format_endpoint(endpoint);
  base::UniqueFd fd(::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW));
  if (!fd.valid()) {
    if (errno == EAFNOSUPPORT) {
      // The bare strerror leaves the user guessing; say what is missing and how to get it.
      DriverError error = system_error("socket CAN_RAW", object, EAFNOSUPPORT);
      error.detail = base::can_unsupported_hint();
      return fail(std::move(error));
    }
    return fail(system_error("socket CAN_RAW", object, errno));
  }
  const unsigned index = ::if_nametoindex(endpoint.interface.c_str());
  if (index == 0) {
    return fail(system_error("if_nametoindex", object, errno));
  }
  // Only the device's frames reach us: its data frames and its flow control share the id.
  can_filter filter{};
  filter.can_id = endpoint.response_id;
  filter.can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
  if (::setsockopt(fd.get(), SOL_CAN_RAW, CAN_RAW_FILTER, &filter, sizeof filter) != 0) {
    return fail(system_error("setsockopt CAN_RAW_FILTER", object, errno));
  }
  enlarge_receive_buffer(fd.get());
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(index);
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    return fail(system_error("bind", object, errno));
  }
  return std::unique_ptr<CanIsoTpTransport>(new CanIsoTpTransport(fd.release(), object, endpoint, options));
}

Status CanIsoTpTransport::write_frame(const CanFrame& frame, Deadline deadline) {
  const can_frame raw = to_socketcan(frame);
  while (true) {
    const ssize_t written = ::write(fd_.get(), &raw, sizeof raw);
    if (written == static_cast<ssize_t>(sizeof raw)) {
      return ok();
    }
    if (written >= 0) {
      return fail(make_error(ErrorKind::system, "write", name_, "short CAN frame write"));
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno != EAGAIN && errno != EWOULDBLOCK && errno != ENOBUFS) {
      return fail(system_error("write", name_, errno));
    }
    if (Clock::now() >= deadline) {
      return fail(system_error("write", name_, errno));  // busy: the queue stayed full
    }
    auto waited =
        detail::wait_for(fd_.get(), POLLOUT, std::min(deadline, Clock::now() + kTxQueueRetry), "write", name_);
    if (!waited) {
      return fail(waited.error());
    }
  }
}

Status CanIsoTpTransport::dispatch(const CanFrame& frame, Deadline deadline) {
  const SimTime now = monotonic_now();
  if (protocol::isotp_frame_type(frame) == protocol::IsoTpFrameType::flow_control) {
    sender_.on_flow_control(now, frame);
    return ok();
  }
  auto result = receiver_.on_frame(now, frame);
  if (result.message) {
    received_.push_back(std::move(*result.message));
  }
  if (result.flow_control) {
    return write_frame(*result.flow_control, deadline);
  }
  return ok();
}

Status CanIsoTpTransport::pump(Deadline wake, Deadline deadline) {
  auto waited = detail::wait_for(fd_.get(), POLLIN, wake, "receive", name_);
  if (!waited) {
    return fail(waited.error());
  }
  if (*waited == detail::WaitOutcome::deadline_passed) {
    return ok();
  }
  while (true) {
    can_frame raw{};
    const ssize_t count = ::read(fd_.get(), &raw, sizeof raw);
    if (count < 0) {
      if (errno == EINTR) {
        continue;
      }
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        return ok();
      }
      return fail(system_error("receive", name_, errno));
    }
    if (count != static_cast<ssize_t>(sizeof raw)) {
      continue;  // not a classic CAN frame
    }
    if (auto frame = from_socketcan(raw)) {
      auto dispatched = dispatch(*frame, deadline);
      if (!dispatched) {
        return dispatched;
      }
    }
  }
}

Status CanIsoTpTransport::run_receiver_timer(Deadline) {
  const auto due = receiver_.deadline();
  const SimTime now = monotonic_now();
  if (due && now >= *due) {
    (void)receiver_.on_timer(now);  // drops the partial telegram; counted by the receiver (D1)
  }
  return ok();
}

Status CanIsoTpTransport::send(ByteView payload, Deadline deadline) {
  if (!fd_.valid()) {
    return fail(make_error(ErrorKind::connection_closed, "send", name_, "transport closed"));
  }
  auto started = sender_.start(monotonic_now(), payload);
  if (!started) {
    return fail(send_error(started.error(), name_));
  }
  while (true) {
    auto due = sender_.poll(monotonic_now());
    for (const CanFrame& frame : due.frames) {
      auto written = write_frame(frame, deadline);
      if (!written) {
        sender_.reset();
        return written;
      }
    }
    if (sender_.state() == protocol::IsoTpSender::State::done) {
      ++counters_.telegrams_sent;
      return ok();
    }
    if (sender_.state() == protocol::IsoTpSender::State::failed) {
      return fail(send_error(sender_.error().value_or(protocol::IsoTpSendError::timeout), name_));
    }
    if (Clock::now() >= deadline) {
      sender_.reset();
      return fail(make_error(ErrorKind::timeout, "send", name_, "telegram not sent before the deadline"));
    }
    const Deadline wake = due.deadline ? std::min(deadline, deadline_at(*due.deadline)) : Clock::now();
    auto pumped = pump(wake, deadline);
    if (!pumped) {
      sender_.reset();
      return pumped;
    }
  }
}

Expected<Bytes, DriverError> CanIsoTpTransport::receive(Deadline deadline) {
  while (received_.empty()) {
    if (!fd_.valid()) {
      return fail(make_error(ErrorKind::connection_closed, "receive", name_, "transport closed"));
    }
    (void)run_receiver_timer(deadline);
    if (Clock::now() >= deadline) {
      return fail(make_error(ErrorKind::timeout, "receive", name_, "no telegram before the deadline"));
    }
    const auto due = receiver_.deadline();
    const Deadline wake = due ? std::min(deadline, deadline_at(*due)) : deadline;
    auto pumped = pump(wake, deadline);
    if (!pumped) {
      return fail(pumped.error());
    }
  }
  Bytes payload = std::move(received_.front());
  received_.pop_front();
  ++counters_.telegrams_received;
  return payload;
}

void CanIsoTpTransport::close() {
  fd_.reset();
  sender_.reset();
  receiver_.reset();
}

TransportCounters CanIsoTpTransport::counters() const {
  TransportCounters counters = counters_;
  counters.dropped_frames = receiver_.counters().errors();
  return counters;
}

}  // namespace ldoem::driver
