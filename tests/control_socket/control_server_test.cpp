// The control socket server on a real event loop: mode 0600, greeting, garbage, 1 MiB lines,
// unknown commands, 100 simultaneous clients, stale and live socket files. Every wait is bounded.
#include "ldoem/control_socket/control_server.hpp"

#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "fake_target.hpp"

namespace ldoem::control_socket::test {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

std::string temp_socket_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("ldoem-ctl-test-" + std::to_string(getpid()) + "-" + name)).string();
}

class ServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto loop = io::EventLoop::create();
    ASSERT_TRUE(loop) << loop.error().message();
    loop_ = std::move(*loop);
    path_ = temp_socket_path(::testing::UnitTest::GetInstance()->current_test_info()->name());
    ServerLimits limits;
    limits.max_clients = limits_clients_;
    auto server = ControlServer::open(*loop_, path_, greeting_line("test"),
                                      [this](std::string_view line) { return handle_line(line, target_); }, limits);
    ASSERT_TRUE(server) << server.error().message();
    server_ = std::move(*server);
  }
  void TearDown() override {
    server_.reset();
    EXPECT_FALSE(std::filesystem::exists(path_)) << "the socket file is removed";
  }

  int connect_client() {
    const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path_.c_str(), sizeof(address.sun_path) - 1);
    EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0) << std::strerror(errno);
    return fd;
  }

  void send_all(int fd, const std::string& bytes) {
    std::size_t at = 0;
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (at < bytes.size() && std::chrono::steady_clock::now() < deadline) {
      const ssize_t sent = send(fd, bytes.data() + at, bytes.size() - at, MSG_NOSIGNAL);
      if (sent > 0) at += static_cast<std::size_t>(sent);
      (void)loop_->run_once(1ms);
    }
    ASSERT_EQ(at, bytes.size());
  }

  // Pumps the loop until `fd` has delivered `count` lines (or 10 s pass).
  std::vector<std::string> read_lines(int fd, std::size_t count) {
    std::vector<std::string> lines;
    std::string partial;
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (lines.size() < count && std::chrono::steady_clock::now() < deadline) {
      (void)loop_->run_once(2ms);
      char buffer[4096];
      const ssize_t got = recv(fd, buffer, sizeof(buffer), 0);
      if (got == 0) break;
      if (got < 0) continue;
      partial.append(buffer, static_cast<std::size_t>(got));
      for (std::size_t newline; (newline = partial.find('\n')) != std::string::npos;) {
        lines.push_back(partial.substr(0, newline));
        partial.erase(0, newline + 1);
      }
    }
    return lines;
  }

  std::size_t limits_clients_ = 128;
  std::unique_ptr<io::EventLoop> loop_;
  std::string path_;
  FakeTarget target_;
  std::unique_ptr<ControlServer> server_;
};

TEST_F(ServerTest, SocketIsOnlyForItsOwner) {
  struct stat info {};
  ASSERT_EQ(stat(path_.c_str(), &info), 0);
  EXPECT_TRUE(S_ISSOCK(info.st_mode));
  EXPECT_EQ(info.st_mode & 0777, 0600u);
  EXPECT_EQ(info.st_uid, getuid());
}

TEST_F(ServerTest, GreetsThenAnswersEachLine) {
  const int fd = connect_client();
  auto greeting = read_lines(fd, 1);
  ASSERT_EQ(greeting.size(), 1u);
  EXPECT_TRUE(json::parse(greeting[0]).contains("QMP"));
  send_all(fd, "{\"execute\": \"query-status\", \"id\": 1}\n{\"execute\": \"nope\", \"id\": 2}\n");
  const auto replies = read_lines(fd, 2);
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_EQ(json::parse(replies[0]), json::parse(R"({"return": {"state": "IDLE"}, "id": 1})"));
  EXPECT_EQ(json::parse(replies[1])["error"]["class"], "CommandNotFound");
  close(fd);
}

