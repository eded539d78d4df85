#include "ldoem/protocol/errors.hpp"

namespace ldoem::protocol {

std::string_view describe(DecodeError error) {
  switch (error) {
    case DecodeError::truncated: return "telegram too short for its layout";
    case DecodeError::bad_length: return "length does not match the layout";
    case DecodeError::unknown_service: return "unknown service code";
    case DecodeError::unpublished_layout: return "service layout not published";
    case DecodeError::unknown_config_key: return "configuration key without a published layout";
    case DecodeError::bad_header: return "bad TCP header";
    case DecodeError::bad_checksum: return "bad TCP XOR checksum";
    case DecodeError::bad_hex: return "non-hex character in serial telegram";
    case DecodeError::bad_crc: return "bad serial CRC";
    case DecodeError::out_of_range: return "parameter out of range";
    case DecodeError::too_large: return "telegram larger than the maximum";
    case DecodeError::bad_sequence: return "segment or package out of sequence";
    case DecodeError::unexpected_frame: return "unexpected frame";
    case DecodeError::bad_flow_control: return "bad ISO-TP flow control";
    case DecodeError::overflow: return "receiver overflow";
    case DecodeError::timeout: return "reassembly timed out";
    case DecodeError::bad_text: return "text does not follow the telegram grammar";
  }
  return "unlisted decode error";
}

std::string_view describe(FailureReason reason) {
  switch (reason) {
    case FailureReason::unknown_service: return "unknown service";
    case FailureReason::wrong_length: return "wrong length";
    case FailureReason::wrong_state: return "not allowed in the current state";
    case FailureReason::out_of_range: return "parameter out of range";
    case FailureReason::framing: return "framing error";
    case FailureReason::flash_not_stored: return "flash write failed";
  }
  return "unlisted failure reason";
}

FailureReason failure_reason_for_framing(DecodeError error) {
  return error == DecodeError::bad_length ? FailureReason::wrong_length : FailureReason::framing;
}

}  // namespace ldoem::protocol
