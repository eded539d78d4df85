#include "ldoem/io/tcp.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>

#include "ldoem/io/event_loop.hpp"

namespace ldoem::io {
namespace {

using namespace std::chrono_literals;

// Accepts the one connection a test made (the listener is non-blocking: poll via the loop).
std::optional<TcpConnection> accept_one(TcpListener& listener) {
  std::optional<TcpConnection> accepted;
  auto loop = EventLoop::create();
  EXPECT_TRUE(loop);
  EXPECT_TRUE((*loop)->watch(listener.fd(), Interest::readable, [&](Readiness) {
    auto next = listener.accept();
    ASSERT_TRUE(next) << next.error().message();
    if (next->has_value()) {
      accepted.emplace(std::move(**next));
      (*loop)->stop();
    }
  }));
  EXPECT_TRUE((*loop)->run_for(2s));
  return accepted;
}

Received receive_all(TcpConnection& connection, std::size_t count) {
  Received all;
  auto loop = EventLoop::create();
  EXPECT_TRUE(loop);
  EXPECT_TRUE((*loop)->watch(connection.fd(), Interest::readable, [&](Readiness) {
    auto received = connection.receive();
    ASSERT_TRUE(received) << received.error().message();
    all.bytes.insert(all.bytes.end(), received->bytes.begin(), received->bytes.end());
    all.peer_closed = all.peer_closed || received->peer_closed;
    if (all.bytes.size() >= count || all.peer_closed) {
      (*loop)->stop();
    }
  }));
  EXPECT_TRUE((*loop)->run_for(2s));
  return all;
}

TEST(Tcp, ListenerOnPortZero_BindsLoopbackAndReportsItsPort) {
  auto listener = TcpListener::listen(0);
  ASSERT_TRUE(listener) << listener.error().message();
  EXPECT_NE(listener->port(), 0);
  EXPECT_EQ(listener->address(), "127.0.0.1");
}

TEST(Tcp, AcceptWithNothingPending_GivesNothing) {
  auto listener = TcpListener::listen(0);
  ASSERT_TRUE(listener) << listener.error().message();
  auto accepted = listener->accept();
  ASSERT_TRUE(accepted) << accepted.error().message();
  EXPECT_FALSE(accepted->has_value());
}

TEST(Tcp, BytesBothWays_ArriveUnchanged) {
  auto listener = TcpListener::listen(0);
  ASSERT_TRUE(listener) << listener.error().message();
  auto client = TcpConnection::connect("127.0.0.1", listener->port());
  ASSERT_TRUE(client) << client.error().message();
  auto server = accept_one(*listener);
  ASSERT_TRUE(server.has_value());
  EXPECT_EQ(server->peer().rfind("127.0.0.1:", 0), 0u) << server->peer();

  const protocol::Bytes request{0x02, 0x55, 0x53, 0x50, 0x00, 0x00, 0x00, 0x02, 0x01, 0x01};
  auto sent = client->send(request);
  ASSERT_TRUE(sent) << sent.error().message();
  EXPECT_EQ(*sent, request.size());
  EXPECT_EQ(receive_all(*server, request.size()).bytes, request);

  const protocol::Bytes reply{0x81, 0x01, 0xFF};
  ASSERT_TRUE(server->send(reply));
  EXPECT_EQ(receive_all(*client, reply.size()).bytes, reply);
}

TEST(Tcp, ClientClosing_IsSeenAsPeerClosed) {
  auto listener = TcpListener::listen(0);
  ASSERT_TRUE(listener) << listener.error().message();
  std::optional<TcpConnection> server;
  {
    auto client = TcpConnection::connect("127.0.0.1", listener->port());
    ASSERT_TRUE(client) << client.error().message();
    server = accept_one(*listener);
    ASSERT_TRUE(server.has_value());
  }
  EXPECT_TRUE(receive_all(*server, 1).peer_closed);
}

TEST(Tcp, SendingToAClosedPeer_IsAnErrorNotASignal) {
  auto listener = TcpListener::listen(0);
  ASSERT_TRUE(listener) << listener.error().message();
  auto client = TcpConnection::connect("127.0.0.1", listener->port());
  ASSERT_TRUE(client) << client.error().message();
  { auto server = accept_one(*listener); ASSERT_TRUE(server.has_value()); }
  const protocol::Bytes data(1024, 0xAB);
  bool failed = false;
  for (int attempt = 0; attempt < 100 && !failed; ++attempt) {
    auto sent = client->send(data);
    failed = !sent;
    if (failed) {
      EXPECT_TRUE(sent.error().error_number == EPIPE || sent.error().error_number == ECONNRESET)
          << sent.error().message();
    }
  }
  EXPECT_TRUE(failed);
}

TEST(Tcp, SecondListenerOnTheSamePort_FailsWithAddressInUse) {
  auto first = TcpListener::listen(0);
  ASSERT_TRUE(first) << first.error().message();
  auto second = TcpListener::listen(first->port());
  ASSERT_FALSE(second);
  EXPECT_EQ(second.error().error_number, EADDRINUSE);
  EXPECT_EQ(second.error().message(),
            "bind 127.0.0.1:" + std::to_string(first->port()) + ": Address already in use");
}

TEST(Tcp, ListenerOnAPortOfAClosedListener_RebindsAtOnce) {
  std::uint16_t port = 0;
  {
    auto first = TcpListener::listen(0);
    ASSERT_TRUE(first) << first.error().message();
    port = first->port();
    auto client = TcpConnection::connect("127.0.0.1", port);
    ASSERT_TRUE(client);
    auto server = accept_one(*first);
    ASSERT_TRUE(server.has_value());
  }  // the server side closed first: its connection sits in TIME_WAIT
  auto again = TcpListener::listen(port);
  EXPECT_TRUE(again) << again.error().message();
}

// D11 power_cycle (docs/decisions-local.md L-faults-5): a stopped listener refuses connects but
// keeps its port, also a port the kernel picked, and listens again on it.
TEST(Tcp, StoppedListener_RefusesConnectsKeepsItsPortAndListensAgain) {
  auto listener = TcpListener::listen(0);
  ASSERT_TRUE(listener) << listener.error().message();
  const std::uint16_t port = listener->port();
  ASSERT_TRUE(listener->stop_listening());
  auto refused = TcpConnection::connect("127.0.0.1", port);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().error_number, ECONNREFUSED);
  auto other = TcpListener::listen(port);  // the port is still ours
  ASSERT_FALSE(other);
  EXPECT_EQ(other.error().error_number, EADDRINUSE);
  ASSERT_TRUE(listener->listen_again());
  auto client = TcpConnection::connect("127.0.0.1", port);
  ASSERT_TRUE(client) << client.error().message();
  EXPECT_TRUE(accept_one(*listener).has_value());
}

// D11 tcp_reset: the peer reads a reset, not an end of stream.
TEST(Tcp, ResetOnClose_ThePeerReadsConnectionReset) {
  auto listener = TcpListener::listen(0);
  ASSERT_TRUE(listener) << listener.error().message();
  auto client = TcpConnection::connect("127.0.0.1", listener->port());
  ASSERT_TRUE(client) << client.error().message();
  {
    auto server = accept_one(*listener);
    ASSERT_TRUE(server.has_value());
    ASSERT_TRUE(server->reset_on_close());
  }
  auto loop = EventLoop::create();
  ASSERT_TRUE(loop);
  std::string read = "nothing";
  ASSERT_TRUE((*loop)->watch(client->fd(), Interest::readable, [&](Readiness) {
    auto received = client->receive();
    read = received ? (received->peer_closed ? "end of stream" : "bytes") : received.error().message();
    (*loop)->stop();
  }));
  EXPECT_TRUE((*loop)->run_for(2s));
  EXPECT_EQ(read, "recv " + client->peer() + ": Connection reset by peer");
}

TEST(Tcp, BadAddress_IsReported) {
  auto listener = TcpListener::listen(0, "localhost:1");
  ASSERT_FALSE(listener);
  EXPECT_EQ(listener.error().error_number, EINVAL);
}

TEST(Tcp, ConnectingWhereNobodyListens_IsRefused) {
  std::uint16_t port = 0;
  {
    auto listener = TcpListener::listen(0);
    ASSERT_TRUE(listener);
    port = listener->port();
  }
  auto client = TcpConnection::connect("127.0.0.1", port);
  ASSERT_FALSE(client);
  EXPECT_EQ(client.error().error_number, ECONNREFUSED);
}

}  // namespace
}  // namespace ldoem::io
