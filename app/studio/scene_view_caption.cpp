// SPDX-License-Identifier: MIT
#include "scene_view_caption.h"

#include <vtkObjectFactory.h>
#include <vtkViewport.h>

#include <algorithm>

namespace deepcut::studio {

vtkStandardNewMacro(CaptionActor);

namespace {

// vtkCornerAnnotation's two tests in its fit, for text in one corner only (the other corners and
// edges measure 0 x 0), on the text's extent `e` in a view of `view` pixels with `lines` lines:
// the size goes up while fits() holds, then down while exceeded() holds. They are not opposites:
// an extent equal to its limit neither fits nor exceeds, and the search stops there. The tests
// on `line_max` and `one_line` only mirror vtkCornerAnnotation's and never decide: `line_max` is
// at least the view's height, above `height`, so the tests on `height` fail first; and
// `0 < height` already implies `0 < one_line`.
struct Room {
  int width, height, line_max, one_line;
  Room(const int view[2], int lines)
      : width(static_cast<int>(0.9 * view[0])),
        height(static_cast<int>(0.9 * view[1])),
        line_max(view[1] * (lines ? lines : 1)),
        one_line(view[1]) {}
  // Every extent below its limit: room for the next size.
  bool fits(const int e[2]) const {
    return e[1] < height && 0 < height && e[0] < width && e[1] < line_max && 0 < one_line;
  }
  // Some extent above its limit: too large.
  bool exceeded(const int e[2]) const { return e[1] > height || e[0] > width || e[1] > line_max; }
};

bool blank(const int e[2]) { return e[0] <= 0 && e[1] <= 0; }

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
}

int CaptionActor::fit(vtkViewport* viewport, const int view[2], int start) {
  const Room room(view, lines_);
  int e[2];
  // The smallest fitted size that scales to the maximum: when the text fits there, any search
  // from there or above ends there or above.
  const int enough = (kMaximumFontSize + kScale - 1) / kScale;
  bool measured_start = false;
  if (start >= enough) {
    measure(viewport, enough, e);
    if (!blank(e) && room.fits(e)) return enough;
    measured_start = start == enough;
  }
  // vtkCornerAnnotation's search: none when the text measures 0 x 0 at the start, else up while
  // the text fits, then down while it is too large.
  if (!measured_start) measure(viewport, start, e);
  if (blank(e)) return -1;
  int size = start;
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
    last_view_[0] = view[0];
    last_view_[1] = view[1];
    const int fitted = fit(viewport, view, start);
    // (as vtkCornerAnnotation: a text that measures 0 x 0 is not drawn, and the next frame fits
    // again unless only the view's size had changed)
    if (fitted < 0) return 0;
    font_size_ = std::min(kMaximumFontSize, kScale * fitted);
    drawn->SetFontSize(font_size_);
    SetPosition(5, view[1] - 5);
    text_changed_ = false;
    built_.Modified();
  }
  if (font_size_ >= kMinimumFontSize) Superclass::RenderOpaqueGeometry(viewport);
  return 1;
}

void CaptionActor::PrintSelf(ostream& os, vtkIndent indent) {
  Superclass::PrintSelf(os, indent);
  os << indent << "Text: " << (text_->GetInput() ? text_->GetInput() : "") << "\n";
  os << indent << "FontSize: " << font_size_ << "\n";
  os << indent << "TextProperty: " << style_.Get() << "\n";
}

int CaptionActor::RenderOverlay(vtkViewport* viewport) {
  if (font_size_ >= kMinimumFontSize) Superclass::RenderOverlay(viewport);
  return 1;
}

}  // namespace deepcut::studio
