// Compressed images for the wire and for files, through OpenCV's codecs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/render/camera_images.h"

namespace culinarycut::render {

// The camera's RGB image as "png" (lossless; quality ignored) or "jpg"/"jpeg" (quality 0..100).
// Throws RenderError for an empty RGB channel, an unknown format or a codec failure.
std::vector<std::uint8_t> EncodeImage(const CameraImages& images, const std::string& format, int quality = 90);

// Depth as a 16-bit PNG in millimetres (0 = nothing, saturating at 65.535 m), the usual format of
// RGB-D datasets. Throws RenderError for an empty depth channel.
std::vector<std::uint8_t> EncodeDepthPng16(const CameraImages& images);

// Writes the RGB image to a file; the format follows the extension. Throws RenderError.
void WriteImageFile(const CameraImages& images, const std::string& path);

}  // namespace culinarycut::render
