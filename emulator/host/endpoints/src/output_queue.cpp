#include "ldoem/endpoints/output_queue.hpp"

#include <algorithm>

namespace ldoem::endpoints {

bool OutputQueue::push(protocol::ByteView bytes) {
  if (bytes.empty()) {
    return true;
  }
  if (bytes.size() > max_bytes_ - std::min(size_bytes_, max_bytes_)) {
    return false;
  }
  chunks_.emplace_back(bytes.begin(), bytes.end());
  size_bytes_ += bytes.size();
  return true;
}

protocol::ByteView OutputQueue::front() const {
  if (chunks_.empty()) {
    return {};
  }
  return protocol::ByteView(chunks_.front()).subspan(front_offset_);
}

void OutputQueue::consume(std::size_t count) {
  while (count > 0 && !chunks_.empty()) {
    const std::size_t available = chunks_.front().size() - front_offset_;
    const std::size_t taken = std::min(count, available);
    front_offset_ += taken;
    size_bytes_ -= taken;
    count -= taken;
    if (front_offset_ == chunks_.front().size()) {
      chunks_.pop_front();
      front_offset_ = 0;
    }
  }
}

void OutputQueue::clear() {
  chunks_.clear();
  front_offset_ = 0;
  size_bytes_ = 0;
}

}  // namespace ldoem::endpoints
