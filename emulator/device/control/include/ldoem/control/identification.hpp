// GET_IDENTIFICATION texts by IDENTITEM (spec 3.3, D3).
#pragma once

#include <cstdint>
#include <map>
#include <string>

namespace ldoem::control {

// Item number -> text, sent without NUL or padding (D3). An item missing here is answered
// SERVICE_FAILURE reason 4 like an unknown item.
using IdentificationTexts = std::map<std::uint16_t, std::string>;

// D3 defaults: name "LD-OEM1000", firmware "ldoem-emud" at the project version, part and serial
// numbers "0000000".
IdentificationTexts default_identification();

}  // namespace ldoem::control
