// Private: WORD layouts of the configuration keys (spec 3.4, D1), shared by SET_CONFIG requests
// and GET_CONFIG replies.
#pragma once

#include "ldoem/protocol/config.hpp"
#include "ldoem/protocol/errors.hpp"
#include "ldoem/base/expected.hpp"
#include "word_reader.hpp"

namespace ldoem::protocol::detail {

// Appends KEY(W) then the key's fields.
void append_config_body(Bytes& out, const ConfigBody& body);

// Reads the fields of `key` from the rest of `reader`, which must hold exactly them
// (bad_length otherwise); `allow_global_zero_pad` accepts S2's extra 0x0000 WORD after the
// global key (D2). unknown_config_key for a key without a layout.
base::Expected<ConfigBody, DecodeError> read_config_fields(std::uint16_t key, WordReader& reader,
                                                     bool allow_global_zero_pad);

}  // namespace ldoem::protocol::detail
