#include "server/connection_gate.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <vector>

#include <spdlog/spdlog.h>

namespace culinarycut::server {

namespace {

constexpr size_t kBufferBytes = 16 * 1024;          // per direction of a relayed connection
constexpr rlim_t kReservedDescriptors = 64;         // gRPC's own, telemetry, files, the renderer
constexpr int kDescriptorsPerConnection = 3;        // client socket, our end to gRPC, gRPC's end
constexpr int kAcceptsPerWake = 64;                 // then serve the relays before accepting more
constexpr int kPumpRoundsPerWake = 8;               // a busy connection yields to the others
constexpr auto kRefusalLogEvery = std::chrono::seconds(10);

// One direction of a relayed connection: bytes read from one socket, not yet written to the other.
struct Direction {
  std::array<char, kBufferBytes> bytes{};
  size_t begin = 0;
  size_t end = 0;
  bool eof = false;       // the source sent FIN
  bool shut = false;      // and gRPC has been told (shutdown SHUT_WR)
  bool empty() const { return begin == end; }
  bool full() const { return end == bytes.size(); }
};

struct Relay {
  int client = -1;
  int backend = -1;
  std::string address;
  Direction up;    // client -> gRPC
  Direction down;  // gRPC -> client
  bool failed = false;
  std::uint32_t client_events = 0;
  std::uint32_t backend_events = 0;
};

std::string ErrnoText() { return std::strerror(errno); }

// The client's IP address as text; IPv4-mapped IPv6 addresses count as their IPv4 address.
std::string AddressText(const sockaddr_storage& peer) {
  char text[INET6_ADDRSTRLEN] = {};
  if (peer.ss_family == AF_INET) {
    inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in&>(peer).sin_addr, text, sizeof text);
  } else if (peer.ss_family == AF_INET6) {
    const in6_addr& v6 = reinterpret_cast<const sockaddr_in6&>(peer).sin6_addr;
    if (IN6_IS_ADDR_V4MAPPED(&v6)) {
      inet_ntop(AF_INET, &v6.s6_addr[12], text, sizeof text);
    } else {
      inet_ntop(AF_INET6, &v6, text, sizeof text);
    }
  }
  return text;
}

// "host:port", "[v6]:port", "ipv4:host:port" -> host (empty: every interface) and port.
std::pair<std::string, std::string> SplitHostPort(std::string address) {
  for (const char* scheme : {"ipv4:", "ipv6:", "dns:"}) {
    if (address.rfind(scheme, 0) == 0) address = address.substr(std::strlen(scheme));
  }
  const size_t colon = address.rfind(':');
  std::string host = address.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  return {host, address.substr(colon + 1)};
}

// Listening sockets for every address `host` resolves to, all on one port (the first's when 0).
std::vector<int> BindListeners(const std::string& listen_address, int& port) {
  auto [host, port_text] = SplitHostPort(listen_address);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (const int code = getaddrinfo(host.empty() ? nullptr : host.c_str(), port_text.c_str(), &hints, &found)) {
    throw std::runtime_error("cannot listen on " + listen_address + ": " + gai_strerror(code) +
                             "; pick another with --listen, e.g. 127.0.0.1:0");
  }
  bool has_v4 = false;
  for (addrinfo* entry = found; entry; entry = entry->ai_next) has_v4 |= entry->ai_family == AF_INET;
  std::vector<int> listeners;
  std::string last_error;
  port = std::atoi(port_text.c_str());
  for (addrinfo* entry = found; entry; entry = entry->ai_next) {
    sockaddr_storage bind_address{};
    std::memcpy(&bind_address, entry->ai_addr, entry->ai_addrlen);
    if (entry->ai_family == AF_INET) reinterpret_cast<sockaddr_in&>(bind_address).sin_port = htons(port);
    if (entry->ai_family == AF_INET6) reinterpret_cast<sockaddr_in6&>(bind_address).sin6_port = htons(port);
    const int fd = socket(entry->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
      last_error = ErrnoText();
      continue;
    }
    const int on = 1;
    // Restart right after a stop (TIME_WAIT); no SO_REUSEPORT: a second server on a taken port must fail.
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    // "[::]" alone takes IPv4 too, as gRPC does; beside an IPv4 address each family binds its own.
    const int v6_only = has_v4 ? 1 : 0;
    if (entry->ai_family == AF_INET6) setsockopt(fd, IPPROTO_IPV6, IPV6_V6ONLY, &v6_only, sizeof v6_only);
    if (bind(fd, reinterpret_cast<sockaddr*>(&bind_address), entry->ai_addrlen) != 0 || listen(fd, SOMAXCONN) != 0) {
      last_error = ErrnoText();
      const bool in_use = errno == EADDRINUSE;
      close(fd);
      if (in_use) {
        for (const int open : listeners) close(open);
        freeaddrinfo(found);
        throw std::runtime_error("cannot listen on " + listen_address + " (port in use: " + last_error +
                                 "); pick another with --listen, e.g. 127.0.0.1:0");
      }
      continue;  // e.g. ::1 on a machine without IPv6: the other addresses still serve
    }
    if (port == 0) {
      sockaddr_storage bound{};
      socklen_t length = sizeof bound;
      getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length);
      port = ntohs(bound.ss_family == AF_INET ? reinterpret_cast<sockaddr_in&>(bound).sin_port
                                              : reinterpret_cast<sockaddr_in6&>(bound).sin6_port);
    }
    listeners.push_back(fd);
  }
  freeaddrinfo(found);
  if (listeners.empty()) {
    throw std::runtime_error("cannot listen on " + listen_address + " (address invalid: " + last_error +
                             "); pick another with --listen, e.g. 127.0.0.1:0");
  }
  return listeners;
}

