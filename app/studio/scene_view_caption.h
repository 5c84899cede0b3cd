// SPDX-License-Identifier: MIT
#pragma once
/// @file scene_view_caption.h
/// The view's caption: text in the upper left corner, the same pixels as vtkCornerAnnotation's
/// upper-left text with the studio's settings (the font size fitted to the view, then doubled and
/// at most 15). vtkCornerAnnotation fits the size by rendering the text at every size from the
/// last one up to where it no longer fits in the view (17 sizes for an open's caption in the
/// studio's window, each glyph loaded and the text rasterized: 118M instructions, a sixth of what
/// a 1M-triangle model's first frame runs on the UI thread besides the renderer's own work), and
/// again whenever the text or the view's size changes (an edit's caption). Any fitted size from 8
/// up gives 15, and the fit ends at 8 or above whenever the text fits at 8 and the search starts
/// there or above (the size only shrinks while the text is too large): this caption measures the
/// text once, at 8, and takes 15 then; otherwise (a view a few hundred pixels wide) it searches
/// as vtkCornerAnnotation does, from the same start. The text is drawn as given (vtkCornerAnnotation
/// replaced tokens meant for image viewers, such as "<slice>", with nothing).

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

  /// The text's style (as vtkCornerAnnotation::GetTextProperty): its size and justification are
  /// the caption's own.
  vtkTextProperty* GetTextProperty() { return style_; }
  /// The text, lines separated by '\n' (as vtkCornerAnnotation::SetText for its upper left corner).
  void SetText(const std::string& text);
  /// The size the text is drawn at, fitted at the last frame that drew text.
  int font_size() const { return font_size_; }
  /// How many sizes the text was measured at by the fits so far.
  int sizes_measured() const { return measured_; }

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

 protected:
  CaptionActor();

 private:
  /// The text's size at font size `size` (what vtkTextMapper::GetSize says).
  void measure(vtkViewport* viewport, int size, int extent[2]);
  /// The fitted size (before scaling) for a view of `view` pixels, as vtkCornerAnnotation finds it
  /// from `start`, the size the text was drawn at before.
  int fit(vtkViewport* viewport, const int view[2], int start);

  vtkNew<vtkTextProperty> style_;
  vtkNew<vtkTextMapper> text_;     // draws
  vtkNew<vtkTextMapper> measure_;  // measures, so the drawn text's image stays while the view resizes
  int lines_ = 0;
  int font_size_ = kMaximumFontSize;  // (vtkCornerAnnotation's first)
  int measured_ = 0;
  int last_view_[2] = {0, 0};
  bool text_changed_ = true;
  vtkTimeStamp built_;  // when the size was last fitted
};

}  // namespace deepcut::studio
