#include "server/telemetry_publisher.h"

namespace culinarycut::server {

TelemetryPublisher::TelemetryPublisher(const std::string& endpoint) : socket_(context_, zmq::socket_type::pub) {
  std::string bind_to = endpoint;
  // ZeroMQ spells "any free port" as '*'.
  if (bind_to.size() > 2 && bind_to.compare(bind_to.size() - 2, 2, ":0") == 0) bind_to.replace(bind_to.size() - 1, 1, "*");
  socket_.set(zmq::sockopt::linger, 0);
  socket_.set(zmq::sockopt::sndhwm, 1000);
  socket_.bind(bind_to);
  endpoint_ = socket_.get(zmq::sockopt::last_endpoint);
}

void TelemetryPublisher::Publish(const std::string& topic, const v1::TelemetryFrame& frame) {
  const std::string payload = frame.SerializeAsString();
  std::lock_guard<std::mutex> lock(mutex_);
  socket_.send(zmq::buffer(topic), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
  socket_.send(zmq::buffer(payload), zmq::send_flags::dontwait);
}

}  // namespace culinarycut::server
