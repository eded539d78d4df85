#include "ldoem/replay/replay_device.hpp"

#include <algorithm>
#include <cmath>

#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/text.hpp"

namespace ldoem::replay {

ReplayDevice::ReplayDevice(std::vector<Exchange> exchanges, double speed)
    : exchanges_(std::move(exchanges)), used_(exchanges_.size(), false), speed_(speed > 0 ? speed : 1.0) {}

std::optional<std::size_t> ReplayDevice::match(protocol::ByteView request) const {
  const auto same = [&](std::size_t index) {
    return std::equal(request.begin(), request.end(), exchanges_[index].request.begin(), exchanges_[index].request.end());
  };
  for (std::size_t index = next_; index < exchanges_.size(); ++index) {
    if (same(index)) return index;
  }
  for (std::size_t index = 0; index < next_ && index < exchanges_.size(); ++index) {
    if (same(index)) return index;
  }
  return std::nullopt;
}

ReplayAnswer ReplayDevice::on_request(SimTime now, protocol::ByteView request) {
  ++counters_.requests;
  ReplayAnswer answer;
  const std::optional<std::size_t> found = match(request);
  if (!found) {
    ++counters_.unexpected;
    const auto decoded = protocol::decode_request(request);
    protocol::ServiceFailure failure;
    if (!decoded) {
      failure = protocol::failure_reply(decoded.error());
    } else {
      failure.request_code = request.size() >= 2 ? protocol::read_word_be(request, 0) : 0;
      failure.reason = protocol::FailureReason::wrong_state;
    }
    answer.diagnostic = "request " + protocol::format_telegram(request) +
                        " is not in the recording (" + std::to_string(exchanges_.size()) +
                        " exchanges); answered SERVICE_FAILURE reason " +
                        std::to_string(static_cast<unsigned>(failure.reason));
    answer.telegrams.push_back({now, protocol::encode_response(failure)});
    return answer;
  }
  const std::size_t index = *found;
  ++(index == next_ ? counters_.in_order : counters_.out_of_order);
  used_[index] = true;
  next_ = index + 1;
  answer.exchange = index;
  for (const auto& recorded : exchanges_[index].answers) {
    const auto scaled = SimTime(static_cast<SimTime::rep>(std::llround(static_cast<double>(recorded.delay.count()) / speed_)));
    answer.telegrams.push_back({now + scaled, recorded.payload});
  }
  return answer;
}

std::size_t ReplayDevice::unused_exchanges() const {
  return static_cast<std::size_t>(std::count(used_.begin(), used_.end(), false));
}

}  // namespace ldoem::replay
