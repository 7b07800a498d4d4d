// Streams one TelemetryFrame per step on a ZeroMQ PUB socket, under the session's telemetry topic
// (Session::telemetry_topic, told only to its creator), for viewers and recorders. Sending never blocks a
// step: slow subscribers lose frames, not the simulation.
#pragma once

#include <memory>
#include <mutex>
#include <string>

#include <zmq.hpp>

#include "culinarycut/v1/simulator.pb.h"

namespace culinarycut::server {

class TelemetryPublisher {
 public:
  // Binds `endpoint` (e.g. tcp://127.0.0.1:5556; port 0 picks a free one). Throws zmq::error_t.
  explicit TelemetryPublisher(const std::string& endpoint);
  // The endpoint actually bound, with the real port.
  const std::string& endpoint() const { return endpoint_; }
  void Publish(const std::string& topic, const v1::TelemetryFrame& frame);

 private:
  zmq::context_t context_{1};
  zmq::socket_t socket_;
  std::string endpoint_;
  std::mutex mutex_;  // ZeroMQ sockets are not thread-safe; sessions publish from many threads
};

}  // namespace culinarycut::server
