#include <cmath>
#include <cstdlib>
#include <set>
#include <thread>

#include <catch2/catch.hpp>

#include "sim/render/render_error.h"
#include "sim/render/robot_visuals.h"
#include "tests/sim/render/render_test_scenes.h"

namespace culinarycut::render {
namespace {

using testing::MakeParticleBlock;
using testing::PandaLinkPoses;
using testing::ReadyPose;
using testing::SharedRenderer;

CameraSpec Camera(const std::string& name, const Eigen::Isometry3d& pose, int width, int height) {
  CameraSpec camera;
  camera.name = name;
  camera.pose_in_world = pose;
  camera.width = width;
  camera.height = height;
  camera.fov_y_deg = 60.0;
  camera.rgb = true;
  camera.depth = true;
  camera.segmentation = true;
  return camera;
}

template <typename T>
T At(const std::vector<T>& image, int width, const Eigen::Vector2d& pixel) {
  const int u = static_cast<int>(std::lround(pixel.x())), v = static_cast<int>(std::lround(pixel.y()));
  return image[static_cast<std::size_t>(v) * width + u];
}

double BoardTopZ(const SceneLayout& layout) { return layout.board_center_m.z() + 0.5 * layout.board_size_m.z(); }

TEST_CASE("Depth of the board plane equals the analytic depth within 1 mm") {
  RenderScene scene;  // no robot, no food: only furniture
  const double top = BoardTopZ(scene.layout);
  SECTION("looking straight down") {
    const CameraSpec camera = Camera("down", LookAt({0.5, 0.0, top + 0.5}, {0.5, 0.0, top}), 101, 101);
    const RenderResult result = SharedRenderer().Render(scene, {camera});
    const CameraImages& images = result.cameras.at(0);
    CHECK(images.depth_m[50 * 101 + 50] == Approx(0.5).margin(0.001));
  }
  SECTION("looking at a slant, at the centre and off-centre pixels") {
    const Eigen::Vector3d eye(0.85, 0.25, top + 0.4), target(0.55, 0.05, top);
    const CameraSpec camera = Camera("slant", LookAt(eye, target), 161, 121);
    const RenderResult result = SharedRenderer().Render(scene, {camera});
    const CameraImages& images = result.cameras.at(0);
    CHECK(images.depth_m[60 * 161 + 80] == Approx((target - eye).norm()).margin(0.001));
    // Off the axis: intersect each pixel's ray with the plane z = top; depth is camera z.
    const Eigen::Matrix3d K_inverse = images.intrinsics.K.inverse();
    for (const Eigen::Vector2i& pixel : {Eigen::Vector2i(70, 50), Eigen::Vector2i(90, 68), Eigen::Vector2i(84, 40)}) {
      const Eigen::Vector3d ray_camera = K_inverse * Eigen::Vector3d(pixel.x(), pixel.y(), 1.0);
      const Eigen::Vector3d ray_world = images.extrinsics.camera_to_world.linear() * ray_camera;
      const double t = (top - eye.z()) / ray_world.z();  // ray_camera.z() == 1: t is the depth
      const Eigen::Vector3d hit = eye + t * ray_world;
      REQUIRE(std::abs(hit.x() - scene.layout.board_center_m.x()) < 0.19);  // still on the board
      REQUIRE(std::abs(hit.y() - scene.layout.board_center_m.y()) < 0.14);
      CHECK(images.depth_m[pixel.y() * 161 + pixel.x()] == Approx(t).margin(0.001));
    }
  }
}

TEST_CASE("Segmentation shows the board, the knife and the robot at their projected centres") {
  RenderScene scene;
  scene.link_poses_world = PandaLinkPoses(ReadyPose());
  const RobotVisuals visuals = BuildRobotVisuals(testing::PandaVisuals());
  const auto& [blade_owner, blade_in_owner] = visuals.link_frames.at("knife_blade");
  const Eigen::Isometry3d blade = scene.link_poses_world[blade_owner] * blade_in_owner;
  // Face the blade's flat side (its local y) from 0.4 m away.
  const Eigen::Vector3d blade_center = blade.translation();
  const CameraSpec knife_camera =
      Camera("knife", LookAt(blade_center + 0.4 * blade.linear().col(1), blade_center), 120, 120);
  // A joint housing (sphere at the link 4 origin) seen from above and in front.
  const Eigen::Vector3d elbow = scene.link_poses_world[4].translation();
  const CameraSpec robot_camera = Camera("robot", LookAt(elbow + Eigen::Vector3d(0.3, 0.3, 0.4), elbow), 120, 120);
  // The board from the default front view, with the robot hidden.
  RenderScene no_robot;
  CameraSpec board_camera = DefaultCameras(no_robot.layout, 128, 96)[0];
  board_camera.segmentation = true;

  const RenderResult with_robot = SharedRenderer().Render(scene, {knife_camera, robot_camera});
  const RenderResult board_only = SharedRenderer().Render(no_robot, {board_camera});
  for (const auto& [images, point, id] :
       {std::make_tuple(&with_robot.cameras[0], blade_center, int(kKnifeSegment)),
        std::make_tuple(&with_robot.cameras[1], elbow, int(kRobotSegment)),
        std::make_tuple(&board_only.cameras[0], no_robot.layout.board_center_m, int(kBoardSegment))}) {
    const Eigen::Vector2d pixel = ProjectOpenCv(images->intrinsics, images->extrinsics, point);
    INFO("camera " << images->name << " pixel " << pixel.transpose());
    REQUIRE(images->segmentation.size() == static_cast<std::size_t>(images->width) * images->height);
    CHECK(At(images->segmentation, images->width, pixel) == id);
  }
  CHECK(with_robot.labels.at(kKnifeSegment).kind == "knife");
  CHECK(with_robot.labels.at(kBoardSegment).kind == "board");
}

TEST_CASE("A food split in two renders as two separate segments, and a whole one as one") {
  RenderScene scene;
  scene.food_names = {"cucumber"};
  const Eigen::Vector3d center(0.5, 0.0, BoardTopZ(scene.layout) + 0.02);
  const Eigen::Vector3d size(0.10, 0.04, 0.04);
  const CameraSpec camera = Camera("top", LookAt(center + Eigen::Vector3d(0, 0, 0.35), center), 160, 120);

  const auto whole = MakeParticleBlock(center, size);
  scene.food = whole.View();
  const RenderResult intact = SharedRenderer().Render(scene, {camera});
  const CameraImages& intact_images = intact.cameras.at(0);
  REQUIRE(intact.labels.size() == 5);
  CHECK(intact.labels[4].kind == "food");
  CHECK(intact.labels[4].food == "cucumber");
  CHECK(At(intact_images.segmentation, 160, ProjectOpenCv(intact_images.intrinsics, intact_images.extrinsics, center)) ==
        4);

  const auto cut = MakeParticleBlock(center, size, /*gap_m=*/0.02);
  scene.food = cut.View();
  const RenderResult split = SharedRenderer().Render(scene, {camera});
  const CameraImages& images = split.cameras.at(0);
  REQUIRE(split.labels.size() == 6);
  CHECK(split.labels[4].piece == 0);
  CHECK(split.labels[5].piece == 1);
  const Eigen::Vector3d left_centroid = center - Eigen::Vector3d(0.03, 0, 0);
  const Eigen::Vector3d right_centroid = center + Eigen::Vector3d(0.03, 0, 0);
  CHECK(At(images.segmentation, 160, ProjectOpenCv(images.intrinsics, images.extrinsics, left_centroid)) == 4);
  CHECK(At(images.segmentation, 160, ProjectOpenCv(images.intrinsics, images.extrinsics, right_centroid)) == 5);
  // The gap between them shows the board.
  CHECK(At(images.segmentation, 160, ProjectOpenCv(images.intrinsics, images.extrinsics, center)) == kBoardSegment);
  std::set<int> ids(images.segmentation.begin(), images.segmentation.end());
  CHECK(ids.count(4) == 1);
  CHECK(ids.count(5) == 1);
  CHECK(ids.count(6) == 0);
}

TEST_CASE("Cut faces show flesh, the rest skin") {
  RenderScene scene;
  scene.food_names = {"cucumber"};
  const Eigen::Vector3d center(0.5, 0.0, BoardTopZ(scene.layout) + 0.02);
  const auto cut = MakeParticleBlock(center, {0.10, 0.04, 0.04}, 0.03);
  scene.food = cut.View();
  // Look into the gap from the side so both a cut face and the skin on top are in view.
  const CameraSpec camera = Camera("side", LookAt(center + Eigen::Vector3d(0.0, -0.25, 0.12), center), 160, 120);
  const CameraImages images = SharedRenderer().Render(scene, {camera}).cameras.at(0);
  const Eigen::Vector3d face = center + Eigen::Vector3d(0.0155, -0.01, 0.0);       // right piece's cut face
  const Eigen::Vector3d skin = center + Eigen::Vector3d(0.035, 0.0, 0.02);          // its top
  const Eigen::Vector2d face_pixel = ProjectOpenCv(images.intrinsics, images.extrinsics, face);
  const Eigen::Vector2d skin_pixel = ProjectOpenCv(images.intrinsics, images.extrinsics, skin);
  REQUIRE(At(images.segmentation, 160, face_pixel) == 5);
  REQUIRE(At(images.segmentation, 160, skin_pixel) == 5);
  auto green_ratio = [&](const Eigen::Vector2d& pixel) {
    const std::size_t at = 3 * (static_cast<std::size_t>(std::lround(pixel.y())) * 160 + std::lround(pixel.x()));
    return static_cast<double>(images.rgb[at + 1]) / (1.0 + images.rgb[at] + images.rgb[at + 2]);
  };
  // Cucumber skin is dark green; its flesh is pale: far more red and blue for the same green.
  CHECK(green_ratio(skin_pixel) > 1.5 * green_ratio(face_pixel));
}

TEST_CASE("Rendering is deterministic and only the requested channels are produced") {
  RenderScene scene;
  scene.scene = "kitchen";
  scene.link_poses_world = PandaLinkPoses(ReadyPose());
  scene.food_names = {"apple"};
  const auto block = MakeParticleBlock({0.5, 0.0, 0.05}, {0.06, 0.06, 0.06});
  scene.food = block.View();
  auto cameras = DefaultCameras(scene.layout, 96, 72);
  cameras[1].depth = true;
  cameras[1].rgb = false;
  cameras[2].rgb = false;  // matrices only
  const RenderResult first = SharedRenderer().Render(scene, cameras);
  const RenderResult second = SharedRenderer().Render(scene, cameras);
  REQUIRE(first.cameras.size() == 3);
  CHECK(first.cameras[0].rgb.size() == 96 * 72 * 3);
  CHECK(first.cameras[0].depth_m.empty());
  CHECK(first.cameras[0].segmentation.empty());
  CHECK(first.cameras[1].rgb.empty());
  CHECK(first.cameras[1].depth_m.size() == 96 * 72);
  CHECK(first.cameras[2].rgb.empty());
  CHECK(first.cameras[2].depth_m.empty());
  CHECK(first.cameras[2].intrinsics.K(0, 0) > 0.0);
  CHECK(first.cameras[0].rgb == second.cameras[0].rgb);
  CHECK(first.cameras[1].depth_m == second.cameras[1].depth_m);
  // Not a blank image: the scene has many distinct colours.
  std::set<int> colours;
  for (std::size_t i = 0; i < first.cameras[0].rgb.size(); i += 3) colours.insert(first.cameras[0].rgb[i] << 16 | first.cameras[0].rgb[i + 1] << 8 | first.cameras[0].rgb[i + 2]);
  CHECK(colours.size() > 200);
}

TEST_CASE("Sessions rendering from several threads at once get the images of sequential calls") {
  std::vector<RenderScene> scenes(4);
  std::vector<testing::ParticleBlock> blocks;
  for (int s = 0; s < 4; ++s) blocks.push_back(MakeParticleBlock({0.45 + 0.03 * s, 0.0, 0.04}, {0.05, 0.03, 0.03}));
  for (int s = 0; s < 4; ++s) {
    scenes[s].scene = s % 2 ? "kitchen" : "table";
    Eigen::VectorXd q = ReadyPose();
    q[0] = 0.1 * s;
    scenes[s].link_poses_world = PandaLinkPoses(q);
    scenes[s].food = blocks[s].View();
    scenes[s].food_names = {"banana"};
  }
  const auto cameras = DefaultCameras(SceneLayout(), 64, 64);
  std::vector<RenderResult> sequential;
  for (const RenderScene& scene : scenes) sequential.push_back(SharedRenderer().Render(scene, cameras));
  std::vector<RenderResult> concurrent(scenes.size());
  std::vector<std::thread> sessions;
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    sessions.emplace_back([&, s] {
      for (int repeat = 0; repeat < 3; ++repeat) concurrent[s] = SharedRenderer().Render(scenes[s], cameras);
    });
  }
  for (std::thread& session : sessions) session.join();
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    for (std::size_t c = 0; c < cameras.size(); ++c) CHECK(concurrent[s].cameras[c].rgb == sequential[s].cameras[c].rgb);
  }
  CHECK(sequential[0].cameras[0].rgb != sequential[1].cameras[0].rgb);
}

