#include "against.hpp"

#include <algorithm>
#include <cmath>

#include "ldoem/capture/capture_reader.hpp"
#include "ldoem/driver/error.hpp"
#include "ldoem/capture/capture_conversation.hpp"
#include "ldoem/protocol/text.hpp"
#include "recording_transport.hpp"
#include "reply_fields.hpp"

namespace ldoem::conformance {
namespace {

namespace p = protocol;
constexpr std::uint16_t kProfileCode = 0x8301;
constexpr std::size_t kDifferencesShownPerTelegram = 12;

bool is_profile(p::ByteView payload) { return payload.size() >= 2 && p::read_word_be(payload, 0) == kProfileCode; }

struct Split {
  std::vector<p::Bytes> replies;
  std::vector<p::Bytes> profiles;
};

Split split(const std::vector<capture::RecordedAnswer>& answers) {
  Split out;
  for (const auto& answer : answers) (is_profile(answer.payload) ? out.profiles : out.replies).push_back(answer.payload);
  return out;
}

// How long to wait for an exchange's telegrams: the recorded spread on the live clock, plus the
// reply timeout.
std::chrono::milliseconds wait_for(const SuiteOptions& options, const capture::Exchange& exchange) {
  base::SimTime last{};
  for (const auto& answer : exchange.answers) last = std::max(last, answer.delay);
  const double scale = options.virtual_time ? 1e6 : options.time_scale;
  const auto spread = std::chrono::milliseconds(
      static_cast<std::int64_t>(std::ceil(std::chrono::duration<double, std::milli>(last).count() / scale)));
  return spread + options.reply_timeout;
}

// Compares one recorded telegram with the live one; appends the report lines. True when equal.
bool compare(const std::string& label, p::ByteView recorded, p::ByteView live, const SuiteOptions& options,
             std::vector<std::string>& lines, std::size_t& differences) {
  const auto diff = compare_fields(reply_fields(recorded), reply_fields(live), options.masks);
  differences += diff.size();
  for (std::size_t i = 0; i < diff.size() && i < kDifferencesShownPerTelegram; ++i) {
    lines.push_back("    " + label + " " + diff[i].name + ": recorded " + diff[i].recorded + ", got " + diff[i].live);
  }
  if (diff.size() > kDifferencesShownPerTelegram) {
    lines.push_back("    " + label + " ... and " + std::to_string(diff.size() - kDifferencesShownPerTelegram) +
                    " more differing fields");
  }
  return diff.empty();
}

}  // namespace

int run_against(const SuiteOptions& options, std::ostream& out, std::ostream& err) {
  capture::ConversationConfig config;
  config.tcp_port = options.against_tcp_port;  // unset: detected from the STX "USP" frames
  auto loaded = capture::read_capture_conversation(*options.against, config);
  if (!loaded) {
    err << "ldoem-conformance: --against " << loaded.error() << '\n';
    return kExitUsageError;
  }
  const auto& telegrams = loaded->conversation.telegrams;
  const auto transport_kind = capture::busiest_transport(telegrams);
  if (!transport_kind) {
    err << "ldoem-conformance: --against " << *options.against << ": no LD-OEM telegram in it\n";
    return kExitUsageError;
  }
  const std::vector<capture::Exchange> exchanges = capture::exchanges_of(telegrams, *transport_kind);
  out << "against " << *options.against << " (" << capture::format_name(loaded->format) << ", "
      << p::transport_name(*transport_kind);
  if (*transport_kind == p::Transport::tcp) {
    out << ", device port " << loaded->conversation.tcp_port << (loaded->conversation.tcp_port_detected ? " (detected)" : "");
  }
  out << "): " << exchanges.size() << " requests\n";
  auto transport = open_suite_transport(options);
  if (!transport) {
    err << "ldoem-conformance: " << transport.error() << '\n';
    out << "0 passed, 1 failed\n";
    return kExitFailed;
  }
  int passed = 0;
  int failed = 0;
  std::size_t total_differences = 0;
  std::uint64_t extra_profiles = 0;
  for (std::size_t index = 0; index < exchanges.size(); ++index) {
    const capture::Exchange& exchange = exchanges[index];
    const std::string name = "against/" + std::to_string(index) + " " + p::format_telegram(exchange.request);
    const Split recorded = split(exchange.answers);
    Split live;
    std::vector<std::string> lines;
    const driver::Deadline deadline = driver::Clock::now() + wait_for(options, exchange);
    if (auto sent = (*transport)->send(exchange.request, deadline); !sent) {
      lines.push_back("    send: " + driver::describe(sent.error()));
    } else {
      while (live.replies.size() < recorded.replies.size() || live.profiles.size() < recorded.profiles.size()) {
        auto received = (*transport)->receive(deadline);
        if (!received) break;
        if (is_profile(*received)) {
          if (live.profiles.size() < recorded.profiles.size()) live.profiles.push_back(std::move(*received));
          else ++extra_profiles;
        } else {
          live.replies.push_back(std::move(*received));
        }
      }
    }
    std::size_t differences = 0;
    bool same = lines.empty();
    for (std::size_t i = 0; i < recorded.replies.size(); ++i) {
      const std::string label = "reply " + std::to_string(i);
      if (i >= live.replies.size()) {
        lines.push_back("    " + label + " missing: recorded " + p::format_telegram(recorded.replies[i]));
        same = false;
        ++differences;
      } else if (!compare(label, recorded.replies[i], live.replies[i], options, lines, differences)) {
        same = false;
      }
    }
    for (std::size_t i = recorded.replies.size(); i < live.replies.size(); ++i) {
      lines.push_back("    unexpected reply: " + p::format_telegram(live.replies[i]));
      same = false;
      ++differences;
    }
    for (std::size_t i = 0; i < recorded.profiles.size(); ++i) {
      const std::string label = "profile " + std::to_string(i);
      if (i >= live.profiles.size()) {
        lines.push_back("    " + label + " missing (" + std::to_string(live.profiles.size()) + " of " +
                        std::to_string(recorded.profiles.size()) + " arrived)");
        same = false;
        ++differences;
        break;
      }
      if (!compare(label, recorded.profiles[i], live.profiles[i], options, lines, differences)) same = false;
    }
    total_differences += differences;
    if (same) {
      out << "PASS " << name << '\n';
      ++passed;
    } else {
      out << "FAIL " << name << ": " << differences << " difference(s)\n";
      for (const auto& line : lines) out << line << '\n';
      ++failed;
    }
  }
  (*transport)->close();
  if (extra_profiles > 0) out << extra_profiles << " live profiles beyond the recorded ones were not compared\n";
  out << total_differences << " differences\n" << passed << " passed, " << failed << " failed" << std::endl;
  return failed == 0 ? kExitAllPassed : kExitFailed;
}

}  // namespace ldoem::conformance
