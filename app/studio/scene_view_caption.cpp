// SPDX-License-Identifier: MIT
#include "scene_view_caption.h"

#include <vtkObjectFactory.h>
#include <vtkViewport.h>

#include <algorithm>

namespace deepcut::studio {

vtkStandardNewMacro(CaptionActor);

namespace {

// The fit's tests (vtkCornerAnnotation::RenderOpaqueGeometry's, for text in one corner: the other
// corners' and edges' extents are 0) on the text's extent `e` in a view of `view` pixels, `lines`
// lines of text.
struct Room {
  int width, height, line_max, one_line;
  Room(const int view[2], int lines)
      : width(static_cast<int>(0.9 * view[0])),
        height(static_cast<int>(0.9 * view[1])),
        line_max(view[1] * (lines ? lines : 1)),
        one_line(view[1]) {}
  // Room to grow: every extent below its limit.
  bool fits(const int e[2]) const {
    return e[1] < height && 0 < height && e[0] < width && e[1] < line_max && 0 < one_line;
  }
  // Too large: an extent above its limit.
  bool exceeded(const int e[2]) const { return e[1] > height || e[0] > width || e[1] > line_max; }
};

int line_count(const std::string& text) {
  return text.empty() ? 0 : 1 + static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

CaptionActor::CaptionActor() {
  SetMapper(text_);
  measure_->SetInput("");
  text_->SetInput("");
}

void CaptionActor::SetText(const std::string& text) {
  if (text == text_->GetInput()) return;
  text_->SetInput(text.c_str());
  measure_->SetInput(text.c_str());
  lines_ = line_count(text);
  text_changed_ = true;
}

void CaptionActor::measure(vtkViewport* viewport, int size, int extent[2]) {
  measure_->GetTextProperty()->SetFontSize(size);
  measure_->GetSize(viewport, extent);
  ++measured_;
}

int CaptionActor::fit(vtkViewport* viewport, const int view[2], int start) {
  const Room room(view, lines_);
  int e[2];
  // The smallest fitted size that scales to the maximum: when the text fits there, any search
  // from there or above ends there or above.
  const int enough = (kMaximumFontSize + kScale - 1) / kScale;
  if (start >= enough) {
    measure(viewport, enough, e);
    if (room.fits(e)) return enough;
  }
  // vtkCornerAnnotation's search: up while the text fits, then down while it is too large.
  int size = start;
  measure(viewport, size, e);
  while (room.fits(e) && size < 100) measure(viewport, ++size, e);
  while (room.exceeded(e) && size > 0) measure(viewport, --size, e);
  return size;
}

int CaptionActor::RenderOpaqueGeometry(vtkViewport* viewport) {
  const int* size = viewport->GetSize();
  const int view[2] = {size[0], size[1]};
  const bool restyled = style_->GetMTime() > built_.GetMTime();
  if (text_changed_ || restyled || view[0] != last_view_[0] || view[1] != last_view_[1]) {
    if (lines_ == 0) return 0;  // (as vtkCornerAnnotation: nothing to fit, nothing drawn)
    vtkTextProperty* drawn = text_->GetTextProperty();
    const int start = drawn->GetFontSize();  // the size drawn before
    if (restyled) {
      drawn->ShallowCopy(style_);
      drawn->SetFontSize(start);
      drawn->SetJustificationToLeft();
      drawn->SetVerticalJustificationToTop();
    }
    measure_->GetTextProperty()->ShallowCopy(drawn);
    font_size_ = std::min(kMaximumFontSize, kScale * fit(viewport, view, start));
    drawn->SetFontSize(font_size_);
    SetPosition(5, view[1] - 5);
    last_view_[0] = view[0], last_view_[1] = view[1];
    text_changed_ = false;
    built_.Modified();
  }
  if (font_size_ >= kMinimumFontSize) Superclass::RenderOpaqueGeometry(viewport);
  return 1;
}

int CaptionActor::RenderOverlay(vtkViewport* viewport) {
  if (font_size_ >= kMinimumFontSize) Superclass::RenderOverlay(viewport);
  return 1;
}

}  // namespace deepcut::studio
