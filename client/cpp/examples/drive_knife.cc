// Example: connect, create a session, lower the knife onto the cutting board and back, printing
// what the server reports. Usage: drive_knife [host:port]
#include <cmath>
#include <cstdio>

#include "culinarycut/client.h"

int main(int argc, char** argv) {
  const std::string address = argc > 1 ? argv[1] : "127.0.0.1:50051";
  try {
    culinarycut::client::Client client(address);
    if (!client.WaitForServer(std::chrono::seconds(5))) {
      std::fprintf(stderr, "drive_knife: no CulinaryCut server answers at %s; start one with culinarycut-server\n",
                   address.c_str());
      return 1;
    }
    const culinarycut::v1::ServerInfo info = client.GetServerInfo();
    std::printf("server %s (build %s)\n", info.version().c_str(), info.build_id().c_str());
    auto session = client.CreateSession();
    culinarycut::client::Observation observation = session->Reset(/*seed=*/0);
    std::printf("session %s, knife TCP at (%.3f, %.3f, %.3f) m\n", session->id().c_str(), observation.tcp_pose[0],
                observation.tcp_pose[1], observation.tcp_pose[2]);
    // Above the board centre, knife edge down, then 4 cm lower, then back up.
    const double above_board[7] = {0.5, 0.0, 0.15, 0.0, 1.0, 0.0, 0.0};
    for (double height : {0.15, 0.06, 0.15}) {
      std::vector<double> target(above_board, above_board + 7);
      target[2] = height;
      for (int step = 0; step < 40; ++step) observation = session->Step("pd_ee_pose_quat", target).observation;
      const double error_mm = 1000.0 * std::sqrt(std::pow(observation.tcp_pose[0] - target[0], 2) +
                                                  std::pow(observation.tcp_pose[1] - target[1], 2) +
                                                  std::pow(observation.tcp_pose[2] - target[2], 2));
      std::printf("frame %4llu  t=%5.2f s  TCP (%.4f, %.4f, %.4f) m  error %.2f mm\n",
                  static_cast<unsigned long long>(observation.frame_id), observation.sim_time, observation.tcp_pose[0],
                  observation.tcp_pose[1], observation.tcp_pose[2], error_mm);
    }
  } catch (const culinarycut::client::RpcError& error) {
    std::fprintf(stderr, "drive_knife: %s\n", error.what());
    return 1;
  }
  return 0;
}
