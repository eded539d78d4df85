// libFuzzer: decode_request, decode_response, decode_profile and the text form on arbitrary
// payloads. Whatever decodes must re-encode to the same bytes (GET_IDENTIFICATION text stops at
// a NUL, so it is compared up to it).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/text.hpp"

using namespace ldoem::protocol;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const ByteView payload(data, size);
  const Bytes bytes(payload.begin(), payload.end());

  if (const auto request = decode_request(payload)) {
    if (encode_request(*request) != bytes) std::abort();
  } else if (request.error().request_code != 0 && size < 2) {
    std::abort();  // D2: REQUEST_CODE 0 when too short
  }

  if (const auto response = decode_response(payload)) {
    const Bytes again = encode_response(*response);
    if (std::holds_alternative<IdentificationReply>(*response)) {
      if (again.size() > bytes.size() || !std::equal(again.begin(), again.end(), bytes.begin())) std::abort();
    } else if (again != bytes) {
      std::abort();
    }
  }

  if (const auto profile = decode_profile(payload)) {
    if (encode_profile(*profile) != bytes) std::abort();
  }

  const auto parsed = parse_telegram(format_telegram(payload));
  if (!parsed || *parsed != bytes) std::abort();
  (void)parse_telegram(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