// The caps the descriptor limit can carry: three descriptors per connection past a reserve.
ConnectionLimits FitToDescriptors(ConnectionLimits limits) {
  rlimit files{};
  if (getrlimit(RLIMIT_NOFILE, &files) != 0 || files.rlim_cur == RLIM_INFINITY) return limits;
  const rlim_t room = files.rlim_cur > 2 * kReservedDescriptors ? files.rlim_cur - kReservedDescriptors
                                                                 : files.rlim_cur / 2;
  const auto fits = static_cast<std::uint32_t>(room / kDescriptorsPerConnection);
  if (limits.max_connections > fits) {
    spdlog::warn("at most {} connections, not {}: the descriptor limit is {} and each takes {} (raise it with "
                 "ulimit -n or LimitNOFILE=)", fits, limits.max_connections, files.rlim_cur,
                 kDescriptorsPerConnection);
    limits.max_connections = fits;
  }
  if (limits.max_per_address > limits.max_connections) limits.max_per_address = limits.max_connections;
  return limits;
}

}  // namespace

// The relay thread's state; only that thread touches it, except `counts` (under `mutex`) and `wake`.
struct ConnectionGate::Loop {
  ConnectionLimits limits;
  std::string backend_path;
  std::vector<int> listeners;
  bool listeners_armed = true;
  int epoll = -1;
  int wake = -1;            // eventfd: StopAccepting and Stop
  int spare = -1;           // given up to accept (and drop) one connection when descriptors run out
  std::atomic<bool> stop_accepting{false};
  std::atomic<bool> stop{false};
  std::unordered_map<int, Relay*> relays;  // both sockets of each relay
  std::map<std::string, std::uint32_t> per_address;
  mutable std::mutex mutex;
  ConnectionCounts counts;
  std::chrono::steady_clock::time_point last_refusal_log{};
  std::chrono::steady_clock::time_point rearm_at{};

  void Run();
  void AcceptFrom(int listener);
  void Admit(int client, const std::string& address);
  void Refuse(int client, const std::string& address, std::uint64_t ConnectionCounts::*counter, const char* why);
  void Pump(Relay& relay);
  void Watch(Relay& relay);
  void Close(Relay* relay);
  void CloseListeners();
  void SetListenersArmed(bool armed);
};

