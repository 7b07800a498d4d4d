#include "sim/render/video_writer.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "sim/render/render_error.h"

namespace culinarycut::render {

struct VideoWriter::State {
  cv::VideoWriter writer;
  std::string path;
  VideoLayout layout;
  int columns = 1;
  int rows = 1;
  cv::Mat canvas;  // BGR, reused for every frame
  cv::Mat tile_rgb;
};

VideoWriter::VideoWriter() = default;
VideoWriter::~VideoWriter() { Close(); }

bool VideoWriter::is_open() const { return state_ && state_->writer.isOpened(); }
int VideoWriter::width() const { return state_ ? state_->canvas.cols : 0; }
int VideoWriter::height() const { return state_ ? state_->canvas.rows : 0; }

void VideoWriter::Open(const std::string& path, double fps, const VideoLayout& layout) {
  Close();
  if (layout.cameras.empty()) throw RenderError("video '" + path + "': the layout names no camera");
  if (layout.tile_width <= 0 || layout.tile_height <= 0 || fps <= 0.0) {
    throw RenderError("video '" + path + "': tile size and fps must be positive");
  }
  auto state = std::make_unique<State>();
  state->path = path;
  state->layout = layout;
  const int count = static_cast<int>(layout.cameras.size());
  state->columns = layout.columns > 0 ? std::min(layout.columns, count) : count;
  state->rows = (count + state->columns - 1) / state->columns;
  // Codecs want even frame sizes.
  const int width = (state->columns * layout.tile_width + 1) / 2 * 2;
  const int height = (state->rows * layout.tile_height + 1) / 2 * 2;
  state->canvas = cv::Mat(height, width, CV_8UC3, cv::Scalar(0, 0, 0));
  if (!state->writer.open(path, cv::CAP_FFMPEG, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps, cv::Size(width, height), true)) {
    throw RenderError("cannot open video file '" + path +
                      "' for writing (missing folder, no permission, or OpenCV built without an mp4 writer)");
  }
  state_ = std::move(state);
  frames_written_ = 0;
}

void VideoWriter::Add(const std::vector<CameraImages>& frames) {
  if (!is_open()) throw RenderError("VideoWriter::Add before Open (or after Close)");
  State& s = *state_;
  for (std::size_t t = 0; t < s.layout.cameras.size(); ++t) {
    const std::string& name = s.layout.cameras[t];
    const CameraImages* found = nullptr;
    for (const CameraImages& frame : frames) {
      if (frame.name == name) found = &frame;
    }
    if (found == nullptr || found->rgb.empty()) {
      throw RenderError("video '" + s.path + "': camera '" + name + "' is missing or has no RGB image");
    }
    const cv::Mat rgb(found->height, found->width, CV_8UC3, const_cast<std::uint8_t*>(found->rgb.data()));
    const int column = static_cast<int>(t) % s.columns, row = static_cast<int>(t) / s.columns;
    cv::Mat tile = s.canvas(cv::Rect(column * s.layout.tile_width, row * s.layout.tile_height, s.layout.tile_width,
                                     s.layout.tile_height));
    if (rgb.cols == tile.cols && rgb.rows == tile.rows) {
      cv::cvtColor(rgb, tile, cv::COLOR_RGB2BGR);
    } else {
      cv::resize(rgb, s.tile_rgb, tile.size(), 0, 0, cv::INTER_AREA);
      cv::cvtColor(s.tile_rgb, tile, cv::COLOR_RGB2BGR);
    }
  }
  s.writer.write(s.canvas);
  ++frames_written_;
}

void VideoWriter::Close() {
  if (state_) state_->writer.release();
  state_.reset();
}

}  // namespace culinarycut::render
