// The gate in front of gRPC: relays bytes both ways unchanged (with half-closes), caps connections
// per client address and in all, and fails at start on a taken port.
#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "server/connection_gate.h"

using culinarycut::server::ConnectionGate;
using culinarycut::server::ConnectionLimits;

namespace {

// A unix-socket echo server standing in for gRPC: echoes each connection until its end of stream, or
// with `hang_up` closes each at once (as gRPC does at its handshake timeout).
class EchoBackend {
 public:
  explicit EchoBackend(const std::string& address, bool hang_up = false) {
    listener_ = socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un path{};
    path.sun_family = AF_UNIX;
    std::strncpy(path.sun_path, address.substr(5).c_str(), sizeof path.sun_path - 1);  // after "unix:"
    REQUIRE(bind(listener_, reinterpret_cast<sockaddr*>(&path), sizeof path) == 0);
    REQUIRE(listen(listener_, 64) == 0);
    thread_ = std::thread([this, hang_up] {
      for (;;) {
        const int connection = accept(listener_, nullptr, nullptr);
        if (connection < 0) return;
        if (hang_up) {
          close(connection);
          continue;
        }
        echoes_.emplace_back([connection] {
          char buffer[4096];
          ssize_t got = 0;
          while ((got = read(connection, buffer, sizeof buffer)) > 0) {
            for (ssize_t sent = 0; sent < got;) sent += write(connection, buffer + sent, got - sent);
          }
          close(connection);
        });
      }
    });
  }
  ~EchoBackend() {
    shutdown(listener_, SHUT_RDWR);
    close(listener_);
    thread_.join();
    for (std::thread& echo : echoes_) echo.join();
  }

 private:
  int listener_ = -1;
  std::thread thread_;
  std::vector<std::thread> echoes_;
};

int ConnectTo(int port, const char* from = "127.0.0.1") {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in source{};
  source.sin_family = AF_INET;
  inet_pton(AF_INET, from, &source.sin_addr);
  REQUIRE(bind(fd, reinterpret_cast<sockaddr*>(&source), sizeof source) == 0);
  sockaddr_in target{};
  target.sin_family = AF_INET;
  target.sin_port = htons(static_cast<std::uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &target.sin_addr);
  REQUIRE(connect(fd, reinterpret_cast<sockaddr*>(&target), sizeof target) == 0);
  timeval five_s{5, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &five_s, sizeof five_s);
  return fd;
}

// True when the gate closed the connection (end of stream or reset) instead of relaying it.
bool ClosedByGate(int fd) {
  const char ping = 'x';
  send(fd, &ping, 1, MSG_NOSIGNAL);
  char echoed = 0;
  return recv(fd, &echoed, 1, 0) <= 0;
}

}  // namespace

TEST_CASE("the gate relays megabytes both ways unchanged and passes a half-close on", "[server][gate]") {
  ConnectionGate gate("127.0.0.1:0", ConnectionLimits{});
  EchoBackend backend(gate.backend_address());
  gate.Start();
  const int client = ConnectTo(gate.port());
  std::vector<char> sent(4 << 20);
  std::mt19937 random(7);
  for (char& byte : sent) byte = static_cast<char>(random());
  // Write from one thread while reading in this one: with both directions full a relay that blocked
  // on either would deadlock here.
  std::thread writer([&] {
    for (size_t at = 0; at < sent.size();) at += static_cast<size_t>(write(client, sent.data() + at, sent.size() - at));
    shutdown(client, SHUT_WR);  // the echo sees end of stream, closes, and the gate closes us
  });
  std::vector<char> received;
  char buffer[65536];
  ssize_t got = 0;
  while ((got = read(client, buffer, sizeof buffer)) > 0) received.insert(received.end(), buffer, buffer + got);
  writer.join();
  CHECK(got == 0);  // an orderly end of stream, not a timeout
  CHECK(received == sent);
  close(client);
  gate.Stop();
  CHECK(gate.counts().relayed == 1);
}

TEST_CASE("when gRPC hangs up, the gate closes the client's side too and frees its slot", "[server][gate]") {
  ConnectionGate gate("127.0.0.1:0", ConnectionLimits{});
  EchoBackend backend(gate.backend_address(), /*hang_up=*/true);
  gate.Start();
  const int silent = ConnectTo(gate.port());  // never sends a byte, never closes
  char byte = 0;
  CHECK(recv(silent, &byte, 1, 0) == 0);  // an end of stream, not the 5 s receive timeout
  for (int attempt = 0; attempt < 50 && gate.counts().open > 0; ++attempt) usleep(10'000);
  CHECK(gate.counts().open == 0);
  close(silent);
  gate.Stop();
}

TEST_CASE("connections past the per-address cap are closed, other addresses still served", "[server][gate]") {
  ConnectionGate gate("127.0.0.1:0", ConnectionLimits{4, 2});
  EchoBackend backend(gate.backend_address());
  gate.Start();
  const int first = ConnectTo(gate.port(), "127.0.0.2");
  const int second = ConnectTo(gate.port(), "127.0.0.2");
  CHECK_FALSE(ClosedByGate(first));
  CHECK_FALSE(ClosedByGate(second));
  const int third = ConnectTo(gate.port(), "127.0.0.2");
  CHECK(ClosedByGate(third));
  const int elsewhere = ConnectTo(gate.port(), "127.0.0.3");
  CHECK_FALSE(ClosedByGate(elsewhere));
  const int fourth_address = ConnectTo(gate.port(), "127.0.0.4");
  CHECK_FALSE(ClosedByGate(fourth_address));
  const int past_total = ConnectTo(gate.port(), "127.0.0.5");
  CHECK(ClosedByGate(past_total));  // 4 open: the total cap
  close(first);
  bool served_again = false;  // the gate sees the close on its next wake-up
  for (int attempt = 0; attempt < 50 && !served_again; ++attempt) {
    const int again = ConnectTo(gate.port(), "127.0.0.2");
    served_again = !ClosedByGate(again);
    close(again);
    if (!served_again) usleep(20'000);
  }
  CHECK(served_again);
  for (const int fd : {second, third, elsewhere, fourth_address, past_total}) close(fd);
  gate.Stop();
  CHECK(gate.counts().refused_address_cap >= 1);
  CHECK(gate.counts().refused_total_cap >= 1);
}

TEST_CASE("a taken port fails at start, naming it", "[server][gate]") {
  ConnectionGate first("127.0.0.1:0", ConnectionLimits{});
  const std::string taken = "127.0.0.1:" + std::to_string(first.port());
  CHECK_THROWS_WITH(ConnectionGate(taken, ConnectionLimits{}), Catch::Contains("cannot listen on " + taken) &&
                                                                   Catch::Contains("in use"));
  CHECK_THROWS_WITH(ConnectionGate("127.0.0.1:0", ConnectionLimits{0, 1}), Catch::Contains("--max-connections"));
}
