// Splits a byte stream into lines with a bound: a line longer than max_line_bytes is reported
// once as too long and skipped up to its newline, so a 1 MiB line costs at most max_line_bytes
// of memory. Pure: bytes in, lines out.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace ldoem::control_socket {

struct AssembledLine {
  std::string text;         // without the newline (and without a trailing '\r')
  bool too_long = false;    // text is empty: the line was skipped
};

class LineAssembler {
 public:
  explicit LineAssembler(std::size_t max_line_bytes) : max_line_bytes_(max_line_bytes) {}
  // Appends complete lines to `out`.
  void feed(std::string_view bytes, std::vector<AssembledLine>& out);
  std::size_t buffered() const { return partial_.size(); }

 private:
  std::size_t max_line_bytes_;
  std::string partial_;
  bool skipping_ = false;  // inside a line already reported as too long
};

}  // namespace ldoem::control_socket