TEST_CASE("A wrist camera follows its link, and cameras of any size render in one call") {
  RenderScene scene;
  scene.link_poses_world = PandaLinkPoses(ReadyPose());
  CameraSpec wrist = WristCamera(80, 60);
  CameraSpec wide = DefaultCameras(scene.layout, 200, 50)[0];
  const RenderResult result = SharedRenderer().Render(scene, {wrist, wide});
  const Eigen::Isometry3d flange_in_link7 = Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.107));
  const Eigen::Isometry3d expected = scene.link_poses_world[7] * flange_in_link7 * wrist.pose_in_world;
  CHECK(result.cameras[0].extrinsics.camera_to_world.isApprox(expected, 1e-9));
  CHECK(result.cameras[0].rgb.size() == 80 * 60 * 3);
  CHECK(result.cameras[1].rgb.size() == 200 * 50 * 3);
  // The knife is in the wrist camera's view.
  const CameraSpec wrist_seg = [&] { CameraSpec c = wrist; c.segmentation = true; return c; }();
  const auto seg = SharedRenderer().Render(scene, {wrist_seg}).cameras[0].segmentation;
  CHECK(std::count(seg.begin(), seg.end(), int(kKnifeSegment)) > 50);
}

TEST_CASE("Bad render requests give RenderError and leave the renderer working") {
  RenderScene scene;
  const auto cameras = DefaultCameras(scene.layout, 32, 32);
  RenderScene bad_scene = scene;
  bad_scene.scene = "garden";
  CHECK_THROWS_WITH(SharedRenderer().Render(bad_scene, cameras), Catch::Contains("unknown scene 'garden'"));
  RenderScene bad_poses = scene;
  bad_poses.link_poses_world.resize(3);
  CHECK_THROWS_WITH(SharedRenderer().Render(bad_poses, cameras), Catch::Contains("needs 8"));
  RenderScene bad_food = scene;
  const auto block = MakeParticleBlock({0.5, 0.0, 0.05}, {0.03, 0.03, 0.03});
  bad_food.food = block.View();
  bad_food.food_names = {"durian"};
  CHECK_THROWS_WITH(SharedRenderer().Render(bad_food, cameras), Catch::Contains("durian"));
  bad_food.food_names = {};
  CHECK_THROWS_WITH(SharedRenderer().Render(bad_food, cameras), Catch::Contains("food_names"));
  CameraSpec attached = cameras[0];
  attached.attached_link = "no_such_link";
  scene.link_poses_world = PandaLinkPoses(ReadyPose());
  CHECK_THROWS_WITH(SharedRenderer().Render(scene, {attached}), Catch::Contains("no_such_link"));
  CHECK(SharedRenderer().Render(scene, cameras).cameras.size() == 3);
  RendererOptions missing_robot;
  missing_robot.robot.owner_names = {"base"};
  missing_robot.robot.visuals.emplace_back();
  missing_robot.robot.visuals.back().shape.kind = VisualShape::Kind::kMesh;
  missing_robot.robot.visuals.back().shape.mesh_path = "/nonexistent/robot.stl";
  CHECK_THROWS_WITH(Renderer::Create(missing_robot), Catch::Contains("/nonexistent/robot.stl"));
  CHECK(SharedRenderer().device_description().find("OpenGL") != std::string::npos);
  CHECK(SharedRenderer().robot_pose_link_names().size() == 8);
}

// Run by the ctest render_egl_failure with __EGL_VENDOR_LIBRARY_FILENAMES naming no file, so that
// libglvnd finds no EGL vendor: starting must fail with a clear RenderError, not crash.
TEST_CASE("A renderer that cannot start EGL reports a clear error", "[.egl_failure]") {
  const char* vendors = std::getenv("__EGL_VENDOR_LIBRARY_FILENAMES");
  REQUIRE(vendors != nullptr);
  REQUIRE(std::string(vendors).find("nonexistent") != std::string::npos);
  try {
    Renderer::Create();
    FAIL("Renderer::Create succeeded without an EGL vendor");
  } catch (const RenderError& error) {
    const std::string message = error.what();
    INFO(message);
    CHECK(message.find("EGL could not start") != std::string::npos);
    CHECK(message.find("install") != std::string::npos);
  }
}

}  // namespace
}  // namespace culinarycut::render
