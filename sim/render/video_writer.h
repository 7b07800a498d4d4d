// Episode videos: an mp4 (fourcc mp4v) of one camera, or of several cameras tiled in a grid.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/render/camera_images.h"

namespace culinarycut::render {

struct VideoLayout {
  std::vector<std::string> cameras;  // camera names, tiled left to right, top to bottom
  int columns = 0;                   // 0 = all in one row
  int tile_width = 224;              // every camera's RGB is resized to the tile (pixels)
  int tile_height = 224;
};

class VideoWriter {
 public:
  VideoWriter();
  ~VideoWriter();  // closes the file
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Throws RenderError naming the path if the file cannot be opened, or for a bad layout.
  void Open(const std::string& path, double fps, const VideoLayout& layout);
  // One video frame from one render call's cameras; throws RenderError if a laid-out camera is
  // missing or has no RGB image, or if the writer is not open.
  void Add(const std::vector<CameraImages>& frames);
  void Close();

  bool is_open() const;
  int frames_written() const { return frames_written_; }
  int width() const;   // of the whole video frame, pixels
  int height() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
  int frames_written_ = 0;
};

}  // namespace culinarycut::render
