// The server's TCP port: accepts every connection itself, refuses those past a total or per-address
// cap, and relays the rest byte for byte to gRPC listening on a private unix socket.
//
// Written here because gRPC 1.51 (Debian 12's) has neither connection caps nor a listener that
// survives EMFILE: its accept loop stops for good the first time accept4 runs out of descriptors.
// The gate holds a spare descriptor to shed connections at that limit and keeps the connections it
// relays below what the descriptor limit allows, so gRPC's own listener never reaches it. TLS passes
// through untouched: gRPC still does the handshake, tokens and client certificates.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

namespace culinarycut::server {

struct ConnectionLimits {
  std::uint32_t max_connections = 1024;  // all addresses together
  std::uint32_t max_per_address = 64;    // one client IP address
};

// What the gate has done since it started (read at shutdown for the log, and by tests).
struct ConnectionCounts {
  std::uint64_t relayed = 0;
  std::uint64_t refused_total_cap = 0;
  std::uint64_t refused_address_cap = 0;
  std::uint64_t refused_no_descriptor = 0;  // accept4 hit EMFILE/ENFILE: shed through the spare descriptor
  std::uint64_t refused_backend = 0;        // gRPC's socket did not take the connection
  std::uint32_t open = 0;
};

class ConnectionGate {
 public:
  // Binds `listen_address` (host:port; [v6]:port; port 0 picks a free one). Throws
  // std::runtime_error naming the address when it cannot. Caps above what the descriptor limit
  // allows (three descriptors per relayed connection) are lowered to it.
  ConnectionGate(const std::string& listen_address, ConnectionLimits limits);
  ~ConnectionGate();
  ConnectionGate(const ConnectionGate&) = delete;
  ConnectionGate& operator=(const ConnectionGate&) = delete;

  int port() const { return port_; }
  const ConnectionLimits& limits() const { return limits_; }
  // A fresh private socket path (in a new 0700 directory) for gRPC to listen on: "unix:/.../grpc.sock".
  const std::string& backend_address() const { return backend_address_; }

  // Starts accepting and relaying to `backend_address()`, where gRPC must already listen.
  void Start();
  // Closes the listening sockets: new connections are refused by the kernel; relays go on.
  void StopAccepting();
  // Closes every relayed connection and waits for the relay thread.
  void Stop();
  ConnectionCounts counts() const;

 private:
  struct Loop;
  ConnectionLimits limits_;
  int port_ = 0;
  std::string backend_dir_;
  std::string backend_address_;
  std::unique_ptr<Loop> loop_;
  std::thread thread_;
};

}  // namespace culinarycut::server
