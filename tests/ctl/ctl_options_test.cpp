// ldoem-ctl's command line -> request (pure).
#include "ldoem/ctl/ctl_options.hpp"

#include <gtest/gtest.h>

#include "ldoem/control_socket/command_table.hpp"

namespace ldoem::ctl {
namespace {

using nlohmann::json;

CtlPlan plan_of(const std::vector<std::string>& args) {
  auto parsed = parse_ctl_options(args);
  if (auto* exit = std::get_if<CtlExit>(&parsed)) {
    ADD_FAILURE() << exit->text;
    return {};
  }
  return std::get<CtlPlan>(parsed);
}

CtlExit exit_of(const std::vector<std::string>& args) {
  auto parsed = parse_ctl_options(args);
  if (auto* exit = std::get_if<CtlExit>(&parsed)) return *exit;
  ADD_FAILURE() << "accepted";
  return {};
}

TEST(CtlOptions, TheIssuesExample) {
  const CtlPlan plan = plan_of({"--control", "/tmp/x.ctl", "inject-fault", "motor_stall", "--duration", "2"});
  EXPECT_EQ(plan.control_path, "/tmp/x.ctl");
  ASSERT_TRUE(plan.request);
  EXPECT_EQ(*plan.request, json::parse(R"({"execute": "inject-fault", "arguments": {"kind": "motor_stall", "duration_s": 2.0}})"));
}

TEST(CtlOptions, TriggersAndParameters) {
  const CtlPlan plan = plan_of({"--control", "p", "--json", "inject-fault", "drop_reply", "--on", "GET_STATUS:3",
                                "--transport", "tcp"});
  EXPECT_TRUE(plan.json_output);
  EXPECT_EQ((*plan.request)["arguments"],
            json::parse(R"({"kind": "drop_reply", "on": {"service": "GET_STATUS", "nth": 3}, "transport": "tcp"})"));
  const CtlPlan every = plan_of({"--control", "p", "inject-fault", "corrupt_checksum", "--every", "GET_PROFILE:10"});
  EXPECT_EQ((*every.request)["arguments"]["every"], json::parse(R"({"service": "GET_PROFILE", "count": 10})"));
}

TEST(CtlOptions, OtherCommands) {
  EXPECT_EQ(*plan_of({"--control", "p", "clear-fault", "4"}).request,
            json::parse(R"({"execute": "clear-fault", "arguments": {"id": 4}})"));
  EXPECT_EQ(*plan_of({"--control", "p", "clear-fault"}).request, json::parse(R"({"execute": "clear-fault"})"));
  EXPECT_EQ(*plan_of({"--control", "p", "query-status"}).request, json::parse(R"({"execute": "query-status"})"));
  EXPECT_EQ(*plan_of({"--control", "p", "power-cycle", "--off", "0.5"}).request,
            json::parse(R"({"execute": "power-cycle", "arguments": {"off_s": 0.5}})"));
  const CtlPlan events = plan_of({"--control", "p", "--timeout", "0", "events", "--count", "3"});
  EXPECT_TRUE(events.follow_events);
  EXPECT_EQ(events.event_count, 3u);
  EXPECT_EQ(events.timeout.count(), 0);
  EXPECT_EQ(*plan_of({"--control", "p", "send", R"({"execute": "quit"})"}).request, json::parse(R"({"execute": "quit"})"));
}

TEST(CtlOptions, ObjectCommands) {
  EXPECT_EQ(*plan_of({"--control", "p", "move-object", "door", "--position", "2,0.5,0", "--rpy", "0,0,90", "--at", "3",
                      "--keep-velocity"})
                 .request,
            json::parse(R"({"execute": "move-object", "arguments": {"name": "door", "position_m": [2.0, 0.5, 0.0],
                            "rpy_deg": [0.0, 0.0, 90.0], "at_s": 3.0, "keep_velocity": true}})"));
  EXPECT_EQ(*plan_of({"--control", "p", "move-object", "door", "--position", "1,2,3"}).request,
            json::parse(R"({"execute": "move-object", "arguments": {"name": "door", "position_m": [1.0, 2.0, 3.0]}})"));
  EXPECT_EQ(exit_of({"--control", "p", "move-object", "door", "--position", "1,2"}).code, kExitUsage);
  EXPECT_EQ(exit_of({"--control", "p", "move-object", "door"}).code, kExitUsage);
  EXPECT_EQ(*plan_of({"--control", "p", "add-object", R"({"name": "c", "sphere": {"radius_m": 1}})", "--at", "2"}).request,
            json::parse(R"({"execute": "add-object", "arguments": {"object": {"name": "c", "sphere": {"radius_m": 1}},
                            "at_s": 2.0}})"));
  EXPECT_EQ(exit_of({"--control", "p", "add-object", "[1, 2]"}).code, kExitUsage);
  EXPECT_EQ(*plan_of({"--control", "p", "remove-object", "c"}).request,
            json::parse(R"({"execute": "remove-object", "arguments": {"name": "c"}})"));
}