ConnectionGate::ConnectionGate(const std::string& listen_address, ConnectionLimits limits)
    : limits_(FitToDescriptors(limits)), loop_(std::make_unique<Loop>()) {
  if (limits.max_connections == 0 || limits.max_per_address == 0) {
    throw std::runtime_error("--max-connections and --max-connections-per-address must be at least 1");
  }
  loop_->limits = limits_;
  loop_->listeners = BindListeners(listen_address, port_);
  // gRPC's socket lives in a directory only this user can enter, so nobody else can bypass the caps.
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp && std::strlen(tmp) < 64 ? tmp : "/tmp") + "/culinarycut-server.XXXXXX";
  if (!mkdtemp(pattern.data())) {
    for (const int fd : loop_->listeners) close(fd);
    throw std::runtime_error("cannot make a private directory for gRPC's socket (" + pattern + "): " + ErrnoText());
  }
  backend_dir_ = pattern;
  loop_->backend_path = backend_dir_ + "/grpc.sock";
  backend_address_ = "unix:" + loop_->backend_path;
  loop_->epoll = epoll_create1(EPOLL_CLOEXEC);
  loop_->wake = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  loop_->spare = open("/dev/null", O_RDONLY | O_CLOEXEC);
}

ConnectionGate::~ConnectionGate() {
  Stop();
  for (const int fd : loop_->listeners) close(fd);
  for (const int fd : {loop_->epoll, loop_->wake, loop_->spare}) {
    if (fd >= 0) close(fd);
  }
  unlink(loop_->backend_path.c_str());
  rmdir(backend_dir_.c_str());
}

void ConnectionGate::Start() {
  epoll_event event{};
  event.events = EPOLLIN;
  event.data.fd = loop_->wake;
  epoll_ctl(loop_->epoll, EPOLL_CTL_ADD, loop_->wake, &event);
  loop_->SetListenersArmed(true);
  thread_ = std::thread([loop = loop_.get()] { loop->Run(); });
}

void ConnectionGate::StopAccepting() {
  loop_->stop_accepting = true;
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = write(loop_->wake, &one, sizeof one);
  if (!thread_.joinable()) loop_->CloseListeners();
}

void ConnectionGate::Stop() {
  if (!thread_.joinable()) return;
  loop_->stop = true;
  StopAccepting();
  thread_.join();
  const ConnectionCounts done = counts();
  spdlog::info("connections: {} relayed; refused {} at --max-connections, {} at --max-connections-per-address, "
               "{} out of descriptors, {} by gRPC's socket", done.relayed, done.refused_total_cap,
               done.refused_address_cap, done.refused_no_descriptor, done.refused_backend);
}

ConnectionCounts ConnectionGate::counts() const {
  std::lock_guard<std::mutex> lock(loop_->mutex);
  return loop_->counts;
}

void ConnectionGate::Loop::Run() {
  std::array<epoll_event, 64> events{};
  while (!stop) {
    if (stop_accepting) CloseListeners();
    // Listeners paused after running out of descriptors come back after 100 ms.
    int timeout_ms = -1;
    if (!listeners_armed && !listeners.empty()) {
      const auto now = std::chrono::steady_clock::now();
      if (now >= rearm_at) {
        SetListenersArmed(true);
      } else {
        timeout_ms = static_cast<int>(std::chrono::ceil<std::chrono::milliseconds>(rearm_at - now).count());
      }
    }
    const int ready = epoll_wait(epoll, events.data(), static_cast<int>(events.size()), timeout_ms);
    for (int i = 0; i < ready; ++i) {
      const int fd = events[i].data.fd;
      if (fd == wake) {
        std::uint64_t drained = 0;
        [[maybe_unused]] const ssize_t read_bytes = read(wake, &drained, sizeof drained);
        continue;
      }
      if (const auto relay = relays.find(fd); relay != relays.end()) {
        Pump(*relay->second);
        continue;
      }
      // A listener; anything else is a relay closed earlier in this batch.
      if (std::find(listeners.begin(), listeners.end(), fd) != listeners.end()) AcceptFrom(fd);
    }
  }
  std::vector<Relay*> open;
  for (const auto& [fd, relay] : relays) {
    if (fd == relay->client) open.push_back(relay);
  }
  for (Relay* relay : open) Close(relay);
  CloseListeners();
}

