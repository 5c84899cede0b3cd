// SPDX-License-Identifier: MIT
#pragma once
/// @file overlay.h
/// What an inspector draws over the model (markers, lines, translucent spheres), as plain data.
/// No VTK here: inspectors build an `Overlay`, the studio turns it into props with
/// `make_overlay_props` (overlay_props.h). Positions are world space.

#include <glm/glm.hpp>
#include <string>
#include <vector>

namespace deepcut {

/// Point markers drawn as screen-space discs (shaded as spheres).
struct OverlayPoints {
  std::vector<glm::vec3> positions;
  /// One colour per point (RGB in [0, 1]); empty: every point gets `color`.
  std::vector<glm::vec3> colors;
  glm::vec3 color{1.0f, 1.0f, 0.0f};
  float size_px = 8.0f;  ///< diameter in pixels (default 8)
  bool on_top = false;   ///< drawn over the model, never hidden by it (default off: depth tested)
};

/// Line segments: `endpoints[2 i]` to `endpoints[2 i + 1]`.
struct OverlayLines {
  std::vector<glm::vec3> endpoints;
  glm::vec3 color{1.0f, 1.0f, 1.0f};
  float width_px = 2.0f;  ///< line width in pixels (default 2)
  bool on_top = false;    ///< default off: depth tested, drawn just in front of coincident surface
};

/// Translucent spheres of world-space radius (particle extents and the like).
struct OverlaySpheres {
  std::vector<glm::vec3> centers;
  std::vector<float> radii;       ///< one per center, world units
  std::vector<glm::vec3> colors;  ///< one per center; empty: every sphere gets `color`
  glm::vec3 color{0.8f, 0.8f, 0.8f};
  float opacity = 0.2f;  ///< default 0.2
};

struct Overlay {
  std::vector<OverlayPoints> points;
  std::vector<OverlayLines> lines;
  std::vector<OverlaySpheres> spheres;

  bool empty() const { return points.empty() && lines.empty() && spheres.empty(); }
  /// Appends everything in `other`.
  void append(const Overlay& other) {
    points.insert(points.end(), other.points.begin(), other.points.end());
    lines.insert(lines.end(), other.lines.begin(), other.lines.end());
    spheres.insert(spheres.end(), other.spheres.begin(), other.spheres.end());
  }
};

/// A continuous colour scale shown beside the view (ParaView's scalar bar).
struct ColorBar {
  std::string title;
  /// Colours at equally spaced values from `min` (first) to `max` (last); at least two.
  std::vector<glm::vec3> stops;
  float min = 0.0f, max = 1.0f;
};

}  // namespace deepcut
