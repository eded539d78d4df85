// libFuzzer: bytes from a control-socket client -> line assembler -> request handling against a
// target that accepts everything. Every line must get exactly one reply line that is a JSON
// object with "return" or "error"; nothing may throw or crash.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/control_socket/line_assembler.hpp"

namespace {

class AcceptingTarget final : public ldoem::control_socket::ControlTarget {
 public:
  ldoem::control_socket::CommandResult inject_fault(const ldoem::faults::FaultSpec& spec) override {
    return nlohmann::json{{"id", ldoem::faults::describe(spec).size()}};
  }
  ldoem::control_socket::CommandResult clear_fault(std::optional<std::uint64_t>) override { return nlohmann::json::object(); }
  nlohmann::json query_faults() override { return nlohmann::json::array(); }
  nlohmann::json query_status() override { return nlohmann::json::object(); }
  void quit() override {}
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  AcceptingTarget target;
  ldoem::control_socket::LineAssembler lines(4096);
  std::vector<ldoem::control_socket::AssembledLine> out;
  lines.feed(std::string_view(reinterpret_cast<const char*>(data), size), out);
  for (const auto& line : out) {
    if (line.too_long) continue;
    const std::string reply = ldoem::control_socket::handle_line(line.text, target);
    const nlohmann::json parsed = nlohmann::json::parse(reply, nullptr, false);
    if (parsed.is_discarded() || !parsed.is_object() || (!parsed.contains("return") && !parsed.contains("error"))) {
      std::abort();
    }
    if (reply.find('\n') != std::string::npos) std::abort();
  }
  return 0;
}
