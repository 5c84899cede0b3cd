// SPDX-License-Identifier: MIT
#pragma once
// Anti-aliasing of the 3D view, and which OpenGL renderer draws it.
//
// Multisampling shades every pixel of a triangle's edge several times. A graphics card does
// that in hardware at no visible cost; a software renderer (Mesa's llvmpipe on a machine
// without a GPU, a virtual machine, a remote desktop) shades each sample on the CPU, and 8x
// multisampling makes each frame of a large model several times slower. `Automatic` turns it
// on for graphics hardware and off for a software renderer; the View menu and
// `--anti-aliasing` choose it explicitly.

#include <optional>
#include <string>

namespace deepcut::studio {

enum class AntiAliasing { Automatic, On, Off };

/// The samples per pixel the view asks for when anti-aliasing is on (the driver may give fewer:
/// Mesa's llvmpipe gives 4).
inline constexpr int kMultisamples = 8;

/// The OpenGL renderer the view draws with, as the driver names it ("llvmpipe (LLVM 15.0.6,
/// 256 bits)", "NVIDIA GeForce RTX 3060/PCIe/SSE2", ...), probed once on an offscreen context
/// with the application's default surface format. Empty when no context could be made.
/// @pre a QGuiApplication exists; call on the UI thread.
const std::string& gl_renderer_name();

/// Whether `renderer` (an OpenGL renderer string) names a renderer that draws on the CPU.
bool is_software_renderer(const std::string& renderer);

/// The samples per pixel for `mode` on a renderer that is (or is not) `software`.
int multisamples_for(AntiAliasing mode, bool software);

/// "auto", "on", "off"; and back (nullopt for anything else).
const char* anti_aliasing_name(AntiAliasing mode);
std::optional<AntiAliasing> parse_anti_aliasing(const std::string& name);

}  // namespace deepcut::studio
