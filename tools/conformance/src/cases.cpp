#include "cases.hpp"

#include <algorithm>
#include <cctype>

namespace ldoem::conformance {

bool Case::applies_to(protocol::Transport kind, Target target) const {
  if (emulator_only && target != Target::emulator) return false;
  return transports.empty() || std::find(transports.begin(), transports.end(), kind) != transports.end();
}

std::vector<Case> all_cases(const VectorTable& vectors) {
  std::vector<Case> cases;
  // Power-up first: it reads the D4 defaults of a fresh emulator before anything changes them,
  // and the spin-up case wants a head that has never turned.
  add_power_up_cases(cases);
  add_spin_up_cases(cases);
  add_vector_cases(cases, vectors);
  add_conversation_cases(cases);
  add_failure_cases(cases);
  add_state_cases(cases);
  add_s1_cases(cases);
  add_timing_cases(cases);
  return cases;
}

std::string slug(std::string_view text) {
  // UTF-8 spellings of the symbols the spec's vector names use.
  struct Replacement {
    std::string_view from;
    std::string_view to;
  };
  constexpr Replacement kReplacements[] = {{"\xC2\xB0", "deg"}, {"\xE2\x88\x92", "-"}, {"\xC3\x97", "x"},
                                           {"\xE2\x86\x92", "_to_"}, {"\xE2\x80\x93", "-"}};
  std::string out;
  auto append = [&out](char c) {
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+') {
      out += c;
    } else if (!out.empty() && out.back() != '_') {
      out += '_';
    }
  };
  for (std::size_t i = 0; i < text.size();) {
    const Replacement* match = nullptr;
    for (const auto& r : kReplacements) {
      if (text.substr(i).starts_with(r.from)) match = &r;
    }
    if (match != nullptr) {
      for (char c : match->to) append(c);
      i += match->from.size();
    } else {
      append(text[i++]);
    }
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

}  // namespace ldoem::conformance
