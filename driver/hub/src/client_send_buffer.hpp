// The bytes queued for one hub client (a byte stream of reply lines; the daemon's bounded
// telegram queue is endpoints::OutputQueue). Sent bytes are skipped with an offset and the buffer is
// compacted only once the sent part is at least half of it, so a reader that takes a few bytes
// at a time costs linear time, not the quadratic time of erasing the front on every send.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ldoem::hub {

class ClientSendBuffer {
 public:
  void append(std::string_view bytes) { buffer_.append(bytes); }
  std::size_t pending() const { return buffer_.size() - sent_; }
  bool empty() const { return pending() == 0; }
  const char* data() const { return buffer_.data() + sent_; }
  // `count` <= pending() bytes have been sent.
  void consume(std::size_t count) {
    sent_ += count;
    if (sent_ == buffer_.size()) {
      buffer_.clear();
      sent_ = 0;
    } else if (sent_ >= kCompactAfter && sent_ >= buffer_.size() / 2) {
      buffer_.erase(0, sent_);
      sent_ = 0;
    }
  }

 private:
  static constexpr std::size_t kCompactAfter = 4096;
  std::string buffer_;
  std::size_t sent_ = 0;
};

}  // namespace ldoem::hub
