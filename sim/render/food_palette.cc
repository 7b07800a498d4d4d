#include "sim/render/food_palette.h"

#include <cmath>
#include <map>

#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

// sRGB 0..255 to linear 0..1, so the palette can be written as the colours one sees.
Eigen::Vector3f FromSrgb(int r, int g, int b) {
  auto linear = [](int channel) {
    const float c = channel / 255.0f;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  };
  return {linear(r), linear(g), linear(b)};
}

const std::map<std::string, FoodColors>& Palette() {
  static const std::map<std::string, FoodColors> palette = {
      {"banana", {FromSrgb(236, 200, 60), FromSrgb(246, 238, 200)}},
      {"cucumber", {FromSrgb(50, 105, 40), FromSrgb(200, 225, 150)}},
      {"apple", {FromSrgb(180, 30, 35), FromSrgb(245, 235, 190)}},
      {"peach", {FromSrgb(240, 150, 90), FromSrgb(250, 190, 110)}},
      {"melon", {FromSrgb(185, 200, 120), FromSrgb(250, 160, 90)}},
      {"orange", {FromSrgb(245, 140, 20), FromSrgb(250, 170, 60)}},
      {"strawberry", {FromSrgb(200, 25, 35), FromSrgb(250, 170, 165)}},
  };
  return palette;
}

}  // namespace

const FoodColors& FoodPalette(const std::string& food) {
  const auto& palette = Palette();
  const auto it = palette.find(food);
  if (it != palette.end()) return it->second;
  std::string known;
  for (const auto& [name, colors] : palette) known += (known.empty() ? "" : ", ") + name;
  throw RenderError("no colours for food '" + food + "'; known foods: " + known);
}

std::vector<std::string> FoodPaletteNames() {
  std::vector<std::string> names;
  for (const auto& [name, colors] : Palette()) names.push_back(name);
  return names;
}

}  // namespace culinarycut::render
