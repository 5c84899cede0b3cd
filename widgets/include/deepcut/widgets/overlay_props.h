// SPDX-License-Identifier: MIT
#pragma once
/// @file overlay_props.h
/// Turns overlay data (overlay.h) into VTK props. Include only in .cpp files: it pulls in VTK.

#include <vtkProp.h>
#include <vtkSmartPointer.h>

#include <vector>

#include "deepcut/widgets/overlay.h"

namespace deepcut {

/// Props for one overlay, split by where they belong: `depth_tested` go into the model's
/// renderer, `on_top` into a renderer layered above it (cleared depth, same camera).
struct OverlayProps {
  std::vector<vtkSmartPointer<vtkProp>> depth_tested;
  std::vector<vtkSmartPointer<vtkProp>> on_top;
};

/// One actor per non-empty set: points as shaded sprites, lines (optionally as tubes),
/// spheres as translucent glyphs.
/// @param overlay  the sets to draw; a `colors` list whose size differs from its positions
///                 is ignored (the set's single colour is used).
/// @param line_tubes  draw lines as lit tubes (nicer, slower on software GL; default on).
/// @returns the props; sets without elements give none.
OverlayProps make_overlay_props(const Overlay& overlay, bool line_tubes = true);

/// A vertical scalar bar for `bar` (title, ramp of `stops`, range).
/// @pre bar.stops has at least two colours (otherwise a grey ramp is used).
vtkSmartPointer<vtkProp> make_color_bar(const ColorBar& bar);

}  // namespace deepcut
