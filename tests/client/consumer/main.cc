// Drives a real server through the installed C++ client: server info, a session, reset, a step,
// an observation with the wrist wrench, session stats, close; then a scene with food, a task and a
// camera: unpacked RGB, depth and segmentation, the food's pieces and the task score. Exit 0 only if
// every check holds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <culinarycut/client.h>

namespace {
int failures = 0;
void Expect(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "consumer: FAILED: %s\n", what);
    ++failures;
  }
}

// What the Python client reads from a cutting scene, read here through the C++ structs.
void CheckFoodTaskAndCamera(culinarycut::client::Client& client) {
  culinarycut::v1::SceneSpec scene;
  scene.set_quality("draft");
  scene.mutable_effects()->set_mpm(true);
  scene.mutable_effects()->set_damage(true);
  scene.mutable_effects()->set_topology(true);
  scene.mutable_effects()->set_force_sensing(true);
  scene.add_objects()->set_food("cucumber");
  scene.mutable_task()->set_instruction("cut the cucumber at the middle");
  culinarycut::v1::CameraSpec* camera = scene.add_cameras();
  camera->set_name("front");
  camera->set_width(64);
  camera->set_height(48);
  for (const char* channel : {"rgb", "depth", "segmentation"}) camera->add_channels(channel);
  auto session = client.CreateSession(scene);
  const culinarycut::client::Observation start = session->Reset(/*seed=*/0);
  Expect(start.instruction == "cut the cucumber at the middle", "the observation carries the instruction");
  Expect(start.food.has_value() && start.food->pieces.size() == 1, "the uncut cucumber is one piece");
  if (start.food && !start.food->pieces.empty()) {
    Expect(start.food->pieces[0].volume_m3 > 0.0 && start.food->pieces[0].particles > 0, "the piece has volume");
  }
  Expect(start.cameras.size() == 1, "one camera");
  if (!start.cameras.empty()) {
    const culinarycut::client::CameraImage& image = start.cameras[0];
    Expect(image.width == 64 && image.height == 48, "the camera's size");
    Expect(image.rgb.size() == 64u * 48u * 3u, "raw RGB unpacked to height x width x 3");
    Expect(image.depth_m.size() == 64u * 48u, "depth unpacked to height x width");
    Expect(image.segmentation.size() == 64u * 48u, "segmentation unpacked to height x width");
    const bool depth_sane = std::all_of(image.depth_m.begin(), image.depth_m.end(),
                                        [](float d) { return std::isfinite(d) && d >= 0.0f && d < 10.0f; });
    Expect(depth_sane, "depth is finite metres");
    Expect(std::any_of(image.depth_m.begin(), image.depth_m.end(), [](float d) { return d > 0.0f; }),
           "the camera sees the scene");
    Expect(std::any_of(image.rgb.begin(), image.rgb.end(), [](std::uint8_t c) { return c != 0; }), "RGB is not blank");
    Expect(!start.segmentation_labels.empty(), "segmentation labels come with the image");
  }
  const culinarycut::client::StepResult step = session->Step("pd_ee_delta_pose", {0.0, 0.0, 0.0, 0.0, 0.0, 0.0});
  Expect(step.task_score.has_value() && !step.success && step.reward == 0.0, "an uncut task scores, not done");
  session->Close();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer HOST:PORT\n");
    return 2;
  }
  try {
    culinarycut::client::Client client(argv[1]);
    Expect(client.WaitForServer(std::chrono::seconds(10)), "the server answers");
    Expect(client.GetServerInfo().protocol() == "culinarycut.v1", "the protocol is culinarycut.v1");
    auto session = client.CreateSession();
    const culinarycut::client::Observation start = session->Reset(/*seed=*/0);
    Expect(start.frame_id == 0 && start.qpos.size() == 7, "reset gives frame 0 and 7 joints");
    const culinarycut::client::StepResult step = session->Step("pd_ee_delta_pose", {0.0, 0.0, -0.1, 0.0, 0.0, 0.0});
    Expect(step.observation.frame_id == 1, "a step advances the frame");
    Expect(step.observation.wrist_wrench.size() == 6, "the wrist wrench has 6 values");
    Expect(!step.task_score.has_value() && !step.success, "no task, no score");
    Expect(session->GetSessionStats().stage_calls().at("physics") == 1, "session stats count the step");
    try {
      session->Step("pd_no_such_mode", {});
      Expect(false, "an unknown mode is refused");
    } catch (const culinarycut::client::RpcError& error) {
      Expect(error.code() == grpc::StatusCode::INVALID_ARGUMENT &&
                 error.details().find("action.control_mode") != std::string::npos,
             "an unknown mode is INVALID_ARGUMENT naming action.control_mode");
    }
    session->Close();
    CheckFoodTaskAndCamera(client);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "consumer: %s\n", error.what());
    return 1;
  }
  std::printf("consumer: %s\n", failures == 0 ? "all checks passed" : "some checks failed");
  return failures == 0 ? 0 : 1;
}
