// power-up/: what a fresh emulator answers before anyone configured it (D4). Emulator only:
// D4 is our decision, and it holds only for a daemon started with --no-flash (or a new flash).
#include "cases.hpp"

namespace ldoem::conformance {
namespace {

using namespace protocol;

void check_d4_defaults(Session& session) {
  session.expect("GET_STATUS", encode_request(GetStatus{}),
                 BytePattern::exactly(reply_bytes(GetStatusReply{status(SensorMode::idle), {}})));
  session.expect("GET_CONFIG global", encode_request(GetConfig{key_word(ConfigKey::global)}),
                 BytePattern::exactly(reply_bytes(GetConfigReply{GlobalConfig{1, 10, 4, false}})));
  session.expect("GET_FUNCTION s0", encode_request(GetFunction{0}),
                 BytePattern::exactly(reply_bytes(GetFunctionReply{0, sector_function::kNormalMeasurement, 2160})));
  session.expect("GET_FUNCTION s1", encode_request(GetFunction{1}),
                 BytePattern::exactly(reply_bytes(GetFunctionReply{1, sector_function::kNoMeasurement, 3600})));
  for (std::uint16_t sector = 2; sector < kSectorCount; ++sector) {
    // D4 says "not initialised" and nothing about the stop angle of such a sector.
    session.expect("GET_FUNCTION s" + std::to_string(sector), encode_request(GetFunction{sector}),
                   BytePattern::exactly(reply_bytes(GetFunctionReply{sector, sector_function::kNotInitialised, 0}))
                       .with_hole(6, 2));
  }
}

}  // namespace

void add_power_up_cases(std::vector<Case>& cases) {
  cases.push_back(Case{"power-up/D4_defaults", check_d4_defaults, true, false, {}});
}

}  // namespace ldoem::conformance
