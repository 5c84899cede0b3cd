// SPDX-License-Identifier: MIT
#include "deepcut/plugins/colors.h"

#include <algorithm>
#include <cmath>

namespace deepcut::plugins {
namespace {

const std::vector<glm::vec3>& ramp() {
  static const std::vector<glm::vec3> stops = {
      {0.0f, 0.0f, 1.0f}, {0.0f, 1.0f, 1.0f}, {0.0f, 1.0f, 0.0f}, {1.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};
  return stops;
}

glm::vec3 hsv(float h, float s, float v) {
  h = h - std::floor(h);
  const float k[3] = {5.0f, 3.0f, 1.0f};
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    const float x = std::fmod(k[i] + h * 6.0f, 6.0f);
    out[i] = v - v * s * std::max(0.0f, std::min({x, 4.0f - x, 1.0f}));
  }
  return out;
}

}  // namespace

glm::vec3 weight_color(float w) {
  if (!(w >= 0.0f)) w = 0.0f;  // NaN too
  w = std::min(w, 1.0f);
  const auto& s = ramp();
  const float x = w * static_cast<float>(s.size() - 1);
  const auto k = std::min(static_cast<std::size_t>(x), s.size() - 2);
  return glm::mix(s[k], s[k + 1], x - static_cast<float>(k));
}

std::vector<glm::vec3> weight_ramp() { return ramp(); }

glm::vec3 category_color(std::size_t i) {
  constexpr float kGoldenAngle = 0.381966f;
  const float h = 0.07f + kGoldenAngle * static_cast<float>(i);
  const float s = (i / 7) % 2 == 0 ? 0.72f : 0.5f;
  const float v = (i / 14) % 2 == 0 ? 0.95f : 0.75f;
  return hsv(h, s, v);
}

glm::vec3 pastel(const glm::vec3& c, float amount) {
  return glm::mix(c, glm::vec3(0.85f), std::clamp(amount, 0.0f, 1.0f));
}

glm::u8vec3 to_rgb8(const glm::vec3& c) {
  const glm::vec3 k = glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f)) * 255.0f + 0.5f;
  return glm::u8vec3(static_cast<std::uint8_t>(k.x), static_cast<std::uint8_t>(k.y),
                     static_cast<std::uint8_t>(k.z));
}

}  // namespace deepcut::plugins