void ConnectionGate::Loop::AcceptFrom(int listener) {
  for (int i = 0; i < kAcceptsPerWake && listeners_armed; ++i) {
    sockaddr_storage peer{};
    socklen_t length = sizeof peer;
    const int client = accept4(listener, reinterpret_cast<sockaddr*>(&peer), &length, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (client >= 0) {
      Admit(client, AddressText(peer));
      continue;
    }
    if (errno == EINTR || errno == ECONNABORTED || errno == EPROTO) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return;
    if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
      // No descriptor to take the connection with: free the spare, take it, drop it, get the spare back.
      if (spare >= 0) {
        close(spare);
        const int shed = accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
        spare = open("/dev/null", O_RDONLY | O_CLOEXEC);
        if (shed >= 0) {
          Refuse(shed, "", &ConnectionCounts::refused_no_descriptor, "out of descriptors");
          continue;
        }
      }
      // Not even that: stop listening for 100 ms rather than spin on a listener that stays readable.
      rearm_at = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
      SetListenersArmed(false);
      return;
    }
    spdlog::warn("accept4 on the gRPC port failed: {}", ErrnoText());
    return;
  }
}

void ConnectionGate::Loop::Refuse(int client, const std::string& address,
                                  std::uint64_t ConnectionCounts::*counter, const char* why) {
  close(client);
  std::uint64_t refused = 0;
  {
    std::lock_guard<std::mutex> lock(mutex);
    ++(counts.*counter);
    refused = counts.refused_total_cap + counts.refused_address_cap + counts.refused_no_descriptor +
              counts.refused_backend;
  }
  const auto now = std::chrono::steady_clock::now();
  if (now - last_refusal_log >= kRefusalLogEvery) {
    last_refusal_log = now;
    spdlog::warn("refused a connection{}{}: {} ({} refused so far, {} open)", address.empty() ? "" : " from ",
                 address, why, refused, relays.size() / 2);
  }
}

void ConnectionGate::Loop::Admit(int client, const std::string& address) {
  if (relays.size() / 2 >= limits.max_connections) {
    Refuse(client, address, &ConnectionCounts::refused_total_cap, "--max-connections reached");
    return;
  }
  std::uint32_t& from_address = per_address[address];
  if (from_address >= limits.max_per_address) {
    Refuse(client, address, &ConnectionCounts::refused_address_cap, "--max-connections-per-address reached");
    return;
  }
  const int backend = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  sockaddr_un path{};
  path.sun_family = AF_UNIX;
  std::strncpy(path.sun_path, backend_path.c_str(), sizeof path.sun_path - 1);
  if (backend < 0 || connect(backend, reinterpret_cast<sockaddr*>(&path), sizeof path) != 0) {
    if (backend >= 0) close(backend);
    if (from_address == 0) per_address.erase(address);
    Refuse(client, address, &ConnectionCounts::refused_backend, "gRPC's socket did not take it");
    return;
  }
  // gRPC sets this on its own sockets; a relay without it would hold back small frames.
  const int on = 1;
  setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
  ++from_address;
  auto* relay = new Relay();
  relay->client = client;
  relay->backend = backend;
  relay->address = address;
  relays[client] = relay;
  relays[backend] = relay;
  for (const int fd : {client, backend}) {
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.fd = fd;
    epoll_ctl(epoll, EPOLL_CTL_ADD, fd, &event);
  }
  relay->client_events = relay->backend_events = EPOLLIN;
  std::lock_guard<std::mutex> lock(mutex);
  ++counts.relayed;
  counts.open = static_cast<std::uint32_t>(relays.size() / 2);
}

