// One-line text form of a telegram (grammar in text.hpp).
#include "ldoem/protocol/text.hpp"

#include <optional>
#include <vector>

#include "ldoem/protocol/service_codes.hpp"

namespace ldoem::protocol {
namespace {

constexpr std::string_view kHexDigits = "0123456789abcdef";
constexpr std::string_view kReplyToken = "reply";

void append_hex(std::string& out, unsigned value, int digits) {
  for (int shift = 4 * (digits - 1); shift >= 0; shift -= 4) out.push_back(kHexDigits[(value >> shift) & 0xF]);
}

std::optional<unsigned> parse_hex(std::string_view token, std::size_t digits) {
  if (token.size() != digits) return std::nullopt;
  unsigned value = 0;
  for (const char c : token) {
    unsigned digit = 0;
    if (c >= '0' && c <= '9') digit = static_cast<unsigned>(c - '0');
    else if (c >= 'a' && c <= 'f') digit = static_cast<unsigned>(c - 'a' + 10);
    else if (c >= 'A' && c <= 'F') digit = static_cast<unsigned>(c - 'A' + 10);
    else return std::nullopt;
    value = (value << 4) | digit;
  }
  return value;
}

// Single spaces only: an empty token (leading, trailing or double space) is not in the grammar.
std::optional<std::vector<std::string_view>> split_tokens(std::string_view text) {
  std::vector<std::string_view> tokens;
  while (true) {
    const auto space = text.find(' ');
    const auto token = text.substr(0, space);
    if (token.empty()) return std::nullopt;
    tokens.push_back(token);
    if (space == std::string_view::npos) return tokens;
    text.remove_prefix(space + 1);
  }
}

std::optional<std::uint16_t> parse_code(const std::vector<std::string_view>& tokens, std::size_t& next) {
  if (const auto word = parse_hex(tokens[0], 4)) {
    next = 1;
    return static_cast<std::uint16_t>(*word);
  }
  if (tokens.size() > 1 && tokens[1] == kReplyToken) {
    next = 2;
    return service_code_from_name(std::string(tokens[0]) + " reply");
  }
  next = 1;
  return service_code_from_name(tokens[0]);
}

}  // namespace

std::string format_telegram(ByteView payload) {
  std::string text;
  if (payload.size() == 1) append_hex(text, payload[0], 2);
  if (payload.size() < 2) return text;
  const std::uint16_t code = read_word_be(payload, 0);
  if (is_known_code(code)) {
    text += service_name(code);
  } else {
    append_hex(text, code, 4);
  }
  std::size_t offset = 2;
  for (; offset + 1 < payload.size(); offset += 2) {
    text.push_back(' ');
    append_hex(text, read_word_be(payload, offset), 4);
  }
  if (offset < payload.size()) {
    text.push_back(' ');
    append_hex(text, payload[offset], 2);
  }
  return text;
}

base::Expected<Bytes, DecodeError> parse_telegram(std::string_view text) {
  if (text.empty()) return Bytes{};
  const auto tokens = split_tokens(text);
  if (!tokens) return base::Unexpected(DecodeError::bad_text);
  if (tokens->size() == 1) {
    if (const auto lone = parse_hex((*tokens)[0], 2)) return Bytes{static_cast<std::uint8_t>(*lone)};
  }
  std::size_t next = 0;
  const auto code = parse_code(*tokens, next);
  if (!code) return base::Unexpected(DecodeError::bad_text);
  Bytes payload;
  append_word_be(payload, *code);
  for (std::size_t i = next; i < tokens->size(); ++i) {
    const bool last = i + 1 == tokens->size();
    if (const auto word = parse_hex((*tokens)[i], 4)) {
      append_word_be(payload, static_cast<std::uint16_t>(*word));
    } else if (const auto byte = parse_hex((*tokens)[i], 2); byte && last) {
      payload.push_back(static_cast<std::uint8_t>(*byte));
    } else {
      return base::Unexpected(DecodeError::bad_text);
    }
  }
  return payload;
}

}  // namespace ldoem::protocol
