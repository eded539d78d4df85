// QMP-shaped request/reply lines (docs/faults.md).
#include "ldoem/control_socket/control_protocol.hpp"

#include <algorithm>

#include <gtest/gtest.h>

#include "fake_target.hpp"
#include "ldoem/control_socket/line_assembler.hpp"

namespace ldoem::control_socket::test {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

json ask(FakeTarget& target, std::string_view line) {
  const std::string reply = handle_line(line, target);
  EXPECT_EQ(reply.find('\n'), std::string::npos) << "one line: " << reply;
  return json::parse(reply);
}

TEST(ControlProtocol, GreetingHasVersionAndCapabilities) {
  const json greeting = json::parse(greeting_line("1.2.3"));
  EXPECT_EQ(greeting["QMP"]["version"]["ldoem"], "1.2.3");
  EXPECT_EQ(greeting["QMP"]["version"]["package"], "ldoem-emud");
  EXPECT_TRUE(greeting["QMP"]["capabilities"].is_array());
  EXPECT_NE(greeting["QMP"]["commands"].dump().find("inject-fault"), std::string::npos);
}

TEST(ControlProtocol, QueryCommandsAnswersTheTableWithEachCommandsArguments) {
  FakeTarget target;
  const json reply = ask(target, R"({"execute": "query-commands", "id": 4})");
  ASSERT_TRUE(reply["return"].is_array()) << reply.dump();
  EXPECT_EQ(reply["id"], 4);
  std::vector<std::string> names;
  for (const json& command : reply["return"]) {
    names.push_back(command["name"].get<std::string>());
    if (command["name"] == "power-cycle") {
      EXPECT_EQ(command["arguments"], json::array({"off_s", "scanner"}));
    }
  }
  EXPECT_EQ(names, command_names());
  EXPECT_NE(std::find(names.begin(), names.end(), "query-commands"), names.end());
  // Every command in the table is dispatched: none is "has not been found" (the object commands
  // of a target without a world say so in their own words).
  for (const std::string& name : names) {
    if (name == "quit") continue;
    const json answer = ask(target, R"({"execute": ")" + name + R"("})");
    EXPECT_FALSE(answer.contains("error") && answer["error"]["desc"].get<std::string>().find("has not been found") !=
                                                 std::string::npos)
        << name;
  }
  EXPECT_EQ(ask(target, R"({"execute": "query-commands", "arguments": {"x": 1}})")["error"]["class"], "GenericError");
}

TEST(ControlProtocol, InjectFaultGoesThroughTheSceneGrammar) {
  FakeTarget target;
  const json reply = ask(target, R"({"execute": "inject-fault", "arguments": {"kind": "motor_stall", "duration_s": 2}, "id": 7})");
  EXPECT_EQ(reply, json::parse(R"({"return": {"id": 1}, "id": 7})"));
  ASSERT_EQ(target.injected.size(), 1u);
  EXPECT_EQ(target.injected[0].kind, faults::FaultKind::motor_stall);
  EXPECT_EQ(target.injected[0].duration, faults::SimTime(2s));
  EXPECT_TRUE(std::holds_alternative<faults::TriggerNow>(target.injected[0].trigger));

  ask(target, R"({"execute": "inject-fault", "arguments": {"kind": "drop_reply", "on": {"service": "GET_STATUS", "nth": 2}}})");
  ASSERT_EQ(target.injected.size(), 2u);
  EXPECT_EQ(std::get<faults::TriggerOnNth>(target.injected[1].trigger), (faults::TriggerOnNth{0x0102, 2}));
}

TEST(ControlProtocol, PowerCycleIsAPowerCycleFault) {
  FakeTarget target;
  ask(target, R"({"execute": "power-cycle", "arguments": {"off_s": 0.5}})");
  ASSERT_EQ(target.injected.size(), 1u);
  EXPECT_EQ(target.injected[0].kind, faults::FaultKind::power_cycle);
  EXPECT_EQ(target.injected[0].off, faults::SimTime(500ms));
}

TEST(ControlProtocol, IdIsEchoedAsGivenAndLeftOutWithout) {
  FakeTarget target;
  EXPECT_EQ(ask(target, R"({"execute": "query-status", "id": {"a": [1, "x"]}})")["id"], json::parse(R"({"a": [1, "x"]})"));
  EXPECT_FALSE(ask(target, R"({"execute": "query-status"})").contains("id"));
}

TEST(ControlProtocol, ScannerArgument_SendsAFaultCommandToThatScanner) {
  FakeTarget first;
  FakeTarget side;
  first.other = &side;
  first.other_name = "side";
  EXPECT_EQ(ask(first, R"({"execute": "inject-fault", "arguments": {"kind": "motor_stall", "scanner": "side"}})"),
            json::parse(R"({"return": {"id": 1}})"));
  EXPECT_EQ(ask(first, R"({"execute": "power-cycle", "arguments": {"off_s": 1, "scanner": "side"}})"),
            json::parse(R"({"return": {"id": 2}})"));
  ask(first, R"({"execute": "clear-fault", "arguments": {"id": 1, "scanner": "side"}})");
  EXPECT_TRUE(first.injected.empty());
  EXPECT_TRUE(first.cleared.empty());
  ASSERT_EQ(side.injected.size(), 2u);
  EXPECT_EQ(side.injected[1].kind, faults::FaultKind::power_cycle);
  ASSERT_EQ(side.cleared.size(), 1u);
  EXPECT_EQ(ask(first, R"({"execute": "query-status", "arguments": {"scanner": "side"}})")["return"]["state"], "IDLE");
  // Without it the command is the first scanner's, as with one scanner.
  ask(first, R"({"execute": "inject-fault", "arguments": {"kind": "motor_stall"}})");
  EXPECT_EQ(first.injected.size(), 1u);
  const json unknown = ask(first, R"({"execute": "query-faults", "arguments": {"scanner": "rear"}, "id": 3})");
  EXPECT_EQ(unknown, json::parse(R"({"error": {"class": "GenericError", "desc": "scanner: no scanner named 'rear'"}, "id": 3})"));
  EXPECT_EQ(ask(first, R"({"execute": "query-status", "arguments": {"scanner": 2}})")["error"]["desc"],
            "scanner: must be a scanner's name");
  // Not a fault command: quit and the object commands act on the daemon, "scanner" is no argument of theirs.
  EXPECT_TRUE(ask(first, R"({"execute": "quit", "arguments": {"scanner": "side"}})").contains("error"));
  EXPECT_FALSE(first.quit_asked);
}

TEST(ControlProtocol, ClearAndQuit) {
  FakeTarget target;
  EXPECT_EQ(ask(target, R"({"execute": "clear-fault"})"), json::parse(R"({"return": {}})"));
  EXPECT_EQ(ask(target, R"({"execute": "clear-fault", "arguments": {"id": 9}})")["error"]["class"], "GenericError");
  EXPECT_EQ(target.cleared, (std::vector<std::optional<std::uint64_t>>{std::nullopt, 9}));
  EXPECT_EQ(ask(target, R"({"execute": "quit"})"), json::parse(R"({"return": {}})"));
  EXPECT_TRUE(target.quit_asked);
}

struct BadLine {
  const char* title;
  const char* line;
  const char* error_class;
  const char* desc_part;
};

const BadLine kBadLines[] = {
    {"not JSON", "hello", "GenericError", "not a JSON value"},
    {"truncated JSON", R"({"execute": "quit")", "GenericError", "not a JSON value"},
    {"not an object", "[1, 2]", "GenericError", "JSON object"},
    {"no execute", R"({"arguments": {}})", "GenericError", "execute"},
    {"execute not text", R"({"execute": 5})", "GenericError", "execute"},
    {"unknown member", R"({"execute": "quit", "extra": 1})", "GenericError", "extra"},
    {"arguments not an object", R"({"execute": "quit", "arguments": [1]})", "GenericError", "arguments"},
    {"unknown command", R"({"execute": "launch-missiles"})", "CommandNotFound", "launch-missiles"},
    {"unknown fault kind", R"({"execute": "inject-fault", "arguments": {"kind": "motor_fire"}})", "GenericError", "motor_fire"},
    {"negative time", R"({"execute": "inject-fault", "arguments": {"kind": "motor_stall", "at_s": -1}})", "GenericError", "at_s"},
    {"fraction over 1", R"({"execute": "inject-fault", "arguments": {"kind": "window_dirt", "fraction": 2}})", "GenericError", "fraction"},
    {"unknown service", R"({"execute": "inject-fault", "arguments": {"kind": "drop_reply", "service": "NOPE"}})", "GenericError", "NOPE"},
    {"array for a field", R"({"execute": "inject-fault", "arguments": {"kind": ["motor_stall"]}})", "GenericError", "kind"},
    {"on not a map", R"({"execute": "inject-fault", "arguments": {"kind": "drop_reply", "on": 3}})", "GenericError", "on"},
    {"arguments to query", R"({"execute": "query-faults", "arguments": {"x": 1}})", "GenericError", "no arguments"},
    {"power-cycle extra", R"({"execute": "power-cycle", "arguments": {"kind": "blind"}})", "GenericError", "off_s"},
    {"clear id text", R"({"execute": "clear-fault", "arguments": {"id": "one"}})", "GenericError", "id"},
    {"move-object without world", R"({"execute": "move-object", "arguments": {"name": "door", "position_m": [1, 2, 3]}})",
     "CommandNotFound", "D12"},
    {"invalid UTF-8", "{\"execute\": \"\xff\xfe\"}", "GenericError", "JSON"},
};

class BadLines : public ::testing::TestWithParam<BadLine> {};

TEST_P(BadLines, GetAnErrorObject) {
  FakeTarget target;
  const BadLine& bad = GetParam();
  const json reply = ask(target, bad.line);
  ASSERT_TRUE(reply.contains("error")) << bad.title << ": " << reply.dump();
  EXPECT_EQ(reply["error"]["class"], bad.error_class) << reply.dump();
  EXPECT_NE(reply["error"]["desc"].get<std::string>().find(bad.desc_part), std::string::npos) << reply.dump();
  EXPECT_TRUE(target.injected.empty());
}

INSTANTIATE_TEST_SUITE_P(Lines, BadLines, ::testing::ValuesIn(kBadLines));

TEST(ControlProtocol, EventLineUsesSimulatedTime) {
  const json event = json::parse(event_line("FAULT_INJECTED", {{"id", 1}}, 2500123us));
  EXPECT_EQ(event["event"], "FAULT_INJECTED");
  EXPECT_EQ(event["data"]["id"], 1);
  EXPECT_EQ(event["timestamp"]["seconds"], 2);
  EXPECT_EQ(event["timestamp"]["microseconds"], 500123);
}

TEST(LineAssembler, SplitsAnywhereAndBoundsLongLines) {
  const std::string input = "{\"a\":1}\r\nsecond\n" + std::string(100, 'x') + "\nlast\n";
  for (std::size_t chunk = 1; chunk <= input.size(); ++chunk) {
    LineAssembler lines(50);
    std::vector<AssembledLine> out;
    for (std::size_t at = 0; at < input.size(); at += chunk) lines.feed(std::string_view(input).substr(at, chunk), out);
    ASSERT_EQ(out.size(), 4u) << chunk;
    EXPECT_EQ(out[0].text, "{\"a\":1}");
    EXPECT_EQ(out[1].text, "second");
    EXPECT_TRUE(out[2].too_long);
    EXPECT_EQ(out[3].text, "last");
    EXPECT_EQ(lines.buffered(), 0u);
  }
}

TEST(LineAssembler, OneMebibyteLineKeepsAtMostTheBound) {
  LineAssembler lines(64 * 1024);
  std::vector<AssembledLine> out;
  const std::string block(4096, 'z');
  for (int i = 0; i < 256; ++i) {
    lines.feed(block, out);
    EXPECT_LE(lines.buffered(), 64u * 1024u);
  }
  lines.feed("\n{}\n", out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].too_long);
  EXPECT_EQ(out[1].text, "{}");
}

}  // namespace
}  // namespace ldoem::control_socket::test