namespace {

// Reads what `from` has into `direction`; true when something happened (bytes or end of stream).
bool ReadInto(int from, Direction& direction, bool& failed) {
  if (direction.eof || direction.full()) return false;
  for (;;) {
    const ssize_t got = read(from, direction.bytes.data() + direction.end, direction.bytes.size() - direction.end);
    if (got > 0) {
      direction.end += static_cast<size_t>(got);
      return true;
    }
    if (got == 0) {
      direction.eof = true;
      return true;
    }
    if (errno == EINTR) continue;
    if (errno != EAGAIN && errno != EWOULDBLOCK) failed = true;
    return false;
  }
}

// Writes what `direction` holds to `to`; true when bytes went out.
bool WriteFrom(Direction& direction, int to, bool& failed) {
  if (direction.empty()) return false;
  for (;;) {
    const ssize_t sent = send(to, direction.bytes.data() + direction.begin, direction.end - direction.begin,
                              MSG_NOSIGNAL);
    if (sent > 0) {
      direction.begin += static_cast<size_t>(sent);
      if (direction.empty()) direction.begin = direction.end = 0;
      return true;
    }
    if (sent < 0 && errno == EINTR) continue;
    if (sent < 0 && errno != EAGAIN && errno != EWOULDBLOCK) failed = true;
    return false;
  }
}

// Passes the client's FIN on to gRPC once its bytes are out.
void PassOnEnd(Direction& direction, int to) {
  if (direction.eof && direction.empty() && !direction.shut) {
    shutdown(to, SHUT_WR);
    direction.shut = true;
  }
}

}  // namespace

void ConnectionGate::Loop::Pump(Relay& relay) {
  for (int round = 0; round < kPumpRoundsPerWake && !relay.failed; ++round) {
    bool moved = ReadInto(relay.client, relay.up, relay.failed);
    moved |= WriteFrom(relay.up, relay.backend, relay.failed);
    moved |= ReadInto(relay.backend, relay.down, relay.failed);
    moved |= WriteFrom(relay.down, relay.client, relay.failed);
    if (!moved) break;
  }
  PassOnEnd(relay.up, relay.backend);
  // gRPC closing its end ends the connection: waiting for the client's own close would let a silent
  // client keep its slot after gRPC's handshake or idle timeout dropped it.
  const bool backend_done = relay.down.eof && relay.down.empty();
  if (relay.failed || backend_done) {
    Close(&relay);
    return;
  }
  Watch(relay);
}

// Waits on each socket for what its relay can do next: read while there is room, write while there are bytes.
void ConnectionGate::Loop::Watch(Relay& relay) {
  const auto want = [](const Direction& incoming, const Direction& outgoing) {
    std::uint32_t events = 0;
    if (!incoming.eof && !incoming.full()) events |= EPOLLIN;
    if (!outgoing.empty()) events |= EPOLLOUT;
    return events;
  };
  const std::uint32_t client_events = want(relay.up, relay.down);
  const std::uint32_t backend_events = want(relay.down, relay.up);
  for (auto [fd, events, current] : {std::tuple{relay.client, client_events, &relay.client_events},
                                     std::tuple{relay.backend, backend_events, &relay.backend_events}}) {
    if (events == *current) continue;
    epoll_event event{};
    event.events = events;
    event.data.fd = fd;
    epoll_ctl(epoll, EPOLL_CTL_MOD, fd, &event);
    *current = events;
  }
}

void ConnectionGate::Loop::Close(Relay* relay) {
  for (const int fd : {relay->client, relay->backend}) {
    epoll_ctl(epoll, EPOLL_CTL_DEL, fd, nullptr);
    relays.erase(fd);
    close(fd);
  }
  if (auto count = per_address.find(relay->address); count != per_address.end() && --count->second == 0) {
    per_address.erase(count);
  }
  delete relay;
  std::lock_guard<std::mutex> lock(mutex);
  counts.open = static_cast<std::uint32_t>(relays.size() / 2);
}

void ConnectionGate::Loop::CloseListeners() {
  for (const int fd : listeners) {
    epoll_ctl(epoll, EPOLL_CTL_DEL, fd, nullptr);
    close(fd);
  }
  listeners.clear();
}

void ConnectionGate::Loop::SetListenersArmed(bool armed) {
  for (const int fd : listeners) {
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.fd = fd;
    epoll_ctl(epoll, armed ? EPOLL_CTL_ADD : EPOLL_CTL_DEL, fd, &event);
  }
  listeners_armed = armed;
}

}  // namespace culinarycut::server
