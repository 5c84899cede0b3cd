// SPDX-License-Identifier: MIT
#pragma once
/// @file plane_representation.h
/// The cutting plane's geometry (VTK naming): vtkImplicitPlaneRepresentation with the studio's
/// colours, a translucent plane cropped to the placed box, tubed edges, no outline dragging and
/// no scaling; the origin may leave the box. Pair with PlaneWidget. Include only in .cpp files.

#include <vtkImplicitPlaneRepresentation.h>

namespace deepcut {

class PlaneRepresentation : public vtkImplicitPlaneRepresentation {
 public:
  static PlaneRepresentation* New();
  vtkTypeMacro(PlaneRepresentation, vtkImplicitPlaneRepresentation)

 protected:
  PlaneRepresentation();
  ~PlaneRepresentation() override = default;

 private:
  PlaneRepresentation(const PlaneRepresentation&) = delete;
  void operator=(const PlaneRepresentation&) = delete;
};

}  // namespace deepcut
