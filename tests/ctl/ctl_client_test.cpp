// The ldoem-ctl binary against a control server on its own thread: reply, error, events, exit
// codes. The server thread runs a bounded loop.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "ldoem/control_socket/control_protocol.hpp"
#include "ldoem/control_socket/control_server.hpp"
#include "ldoem/ctl/ctl_client.hpp"

namespace ldoem::ctl {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

class StubTarget final : public control_socket::ControlTarget {
 public:
  control_socket::CommandResult inject_fault(const faults::FaultSpec&) override { return json{{"id", 3}}; }
  control_socket::CommandResult clear_fault(std::optional<std::uint64_t>) override {
    return control_socket::CommandError{"GenericError", "no active fault 9"};
  }
  json query_faults() override { return json::array(); }
  json query_status() override { return {{"state", "MEASURE"}, {"head_hz", 10}}; }
  void quit() override {}
};

struct Result {
  int code;
  std::string out;
};

// Runs ldoem-ctl with `args`, stdout captured, while the server's loop runs on another thread.
class CtlRun : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (std::filesystem::temp_directory_path() / ("ldoem-ctl-run-" + std::to_string(getpid()))).string();
    auto loop = io::EventLoop::create();
    ASSERT_TRUE(loop);
    loop_ = std::move(*loop);
    auto server = control_socket::ControlServer::open(*loop_, path_, control_socket::greeting_line("t"),
                                                      [this](std::string_view line) { return control_socket::handle_line(line, target_); });
    ASSERT_TRUE(server) << server.error().message();
    server_ = std::move(*server);
    thread_ = std::thread([this] {
      const auto deadline = std::chrono::steady_clock::now() + 30s;
      while (!stop_ && std::chrono::steady_clock::now() < deadline) {
        (void)loop_->run_once(5ms);
        if (broadcast_.exchange(false)) server_->broadcast(control_socket::event_line("FAULT_INJECTED", {{"id", 1}}, 1500ms));
      }
    });
  }
  void TearDown() override {
    stop_ = true;
    thread_.join();
    server_.reset();
  }
  Result run(const std::string& args) {
    const std::string command = std::string(LDOEM_CTL_PATH) + " --control " + path_ + " " + args + " 2>/dev/null";
    FILE* pipe = popen(command.c_str(), "r");
    std::string out;
    std::array<char, 4096> chunk{};
    while (std::fgets(chunk.data(), chunk.size(), pipe)) out += chunk.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
  }

  std::string path_;
  StubTarget target_;
  std::unique_ptr<io::EventLoop> loop_;
  std::unique_ptr<control_socket::ControlServer> server_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> broadcast_{false};
};

TEST_F(CtlRun, InjectPrintsTheReply) {
  const Result result = run("inject-fault motor_stall --duration 2");
  EXPECT_EQ(result.code, kExitOk);
  EXPECT_EQ(result.out, "id: 3\n");
  const Result raw = run("--json query-status");
  EXPECT_EQ(raw.code, kExitOk);
  EXPECT_EQ(json::parse(raw.out)["return"]["state"], "MEASURE");
}

TEST_F(CtlRun, ErrorReplyIsExitOne) {
  EXPECT_EQ(run("clear-fault 9").code, kExitFailure);
  EXPECT_EQ(run("send '{\"execute\": \"nope\"}'").code, kExitFailure);
}

TEST_F(CtlRun, EventsAreFollowedUpToCount) {
  std::thread trigger([this] {
    std::this_thread::sleep_for(300ms);
    broadcast_ = true;
  });
  const Result result = run("--timeout 10 events --count 1");
  trigger.join();
  EXPECT_EQ(result.code, kExitOk);
  EXPECT_EQ(result.out, "1.500000 FAULT_INJECTED {\"id\":1}\n");
}

TEST(CtlClient, UnreachableDaemonIsExitOne) {
  CtlPlan plan;
  plan.control_path = "/nonexistent/ldoem.ctl";
  plan.request = json{{"execute", "query-status"}};
  std::ostringstream out, err;
  EXPECT_EQ(run_ctl(plan, out, err), kExitFailure);
  EXPECT_NE(err.str().find("connect /nonexistent/ldoem.ctl"), std::string::npos) << err.str();
}

TEST(CtlClient, HumanText) {
  EXPECT_EQ(human_text(json::parse(R"({"return": {}})")), "ok\n");
  EXPECT_EQ(human_text(json::parse(R"({"return": []})")), "none\n");
  EXPECT_EQ(human_text(json::parse(R"({"error": {"class": "GenericError", "desc": "bad"}})")), "error GenericError: bad\n");
  EXPECT_EQ(human_text(json::parse(R"({"return": {"a": {"b": 1}, "c": "x"}})")), "a.b: 1\nc: x\n");
}

}  // namespace
}  // namespace ldoem::ctl
