// libFuzzer target: the hub's line protocol parsers (driver/hub). A request or reply line that
// parses must format back to a line that parses to the same value (parse and format are
// inverse, hub_protocol.hpp), and a parsed MOVEMOTOR stays within the hub's move limits.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "ldoem/hub/hub_protocol.hpp"

namespace h = ldoem::hub;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  if (const auto request = h::parse_request(line)) {
    const auto again = h::parse_request(h::format_request(*request));
    if (!again || !(*again == *request)) std::abort();
    if (const auto* move = std::get_if<h::MotorMove>(&request->command)) {
      if (move->steps > h::kMaxMoveSteps) std::abort();
      if (move->step_rate_hz && !(*move->step_rate_hz >= h::kMinStepRateHz && *move->step_rate_hz <= h::kMaxStepRateHz))
        std::abort();
    }
  }
  if (const auto reply = h::parse_reply(line)) {
    const auto again = h::parse_reply(h::format_reply(*reply));
    if (!again || !(*again == *reply)) std::abort();
    (void)h::status_from(*reply);
    (void)h::profile_from(*reply);
    (void)h::info_from(*reply);
  }
  return 0;
}