TEST_F(ServerTest, GarbageAndAHugeLineGetErrorsAndTheServerLives) {
  const int fd = connect_client();
  read_lines(fd, 1);
  std::string garbage;
  for (int i = 0; i < 256; ++i) garbage += static_cast<char>(i == '\n' ? 'x' : i);
  send_all(fd, garbage + "\n");
  send_all(fd, std::string(1024 * 1024, '{') + "\n");
  send_all(fd, "{\"execute\": \"query-status\"}\n");
  const auto replies = read_lines(fd, 3);
  ASSERT_EQ(replies.size(), 3u);
  EXPECT_EQ(json::parse(replies[0])["error"]["class"], "GenericError");
  EXPECT_NE(replies[1].find("line longer than"), std::string::npos) << replies[1];
  EXPECT_EQ(json::parse(replies[2])["return"]["state"], "IDLE");
  close(fd);
}

TEST_F(ServerTest, HundredSimultaneousClientsEachGetTheirError) {
  std::vector<int> fds;
  for (int i = 0; i < 100; ++i) fds.push_back(connect_client());
  for (int fd : fds) ASSERT_EQ(read_lines(fd, 1).size(), 1u);
  EXPECT_EQ(server_->client_count(), 100u);
  for (std::size_t i = 0; i < fds.size(); ++i) {
    send_all(fds[i], "{\"execute\": \"bogus-" + std::to_string(i) + "\", \"id\": " + std::to_string(i) + "}\n");
  }
  for (std::size_t i = 0; i < fds.size(); ++i) {
    const auto reply = read_lines(fds[i], 1);
    ASSERT_EQ(reply.size(), 1u) << i;
    const json parsed = json::parse(reply[0]);
    EXPECT_EQ(parsed["id"], i);
    EXPECT_EQ(parsed["error"]["class"], "CommandNotFound");
  }
  for (int fd : fds) close(fd);
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (server_->client_count() > 0 && std::chrono::steady_clock::now() < deadline) (void)loop_->run_once(2ms);
  EXPECT_EQ(server_->client_count(), 0u);
}

TEST_F(ServerTest, EventsGoToEveryClient) {
  const int a = connect_client();
  const int b = connect_client();
  read_lines(a, 1);
  read_lines(b, 1);
  server_->broadcast(event_line("FAULT_INJECTED", {{"id", 1}}, 1s));
  for (int fd : {a, b}) {
    const auto lines = read_lines(fd, 1);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(json::parse(lines[0])["event"], "FAULT_INJECTED");
  }
  close(a);
  close(b);
}

TEST(ControlServerOpen, LiveSocketIsRefusedStaleOneReplacedOtherFilesKept) {
  auto loop = io::EventLoop::create();
  ASSERT_TRUE(loop);
  const std::string path = temp_socket_path("live");
  FakeTarget target;
  auto handler = [&target](std::string_view line) { return handle_line(line, target); };
  {
    auto first = ControlServer::open(**loop, path, "{}", handler);
    ASSERT_TRUE(first) << first.error().message();
    auto second = ControlServer::open(**loop, path, "{}", handler);
    ASSERT_FALSE(second);
    EXPECT_NE(second.error().message().find("another daemon"), std::string::npos) << second.error().message();
  }
  // A dead daemon's socket: bound, closed, file left behind.
  {
    const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path.c_str(), sizeof(address.sun_path) - 1);
    ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
    close(fd);
    ASSERT_TRUE(std::filesystem::exists(path));
  }
  {
    auto replaced = ControlServer::open(**loop, path, "{}", handler);
    EXPECT_TRUE(replaced) << replaced.error().message();
  }
  const std::string not_a_socket = temp_socket_path("plain-file");
  { std::ofstream(not_a_socket) << "x"; }
  auto refused = ControlServer::open(**loop, not_a_socket, "{}", handler);
  ASSERT_FALSE(refused);
  EXPECT_TRUE(std::filesystem::exists(not_a_socket)) << "never deletes a file that is not a socket";
  std::filesystem::remove(not_a_socket);
}

}  // namespace
}  // namespace ldoem::control_socket::test
