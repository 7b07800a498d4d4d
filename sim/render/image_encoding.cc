#include "sim/render/image_encoding.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

cv::Mat RgbAsBgr(const CameraImages& images) {
  if (images.rgb.size() != static_cast<std::size_t>(images.width) * images.height * 3 || images.rgb.empty()) {
    throw RenderError("camera '" + images.name + "' has no RGB image to encode (was rgb requested?)");
  }
  const cv::Mat rgb(images.height, images.width, CV_8UC3, const_cast<std::uint8_t*>(images.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);  // OpenCV codecs expect BGR
  return bgr;
}

}  // namespace

std::vector<std::uint8_t> EncodeImage(const CameraImages& images, const std::string& format, int quality) {
  std::string extension;
  std::vector<int> parameters;
  if (format == "png") {
    extension = ".png";
    parameters = {cv::IMWRITE_PNG_COMPRESSION, 3};  // fast; PNG is lossless at every level
  } else if (format == "jpg" || format == "jpeg") {
    extension = ".jpg";
    parameters = {cv::IMWRITE_JPEG_QUALITY, std::clamp(quality, 0, 100)};
  } else {
    throw RenderError("unknown image format '" + format + "'; choose png or jpg");
  }
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(extension, RgbAsBgr(images), bytes, parameters)) {
    throw RenderError("OpenCV could not encode camera '" + images.name + "' as " + format);
  }
  return bytes;
}

std::vector<std::uint8_t> EncodeDepthPng16(const CameraImages& images) {
  if (images.depth_m.empty()) throw RenderError("camera '" + images.name + "' has no depth image to encode");
  cv::Mat millimetres(images.height, images.width, CV_16UC1);
  for (int v = 0; v < images.height; ++v) {
    for (int u = 0; u < images.width; ++u) {
      const float depth = images.depth_m[static_cast<std::size_t>(v) * images.width + u];
      const float mm = std::isfinite(depth) ? std::round(depth * 1000.0f) : 0.0f;
      millimetres.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::clamp(mm, 0.0f, 65535.0f));
    }
  }
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(".png", millimetres, bytes)) throw RenderError("OpenCV could not encode a 16-bit PNG");
  return bytes;
}

void WriteImageFile(const CameraImages& images, const std::string& path) {
  if (!cv::imwrite(path, RgbAsBgr(images))) {
    throw RenderError("cannot write image file '" + path + "' (missing folder, no permission or unknown extension)");
  }
}

}  // namespace culinarycut::render
