// The command table (command_table.hpp): every command declared once, with its help and argument
// schema; query-commands answers exactly the table, and handle_line checks each request against it.
#include "ldoem/control_socket/command_handlers.hpp"
#include "ldoem/control_socket/command_table.hpp"

#include <set>

#include <gtest/gtest.h>

#include "fake_target.hpp"

namespace ldoem::control_socket::test {
namespace {

using nlohmann::json;

// Not `ask`: the unity build (asan preset) puts this file beside control_protocol_test.cpp.
json ask_request(FakeTarget& target, const json& request) { return json::parse(handle_line(request.dump(), target)); }

TEST(CommandTable, EveryEntryHasANameAOneLineHelpAHandlerAndDistinctArguments) {
  std::set<std::string> names;
  for (const CommandSpec& command : command_table()) {
    EXPECT_FALSE(command.name.empty());
    EXPECT_TRUE(names.insert(command.name).second) << "declared twice: " << command.name;
    EXPECT_FALSE(command.help.empty()) << command.name;
    EXPECT_EQ(command.help.find('\n'), std::string::npos) << command.name << ": one line";
    EXPECT_LE(command.help.size(), 80u) << command.name;
    EXPECT_NE(command_handler(command.name), nullptr) << command.name << ": no handler (command_handlers.cpp)";
    std::set<std::string> arguments;
    for (const ArgumentSpec& argument : command.arguments) {
      EXPECT_FALSE(argument.name.empty()) << command.name;
      EXPECT_NE(argument.name, "scanner") << command.name << ": per_scanner adds it";
      EXPECT_TRUE(arguments.insert(argument.name).second) << command.name << ": " << argument.name << " twice";
    }
    EXPECT_EQ(find_command(command.name), &command);
  }
  EXPECT_EQ(find_command("launch-missiles"), nullptr);
  EXPECT_EQ(command_handler("launch-missiles"), nullptr);
  EXPECT_EQ(command_names().size(), command_table().size());
}

TEST(CommandTable, QueryCommandsIsTheTable) {
  FakeTarget target;
  const json reply = ask_request(target, {{"execute", "query-commands"}});
  json expected = json::array();
  for (const CommandSpec& command : command_table()) {
    json schema = json::object();
    std::vector<std::string> names;
    for (const ArgumentSpec& argument : command.arguments) {
      names.push_back(argument.name);
      schema[argument.name] = {{"type", std::string(json_type_name(argument.type))}, {"required", argument.required}};
      if (!argument.what.empty()) schema[argument.name]["description"] = argument.what;
    }
    if (command.per_scanner) {
      names.push_back("scanner");
      schema["scanner"] = {{"type", "string"}, {"required", false}, {"description", "a scanner's name"}};
    }
    expected.push_back({{"name", command.name}, {"help", command.help}, {"arguments", names}, {"schema", schema}});
  }
  EXPECT_EQ(reply, json({{"return", expected}}));
  // A schema entry as clients read it.
  for (const json& command : reply["return"]) {
    if (command["name"] == "move-object") {
      const json position = {{"type", "array"}, {"required", true}, {"description", "a list of three numbers (metres)"}};
      EXPECT_EQ(command["schema"]["position_m"], position);
    }
  }
}

TEST(CommandTable, AnArgumentNotInTheSchemaIsAGenericErrorForEveryCommand) {
  for (const CommandSpec& command : command_table()) {
    FakeTarget target;
    const json reply = ask_request(target, {{"execute", command.name}, {"arguments", {{"bogus", 1}}}, {"id", 5}});
    ASSERT_TRUE(reply.contains("error")) << command.name << " -> " << reply.dump();
    EXPECT_EQ(reply["error"]["class"], "GenericError") << reply.dump();
    EXPECT_NE(reply["error"]["desc"].get<std::string>().find(command.name + ": unknown argument 'bogus'"), std::string::npos)
        << reply.dump();
    EXPECT_EQ(reply["id"], 5);
    EXPECT_TRUE(target.injected.empty() && target.cleared.empty() && !target.quit_asked) << command.name;
  }
}

TEST(CommandTable, TypesAndRequiredArgumentsAreCheckedBeforeTheHandler) {
  FakeTarget target;
  EXPECT_EQ(ask_request(target, {{"execute", "inject-fault"}, {"arguments", {{"duration_s", 2}}}})["error"]["desc"],
            "inject-fault: needs kind (a D11 fault name (motor_stall, drop_reply, ...))");
  EXPECT_EQ(ask_request(target, {{"execute", "power-cycle"}, {"arguments", {{"off_s", "long"}}}})["error"]["desc"],
            "off_s: must be a number");
  EXPECT_EQ(ask_request(target, {{"execute", "clear-fault"}, {"arguments", {{"id", -1}}}})["error"]["desc"],
            "id: must be a fault id (query-faults)");
  EXPECT_EQ(ask_request(target, {{"execute", "move-object"}, {"arguments", {{"name", "door"}, {"position_m", "here"}}}})["error"]["desc"],
            "position_m: must be a list of three numbers (metres)");
  EXPECT_EQ(ask_request(target, {{"execute", "add-object"}, {"arguments", {{"object", "box"}}}})["error"]["desc"],
            "object: must be one entry of a scene's objects list (docs/scenes.md)");
  EXPECT_TRUE(target.injected.empty());
  EXPECT_TRUE(target.cleared.empty());
  // A well-typed request goes on to the handler (here: a target without a world says so).
  EXPECT_EQ(ask_request(target, {{"execute", "remove-object"}, {"arguments", {{"name", "crate"}}}})["error"]["class"], "CommandNotFound");
}

}  // namespace
}  // namespace ldoem::control_socket::test
