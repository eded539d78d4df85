#include "ldoem/control_socket/line_assembler.hpp"

namespace ldoem::control_socket {

void LineAssembler::feed(std::string_view bytes, std::vector<AssembledLine>& out) {
  while (!bytes.empty()) {
    const std::size_t newline = bytes.find('\n');
    const std::string_view piece = bytes.substr(0, newline);
    if (!skipping_) {
      if (partial_.size() + piece.size() > max_line_bytes_) {
        partial_.clear();
        skipping_ = true;
        out.push_back(AssembledLine{{}, true});
      } else {
        partial_.append(piece);
      }
    }
    if (newline == std::string_view::npos) return;
    if (!skipping_) {
      if (!partial_.empty() && partial_.back() == '\r') partial_.pop_back();
      out.push_back(AssembledLine{std::move(partial_), false});
    }
    partial_.clear();
    skipping_ = false;
    bytes.remove_prefix(newline + 1);
  }
}

}  // namespace ldoem::control_socket