TEST(CtlOptions, ScannerGoesIntoTheFaultCommandsArguments) {
  EXPECT_EQ(*plan_of({"--control", "p", "--scanner", "side", "inject-fault", "motor_stall"}).request,
            json::parse(R"({"execute": "inject-fault", "arguments": {"kind": "motor_stall", "scanner": "side"}})"));
  EXPECT_EQ(*plan_of({"--control", "p", "--scanner", "side", "query-status"}).request,
            json::parse(R"({"execute": "query-status", "arguments": {"scanner": "side"}})"));
  EXPECT_EQ(*plan_of({"--control", "p", "--scanner", "side", "clear-fault", "3"}).request,
            json::parse(R"({"execute": "clear-fault", "arguments": {"id": 3, "scanner": "side"}})"));
  for (const std::vector<std::string>& daemon_wide :
       {std::vector<std::string>{"--control", "p", "--scanner", "side", "quit"},
        std::vector<std::string>{"--control", "p", "--scanner", "side", "remove-object", "crate"},
        std::vector<std::string>{"--control", "p", "--scanner", "side", "events"},
        std::vector<std::string>{"--control", "p", "--scanner", "side", "send", "{\"execute\": \"quit\"}"}}) {
    const CtlExit exit = exit_of(daemon_wide);
    EXPECT_EQ(exit.code, 2);
    EXPECT_NE(exit.text.find("--scanner: only with"), std::string::npos) << exit.text;
  }
}

TEST(CtlOptions, HelpIsExitZeroWithExamples) {
  // --help is one screen pointing to --help-all, which has the examples (and the man page).
  const CtlExit brief = exit_of({"--help"});
  EXPECT_EQ(brief.code, kExitOk);
  EXPECT_NE(brief.text.find("--help-all"), std::string::npos) << brief.text;
  const CtlExit help = exit_of({"--help-all"});
  EXPECT_EQ(help.code, kExitOk);
  EXPECT_NE(help.text.find("inject-fault motor_stall --duration 2"), std::string::npos);
  EXPECT_NE(help.text.find("Exit codes"), std::string::npos);
}

// Issue 22 item 3: ldoem-ctl's commands and their help come from the control socket's table.
TEST(CtlOptions, EveryTableCommand_IsInTheHelpWithTheTablesHelpLine) {
  const CtlExit brief = exit_of({"--help"});
  const CtlExit all = exit_of({"--help-all"});
  for (const auto& command : control_socket::command_table()) {
    EXPECT_NE(brief.text.find("  " + command.name + " "), std::string::npos) << command.name << " in:\n" << brief.text;
    EXPECT_NE(all.text.find(command.help), std::string::npos) << command.name << " in:\n" << all.text;
  }
}

TEST(CtlOptions, ATableCommandWithoutOptionsOfItsOwn_SendsItsName) {
  EXPECT_EQ(*plan_of({"--control", "p", "query-commands"}).request, json::parse(R"({"execute": "query-commands"})"));
  EXPECT_EQ(*plan_of({"--control", "p", "qmp_capabilities"}).request, json::parse(R"({"execute": "qmp_capabilities"})"));
  EXPECT_EQ(*plan_of({"--control", "p", "quit"}).request, json::parse(R"({"execute": "quit"})"));
}

TEST(CtlOptions, UsageErrorsAreExitTwo) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"inject-fault", "motor_stall"},                       // no --control
           {"--control", "p"},                                    // no command
           {"--control", "p", "inject-fault"},                    // no kind
           {"--control", "p", "inject-fault", "x", "--on", "GET_STATUS"},  // no :N
           {"--control", "p", "inject-fault", "x", "--duration", "soon"},
           {"--control", "p", "send", "not json"},
           {"--control", "p", "launch"},
       }) {
    const CtlExit exit = exit_of(args);
    EXPECT_EQ(exit.code, kExitUsage) << exit.text;
    EXPECT_EQ(exit.text.rfind("ldoem-ctl: ", 0), 0u) << exit.text;
  }
}

TEST(CtlOptions, AnUnknownCommand_IsNamedWithTheCommandsThereAre) {
  const CtlExit exit = exit_of({"--control", "/tmp/x.ctl", "bogus"});
  EXPECT_EQ(exit.code, kExitUsage);
  EXPECT_NE(exit.text.find("unknown command 'bogus'"), std::string::npos) << exit.text;
  EXPECT_NE(exit.text.find("inject-fault"), std::string::npos) << exit.text;
  // After a value-taking option too, the command word is found.
  EXPECT_NE(exit_of({"--timeout", "3", "--control=/tmp/x.ctl", "querystatus"}).text.find("'querystatus'"),
            std::string::npos);
}

TEST(CtlOptions, Version_PrintsTheProjectsVersion) {
  const CtlExit exit = exit_of({"--version"});
  EXPECT_EQ(exit.code, kExitOk);
  EXPECT_EQ(exit.text, std::string("ldoem-ctl ") + LDOEM_VERSION);
}

TEST(CtlOptions, Help_NamesValuesByMeaningNotByCli11Type) {
  for (const auto& args : {std::vector<std::string>{"--help"}, {"--help-all"}, {"inject-fault", "--help"}, {"move-object", "--help"}}) {
    const CtlExit exit = exit_of(args);
    EXPECT_EQ(exit.code, kExitOk);
    for (const char* raw : {"FLOAT", "TEXT", "UINT", "INT", "[0 - "}) {
      EXPECT_EQ(exit.text.find(raw), std::string::npos) << raw << " in:\n" << exit.text;
    }
  }
}

}  // namespace
}  // namespace ldoem::ctl
