// Prints, as JSON, what ldoem's own reader finds in a capture: per transport the service code of
// every telegram, and for each profile its point counts and first distance. check_dissector.py
// compares tshark's decoding of the same capture with it (--capture FILE --expect JSON).
// Usage: ldoem_capture_expectations CAPTURE > expect.json
#include <iomanip>
#include <sstream>
#include <iostream>
#include <map>

#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/protocol/profile.hpp"

using namespace ldoem;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: ldoem_capture_expectations CAPTURE\n";
    return 2;
  }
  const auto loaded = capture::read_capture_conversation(argv[1]);
  if (!loaded) {
    std::cerr << "ldoem_capture_expectations: " << loaded.error() << "\n";
    return 1;
  }
  std::map<std::string, std::vector<std::uint16_t>> codes;
  std::map<std::string, std::vector<std::string>> profiles;
  for (const auto& telegram : loaded->conversation.telegrams) {
    const std::string transport(protocol::transport_name(telegram.transport));
    if (telegram.payload.size() < 2) continue;
    const std::uint16_t code = protocol::read_word_be(telegram.payload, 0);
    codes[transport].push_back(code);
    if (code != 0x8301) continue;
    const auto profile = protocol::decode_profile(telegram.payload);
    if (!profile) continue;
    std::ostringstream entry;
    entry << std::setprecision(17) << "{\"format\": " << profile->format << ", \"points\": [";
    std::size_t total = 0;
    double first = 0;
    bool have_first = false;
    for (std::size_t s = 0; s < profile->sectors.size(); ++s) {
      const auto& points = profile->sectors[s].points;
      entry << (s ? ", " : "") << points.size();
      total += points.size();
      if (!have_first && !points.empty()) {
        first = points[0].distance_q8_m / 256.0;
        have_first = true;
      }
    }
    entry << "], \"total\": " << total << ", \"first_distance_m\": " << first << "}";
    profiles[transport].push_back(entry.str());
  }
  const auto print_map = [](const auto& map, auto&& item) {
    std::cout << "{";
    bool first_key = true;
    for (const auto& [key, values] : map) {
      std::cout << (first_key ? "" : ", ") << "\"" << key << "\": [";
      for (std::size_t i = 0; i < values.size(); ++i) std::cout << (i ? ", " : "") << item(values[i]);
      std::cout << "]";
      first_key = false;
    }
    std::cout << "}";
  };
  std::cout << "{\"telegrams\": ";
  print_map(codes, [](std::uint16_t code) { return std::to_string(code); });
  std::cout << ", \"profiles\": ";
  print_map(profiles, [](const std::string& text) { return text; });
  std::cout << "}\n";
  return 0;
}
