// SPDX-License-Identifier: MIT
#include "anti_aliasing.h"

#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFunctions>
#include <algorithm>
#include <cctype>

namespace deepcut::studio {

namespace {

std::string probe_renderer() {
  QOffscreenSurface surface;
  surface.create();
  QOpenGLContext context;
  if (!surface.isValid() || !context.create() || !context.makeCurrent(&surface)) return {};
  const auto* name = reinterpret_cast<const char*>(context.functions()->glGetString(GL_RENDERER));
  std::string out = name ? name : "";
  context.doneCurrent();
  return out;
}

}  // namespace

const std::string& gl_renderer_name() {
  static const std::string name = probe_renderer();
  return name;
}

bool is_software_renderer(const std::string& renderer) {
  std::string lower = renderer;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  // Mesa (llvmpipe, softpipe, swrast's "Software Rasterizer", OpenSWR), Windows' GDI and Basic
  // Render drivers, Apple's software renderer.
  for (const char* word : {"llvmpipe", "softpipe", "software", "swrast", "swr", "gdi generic", "basic render"})
    if (lower.find(word) != std::string::npos) return true;
  return false;
}

int multisamples_for(AntiAliasing mode, bool software) {
  switch (mode) {
    case AntiAliasing::On:
      return kMultisamples;
    case AntiAliasing::Off:
      return 0;
    case AntiAliasing::Automatic:
      break;
  }
  return software ? 0 : kMultisamples;
}

const char* anti_aliasing_name(AntiAliasing mode) {
  switch (mode) {
    case AntiAliasing::On:
      return "on";
    case AntiAliasing::Off:
      return "off";
    case AntiAliasing::Automatic:
      break;
  }
  return "auto";
}

std::optional<AntiAliasing> parse_anti_aliasing(const std::string& name) {
  for (AntiAliasing mode : {AntiAliasing::Automatic, AntiAliasing::On, AntiAliasing::Off})
    if (name == anti_aliasing_name(mode)) return mode;
  return std::nullopt;
}

}  // namespace deepcut::studio
