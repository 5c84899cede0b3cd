// SPDX-License-Identifier: MIT
#pragma once
/// @file offscreen_frames.h
/// Set-up shared by the studio tests that compare frames VTK draws without a main window
/// (caption_test.cpp, surface_mapper_test.cpp; VTK only, no studio test support library): one
/// offscreen render window for the whole program, frames read back as RGB bytes, compared byte
/// for byte.

#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>

namespace deepcut::test::studio {

/// An offscreen render window of `width` x `height`, to draw every case of a test program in: a
/// window closed and another opened at once can find the X server resetting after its last
/// client left.
inline vtkSmartPointer<vtkRenderWindow> offscreen_window(int width, int height) {
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetSize(width, height);
  return window;
}

/// The frame of `renderer` drawn alone in `window`, at the window's size, as RGB bytes; empty
/// when the read-back did not give the whole frame.
inline vtkSmartPointer<vtkUnsignedCharArray> frame_of(vtkRenderWindow* window, vtkRenderer* renderer) {
  window->AddRenderer(renderer);
  window->Render();
  const int* size = window->GetSize();
  auto pixels = vtkSmartPointer<vtkUnsignedCharArray>::New();
  window->GetPixelData(0, 0, size[0] - 1, size[1] - 1, 1, pixels);
  if (pixels->GetNumberOfValues() != 3 * vtkIdType(size[0]) * size[1]) pixels->Initialize();  // not whole
  window->RemoveRenderer(renderer);
  return pixels;
}

/// Whether two frames have the same bytes. An empty frame (a failed read-back, see frame_of) is
/// never the same as another: two failed read-backs must not pass for equal frames.
inline bool same_pixels(vtkUnsignedCharArray* a, vtkUnsignedCharArray* b) {
  return a->GetNumberOfValues() > 0 && a->GetNumberOfValues() == b->GetNumberOfValues() &&
         std::equal(a->GetPointer(0), a->GetPointer(0) + a->GetNumberOfValues(), b->GetPointer(0));
}

}  // namespace deepcut::test::studio
