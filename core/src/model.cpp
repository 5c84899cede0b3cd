// SPDX-License-Identifier: MIT
#include "deepcut/core/model.h"

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>

namespace deepcut {

glm::mat4 Node::local_matrix() const {
  if (matrix) return *matrix;
  return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) * glm::scale(glm::mat4(1.0f), scale);
}

float Animation::duration() const {
  float d = 0.0f;
  for (const auto& s : samplers)
    if (!s.input.empty()) d = std::max(d, s.input.back());
  return d;
}

std::vector<int> Model::parents() const {
  std::vector<int> parent(nodes.size(), -1);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (int c : nodes[i].children)
      if (c >= 0 && static_cast<std::size_t>(c) < nodes.size()) parent[c] = static_cast<int>(i);
  return parent;
}

std::vector<int> Model::root_nodes() const {
  if (default_scene >= 0 && static_cast<std::size_t>(default_scene) < scenes.size()) return scenes[default_scene];
  std::vector<int> roots;
  const auto parent = parents();
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (parent[i] < 0) roots.push_back(static_cast<int>(i));
  return roots;
}

}  // namespace deepcut
