// SPDX-License-Identifier: MIT
#pragma once
/// @file scene_view_caption.h
/// The view's caption: text in the upper left corner of the view. What it guarantees: every frame
/// has the same pixels as vtkCornerAnnotation's (VTK 9.1) with the text in its upper left corner
/// and the studio's settings (the font size fitted to the view, times 2, at most 15, not drawn
/// below 6), at any view size, DPI and style, except that the text is drawn as given, where
/// vtkCornerAnnotation replaced image viewers' tokens such as "<slice>" or "<window>" with
/// nothing (the caption shows file and joint names, which may hold such text).
/// What it does differently: vtkCornerAnnotation fits the size by measuring the text at every
/// size from the last one drawn to where it no longer fits, whenever the text, the style or the
/// view's size changes. Any fitted size from 8 up is drawn at 15, and a search that starts at 8 or
/// above ends at 8 or above when the text fits at 8 (the size only shrinks while the text is too
/// large): so the caption measures the text at 8 first and, when it fits, stops there; otherwise
/// (a view a few hundred pixels wide or a few dozen high) it searches as vtkCornerAnnotation does.

#include <vtkActor2D.h>
#include <vtkNew.h>
#include <vtkTextMapper.h>
#include <vtkTextProperty.h>

#include <string>

namespace deepcut::studio {

class CaptionActor : public vtkActor2D {
 public:
  static CaptionActor* New();
  vtkTypeMacro(CaptionActor, vtkActor2D)
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The text's style (as vtkCornerAnnotation::GetTextProperty): its size and justification are
  /// the caption's own.
  vtkTextProperty* GetTextProperty() { return style_; }
  /// The text, lines separated by '\n' (as vtkCornerAnnotation::SetText for its upper left corner).
  void SetText(const std::string& text);
  /// The size the text is drawn at, fitted at the last frame that fitted it.
  int font_size() const { return font_size_; }

  /// Fits the size when the text, its style or the view's size changed, then draws.
  int RenderOpaqueGeometry(vtkViewport* viewport) override;
  int RenderTranslucentPolygonalGeometry(vtkViewport*) override { return 0; }
  int RenderOverlay(vtkViewport* viewport) override;
  vtkTypeBool HasTranslucentPolygonalGeometry() override { return 0; }

  // vtkCornerAnnotation's settings, as the studio sets them: the fitted size times this, at most
  // the maximum; smaller than the minimum, the text is not drawn.
  static constexpr int kScale = 2;
  static constexpr int kMaximumFontSize = 15;
  static constexpr int kMinimumFontSize = 6;

  CaptionActor(const CaptionActor&) = delete;
  CaptionActor& operator=(const CaptionActor&) = delete;

 protected:
  CaptionActor();
  ~CaptionActor() override = default;

 private:
  /// The text's size at font size `size` (what vtkTextMapper::GetSize says).
  void measure(vtkViewport* viewport, int size, int extent[2]);
  /// The fitted size (before scaling) for a view of `view` pixels, as vtkCornerAnnotation finds it
  /// from `start`, the size the text was drawn at before; -1 when the text measures 0 x 0 at
  /// `start` (vtkCornerAnnotation then gives up: no fit, nothing drawn).
  int fit(vtkViewport* viewport, const int view[2], int start);

  vtkNew<vtkTextProperty> style_;
  vtkNew<vtkTextMapper> text_;     // draws
  vtkNew<vtkTextMapper> measure_;  // measures, so the drawn text's image stays while the view resizes
  int lines_ = 0;
  int font_size_ = kMaximumFontSize;  // (vtkCornerAnnotation's first)
  int last_view_[2] = {0, 0};
  bool text_changed_ = true;
  vtkTimeStamp built_;  // when the size was last fitted
};

}  // namespace deepcut::studio
